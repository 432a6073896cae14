"""Coefficient-of-restitution laws: constant, tabulated (log-linear, held at the ends), Thornton
(1997) with its yield speed; the table every law becomes for the kernels."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.contact import ConstantRestitution, TabulatedRestitution, ThorntonRestitution
from pdamper.contact.cor_table import SPEED_GRID, tabulate_law
from pdamper.contact.cor_thornton import thornton_restitution, yield_speed
from pdamper.contact.hertz_gonthier import chi_for_restitution, restitution_for_chi
from pdamper.errors import InputError
from pdamper.contact.friction_tanh import TanhFriction
from pdamper.contact.hertz_gonthier import HertzGonthier
from pdamper.kernels.bundles import ContactTable
from pdamper.kernels.contact import damping_at_touch
from pdamper.materials import PVC, STEEL_S235, effective_modulus

R = 0.005


# --------------------------------------------------------------------- constant

def test_constant_law_is_constant_and_defaults_to_0_9():
    law = ConstantRestitution()
    assert law.value == 0.9
    assert law.restitution(0.3) == 0.9
    np.testing.assert_array_equal(law.restitution(np.array([1e-4, 1.0, 50.0])), 0.9)
    assert ConstantRestitution(value=1.0).restitution(1.0) == 1.0


@pytest.mark.parametrize("value", [0.0, -0.1, 1.01, float("nan")])
def test_constant_law_outside_zero_one_is_rejected(value):
    with pytest.raises(InputError, match=r"must be in \(0, 1\]"):
        ConstantRestitution(value=value)


# --------------------------------------------------------------------- table

def test_table_interpolates_linearly_in_log_speed():
    law = TabulatedRestitution(speeds=(0.01, 1.0), values=(0.95, 0.75))
    assert law.restitution(0.01) == pytest.approx(0.95)
    assert law.restitution(1.0) == pytest.approx(0.75)
    # the geometric mean is halfway in log(speed)
    assert law.restitution(0.1) == pytest.approx(0.85)
    assert law.restitution(10 ** -1.5) == pytest.approx(0.90)
    # and not halfway in speed
    assert law.restitution(0.505) != pytest.approx(0.85, abs=1e-3)


def test_table_is_held_at_its_end_values():
    law = TabulatedRestitution(speeds=(0.01, 0.1, 1.0), values=(0.95, 0.9, 0.7))
    np.testing.assert_allclose(law.restitution(np.array([1e-6, 0.0, 0.005])), 0.95)
    np.testing.assert_allclose(law.restitution(np.array([1.0, 3.0, 1e3])), 0.7)


def test_single_point_table_is_a_constant():
    law = TabulatedRestitution(speeds=(0.5,), values=(0.8,))
    np.testing.assert_allclose(law.restitution(np.array([1e-3, 0.5, 20.0])), 0.8)


@pytest.mark.parametrize("speeds,values,match", [
    ((0.1, 1.0), (0.9,), "equal length"),
    ((), (), "equal length"),
    ((1.0, 0.1), (0.9, 0.8), "strictly increasing"),
    ((0.1, 0.1), (0.9, 0.8), "strictly increasing"),
    ((0.0, 0.1), (0.9, 0.8), "positive"),
    ((-1.0, 0.1), (0.9, 0.8), "positive"),
    ((0.1, 1.0), (0.9, 1.2), r"in \(0, 1\]"),
    ((0.1, 1.0), (0.0, 0.5), r"in \(0, 1\]"),
    ((0.1, float("inf")), (0.9, 0.8), "positive"),
])
def test_table_validation_messages(speeds, values, match):
    with pytest.raises(InputError, match=match):
        TabulatedRestitution(speeds=speeds, values=values)


def test_every_law_becomes_a_table_on_the_speed_grid():
    assert SPEED_GRID[0] == pytest.approx(1e-5) and SPEED_GRID[-1] == pytest.approx(100.0)
    assert SPEED_GRID.size == 257
    np.testing.assert_array_equal(tabulate_law(ConstantRestitution(value=0.7)), 0.7)
    law = TabulatedRestitution(speeds=(0.01, 1.0), values=(0.95, 0.75))
    tab = tabulate_law(law)
    np.testing.assert_allclose(tab, law.restitution(SPEED_GRID))
    assert np.all(np.diff(tab) <= 0)


# --------------------------------------------------------------------- Thornton

def test_thornton_is_elastic_below_the_yield_speed_and_continuous_at_it():
    vy = 0.05
    v = np.array([1e-4, 0.01, 0.049, 0.05])
    np.testing.assert_array_equal(thornton_restitution(v, vy), 1.0)
    # at v = v_y the plastic branch gives exactly 1 too: no jump
    assert thornton_restitution(vy * (1 + 1e-9), vy) == pytest.approx(1.0, abs=1e-8)


def test_thornton_decreases_above_the_yield_speed_towards_zero():
    vy = 0.05
    v = vy * np.geomspace(1.001, 1e4, 200)
    e = thornton_restitution(v, vy)
    assert np.all(np.diff(e) < 0)
    assert np.all((e > 0) & (e < 1))
    # far above yield Thornton's law falls as (v_y / v)^(1/4) with the prefactor 1.185
    pref = math.sqrt(6 * math.sqrt(3) / 5) * (1 / (2 * math.sqrt(6 / 5))) ** 0.25
    assert pref == pytest.approx(1.185, abs=1e-3)
    assert e[-1] == pytest.approx(pref * (1e-4) ** 0.25, rel=1e-3)


def test_thornton_matches_its_closed_form():
    vy, v = 0.02, 0.5
    x = vy / v
    expected = math.sqrt(6 * math.sqrt(3) / 5 * (1 - x * x / 6)) * (x / (x + 2 * math.sqrt(6 / 5 - x * x / 5))) ** 0.25
    assert thornton_restitution(v, vy) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("p_y", [1e8, 1e9, 3e9])
def test_yield_speed_of_a_sphere_on_a_rigid_flat_is_thorntons(p_y):
    # Thornton (1997): v_y = 1.56 (p_y^5 / (E*^4 rho))^(1/2); the exact constant is pi^2/sqrt(40)
    es = effective_modulus(STEEL_S235, PVC)
    rho = STEEL_S235.density
    m = rho * 4 / 3 * math.pi * R**3
    vy = yield_speed(p_y, es, R, m)
    assert vy == pytest.approx(1.56 * math.sqrt(p_y**5 / (es**4 * rho)), rel=1e-3)
    assert vy == pytest.approx(math.pi**2 / math.sqrt(40) * math.sqrt(p_y**5 / (es**4 * rho)), rel=1e-12)
    # independent of the sphere size
    m2 = rho * 4 / 3 * math.pi * (3 * R) ** 3
    assert yield_speed(p_y, es, 3 * R, m2) == pytest.approx(vy, rel=1e-12)


def test_thornton_law_uses_the_contacts_yield_speed():
    es = effective_modulus(STEEL_S235, STEEL_S235)
    m = STEEL_S235.density * 4 / 3 * math.pi * R**3
    law = ThorntonRestitution(yield_pressure=2e9)
    vy = yield_speed(2e9, es, R / 2, m / 2)
    v = np.array([0.5 * vy, 2 * vy, 20 * vy])
    np.testing.assert_allclose(law.restitution(v, e_star=es, r_star=R / 2, m_star=m / 2), thornton_restitution(v, vy))


@pytest.mark.parametrize("p_y", [0.0, -1e9, float("nan"), float("inf")])
def test_thornton_needs_a_positive_yield_pressure(p_y):
    with pytest.raises(InputError, match="yield_pressure"):
        ThorntonRestitution(yield_pressure=p_y)


# --------------------------------------------------------------------- what the kernel does with a law

def _kernel_table(eps_on_grid, e_star=1e9, yield_pressure=0.0):
    """A one-material-pair contact table of Gonthier's calibrated law for ``eps`` on the speed grid."""
    chi = np.ascontiguousarray(np.asarray(chi_for_restitution(np.clip(eps_on_grid, 1e-6, 1.0)))[None, :])
    return ContactTable(law=HertzGonthier(), tangential=TanhFriction(), n_materials=1, modulus=np.array([e_star]),
                        shear_modulus=np.array([e_star / 3]), friction=np.zeros(1), coefficient=chi,
                        tangential_damping=np.zeros_like(chi), yield_pressure=np.array([yield_pressure]),
                        log_speed0=math.log(SPEED_GRID[0]),
                        dlog_speed=math.log(SPEED_GRID[1] / SPEED_GRID[0]), tau=1000.0, v_floor=1e-3,
                        overlap_limit=0.05)


@pytest.mark.parametrize("v", [0.003, 0.04, 0.3, 2.0])
def test_damping_at_touch_gives_the_tabulated_laws_restitution(v):
    law = TabulatedRestitution(speeds=(0.01, 1.0), values=(0.95, 0.6))
    d = damping_at_touch(_kernel_table(tabulate_law(law)), v, 0, 1.0, R, 1e-3)
    assert restitution_for_chi(d * v) == pytest.approx(float(law.restitution(v)), abs=2e-3)


@pytest.mark.parametrize("ratio", [0.5, 1.5, 5.0, 40.0])
def test_damping_at_touch_computes_thorntons_yield_speed_per_contact(ratio):
    es = effective_modulus(STEEL_S235, PVC)
    m = STEEL_S235.density * 4 / 3 * math.pi * R**3
    p_y = 2e8
    vy = yield_speed(p_y, es, R, m)
    table = _kernel_table(thornton_restitution(SPEED_GRID, 1.0), es, p_y)  # the table is over v / v_y
    v = ratio * vy
    d = damping_at_touch(table, v, 0, 1.0, R, m)
    assert restitution_for_chi(d * v) == pytest.approx(float(thornton_restitution(v, vy)), abs=2e-3)


def test_damping_at_touch_floors_the_approach_speed():
    table = _kernel_table(np.full(SPEED_GRID.size, 0.9))
    d0 = damping_at_touch(table, 0.0, 0, 1.0, R, 1e-3)
    d1 = damping_at_touch(table, 1e-3, 0, 1.0, R, 1e-3)
    assert d0 == d1 == pytest.approx(chi_for_restitution(0.9) / 1e-3)
    assert damping_at_touch(table, -0.2, 0, 1.0, R, 1e-3) == d1
