"""The damper's hysteresis loop: the driving force against the container's displacement over one
drive cycle, filtered to its first harmonics or reduced to the first harmonic alone.

A bed's force on the container is a train of impacts; drawn raw against the displacement it is a
scribble. Over the analysed window (whole cycles after the dropped ones, as the complex power
method, :func:`pdamper.analysis.complex_power`) the force F(t) and the displacement x(t) are
written as Fourier series in the drive's phase phi = Omega t,

    x(phi) = X_0 + Re sum_k X_k e^{i k phi},   F(phi) = F_0 + Re sum_k F_k e^{i k phi},   k = 1 .. K,

the coefficients averaged over the window's cycles. ``harmonics=K`` keeps K of them: K = 1 is the
**first-harmonic loop**, an ellipse, whose area is the complex power's energy per cycle (eq. 4),
``E = pi Im(F_1 conj X_1) = (2 pi / Omega) Re(P)``; a larger K is the **filtered loop**, the
periodic part of the force with its impacts smoothed to K harmonics. The area of any loop is

    oint F dx = pi sum_k k Im(F_k conj X_k)  [J per cycle],

the energy the drive puts into the bed each cycle (dissipated, in a steady state); under a
harmonic drive x has one harmonic, so every K gives the same area (orthogonality) and only the
shape changes. The container's own inertia (a force in phase with x) encloses no area.

Pure functions of arrays (numpy only): :func:`hysteresis_loop` returns a :class:`HysteresisLoop`;
:func:`pdamper.plotting.hysteresis.plot_hysteresis` draws the raw, filtered and first-harmonic loops.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, shown

__all__ = ["HysteresisLoop", "hysteresis_loop"]


@dataclass(frozen=True)
class HysteresisLoop:
    """One drive cycle of force against displacement (module docstring), SI units.

    Attributes
    ----------
    phase : numpy.ndarray
        The drive's phase phi [rad], 0 to 2 pi, of the loop's points.
    position : numpy.ndarray
        The container's displacement x(phi) [m].
    force : numpy.ndarray
        The driving force F(phi) [N].
    harmonics : int
        K, the harmonics kept (1: the first-harmonic ellipse).
    energy_per_cycle_J : float
        The loop's area, oint F dx [J]: the energy put in per cycle.
    frequency_hz : float
        The drive frequency [Hz].
    cycles : int
        The whole cycles the coefficients are averaged over.
    window_s : tuple
        The analysed window [s] (its start and end).
    force_harmonics, position_harmonics : numpy.ndarray
        The complex coefficients F_k, X_k [N, m] for k = 0 .. K (k = 0: the mean).
    """

    phase: np.ndarray
    position: np.ndarray
    force: np.ndarray
    harmonics: int
    energy_per_cycle_J: float
    frequency_hz: float
    cycles: int
    window_s: tuple
    force_harmonics: np.ndarray = field(repr=False)
    position_harmonics: np.ndarray = field(repr=False)


def _coefficients(values: np.ndarray, phase: np.ndarray, k_max: int) -> np.ndarray:
    """c_0 (the mean) and c_k = 2 <v e^{-i k phi}> of samples spread evenly over whole cycles."""
    k = np.arange(k_max + 1)
    c = (values[None, :] * np.exp(-1j * k[:, None] * phase[None, :])).mean(axis=1) * 2.0
    c[0] = values.mean()
    return c


def _series(c: np.ndarray, phase: np.ndarray) -> np.ndarray:
    k = np.arange(1, c.size)
    return c[0].real + (c[1:, None] * np.exp(1j * k[:, None] * phase[None, :])).real.sum(axis=0)


def hysteresis_loop(time, force, position, frequency, *, drop_cycles: int = 2, harmonics: int = 1,
                    points: int = 361) -> HysteresisLoop:
    """The hysteresis loop of a record (module docstring): ``time`` [s], ``force`` [N] and
    ``position`` [m] samples (a run's :class:`~pdamper.recorders.signals.Signals`, a measured
    record), the drive ``frequency`` [Hz]; the first ``drop_cycles`` cycles left out (the paper's
    2), the whole cycles after them used; ``harmonics`` K kept (1: the first-harmonic ellipse;
    e.g. 10: the filtered loop); ``points`` along the cycle.

    >>> import numpy as np
    >>> t = np.arange(0, 10, 1e-3)
    >>> x, f = 0.01 * np.sin(2 * np.pi * t), 3.0 * np.cos(2 * np.pi * t)   # F leads x by 90 deg
    >>> round(hysteresis_loop(t, f, x, 1.0).energy_per_cycle_J / (np.pi * 3.0 * 0.01), 6)
    1.0
    """
    t = np.asarray(time, dtype=float).ravel()
    f = np.asarray(force, dtype=float).ravel()
    x = np.asarray(position, dtype=float).ravel()
    if not (t.shape == f.shape == x.shape) or t.size < 4:
        raise InputError(f"hysteresis_loop: time, force and position need one length of at least 4 samples (got "
                         f"{t.size}, {f.size}, {x.size})")
    if not (np.isfinite(t).all() and np.isfinite(f).all() and np.isfinite(x).all()) or np.any(np.diff(t) <= 0):
        raise InputError("hysteresis_loop: the samples must be finite, at strictly increasing times")
    if isinstance(frequency, bool) or not isinstance(frequency, (int, float, np.floating)) or not (
            frequency > 0 and math.isfinite(frequency)):
        raise InputError(f"hysteresis_loop: frequency = {shown(frequency)}; give the drive frequency in Hz, > 0")
    if isinstance(harmonics, bool) or not isinstance(harmonics, (int, np.integer)) or not 1 <= harmonics <= 1000:
        raise InputError(f"hysteresis_loop: harmonics = {shown(harmonics)}; give a whole number from 1 (the "
                         "first-harmonic ellipse) to 1000")
    period = 1.0 / float(frequency)
    step = float(np.median(np.diff(t)))
    start = t[0] + drop_cycles * period
    # each sample stands for its interval (a run's are interval means stamped at the centre), so the
    # record spans n steps, as the complex power method counts it
    cycles = int(math.floor((t[-1] + step - start) / period + 1e-9))
    if cycles < 1:
        raise InputError(f"hysteresis_loop: the record ({t[-1] - t[0]:.4g} s) holds no whole cycle of "
                         f"{period:.4g} s after the {drop_cycles} dropped; record longer or drop fewer")
    # evenly spread over the window's whole cycles: as many points a cycle as the record has, and
    # enough for the harmonics kept (the samples of a run are even already; a record may not be)
    per_cycle = max(int(round(period / step)), 8 * int(harmonics), 64)
    grid = start + (np.arange(cycles * per_cycle) + 0.5) * (period / per_cycle)
    phase = 2.0 * np.pi * float(frequency) * (grid - t[0])
    cf = _coefficients(np.interp(grid, t, f), phase, int(harmonics))
    cx = _coefficients(np.interp(grid, t, x), phase, int(harmonics))
    k = np.arange(1, int(harmonics) + 1)
    energy = float(np.pi * np.sum(k * np.imag(cf[1:] * np.conj(cx[1:]))))
    phi = np.linspace(0.0, 2.0 * np.pi, int(points))
    # the loop's phase counts from the window's start (a whole number of cycles after t[0])
    return HysteresisLoop(phase=phi, position=_series(cx, phi), force=_series(cf, phi), harmonics=int(harmonics),
                          energy_per_cycle_J=energy, frequency_hz=float(frequency), cycles=cycles,
                          window_s=(float(start), float(start + cycles * period)), force_harmonics=cf,
                          position_harmonics=cx)
