"""The response spectrum (pdamper.structure.spectrum) against closed forms and a second code.

- A harmonic ground motion a_g = A sin(Omega t) from rest: the oscillator's exact response is the
  steady phasor plus the free vibration that starts it at rest; its peak over the samples is the
  spectrum's SD, at resonance (T = 2 pi / Omega, after the transient has died) PSA = A / (2 zeta).
- The same samples through scipy.signal.lsim (a first-order hold: linear between samples, as the
  recurrence assumes): the same peaks to rounding.
- The limits: a stiff oscillator follows the ground (PSA -> PGA); PSA = omega^2 SD.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import lsim

from pdamper.errors import InputError
from pdamper.structure.spectrum import response_spectrum, spectral_acceleration

ZETA = 0.05


def _harmonic_exact(t, amplitude, big_omega, period, zeta=ZETA):
    """u(t) of u'' + 2 zeta w u' + w^2 u = -A sin(W t) from rest, in closed form."""
    w = 2 * math.pi / period
    wd = w * math.sqrt(1 - zeta**2)
    U = -amplitude / (w * w - big_omega**2 + 2j * zeta * w * big_omega)  # u_p = Im(U e^{iWt})
    u0, v0 = -np.imag(U), -np.imag(1j * big_omega * U)                    # u_h starts at -u_p(0), -u_p'(0)
    uh = np.exp(-zeta * w * t) * (u0 * np.cos(wd * t) + (v0 + zeta * w * u0) / wd * np.sin(wd * t))
    return np.imag(U * np.exp(1j * big_omega * t)) + uh


@pytest.mark.parametrize("period", [0.3, 0.7, 1.0, 1.6, 4.0])
def test_a_harmonic_ground_motion_s_spectrum_is_its_closed_form(period):
    f, amplitude = 1.0, 2.5
    t = np.arange(0.0, 30.0, 0.002)                 # 500 samples a period of the ground
    s = response_spectrum(t, amplitude * np.sin(2 * math.pi * f * t), [period])
    exact = np.max(np.abs(_harmonic_exact(t, amplitude, 2 * math.pi * f, period)))
    # the record is linear between samples, the closed form a sine: they part by ~ (Omega dt)^2 / 12
    assert s.sd[0] == pytest.approx(exact, rel=2e-5)
    w = 2 * math.pi / period
    assert s.psa[0] == pytest.approx(w * w * s.sd[0], rel=1e-14) and s.psv[0] == pytest.approx(w * s.sd[0], rel=1e-14)


def test_at_resonance_the_pseudo_acceleration_is_the_ground_s_peak_over_twice_the_damping():
    t = np.arange(0.0, 80.0, 0.002)                 # 80 periods: e^(-zeta w t) = 1e-11 at the end
    amplitude = 0.3 * 9.80665
    psa = spectral_acceleration(t, amplitude * np.sin(2 * math.pi * t), 1.0)
    assert psa == pytest.approx(amplitude / (2 * ZETA), rel=1e-4)


def test_the_recurrence_agrees_with_scipy_lsim_on_the_same_samples():
    rng = np.random.default_rng(7)
    t = np.arange(3000) * 0.01
    a = rng.normal(size=t.size) * np.sin(np.pi * t / t[-1])
    periods = [0.05, 0.2, 0.5, 1.0, 3.0]
    s = response_spectrum(t, a, periods)
    for T, sd in zip(periods, s.sd):
        w = 2 * math.pi / T
        _, u, _ = lsim(([-1.0], [1.0, 2 * ZETA * w, w * w]), a, t, interp=True)
        assert sd == pytest.approx(np.max(np.abs(u)), rel=1e-8)


def test_a_stiff_oscillator_follows_the_ground_and_bad_input_is_refused():
    t = np.arange(0.0, 5.0, 0.001)
    a = np.sin(2 * math.pi * 2 * t) + 0.5 * np.sin(2 * math.pi * 5 * t)
    s = response_spectrum(t, a, [0.002, 1.0])
    assert s.psa[0] == pytest.approx(s.pga, rel=2e-3) and s.pga == pytest.approx(np.max(np.abs(a)))
    assert s.at(1.0) == s.psa[1]
    for bad in ([0.0], [-1.0], [math.nan]):
        with pytest.raises(InputError, match="periods"):
            response_spectrum(t, a, bad)
    with pytest.raises(InputError, match="increasing"):
        response_spectrum(t[::-1], a, [1.0])
    with pytest.raises(InputError, match="damping"):
        response_spectrum(t, a, [1.0], damping=0.0)
