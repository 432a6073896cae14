"""Free decay and forced response of a structure: envelope, equivalent damping, steady amplitude.

Pure functions on sampled displacements (beyond the paper; used by :mod:`pdamper.studies.structure`).

- :func:`extrema` -- the alternating maxima and minima of a record, refined by a parabola
  through each extreme sample and its neighbours: the envelope of a decay.
- :func:`decay_damping` -- the equivalent damping ratio against amplitude from the logarithmic
  decrement of extremes one period apart: ``delta = ln(a_k / a_{k+2})``,
  ``zeta = delta / sqrt(4 pi^2 + delta^2)``, at amplitude ``sqrt(a_k a_{k+2})`` (a particle
  damper's damping depends on the amplitude, so it is a curve, not a number).
- :func:`harmonic_amplitude` -- the amplitude at a given frequency over the last whole cycles of
  a record (Fourier coefficient), for the steady state of a forced response.
- :func:`amplitude_jumps` -- where a forced response's amplitude steps by more than
  :data:`JUMP` from one frequency to the next (a jump between branches, or a transient).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError, shown

__all__ = ["extrema", "decay_damping", "harmonic_amplitude", "harmonic_phasor", "amplitude_jumps", "JUMP"]

#: A jump between two neighbours of a response: their amplitudes differ by more than this fraction.
JUMP = 0.25


def extrema(time, x, *, offset: float = 0.0):
    """Times [s] and absolute values of the alternating extremes of ``x - offset``.

    An extreme is a sample larger (smaller) than both neighbours; consecutive extremes of the
    same sign (noise on a crest) keep the larger one, so maxima and minima alternate.

    >>> t = np.linspace(0, 2, 2001)
    >>> te, a = extrema(t, np.exp(-t) * np.cos(2 * np.pi * 2 * t))
    >>> len(te), round(float(a[1]), 2)
    (8, 0.61)
    """
    t = np.asarray(time, dtype=float)
    y = np.asarray(x, dtype=float) - offset
    if t.shape != y.shape or t.ndim != 1:
        raise InputError(f"extrema: time and displacement must be 1-D of equal length, got {t.shape} and {y.shape}")
    if y.size < 3:
        return np.zeros(0), np.zeros(0)
    mid = y[1:-1]
    up = (mid >= y[:-2]) & (mid > y[2:]) & (mid > 0)
    dn = (mid <= y[:-2]) & (mid < y[2:]) & (mid < 0)
    idx = np.flatnonzero(up | dn) + 1
    times, amps, signs = [], [], []
    for i in idx:
        y0, y1, y2 = y[i - 1], y[i], y[i + 1]
        den = y0 - 2 * y1 + y2
        s = 0.5 * (y0 - y2) / den if den != 0 else 0.0
        s = min(max(s, -0.5), 0.5)
        val = y1 - 0.25 * (y0 - y2) * s
        ti = t[i] + s * (t[i + 1] - t[i])
        sg = 1 if y1 > 0 else -1
        if signs and signs[-1] == sg:
            if abs(val) > amps[-1]:
                times[-1], amps[-1] = ti, abs(val)
            continue
        times.append(ti)
        amps.append(abs(val))
        signs.append(sg)
    return np.asarray(times), np.asarray(amps)


def decay_damping(time, x, *, offset: float = 0.0):
    """Equivalent damping ratio [-] against amplitude [m] of a free decay.

    Returns ``(t, amplitude, zeta)``: one value per extreme that has extremes on both sides,
    from the decrement over the full period around it.

    >>> t = np.linspace(0, 10, 20001)
    >>> z, w = 0.01, 2 * np.pi * 2
    >>> _, a, zeta = decay_damping(t, np.exp(-z * w * t) * np.cos(w * np.sqrt(1 - z * z) * t))
    >>> bool(np.all(np.abs(zeta - z) < 2e-4))
    True
    """
    te, a = extrema(time, x, offset=offset)
    if a.size < 3:
        return np.zeros(0), np.zeros(0), np.zeros(0)
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = np.log(a[:-2] / a[2:])
    zeta = delta / np.sqrt(4 * math.pi**2 + delta**2)
    return te[1:-1], np.sqrt(a[:-2] * a[2:]), zeta


def harmonic_phasor(time, x, frequency: float, *, cycles: int) -> complex:
    """Complex amplitude x^ [m] of the component of ``x`` at ``frequency`` [Hz] over the last
    ``cycles`` whole periods, in the convention ``x(t) = Im(x^ e^{i Omega t})`` (against a force
    ``F0 sin(Omega t)``: its phase is the response's phase lag, 0 in phase with the force,
    -90 deg at resonance); ``|x^|`` is :func:`harmonic_amplitude`.

    >>> t = (np.arange(5000) + 0.5) * 1e-3
    >>> z = harmonic_phasor(t, 0.01 * np.sin(2 * np.pi * 2 * t - 0.3), 2.0, cycles=4)
    >>> round(abs(z), 6), round(float(np.angle(z)), 6)
    (0.01, -0.3)
    """
    amp = harmonic_amplitude(time, x, frequency, cycles=cycles)  # checks the arguments
    t = np.asarray(time, dtype=float)
    dt = t[1] - t[0]
    n = int(round(cycles / frequency / dt))
    c = np.sum(np.asarray(x, dtype=float)[-n:] * np.exp(-2j * math.pi * frequency * t[-n:])) * dt
    z = 2j * c / (n * dt)
    return complex(z / abs(z) * amp) if abs(z) > 0 else 0j


def harmonic_amplitude(time, x, frequency: float, *, cycles: int):
    """Amplitude [m] of the component of ``x`` at ``frequency`` [Hz] over the last ``cycles``
    whole periods of a uniformly sampled record (``|2/T int x e^{-i Omega t} dt|``).

    >>> t = (np.arange(5000) + 0.5) * 1e-3
    >>> round(harmonic_amplitude(t, 0.01 * np.sin(2 * np.pi * 2 * t + 0.3), 2.0, cycles=4), 6)
    0.01
    """
    t = np.asarray(time, dtype=float)
    y = np.asarray(x, dtype=float)
    if not (frequency > 0):
        raise InputError(f"harmonic_amplitude: frequency = {shown(frequency)} Hz; must be > 0")
    if isinstance(cycles, bool) or int(cycles) != cycles or cycles < 1:
        raise InputError(f"harmonic_amplitude: cycles = {shown(cycles)}; must be a whole number >= 1")
    dt = t[1] - t[0]
    n = int(round(cycles / frequency / dt))
    if n > t.size or n < 4:
        raise InputError(f"harmonic_amplitude: the record ({t.size * dt:.3g} s) is shorter than the "
                         f"{cycles} cycles at {frequency:g} Hz asked for; run longer or measure fewer cycles")
    tt, yy = t[-n:], y[-n:]
    c = np.sum(yy * np.exp(-2j * math.pi * frequency * tt)) * dt
    return float(2.0 * abs(c) / (n * dt))


def amplitude_jumps(frequencies, amplitudes, *, jump: float = JUMP) -> list:
    """The steps of a response of ``amplitudes`` [m] at ``frequencies`` [Hz] (in the order run, a
    stepped sine's) by more than ``jump`` of the larger of two neighbours: (f_before, f_after,
    x_before, x_after) each.

    >>> amplitude_jumps([1.0, 1.1, 1.2], [0.010, 0.011, 0.004])
    [(1.1, 1.2, 0.011, 0.004)]
    """
    f, x = list(frequencies), list(amplitudes)
    return [(f[k - 1], f[k], x[k - 1], x[k]) for k in range(1, len(x))
            if abs(x[k] - x[k - 1]) > jump * max(x[k], x[k - 1])]
