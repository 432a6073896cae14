"""Effective mass and equivalent damping from the complex power (closed forms).

A force ``F = m x'' + c x' + k x`` on a container moved at ``x = X sin(Omega t + phi)`` has
``P = 1/2 |V*|^2 (c + i Omega (m - k / Omega^2))``, so the effective mass is ``m - k/Omega^2`` and
the equivalent damping ``c``, whatever the motion signal, the sampling and the phase.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.analysis import analyze_record, complex_power
from pdamper.errors import InputError

X, F_DRIVE, M, C, K = 0.012, 2.0, 0.149, 4.0, 30.0
W = 2 * math.pi * F_DRIVE


def record(fs=1000.0, f=F_DRIVE, cycles=20, phase=0.3, m=M, c=C, k=K, jitter=0.0):
    """Time, force and the three motion signals of ``F = m a + c v + k x``, harmonic at ``f``."""
    w = 2 * math.pi * f
    t = np.arange(int(cycles * fs / f)) / fs
    if jitter:
        t = t + np.random.default_rng(1).uniform(-jitter, jitter, t.size) / fs
    x = X * np.sin(w * t + phase)
    v = X * w * np.cos(w * t + phase)
    a = -X * w**2 * np.sin(w * t + phase)
    return t, m * a + c * v + k * x, {"position": x, "velocity": v, "acceleration": a}


@pytest.mark.parametrize("motion", ["position", "velocity", "acceleration"])
@pytest.mark.parametrize("fs, f, jitter", [(1000.0, 2.0, 0.0),      # 500 samples per period, as sampled
                                           (1000.0, 2.37, 0.0),     # resampled onto whole cycles
                                           (1000.0, 2.0, 0.2)])     # jittered stamps: least squares
def test_mass_spring_dashpot_gives_m_minus_k_over_omega2_and_c(motion, fs, f, jitter):
    t, force, sig = record(fs=fs, f=f, jitter=jitter)
    r = analyze_record(t, force, **{motion: sig[motion]}, frequency=f)
    w = 2 * math.pi * f
    assert r.effective_mass_kg == pytest.approx(M - K / w**2, rel=1e-9)
    assert r.equivalent_damping_N_s_per_m == pytest.approx(C, rel=1e-9)
    assert r.container_mass_kg == 0.0 and r.total_effective_mass_kg == r.effective_mass_kg


def test_the_container_mass_is_removed_from_the_mass_and_leaves_the_damping():
    m_c = 0.08
    t, force, sig = record(m=M + m_c)
    r = complex_power(t, force, sig["velocity"], frequency=F_DRIVE, container_mass="80g")
    assert r.container_mass_kg == pytest.approx(m_c, rel=1e-15)
    assert r.effective_mass_kg == pytest.approx(M - K / W**2, rel=1e-9)
    assert r.total_effective_mass_kg == pytest.approx(M + m_c - K / W**2, rel=1e-9)
    assert r.equivalent_damping_N_s_per_m == pytest.approx(C, rel=1e-9)
    d = r.to_dict()
    assert d["effective_mass_kg"] == r.effective_mass_kg and d["container_mass_kg"] == pytest.approx(m_c)
    assert d["equivalent_damping_N_s_per_m"] == r.equivalent_damping_N_s_per_m


def test_a_pure_spring_has_a_negative_effective_mass_and_no_damping():
    t, force, sig = record(m=0.0, c=0.0)
    r = analyze_record(t, force, position=sig["position"])
    assert r.effective_mass_kg == pytest.approx(-K / W**2, rel=1e-9)
    assert abs(r.equivalent_damping_N_s_per_m) <= 1e-12 * K / W


def test_equivalent_damping_and_eta_star_agree():
    """eta* = E_diss / (1/2 m_bed |V*|^2) = c_eq / (m_bed Omega): the same Re(P) twice."""
    t, force, sig = record()
    r = complex_power(t, force, sig["velocity"], bed_mass=M)
    assert r.eta_star == pytest.approx(r.equivalent_damping_N_s_per_m / (M * W), rel=1e-12)


@pytest.mark.parametrize("bad", [-0.1, math.nan, "x", True])
def test_a_bad_container_mass_is_refused_with_its_value(bad):
    t, force, sig = record(cycles=4)
    with pytest.raises(InputError, match="container.mass"):
        complex_power(t, force, sig["velocity"], container_mass=bad)
