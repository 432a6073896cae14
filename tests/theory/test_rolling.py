"""Rolling collect-and-collide, eqs. (9)-(17), checked against independent computations."""

import math
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import ellipe

from pdamper import theory
from pdamper.errors import InputError


def bed_velocity_eq10(theta):
    """Eq. (10) over V, written out independently of the package."""
    return (2 * math.cos(theta) + math.sqrt(25 + 10 * math.sin(theta) ** 2)) / 7


def gap_by_quadrature(theta):
    """h/X from eq. (12) with eq. (10) integrated numerically (θ = Ωt)."""
    travelled = quad(bed_velocity_eq10, 0.0, theta, epsabs=1e-14, epsrel=1e-13)[0]
    return travelled - math.sin(theta)


def test_x_opt_over_h_matches_quadrature_and_the_elliptic_closed_form():
    by_quadrature = 1.0 / gap_by_quadrature(math.pi)
    assert theory.X_OPT_OVER_H == pytest.approx(by_quadrature, rel=1e-10)
    assert theory.X_OPT_OVER_H == pytest.approx(7 / (10 * ellipe(-0.4)), rel=1e-14)
    assert theory.X_OPT_OVER_H == pytest.approx(0.40751, abs=1e-4)  # the paper rounds to 0.4


@pytest.mark.parametrize("theta", [1e-3, 0.1, 0.7, 1.5, 2.2, 3.0, math.pi])
def test_elliptic_reduction_of_eq_12_matches_quadrature(theta):
    assert theory.clearance_over_stroke(theta) == pytest.approx(gap_by_quadrature(theta),
                                                                rel=1e-9, abs=1e-15)


@pytest.mark.parametrize("h", [1e-3, 0.01, 0.03, 2.0])
def test_optimal_stroke_scales_with_clearance_and_hits_at_pi(h):
    x_opt = theory.optimal_stroke(h)
    assert x_opt / h == pytest.approx(theory.X_OPT_OVER_H, rel=1e-15)
    assert theory.impact_phase_rolling(x_opt, h) == pytest.approx(math.pi, rel=1e-12)


def test_eta_max_and_eq_14_at_pi_equals_eq_15():
    h, f, m = 0.03, 2.0, 0.149
    x_opt = theory.optimal_stroke(h)
    assert theory.ETA_MAX == pytest.approx(20 / (7 * math.pi), rel=1e-15)
    assert theory.eta_rolling(x_opt, h) == pytest.approx(20 / (7 * math.pi), rel=1e-12)
    v = x_opt * 2 * math.pi * f
    energy = theory.energy_per_cycle_rolling(x_opt, h, frequency=f, bed_mass=m)
    assert energy == pytest.approx(20 / 7 * m * v**2, rel=1e-12)  # eq. (15)


def test_impact_phase_against_an_independent_root_finder():
    h = 0.03
    for x in [0.0125, 0.015, 0.03, 0.05, 0.3]:
        expected = brentq(lambda th: gap_by_quadrature(th) - h / x, 1e-6, math.pi, xtol=1e-14)
        assert theory.impact_phase_rolling(x, h) == pytest.approx(expected, rel=1e-9)


def test_below_x_opt_the_rolling_law_is_nan():
    h = 0.03
    x = np.array([0.5, 0.99, 0.999999]) * theory.optimal_stroke(h)
    assert np.all(np.isnan(theory.impact_phase_rolling(x, h)))
    assert np.all(np.isnan(theory.eta_rolling(x, h)))
    assert np.all(np.isnan(theory.energy_per_cycle_rolling(x, h, frequency=2.0, bed_mass=0.1)))


def test_a_40_point_sweep_is_one_fast_vectorised_call():
    strokes = np.geomspace(0.5e-3, 50e-3, 40)
    start = time.perf_counter()
    eta = theory.eta_rolling(strokes, 0.03)
    assert time.perf_counter() - start < 0.1
    assert eta.shape == (40,)
    above = strokes >= theory.optimal_stroke(0.03)
    assert np.all(np.isnan(eta[~above])) and np.all(np.isfinite(eta[above]))
    assert np.all(np.diff(eta[above]) < 0)  # η* falls above X_opt


def test_scalar_in_scalar_out_and_broadcasting():
    assert isinstance(theory.eta_rolling(0.02, 0.03), float)
    grid = theory.eta_rolling(np.array([[0.02], [0.04]]), np.array([0.01, 0.03]))
    assert grid.shape == (2, 2)
    assert grid[1, 0] == pytest.approx(theory.eta_rolling(0.04, 0.01))


def test_velocities_obey_the_energy_balance_9_and_rolling_condition():
    th = np.linspace(0.0, math.pi, 101)
    v_p = theory.bed_velocity(th)
    slip = theory.relative_velocity(th)
    np.testing.assert_allclose(slip, v_p - np.cos(th), atol=1e-15)  # eq. (11) = (10) - x_c'
    # eq. (9) per unit mass with I = 2/5 m r², φ' = Δ/r:  x_p'² + 2/5 Δ² = V²
    np.testing.assert_allclose(v_p**2 + 0.4 * slip**2, 1.0, rtol=1e-14)
    assert np.all(np.diff(v_p) <= 1e-15) and np.all(np.diff(slip) >= -1e-15)  # Fig. 5b
    assert theory.bed_velocity(0.3, 2.0) == pytest.approx(2 * bed_velocity_eq10(0.3))


def test_bed_position_is_the_integral_of_the_bed_velocity():
    th = np.linspace(0.0, math.pi, 2001)
    x_p = theory.bed_position(th, 0.012)
    derivative = np.gradient(x_p, th, edge_order=2)
    np.testing.assert_allclose(derivative, 0.012 * theory.bed_velocity(th), rtol=1e-5)


@pytest.mark.parametrize("x_over_h", [theory.X_OPT_OVER_H * 1.0001, 0.45, 0.6, 1.0, 2.5, 10.0])
@pytest.mark.parametrize("frequency", [0.5, 2.0, 10.0])
def test_eq_14_agrees_with_direct_integration_of_the_block(x_over_h, frequency):
    h = 0.03
    x = x_over_h * h
    hit = theory.integrate_rolling_block(x, h, frequency=frequency, bed_mass=0.149)
    assert hit.phase == pytest.approx(theory.impact_phase_rolling(x, h), rel=1e-6)
    assert hit.eta == pytest.approx(theory.eta_rolling(x, h), rel=1e-6)
    energy = theory.energy_per_cycle_rolling(x, h, frequency=frequency, bed_mass=0.149)
    assert hit.energy_per_cycle == pytest.approx(energy, rel=1e-6)
    v = x * 2 * math.pi * frequency
    assert hit.bed_velocity == pytest.approx(theory.bed_velocity(hit.phase, v), rel=1e-6)


def test_block_reaches_the_far_wall_at_pi_at_x_opt_for_any_frequency():
    h = 0.01
    x_opt = theory.optimal_stroke(h)  # no frequency argument: X_opt is frequency independent
    for f in (0.5, 2.0, 20.0):
        hit = theory.integrate_rolling_block(x_opt, h, frequency=f)
        assert hit.phase == pytest.approx(math.pi, rel=1e-6)
        assert hit.eta == pytest.approx(theory.ETA_MAX, rel=1e-6)
    below = theory.integrate_rolling_block(0.98 * x_opt, h, frequency=2.0)
    assert math.isnan(below.phase) and math.isnan(below.energy_per_cycle)


def test_block_result_does_not_depend_on_sphere_radius():
    a = theory.integrate_rolling_block(0.02, 0.03, frequency=2.0, particle_radius=2.5e-3)
    b = theory.integrate_rolling_block(0.02, 0.03, frequency=2.0, particle_radius=5e-3)
    assert a.eta == pytest.approx(b.eta, rel=1e-8)


def test_eta_theory_is_scattered_then_rolling():
    h = 0.03
    x_opt = theory.optimal_stroke(h)
    x = np.array([0.5 * x_opt, 0.999 * x_opt, x_opt, 2 * x_opt])
    eta = theory.eta_theory(x, h)
    np.testing.assert_allclose(eta[:2], theory.eta_scattered(x[:2], h))
    np.testing.assert_allclose(eta[2:], theory.eta_rolling(x[2:], h))
    assert eta[2] - eta[1] > 0.5  # the jump at X_opt from 0.41 to 0.91


@settings(max_examples=200, deadline=None)
@given(h=st.floats(1e-4, 1.0), factor=st.floats(1.0, 1e4))
def test_rolling_law_is_bounded_and_solves_eq_12(h, factor):
    x = factor * theory.optimal_stroke(h)
    theta = theory.impact_phase_rolling(x, h)
    assert 0.0 < theta <= math.pi
    assert theory.clearance_over_stroke(theta) == pytest.approx(h / x, rel=1e-9)
    eta = theory.eta_rolling(x, h)
    assert 0.0 < eta <= theory.ETA_MAX * (1 + 1e-12)


@settings(max_examples=100, deadline=None)
@given(h=st.floats(1e-4, 1.0), a=st.floats(1.0, 100.0), b=st.floats(1.0, 100.0))
def test_rolling_law_decreases_with_stroke(h, a, b):
    lo, hi = sorted((a, b))
    if hi / lo < 1 + 1e-6:
        return
    x_opt = theory.optimal_stroke(h)
    assert theory.eta_rolling(hi * x_opt, h) < theory.eta_rolling(lo * x_opt, h)


@pytest.mark.parametrize("stroke, h", [(0.0, 0.03), (-0.01, 0.03), (math.inf, 0.03),
                                       ([0.01, math.nan], 0.03), (0.01, 0.0), (0.01, -1.0),
                                       ("12 kg", 0.03), (["12mm", "3 s"], 0.03)])
def test_bad_inputs_raise_input_error(stroke, h):
    with pytest.raises(InputError):
        theory.eta_rolling(stroke, h)


def test_bad_energy_inputs():
    with pytest.raises(InputError, match="bed_mass"):
        theory.energy_per_cycle_rolling(0.02, 0.03, frequency=2.0, bed_mass=-1.0)
    with pytest.raises(InputError, match="frequency"):
        theory.integrate_rolling_block(0.02, 0.03, frequency=0.0)
