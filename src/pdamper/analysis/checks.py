"""Input checks of a record for the complex power method: 1-D, equal lengths, finite, time
strictly increasing (and whether it is a uniform grid), and the method's settings. Each problem is
one :class:`pdamper.errors.InputError` that says what is wrong and how to fix it."""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import InputError, shown



def _as_1d(name: str, x) -> np.ndarray:
    if x is None:
        raise InputError(f"{name} is missing; give an array of samples")
    try:
        arr = np.asarray(x, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be an array of real numbers; got {type(x).__name__}") from None
    if arr.ndim != 1:
        raise InputError(f"{name} must be a 1-D array of samples; got shape {arr.shape}")
    return arr


def _check_lengths(arrays: dict) -> None:
    sizes = {k: v.size for k, v in arrays.items()}
    if len(set(sizes.values())) != 1:
        listing = ", ".join(f"{k} {n}" for k, n in sizes.items())
        raise InputError(f"time, force and motion must have the same number of samples; got {listing}")
    n = next(iter(sizes.values()))
    if n < 3:
        raise InputError(
            f"the record has {n} sample{'s' if n != 1 else ''}; at least 3 are needed "
            "(and enough for one whole drive cycle after the dropped ones)")


#: Largest magnitude a signal may have: its squares summed over millions of samples stay finite.
_MAX_MAGNITUDE = 1e100


def _check_finite(name: str, x: np.ndarray, t: np.ndarray | None) -> None:
    bad = np.flatnonzero(~np.isfinite(x))
    if bad.size:
        i = int(bad[0])
        at = f" (time {t[i]:.6g} s)" if t is not None and np.isfinite(t[i]) else ""
        raise InputError(
            f"{name} has {bad.size} non-finite value{'s' if bad.size > 1 else ''} "
            f"({x[i]}), the first at index {i}{at}; remove or fill the bad samples")
    big = float(np.max(np.abs(x), initial=0.0))
    if big > _MAX_MAGNITUDE:
        raise InputError(
            f"{name} has values up to {big:.3g}: too large to analyse (sums of their squares overflow double "
            f"precision beyond {_MAX_MAGNITUDE:.0e}); no force, motion or time in SI units comes near that: check "
            "the column's unit or scale the record")


def _uniform_grid(t: np.ndarray, tol: float) -> tuple[float, float]:
    """First time and sample interval of a strictly increasing, uniform time axis."""
    steps = np.diff(t)
    bad = np.flatnonzero(~(steps > 0))
    if bad.size:
        i = int(bad[0])
        raise InputError(
            f"time must increase strictly from sample to sample; at index {i + 1} it goes "
            f"from {t[i]:.9g} s to {t[i + 1]:.9g} s; sort the record and remove repeated rows")
    n = t.size
    dt = (t[-1] - t[0]) / (n - 1)
    dev = t - (t[0] + np.arange(n) * dt)
    j = int(np.argmax(np.abs(dev)))
    rel = abs(dev[j]) / dt
    if rel > tol:
        raise InputError(
            f"time is not uniformly sampled: intervals range from {steps.min():.6g} s to "
            f"{steps.max():.6g} s and sample {j} (t = {t[j]:.9g} s) is off the uniform grid by "
            f"{abs(dev[j]):.3g} s = {rel:.3g} sample intervals (allowed {tol:g}); resample "
            "the record onto a constant sample rate (or write the time with more digits)")
    return float(t[0]), float(dt)


def _check_tolerance(tol) -> None:
    if isinstance(tol, bool) or not isinstance(tol, numbers.Real) or not tol >= 0.0:
        raise InputError(f"time_tolerance must be a number of sample intervals >= 0; got {shown(tol)}")


def _check_frequency(frequency) -> float:
    if isinstance(frequency, bool) or not isinstance(frequency, numbers.Real):
        raise InputError(f"frequency must be a number in Hz; got {shown(frequency)}")
    f = float(frequency)
    if not math.isfinite(f) or f <= 0.0:
        raise InputError(f"frequency must be a positive number of Hz; got {shown(frequency)}")
    return f


def _check_drop(drop_cycles) -> int:
    if isinstance(drop_cycles, bool) or not isinstance(drop_cycles, numbers.Integral):
        if isinstance(drop_cycles, numbers.Real) and float(drop_cycles).is_integer():
            drop_cycles = int(drop_cycles)
        else:
            raise InputError(f"drop_cycles must be a whole number of cycles (0, 1, 2, ...); "
                             f"got {shown(drop_cycles)}")
    if drop_cycles < 0:
        raise InputError(f"drop_cycles must be 0 or more; got {drop_cycles}")
    return int(drop_cycles)


def _check_bed_mass(bed_mass) -> float | None:
    if bed_mass is None:
        return None
    if isinstance(bed_mass, bool) or not isinstance(bed_mass, numbers.Real):
        raise InputError(f"bed mass must be a number in kg; got {shown(bed_mass)}")
    m = float(bed_mass)
    if not math.isfinite(m) or m <= 0.0:
        raise InputError(f"bed mass must be positive (the mass of all particles, in kg); got {shown(bed_mass)}")
    return m
