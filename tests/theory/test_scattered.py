"""Scattered state, eqs. (7)-(8)."""

import math

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.theory import energy_per_cycle_scattered, eta_scattered


def test_linear_in_stroke_and_kappa():
    strokes = np.geomspace(0.5e-3, 12e-3, 40)
    eta = eta_scattered(strokes, 0.03)
    assert eta.shape == (40,)
    np.testing.assert_allclose(eta, strokes / 0.03, rtol=1e-15)
    np.testing.assert_allclose(eta_scattered(strokes, 0.03, kappa=0.5), 0.5 * eta, rtol=1e-15)


def test_scalar_in_scalar_out():
    value = eta_scattered(0.006, 0.03)
    assert isinstance(value, float)
    assert value == pytest.approx(0.2)


def test_energy_is_eq_7_times_two_pi():
    x, h, f, m, kappa = 0.004, 0.01, 2.0, 0.149, 1.3
    v = x * 2 * math.pi * f
    e_diss = kappa * x / h * 0.5 * m * v**2  # eq. (7)
    got = energy_per_cycle_scattered(x, h, frequency=f, bed_mass=m, kappa=kappa)
    assert got == pytest.approx(2 * math.pi * e_diss, rel=1e-14)  # eq. (4)


@pytest.mark.parametrize("kwargs", [
    {"stroke": 0.0, "clearance": 0.03},
    {"stroke": [0.001, -0.002], "clearance": 0.03},
    {"stroke": 0.001, "clearance": 0.0},
    {"stroke": 0.001, "clearance": 0.03, "kappa": -1.0},
    {"stroke": math.nan, "clearance": 0.03},
])
def test_bad_inputs(kwargs):
    with pytest.raises(InputError):
        eta_scattered(**kwargs)


def test_bad_energy_inputs():
    with pytest.raises(InputError, match="bed_mass"):
        energy_per_cycle_scattered(0.004, 0.01, frequency=2.0, bed_mass=0.0)
    with pytest.raises(InputError, match="frequency"):
        energy_per_cycle_scattered(0.004, 0.01, frequency=-2.0, bed_mass=0.1)
