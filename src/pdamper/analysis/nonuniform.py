"""The complex power method at the true time stamps of a record that is not uniformly sampled.

Loggers write time stamps with clock jitter, round them (0.1 ms at 1234.5 Hz), or drop a sample.
Such a record is not resampled: the phasors at the drive frequency are found by least squares at
the samples' own times over the whole cycles of the window,

    s(t_k) ~ c0 + sum_{h=1..H} Re( S_h exp(i h Omega (t_k - t_w)) ),

with the drive (h = 1) and its harmonics up to H (20, fewer where a period has few samples) in the
model, so that on a sample set that is not a uniform grid the harmonics of an impulsive force do
not leak into the drive's phasor. On a uniform grid of whole cycles this projection is the DFT bin
the uniform path uses; for a record of sinusoids it is exact whatever the time stamps are. The
velocity phasor follows from the motion's as on the uniform path (``V* = i Omega X*``,
``V* = A*/(i Omega)``), and eqs. (3)-(5) as there.

The time-domain cross-checks (cycle energies, mean power) integrate ``F v`` with the trapezoid
rule at the samples; the velocity at the samples comes from a cubic spline through the motion at
its true times (derivative of the position, antiderivative of the acceleration).

Refused, with the reason, is only what cannot give a correct answer: times that do not increase,
a gap longer than a quarter of the drive period (a phase of the cycle is not observed), or fewer
than 8 samples per period on average.

The report (:class:`TimeBase`) gives the jitter (RMS deviation of the intervals from their median,
in intervals), the gaps (intervals over 1.5 median intervals, e.g. a dropped sample) and the
effective sample rate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .sinusoid import MIN_DETECTED_SHARE, MIN_GIVEN_SHARE, detect_uniform, linear_residual, sinusoid_rss

__all__ = ["TimeBase", "time_base", "analyze_nonuniform", "MAX_GAP_PERIODS", "MIN_SAMPLES_PER_PERIOD"]

#: A gap longer than this fraction of the drive period is refused.
MAX_GAP_PERIODS = 0.25
#: At least this many samples per period on average.
MIN_SAMPLES_PER_PERIOD = 8
#: Harmonics of the drive in the least-squares model (fewer when a period has few samples).
HARMONICS = 20


@dataclass(frozen=True, kw_only=True)
class TimeBase:
    """How a record's time stamps are spaced.

    Attributes
    ----------
    uniform : bool
        True if every stamp lies on a uniform grid within the tolerance (the FFT path is used).
    interval_s : float
        Median sample interval [s].
    effective_rate_hz : float
        ``(n - 1) / (t_last - t_first)`` [Hz].
    jitter : float
        RMS deviation of the stamps from the best uniform grid through them, in intervals (a
        dropped sample skips a slot of the grid).
    gaps : int
        Intervals longer than 1.5 median intervals (dropped samples).
    max_gap_s : float
        The longest interval [s].
    """

    uniform: bool
    interval_s: float
    effective_rate_hz: float
    jitter: float
    gaps: int
    max_gap_s: float

    def to_dict(self) -> dict:
        return {"uniform": self.uniform, "interval_s": self.interval_s, "effective_rate_hz": self.effective_rate_hz,
                "jitter": self.jitter, "gaps": self.gaps, "max_gap_s": self.max_gap_s}


def time_base(t: np.ndarray, uniform: bool) -> TimeBase:
    """The spacing report of strictly increasing times ``t``."""
    steps = np.diff(t)
    med = float(np.median(steps))
    # the stamps' deviation from the best uniform grid through them (a dropped sample skips a slot)
    slot = np.concatenate([[0.0], np.cumsum(np.maximum(np.round(steps / med), 1.0))])
    dt, t0 = np.polyfit(slot, t, 1)
    jitter = float(np.sqrt(np.mean((t - (t0 + slot * dt)) ** 2)) / dt)
    return TimeBase(uniform=uniform, interval_s=med, effective_rate_hz=float((t.size - 1) / (t[-1] - t[0])),
                    jitter=jitter, gaps=int(np.count_nonzero(steps > 1.5 * med)), max_gap_s=float(steps.max()))


def detect_nonuniform(t: np.ndarray, s: np.ndarray, name: str) -> tuple[float, float]:
    """Drive frequency [Hz] of a motion at non-uniform times: the FFT peak of the signal
    interpolated onto the mean grid, refined by the sinusoid fit at the true times."""
    from scipy.optimize import minimize_scalar

    n = t.size
    grid = t[0] + np.arange(n) * (t[-1] - t[0]) / (n - 1)
    f0, _ = detect_uniform(np.interp(grid, t, s), float(grid[1] - grid[0]), name)
    u = t - 0.5 * (t[0] + t[-1])
    r = linear_residual(u, s)
    tss = float(r @ r)

    rss = sinusoid_rss(u, s)
    half_bin = 0.5 / (t[-1] - t[0])
    best = minimize_scalar(rss, bounds=(f0 - half_bin, f0 + half_bin), method="bounded",
                           options={"xatol": 1e-13 * f0, "maxiter": 200})
    f = float(best.x)
    share = 1.0 - rss(f) / tss if tss > 0 else 0.0
    if share < MIN_DETECTED_SHARE:
        raise InputError(f"no clear drive peak in the {name} signal at {f:.6g} Hz ({100 * max(share, 0):.0f} % of its "
                         "variance); give the drive frequency (frequency=..., --frequency 2Hz)")
    return f, share


def _phasors(tau: np.ndarray, y: np.ndarray, omega: float, harmonics: int) -> np.ndarray:
    """Least-squares complex amplitudes of harmonics 1..H of ``y`` at times ``tau`` (plus a constant)."""
    cols = [np.ones_like(tau)]
    for h in range(1, harmonics + 1):
        cols += [np.cos(h * omega * tau), np.sin(h * omega * tau)]
    basis = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(basis, y, rcond=None)
    a, b = coef[1::2], coef[2::2]
    return a - 1j * b  # y = Re(S exp(i h omega tau)) = a cos - b' sin with S = a - i b


def analyze_nonuniform(t, F, s, kind, *, frequency, drop, bed, keep_signals, uniform_error: str):
    """The complex power method on a record whose times are not a uniform grid (module docstring)."""
    from scipy.interpolate import CubicSpline

    from .checks import _check_frequency
    from .results import PowerResult, Signals

    tb = time_base(t, uniform=False)
    if frequency is None:
        f, _ = detect_nonuniform(t, s, kind)
        detected = True
    else:
        f = _check_frequency(frequency)
        detected = False
    period = 1.0 / f
    omega = 2.0 * math.pi * f
    per_period = period * tb.effective_rate_hz
    if per_period < MIN_SAMPLES_PER_PERIOD:
        raise InputError(f"the record has {per_period:.3g} samples per drive period of {f:.6g} Hz on average; at least "
                         f"{MIN_SAMPLES_PER_PERIOD} are needed to find the phasors at uneven time stamps "
                         f"({uniform_error.split(';')[0]})")
    if tb.max_gap_s > MAX_GAP_PERIODS * period:
        j = int(np.argmax(np.diff(t)))
        raise InputError(f"the record has a gap of {tb.max_gap_s:.6g} s after t = {t[j]:.9g} s, "
                         f"{tb.max_gap_s / period:.2g} of the drive period: that part of the cycle is not observed; "
                         "cut the record at the gap or fill it")
    t0 = float(t[0])
    n_total = int(math.floor((t[-1] - t0) / period + 1e-9))
    n_used = n_total - drop
    if n_used < 1:
        raise InputError(
            f"the record holds {(t[-1] - t0) / period:.3g} cycles of {f:.6g} Hz ({n_total} whole) and the "
            f"first {drop} are dropped, which leaves no whole cycle to analyse; use a longer record or fewer "
            f"dropped cycles (drop_cycles, --drop-cycles {max(n_total - 1, 0)})")
    w0, w1 = t0 + drop * period, t0 + n_total * period
    inside = (t >= w0) & (t < w1)
    tau = t[inside] - w0
    harmonics = max(1, min(HARMONICS, int(per_period / 2) - 1))
    S_star = complex(_phasors(tau, s[inside], omega, harmonics)[0])
    F_star = complex(_phasors(tau, F[inside], omega, harmonics)[0])
    V_star = S_star if kind == "velocity" else (1j * omega * S_star if kind == "position" else S_star / (1j * omega))
    s_win = s[inside]
    var = float(np.mean((s_win - s_win.mean()) ** 2))
    share = 0.5 * abs(S_star) ** 2 / var if var > 0.0 else 0.0
    if not detected and share < MIN_GIVEN_SHARE:
        raise InputError(f"the {kind} signal has almost nothing at the given drive frequency {f:.6g} Hz "
                         f"({100 * share:.2g} % of its variance in the window); check the frequency, or omit it")
    P = 0.5 * F_star * np.conj(V_star)                                  # (3)
    energy = (2.0 * math.pi / omega) * P.real                           # (4)
    e_diss = energy / (2.0 * math.pi)
    v_amp = abs(V_star)
    eta = math.nan if bed is None or v_amp == 0.0 else e_diss / (0.5 * bed * v_amp**2)   # (5)

    # velocity at the samples (for the cross-checks and plots)
    if kind == "velocity":
        v_k = s
    elif kind == "position":
        v_k = CubicSpline(t - t0, s)(t - t0, 1)
    else:
        v_k = CubicSpline(t - t0, s).antiderivative()(t - t0)
        v_k = v_k - float(np.mean(v_k[inside]))
    power = F * v_k
    edges = t0 + np.arange(n_total + 1) * period
    p_edges = np.interp(edges, t, power)
    cycle_e = np.empty(n_total)
    for c in range(n_total):
        m = (t > edges[c]) & (t < edges[c + 1])
        tt = np.concatenate([[edges[c]], t[m], [edges[c + 1]]])
        pp = np.concatenate([[p_edges[c]], power[m], [p_edges[c + 1]]])
        cycle_e[c] = float(np.sum(0.5 * (pp[1:] + pp[:-1]) * np.diff(tt)))
    used = np.arange(n_total) >= drop
    mean_power = float(cycle_e[used].mean())
    spread = math.nan
    if n_used >= 2:
        apparent = math.pi * abs(F_star) * v_amp / omega
        scale = max(abs(float(cycle_e[used].mean())), 1e-9 * apparent)
        if scale > 0.0:
            spread = float(np.std(cycle_e[used], ddof=1)) / scale
    starts = edges[:-1]
    for arr in (cycle_e, starts, used):
        arr.setflags(write=False)
    return PowerResult(
        frequency_hz=float(f), frequency_detected=detected, sample_rate_hz=tb.effective_rate_hz, resampled=False,
        motion=kind, cycles_dropped=drop, cycles_used=n_used, window_s=(float(w0), float(w1)),
        complex_power_W=complex(P), force_phasor_N=complex(F_star), velocity_phasor_m_s=complex(V_star),
        force_amplitude_N=float(abs(F_star)), velocity_amplitude_m_s=float(v_amp), energy_per_cycle_J=float(energy),
        dissipated_energy_J=float(e_diss), eta_star=float(eta), bed_mass_kg=math.nan if bed is None else float(bed),
        mean_power_check_J=mean_power, drive_share=float(min(share, 1.0)), cycle_energies_J=cycle_e,
        cycle_start_s=starts, cycle_used=used, cycle_energy_spread=spread,
        signals=Signals(time_s=t, force_N=F, velocity_m_s=np.asarray(v_k, dtype=float), motion=kind)
        if keep_signals else None,
        time_base=tb)
