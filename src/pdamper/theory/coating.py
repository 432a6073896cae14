r"""A wall coating chosen by the contact time it gives: Hertz's impact of a sphere on a flat wall.

Meyer & Seifried ("Design of robust particle dampers using inner structures and coated container
walls", Granular Matter 25 (2023) 20, doi:10.1007/s10035-022-01298-4) line the walls that the bed
hits with soft polymers and pick the coating's Young's modulus from Hertz impact theory: a softer
wall lengthens the impact, so the bed stays at the wall for a longer part of the cycle. The
closed form is Hertz's duration of an elastic impact of a sphere (mass m, radius r) on a flat
wall at approach speed v (Johnson, Contact Mechanics, 1985, eq. 11.24):

    t_c = 2.868 (m^2 / (r E*^2 v))^(1/5),      1/E* = (1 - nu_s^2)/E_s + (1 - nu_w^2)/E_w,

and its inverse for the wall: ``E* = sqrt(2.868^5 m^2 / (r v t_c^5))`` and
``E_w = (1 - nu_w^2) / (1/E* - (1 - nu_s^2)/E_s)``. A contact time shorter than the sphere's
impact on a rigid wall (E_w -> inf) cannot be had from the wall; that is an error, not a number.

The coating is treated as a half-space (thick against the contact radius, a few tenths of a
millimetre for the paper's spheres); a thin coating on a stiff wall is stiffer than this says.
"""

from __future__ import annotations

import math

from ..units import quantities
from ._common import positive
from ..errors import InputError, shown

__all__ = ["HERTZ_TIME_FACTOR", "hertz_contact_time", "wall_modulus_for_contact_time"]

#: 2.868: Hertz's factor of the impact duration (Johnson 1985, eq. 11.24).
HERTZ_TIME_FACTOR = 2.868265


def _poisson(name, nu) -> float:
    if isinstance(nu, bool) or not isinstance(nu, (int, float)) or not (-1.0 < nu < 0.5):
        raise InputError(f"{name} = {shown(nu)}; a Poisson ratio must be in (-1, 0.5) (steel 0.3, silicone 0.48)")
    return float(nu)


def _impact(sphere_radius, sphere_density, sphere_modulus, sphere_poisson, wall_poisson, impact_speed):
    """The checked inputs of an impact: (m, r, (1 - nu_s^2)/E_s, 1 - nu_w^2, v)."""
    r = positive("sphere_radius", sphere_radius, "m", "0.005 (5 mm)")
    rho = positive("sphere_density", sphere_density, "kg/m^3", "7900 (steel)")
    es = positive("sphere_modulus", sphere_modulus, "Pa", "208e9 (steel)")
    v = positive("impact_speed", impact_speed, "m/s", "0.3")
    nus, nuw = _poisson("sphere_poisson", sphere_poisson), _poisson("wall_poisson", wall_poisson)
    return rho * 4.0 / 3.0 * math.pi * r**3, r, (1 - nus**2) / es, 1 - nuw**2, v


@quantities(sphere_radius="length", sphere_density="density", sphere_modulus="pressure", wall_modulus="pressure",
            impact_speed="velocity")
def hertz_contact_time(*, sphere_radius: float, sphere_density: float, sphere_modulus: float, sphere_poisson: float,
                       wall_modulus: float, wall_poisson: float, impact_speed: float) -> float:
    """Duration t_c [s] of an elastic Hertz impact of a sphere on a flat wall.

    >>> round(hertz_contact_time(sphere_radius=0.005, sphere_density=7900, sphere_modulus=208e9,
    ...       sphere_poisson=0.3, wall_modulus=10e6, wall_poisson=0.48, impact_speed=0.3) * 1e3, 2)
    1.67
    """
    m, r, sphere_share, wall_factor, v = _impact(sphere_radius, sphere_density, sphere_modulus, sphere_poisson,
                                                 wall_poisson, impact_speed)
    ew = positive("wall_modulus", wall_modulus, "Pa", "10e6 (silicone)")
    e_star = 1.0 / (sphere_share + wall_factor / ew)
    return HERTZ_TIME_FACTOR * (m * m / (r * e_star**2 * v)) ** 0.2


@quantities(contact_time="time", sphere_radius="length", sphere_density="density", sphere_modulus="pressure",
            impact_speed="velocity")
def wall_modulus_for_contact_time(contact_time: float, *, sphere_radius: float, sphere_density: float,
                                  sphere_modulus: float, sphere_poisson: float, wall_poisson: float,
                                  impact_speed: float) -> float:
    """The wall's Young's modulus E_w [Pa] that makes a sphere's impact at ``impact_speed`` last
    ``contact_time`` [s] (the inverse of :func:`hertz_contact_time`).

    >>> e = wall_modulus_for_contact_time(1.6733e-3, sphere_radius=0.005, sphere_density=7900,
    ...     sphere_modulus=208e9, sphere_poisson=0.3, wall_poisson=0.48, impact_speed=0.3)
    >>> round(e / 1e6, 1)
    10.0
    """
    tc = positive("contact_time", contact_time, "s", "2e-3 (2 ms)")
    m, r, sphere_share, wall_factor, v = _impact(sphere_radius, sphere_density, sphere_modulus, sphere_poisson,
                                                 wall_poisson, impact_speed)
    e_star = math.sqrt(HERTZ_TIME_FACTOR**5 * m * m / (r * v * tc**5))
    rest = 1.0 / e_star - sphere_share
    if rest <= 0:
        shortest = HERTZ_TIME_FACTOR * (m * m * sphere_share**2 / (r * v)) ** 0.2
        raise InputError(f"contact_time = {tc:.3g} s is shorter than the impact on a rigid wall ({shortest:.3g} s at "
                         f"{v:g} m/s): no wall modulus gives it; ask for a longer contact time")
    return wall_factor / rest
