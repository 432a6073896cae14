"""Records that are not uniformly sampled: the phasors at the true time stamps (least squares)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.analysis import analyze_record, detect_frequency
from pdamper.errors import InputError

F_HZ, X, C = 2.0, 0.01, 3.0
W = 2 * math.pi * F_HZ
EXACT = math.pi * C * W * X**2  # energy per cycle of a viscous damper c = 3 N s/m


def _signals(t, impulsive=False):
    x = X * np.sin(W * t)
    F = C * X * W * np.cos(W * t) + 7.0 * X * W**2 * np.sin(W * t)  # damping + an elastic part
    if impulsive:  # harmonics of an impact-like force, in phase with the velocity
        F = F + 0.3 * np.cos(W * t) ** 9
    return F, x


@pytest.mark.parametrize("kind", ["position", "velocity", "acceleration"])
def test_a_record_of_sinusoids_is_exact_whatever_the_time_stamps(kind):
    rng = np.random.default_rng(0)
    t = np.arange(10_000) * 1e-3 + rng.uniform(-0.02, 0.02, 10_000) * 1e-3  # 2 % clock jitter
    F, x = _signals(t)
    motion = {"position": x, "velocity": X * W * np.cos(W * t), "acceleration": -X * W**2 * np.sin(W * t)}[kind]
    r = analyze_record(t, F, **{kind: motion}, frequency=F_HZ, bed_mass=0.149)
    assert r.energy_per_cycle_J == pytest.approx(EXACT, rel=1e-9)
    assert r.velocity_amplitude_m_s == pytest.approx(X * W, rel=1e-9)
    assert not r.time_base.uniform and 0.01 < r.time_base.jitter < 0.013  # uniform(-2 %, 2 %): RMS 1.15 %
    assert r.eta_star == pytest.approx(EXACT / (2 * math.pi) / (0.5 * 0.149 * (X * W) ** 2), rel=1e-9)


@pytest.mark.parametrize("case", ["jitter", "rounded", "dropped"])
def test_logger_time_stamps_give_the_uniform_answer(case):
    """Jitter of 2 %, times written to 0.1 ms at 1234.5 Hz, one dropped sample: the same eta* as
    the same signals uniformly sampled, and the spacing reported."""
    rng = np.random.default_rng(3)
    rate = 1234.5 if case == "rounded" else 1000.0
    true = np.arange(int(12 * rate)) / rate
    stamps = true
    if case == "jitter":
        true = true + rng.uniform(-0.02, 0.02, true.size) / rate
        stamps = true
    elif case == "rounded":
        stamps = np.round(true, 4)
    else:
        true = stamps = np.delete(true, 3000)
    F, x = _signals(true, impulsive=True)
    ref_t = np.arange(int(12 * rate)) / rate
    Fr, xr = _signals(ref_t, impulsive=True)
    ref = analyze_record(ref_t, Fr, position=xr, bed_mass=0.149)
    for freq in (None, F_HZ):  # detected and given
        r = analyze_record(stamps, F, position=x, bed_mass=0.149, frequency=freq)
        assert r.frequency_hz == pytest.approx(F_HZ, rel=1e-6)
        assert r.eta_star == pytest.approx(ref.eta_star, rel=2e-5 if case == "rounded" else 1e-6)
        assert r.time_base.effective_rate_hz == pytest.approx(rate, rel=1e-3)
        assert r.time_base.gaps == (1 if case == "dropped" else 0)
        assert r.mean_power_check_J == pytest.approx(r.energy_per_cycle_J, rel=2e-3)
    assert detect_frequency(stamps, x) == pytest.approx(F_HZ, rel=1e-6)


def test_what_cannot_give_a_correct_answer_is_refused_with_the_reason():
    t = np.arange(10_000) * 1e-3
    F, x = _signals(t)
    gap = np.concatenate([t[:2000], t[2300:]])  # 0.3 s missing: 0.6 of a period
    with pytest.raises(InputError, match=r"gap of 0.301 s .* 0.6 of the drive period.*not observed"):
        analyze_record(gap, np.concatenate([F[:2000], F[2300:]]), position=np.concatenate([x[:2000], x[2300:]]))
    coarse = np.arange(50) * 0.2 + np.r_[0, np.full(49, 0.001)]  # 2.5 samples per period
    with pytest.raises(InputError, match="samples per drive period"):
        analyze_record(coarse, F[::200], position=x[::200], frequency=F_HZ)
