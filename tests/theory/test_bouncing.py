"""Bouncing collect-and-collide (block without rolling), SPEC Sect. 4."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdamper import theory
from pdamper.errors import InputError


def test_optimum_at_h_over_pi_hits_at_pi_with_four_over_pi():
    h = 0.03
    x_opt = theory.optimal_stroke_bouncing(h)
    assert x_opt == pytest.approx(h / math.pi, rel=1e-15)
    assert theory.impact_phase_bouncing(x_opt, h) == pytest.approx(math.pi, rel=1e-12)
    assert theory.eta_bouncing(x_opt, h) == pytest.approx(4 / math.pi, rel=1e-12)
    assert theory.ETA_MAX_BOUNCING == pytest.approx(4 / math.pi, rel=1e-15)


def test_nan_below_the_optimum_and_finite_above():
    h = 0.01
    x = np.array([0.9, 0.999999, 1.5, 3.0]) * h / math.pi
    eta = theory.eta_bouncing(x, h)
    assert np.all(np.isnan(eta[:2])) and np.all(np.isfinite(eta[2:]))


def test_energy_per_cycle():
    x, h, f, m = 0.02, 0.03, 2.0, 0.149
    theta = theory.impact_phase_bouncing(x, h)
    v = x * 2 * math.pi * f
    expected = m * v**2 * (1 - math.cos(theta)) ** 2  # two impacts of ½ m (V(1 - cos θ))²
    assert theory.energy_per_cycle_bouncing(x, h, frequency=f, bed_mass=m) == pytest.approx(
        expected, rel=1e-12)


def test_small_phase_limit():
    # θ - sin θ = θ³/6 - θ⁵/120 + ... for large strokes, so θ ≈ θ0 (1 + θ0²/60), θ0 = (6h/X)^(1/3).
    h, x = 0.01, 1e3
    theta0 = (6 * h / x) ** (1 / 3)
    assert theory.impact_phase_bouncing(x, h) == pytest.approx(theta0 * (1 + theta0**2 / 60),
                                                               rel=1e-6)


def test_bouncing_optimum_lies_below_the_rolling_one():
    assert theory.optimal_stroke_bouncing(0.03) < theory.optimal_stroke(0.03)
    assert theory.ETA_MAX_BOUNCING > theory.ETA_MAX


@settings(max_examples=200, deadline=None)
@given(h=st.floats(1e-4, 1.0), factor=st.floats(1.0, 1e4))
def test_impact_equation_is_solved(h, factor):
    x = factor * h / math.pi
    theta = theory.impact_phase_bouncing(x, h)
    assert 0.0 < theta <= math.pi
    assert theta - math.sin(theta) == pytest.approx(h / x, rel=1e-9)
    assert 0.0 < theory.eta_bouncing(x, h) <= 4 / math.pi * (1 + 1e-12)


def test_bad_inputs():
    with pytest.raises(InputError):
        theory.eta_bouncing(-0.01, 0.03)
    with pytest.raises(InputError):
        theory.optimal_stroke_bouncing(0.0)
