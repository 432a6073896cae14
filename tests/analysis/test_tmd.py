"""The damper as an equivalent TMD (pdamper.analysis.tmd): the fit of a mass and a dashpot recovers a
linear damper's, and on a harmonic record it is the bed's impedance; the numbers per mode are the closed
forms of a mode carrying that mass and dashpot."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.analysis.tmd import equivalent_damper, tmd_numbers
from pdamper.theory import tmd as th


def test_the_fit_recovers_a_linear_damper_from_a_record_with_an_offset():
    t = np.arange(0.0, 4.0, 1e-3)
    v = 0.05 * np.sin(2 * np.pi * 3.0 * t) + 0.02 * np.sin(2 * np.pi * 7.1 * t + 0.4)
    a = np.gradient(v, t)
    force = 0.013 + 0.2 * a + 1.5 * v
    fit = equivalent_damper(force, a, v)
    assert (fit["mass_kg"], fit["damping_N_s_per_m"], fit["offset_N"]) == pytest.approx((0.2, 1.5, 0.013), rel=1e-9)
    assert fit["r2"] == pytest.approx(1.0, abs=1e-12)
    # a force a linear damper cannot follow (a 50 Hz rattle, orthogonal to the motion) lowers r2 and
    # leaves the mass and the dissipating part
    rattle = force + 0.3 * np.sin(2 * np.pi * 50.0 * t)
    fit = equivalent_damper(rattle, a, v)
    assert (fit["mass_kg"], fit["damping_N_s_per_m"]) == pytest.approx((0.2, 1.5), rel=2e-2) and fit["r2"] < 0.5


def test_on_a_harmonic_record_the_fit_is_the_impedance():
    """x = X sin(W t), F = Re/Im parts of Z x: the fit gives m_eff = -Re Z / W^2, c = Im Z / W."""
    w = 2 * np.pi * 2.0
    t = np.arange(0.0, 5.0, 1e-3)  # ten whole periods
    X = 0.012
    m_eff, c_eq = 0.08, 0.9
    x = X * np.sin(w * t)
    v, a = X * w * np.cos(w * t), -X * w * w * np.sin(w * t)
    fit = equivalent_damper(m_eff * a + c_eq * v, a, v)
    assert (fit["mass_kg"], fit["damping_N_s_per_m"]) == pytest.approx((m_eff, c_eq), rel=1e-9)
    assert x.size == t.size


def test_the_numbers_per_mode_are_those_of_a_mode_carrying_the_mass_and_dashpot():
    m = np.array([1.0, 1.0])
    w = 2 * np.pi * np.array([2.0, 7.0])
    k = m * w**2
    zeta = np.array([0.01, 0.02])
    c = 2 * zeta * m * w
    pd = np.array([0.3, -0.2])
    bed, ma, ca = 0.05, 0.02, 0.4
    n = tmd_numbers((m, k, c, pd), bed_mass=bed, damper={"mass_kg": ma, "damping_N_s_per_m": ca, "r2": 0.7})
    mu = bed * pd**2 / m
    assert n["mass_ratio"] == pytest.approx(mu) and n["effective_mass_ratio"] == pytest.approx(ma * pd**2 / m)
    assert n["mass_at_damper_kg"] == pytest.approx(m / pd**2)
    # the mode with phi^2 m_a added and phi^2 c_a: its frequency and damping ratio
    m2 = m + pd**2 * ma
    assert n["frequency_with_damper_hz"] == pytest.approx(np.sqrt(k / m2) / (2 * np.pi), rel=1e-12)
    assert n["detuning"] == pytest.approx(th.added_mass_detuning(ma * pd**2 / m), rel=1e-12)
    assert n["damping_ratio_with_damper"] == pytest.approx((c + pd**2 * ca) / (2 * np.sqrt(k * m2)), rel=1e-12)
    assert n["added_damping_ratio"] == pytest.approx(pd**2 * ca / (2 * np.sqrt(k * m2)), rel=1e-12)
    assert n["q"] == pytest.approx(1 / (2 * zeta)) and n["q_with_damper"] == pytest.approx(
        1 / (2 * np.asarray(n["damping_ratio_with_damper"])))
    assert n["share_of_den_hartog"] == pytest.approx(np.asarray(n["added_damping_ratio"])
                                                     / th.den_hartog_equivalent_damping(mu))
    assert n["den_hartog_tuning"] == pytest.approx(1 / (1 + mu)) and n["fit_r2"] == 0.7
    assert math.isfinite(n["den_hartog_damping_ratio"][0])
