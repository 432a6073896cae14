"""Input checks and the phase solver shared by the theory modules (private)."""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..errors import InputError, shown

__all__ = ["positive", "positive_array", "as_output", "solve_phase"]


def _show(value) -> str:
    return f"{value:g}" if _is_real(value) else repr(value)


def _is_real(value) -> bool:
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def positive(name: str, value, unit: str, example: str) -> float:
    """``value`` as a float, or :class:`InputError` unless it is a finite number > 0."""
    if not _is_real(value) or not math.isfinite(value) or value <= 0:
        raise InputError(f"{name} = {_show(value)} is not allowed: {name} must be a finite "
                         f"number > 0 in {unit}, e.g. {example}")
    return float(value)


def positive_array(name: str, value, unit: str, example: str) -> np.ndarray:
    """``value`` as a float array, or :class:`InputError` unless every entry is finite and > 0."""
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"{name} = {shown(value)} is not a number or an array of numbers; "
                         f"give {name} in {unit}, e.g. {example}") from None
    bad = ~np.isfinite(arr) | (arr <= 0)
    if np.any(bad):
        first = arr[bad].flat[0]
        where = "" if arr.ndim == 0 else f" (entry {int(np.flatnonzero(bad.ravel())[0])})"
        raise InputError(f"{name} = {first:g}{where} is not allowed: {name} must be finite "
                         f"and > 0 in {unit}, e.g. {example}")
    return arr


def as_output(arr: np.ndarray, *inputs):
    """A float for scalar inputs, else the array."""
    return float(arr) if all(np.ndim(x) == 0 for x in inputs) else arr


def solve_phase(func, dfunc, target: np.ndarray, upper: float = math.pi) -> np.ndarray:
    """Solve ``func(theta) = target`` elementwise for theta in (0, upper].

    ``func`` must be increasing and convex on (0, upper] with ``func(0) = 0``; the two impact
    equations of the collect-and-collide laws are. Newton's method started to the right of the
    root then converges monotonically from above and never leaves the bracket. Entries with
    ``target > func(upper)`` (beyond a relative round-off of 1e-12) give NaN; entries within
    that round-off give ``upper``.
    """
    target = np.asarray(target, dtype=float)
    top = func(upper)
    out = np.full(target.shape, np.nan)
    ok = target <= top * (1 + 1e-12)
    y = np.minimum(target[ok], top)
    if y.size == 0:
        return out
    # Start close to, and to the right of, the root: func ~ theta^3/6 near 0 for both laws.
    theta = np.minimum(upper, 1.5 * np.cbrt(6 * y))
    theta = np.where(func(theta) >= y, theta, upper)
    for _ in range(200):
        step = (func(theta) - y) / dfunc(theta)
        step = np.where(np.isfinite(step), np.maximum(step, 0.0), 0.0)
        theta = theta - step
        if np.all(step <= 4 * np.finfo(float).eps * theta):
            break
    out[ok] = theta
    return out
