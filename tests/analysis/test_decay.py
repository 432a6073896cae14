"""Envelope, damping from the logarithmic decrement and harmonic amplitude on known signals."""

import math

import numpy as np
import pytest

from pdamper.analysis import decay_damping, extrema, harmonic_amplitude
from pdamper.errors import InputError


def _decay(zeta, t):
    w = 2 * math.pi * 2.0
    return 0.02 * np.exp(-zeta * w * t) * np.cos(w * math.sqrt(1 - zeta**2) * t)


def test_constant_damping_is_recovered_at_every_amplitude():
    t = np.arange(1, 20001) * 1e-3
    _, amp, zeta = decay_damping(t, _decay(0.005, t))
    assert amp.size > 70
    assert np.all(np.abs(zeta - 0.005) < 5e-5)
    assert np.all(np.diff(amp) < 0)


def test_amplitude_dependent_damping_shows_as_a_curve():
    # faster decay in the first half, slower in the second
    t = np.arange(1, 20001) * 1e-3
    x = np.concatenate([_decay(0.02, t[t < 10]), _decay(0.02, 10.0) / _decay(0.005, 10.0) * _decay(0.005, t[t >= 10])])
    tt, _, zeta = decay_damping(t, x)
    assert np.median(zeta[tt < 9]) == pytest.approx(0.02, rel=0.01)
    assert np.median(zeta[tt > 11]) == pytest.approx(0.005, rel=0.02)


def test_extrema_alternate_and_skip_noise_on_a_crest():
    t = np.linspace(0, 1, 1001)
    x = np.sin(2 * np.pi * 3 * t)
    x[83] += 1e-3  # a bump next to the first crest at t = 1/12
    te, a = extrema(t, x)
    assert te.size == 6 and np.allclose(a, 1.0, atol=2e-3)


def test_harmonic_amplitude_ignores_other_frequencies_and_checks_length():
    t = np.arange(8000) * 1e-3
    x = 0.01 * np.sin(2 * np.pi * 2 * t + 1) + 0.005 * np.sin(2 * np.pi * 3 * t)
    assert harmonic_amplitude(t, x, 2.0, cycles=8) == pytest.approx(0.01, rel=1e-6)
    with pytest.raises(InputError, match="shorter"):
        harmonic_amplitude(t, x, 2.0, cycles=40)


def test_amplitude_jumps_are_the_steps_beyond_the_fraction():
    from pdamper.analysis.decay import JUMP, amplitude_jumps

    f = [2.9, 2.95, 3.0, 3.05]
    x = [0.010, 0.0124, 0.0131, 0.004]  # +24 %, +5.6 %, -69 %
    assert amplitude_jumps(f, x) == [(3.0, 3.05, 0.0131, 0.004)] and JUMP == 0.25
    assert amplitude_jumps(f, x, jump=0.15) == [(2.9, 2.95, 0.010, 0.0124), (3.0, 3.05, 0.0131, 0.004)]
    assert amplitude_jumps([3.0], [0.01]) == []
