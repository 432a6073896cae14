"""The coating calculator: Hertz's impact duration on a wall and its inverse."""

import math

import pytest

from pdamper import theory
from pdamper.errors import InputError

STEEL = dict(sphere_radius=0.005, sphere_density=7900.0, sphere_modulus=208e9, sphere_poisson=0.3)


@pytest.mark.parametrize("e_wall", [5e6, 26e6, 3e9])
def test_the_wall_modulus_for_a_contact_time_inverts_the_contact_time(e_wall):
    tc = theory.hertz_contact_time(**STEEL, wall_modulus=e_wall, wall_poisson=0.45, impact_speed=0.4)
    back = theory.wall_modulus_for_contact_time(tc, **STEEL, wall_poisson=0.45, impact_speed=0.4)
    assert back == pytest.approx(e_wall, rel=1e-9)


def test_a_softer_wall_and_a_slower_impact_last_longer_as_hertz_says():
    t = lambda e, v: theory.hertz_contact_time(**STEEL, wall_modulus=e, wall_poisson=0.45, impact_speed=v)  # noqa: E731
    # t_c ~ E*^(-2/5) v^(-1/5) when the wall dominates E*
    assert t(1e6, 0.3) / t(32e6, 0.3) == pytest.approx(32 ** 0.4, rel=1e-3)
    assert t(1e6, 0.3) / t(1e6, 0.3 * 32) == pytest.approx(2.0, rel=1e-9)


def test_a_contact_time_shorter_than_on_a_rigid_wall_is_refused_with_the_limit():
    with pytest.raises(InputError, match="rigid wall"):
        theory.wall_modulus_for_contact_time(1e-6, **STEEL, wall_poisson=0.45, impact_speed=0.4)
    with pytest.raises(InputError, match="Poisson"):
        theory.hertz_contact_time(**{**STEEL, "sphere_poisson": 0.7}, wall_modulus=1e6, wall_poisson=0.4,
                                  impact_speed=1.0)
    assert math.isfinite(theory.wall_modulus_for_contact_time("2ms", **STEEL, wall_poisson=0.45, impact_speed="0.3m/s"))
