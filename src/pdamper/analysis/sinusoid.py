"""The drive sinusoid of a motion signal, the lowest piece of the analysis: the least-squares fit
of ``a cos(2 pi f t) + b sin(2 pi f t) + c + d t`` that :func:`pdamper.analysis.detect_frequency`
(uniform samples), :mod:`.nonuniform` (uneven samples) and :func:`pdamper.analysis.complex_power`
share, and the shares of the motion's variance a drive must carry."""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = ["MIN_DETECTED_SHARE", "MIN_GIVEN_SHARE", "detect_uniform", "linear_residual", "sinusoid_rss"]

#: A detected drive must explain at least this share of the detrended motion variance.
MIN_DETECTED_SHARE = 0.5
#: A given drive frequency must carry at least this share of the motion variance in the window.
MIN_GIVEN_SHARE = 0.01


def linear_residual(u: np.ndarray, s: np.ndarray) -> np.ndarray:
    """``s`` minus its least-squares straight line ``c + d u`` (the trend a drive detection removes)."""
    trend = np.column_stack([np.ones(u.size), u])
    coef, *_ = np.linalg.lstsq(trend, s, rcond=None)
    return s - trend @ coef


def detect_uniform(s: np.ndarray, dt: float, name: str) -> tuple[float, float]:
    """Drive frequency [Hz] of the uniformly sampled motion ``s`` (step ``dt`` [s]) and the share of
    its detrended variance that the fitted sinusoid carries (:func:`pdamper.analysis.detect_frequency`
    describes the method); :class:`InputError` when there is no clear drive peak."""
    from scipy.fft import next_fast_len
    from scipy.optimize import minimize_scalar

    n = s.size
    u = (np.arange(n) - 0.5 * (n - 1)) * dt          # centred time
    r = linear_residual(u, s)
    tss = float(r @ r)
    if not tss > 0.0 or tss <= 1e-28 * float(s @ s):
        raise InputError(
            f"no clear drive peak: the {name} signal is constant (or a straight line); "
            "give the drive frequency (frequency=..., --frequency 2Hz)")
    record = n * dt
    nfft = next_fast_len(4 * n)
    spec = np.abs(np.fft.rfft(r * np.hanning(n), nfft))
    freqs = np.fft.rfftfreq(nfft, dt)
    lo = int(np.searchsorted(freqs, 1.5 / record))
    if lo >= spec.size - 1:
        raise InputError(
            f"no clear drive peak: the record ({n} samples) is too short to find a "
            "frequency; give the drive frequency (frequency=..., --frequency 2Hz)")
    k = lo + int(np.argmax(spec[lo:]))
    if k == lo and spec[lo - 1] > spec[lo]:
        raise InputError(
            f"no clear drive peak in the {name} signal: its spectrum falls from DC "
            f"with no peak above {1.5 / record:.3g} Hz (the record has less than 1.5 "
            "cycles of anything); give the drive frequency (frequency=..., --frequency 2Hz)")
    f0 = freqs[k]
    if 0 < k < spec.size - 1 and np.all(spec[k - 1:k + 2] > 0):
        a, b, c = np.log(spec[k - 1:k + 2])
        den = a - 2.0 * b + c
        if den < 0:
            f0 = freqs[k] + 0.5 * (a - c) / den * (freqs[1] - freqs[0])

    rss = sinusoid_rss(u, s)
    half_bin = 0.5 / record
    lo_f = max(f0 - half_bin, 0.5 / record)
    hi_f = min(f0 + half_bin, 0.5 / dt)
    best = minimize_scalar(rss, bounds=(lo_f, hi_f), method="bounded",
                           options={"xatol": 1e-13 * f0, "maxiter": 200})
    f = float(_gauss_newton(s, u, float(best.x), rss))
    share = 1.0 - rss(f) / tss
    if share < MIN_DETECTED_SHARE:
        raise InputError(
            f"no clear drive peak in the {name} signal: the strongest sinusoid "
            f"({f:.6g} Hz) carries only {100 * max(share, 0.0):.0f} % of its variance "
            f"(at least {100 * MIN_DETECTED_SHARE:.0f} % needed); give the drive frequency "
            "(frequency=..., --frequency 2Hz)")
    return f, share


def sinusoid_rss(u: np.ndarray, s: np.ndarray):
    """The residual sum of squares of the best fit ``a cos(2 pi f u) + b sin(2 pi f u) + c + d u`` to
    ``s`` at times ``u``, as a function of f."""
    n = s.size

    def rss(f):
        w = 2.0 * math.pi * f * u
        basis = np.column_stack([np.cos(w), np.sin(w), np.ones(n), u])
        cf, *_ = np.linalg.lstsq(basis, s, rcond=None)
        e = s - basis @ cf
        return float(e @ e)

    return rss


def _gauss_newton(s: np.ndarray, u: np.ndarray, f: float, rss) -> float:
    """Polish a frequency estimate [Hz] by Gauss-Newton steps on the sinusoid-fit residual.

    The bounded scalar search stops at ~1e-9 relative (the residual is flat to
    rounding near its minimum); a few Gauss-Newton steps on the full model
    ``a cos(w u) + b sin(w u) + c + d u`` bring a clean sinusoid to ~1e-13.
    """
    n = s.size
    best = rss(f)
    for _ in range(4):
        w = 2.0 * math.pi * f
        cw, sw = np.cos(w * u), np.sin(w * u)
        basis = np.column_stack([cw, sw, np.ones(n), u])
        cf, *_ = np.linalg.lstsq(basis, s, rcond=None)
        a, b = cf[0], cf[1]
        jac = np.column_stack([basis, u * (b * cw - a * sw)])
        step, *_ = np.linalg.lstsq(jac, s - basis @ cf, rcond=None)
        f_new = f + step[4] / (2.0 * math.pi)
        new = rss(f_new)
        if not new <= best:
            break
        converged = abs(f_new - f) <= 1e-15 * abs(f)
        f, best = f_new, new
        if converged:
            break
    return f
