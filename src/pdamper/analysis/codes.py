"""The numbers building codes ask for: absolute floor accelerations, inter-storey drift ratios, and
the verdict of each against a limit the user gives (docs/structure.md, "The numbers codes ask for").

Pure functions on arrays; the studies (:mod:`pdamper.studies.transient`, ``structure``) call them
with and without the damper.

- :func:`floor_accelerations` -- every dof's absolute acceleration from its sampled displacement
  relative to the ground: the second difference ``(x_{i+1} - 2 x_i + x_{i-1}) / dt^2`` (the
  acceleration averaged over a triangle of half-width dt, as an accelerometer sampled at 1/dt sees
  it: an impact's 50 us spike is spread over it) plus the ground's acceleration;
- :func:`storey_drift_ratios` -- Delta_j / h_j with Delta_j = x(floor j) - x(floor j - 1), x(ground) = 0
  (:class:`pdamper.structure.storeys.Storeys`);
- :func:`time_numbers` -- peak and RMS of both over a record, and the residual drift ratio: the
  mean drift over the record's last ``residual_window`` (a permanent offset stays, an oscillation
  averages out);
- :func:`harmonic_numbers` -- the same of a steady harmonic response from its complex amplitudes
  (peak = amplitude, RMS = amplitude / sqrt 2);
- :class:`Limits`, :func:`parse_limits` -- the limits (``drift=0.5%``, ``acceleration=0.15m/s^2``,
  ``residual_drift=0.2%``, ``rms_acceleration=0.05m/s^2``);
- :func:`code_summary` -- with and without the damper side by side, their ratios and each limit's
  verdict per dof or storey (the JSON ``codes`` object of ``pdamper transient`` and ``response``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ..errors import InputError, shown

__all__ = ["Limits", "LIMITS", "parse_limits", "floor_accelerations", "storey_drift_ratios", "time_numbers",
           "harmonic_numbers", "worst", "code_summary", "verdicts", "bare_key", "reduction_key", "STANDARD_GRAVITY",
           "MAX_DRIFT"]

#: g_n [m/s^2]: ``--limit acceleration=0.015g`` is 0.015 g_n.
STANDARD_GRAVITY = 9.80665

#: The largest drift ratio a limit may be (20 %): ``drift=1`` means 100 %, surely meant as 1 %.
MAX_DRIFT = 0.2

#: The quantities a limit applies to: key -> (dimension, what it bounds, the number it bounds, example).
LIMITS = {
    "drift": ("dimensionless", "peak inter-storey drift ratio", "drift_ratio_peak", "0.5%"),
    "residual_drift": ("dimensionless", "residual inter-storey drift ratio", "drift_ratio_residual", "0.2%"),
    "acceleration": ("acceleration", "peak absolute floor acceleration", "acceleration_peak_m_s2", "0.15m/s^2"),
    "rms_acceleration": ("acceleration", "RMS absolute floor acceleration", "acceleration_rms_m_s2", "0.05m/s^2"),
}


@dataclass(frozen=True, kw_only=True)
class Limits:
    """Limits on the numbers codes ask for (None: no limit): ``drift``, ``residual_drift`` (drift
    ratios [-], 0.005 = 0.5 %), ``acceleration``, ``rms_acceleration`` [m/s^2]. A value at or below
    its limit passes."""

    drift: float | None = None
    residual_drift: float | None = None
    acceleration: float | None = None
    rms_acceleration: float | None = None

    def __post_init__(self):
        for f in fields(self):
            v = getattr(self, f.name)
            if v is None:
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (v > 0 and math.isfinite(v)):
                raise InputError(f"--limit {f.name}={shown(v)}: a limit must be > 0, e.g. --limit {f.name}="
                                 f"{LIMITS[f.name][3]}")
            object.__setattr__(self, f.name, float(v))

    def given(self) -> dict:
        """The limits given: key -> value (SI)."""
        return {f.name: getattr(self, f.name) for f in fields(self) if getattr(self, f.name) is not None}


def parse_limits(items) -> Limits:
    """``["drift=0.5%", "acceleration=0.15m/s^2"]`` (the ``--limit`` options) -> :class:`Limits`;
    values with units as a person types them (``0.5%``, ``0.005``, ``15cm/s^2``, ``0.015g`` for
    g_n). One line of error naming the option for an unknown key, a key given twice or a bad value.

    >>> parse_limits(["drift=0.5%", "acceleration=0.015g"]).given()
    {'drift': 0.005, 'acceleration': 0.14709975}
    """
    from ..units import parse_quantity

    out: dict = {}
    for item in items or ():
        key, eq, text = str(item).partition("=")
        key, text = key.strip(), text.strip()
        if not eq or not key or not text:
            raise InputError(f"--limit {shown(item)}: write KEY=VALUE, e.g. --limit drift=0.5% or --limit "
                             "acceleration=0.15m/s^2")
        if key not in LIMITS:
            raise InputError(f"--limit {shown(item)}: unknown quantity {shown(key)}; give one of {', '.join(LIMITS)}")
        if key in out:
            raise InputError(f"--limit {key} is given twice; give each quantity's limit once")
        dim, _, _, ex = LIMITS[key]
        if dim == "acceleration" and text.endswith("g") and not text.endswith(("kg", "mg")):
            number = text[:-1].strip()
            try:
                value = float(number) * STANDARD_GRAVITY
            except ValueError:
                raise InputError(f"--limit {shown(item)}: {shown(text)} is not an acceleration; e.g. {key}={ex} or "
                                 f"{key}=0.015g") from None
            value = float(f"{value:.12g}")
        else:
            value = parse_quantity(text, dim, name=f"--limit {key}")
        if not (value > 0 and math.isfinite(value)):
            raise InputError(f"--limit {shown(item)}: a limit must be > 0, e.g. --limit {key}={ex}")
        if dim == "dimensionless" and value > MAX_DRIFT:
            raise InputError(f"--limit {shown(item)} is a drift of {100 * value:g} % of the storey's height (a number "
                             f"without % is a ratio); did you mean {key}={text}%?")
        out[key] = value
    return Limits(**out)


def _uniform_step(time) -> float:
    t = np.asarray(time, dtype=float)
    if t.ndim != 1 or t.size < 3:
        raise InputError("floor accelerations need three or more samples")
    dt = np.diff(t)
    if not (np.all(dt > 0) and np.max(np.abs(dt - dt[0])) <= 1e-9 * dt[0] + 1e-15):
        raise InputError("floor accelerations need uniformly spaced samples")
    return float(dt[0])


def floor_accelerations(time, x, ground=None):
    """(times [s], a [m/s^2]): every dof's absolute acceleration at the inner samples of ``time``
    (uniform; the first and the last dropped) from its displacement ``x`` [samples, dofs] relative
    to the ground, the second difference plus ``ground`` (the ground's acceleration at ``time``
    [m/s^2], None: the ground at rest).

    >>> t = np.linspace(0.0, 1.0, 1001)
    >>> _, a = floor_accelerations(t, np.sin(2 * np.pi * t)[:, None])
    >>> round(float(np.max(np.abs(a))) / (2 * np.pi) ** 2, 4)
    1.0
    """
    dt = _uniform_step(time)
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    a = (x[2:] - 2.0 * x[1:-1] + x[:-2]) / (dt * dt)
    if ground is not None:
        a = a + np.asarray(ground, dtype=float)[1:-1, None]
    return np.asarray(time, dtype=float)[1:-1], a


def storey_drift_ratios(x, storeys) -> np.ndarray:
    """Delta_j / h_j [-] of each storey of ``storeys`` (:class:`~pdamper.structure.storeys.Storeys`)
    from the dofs' displacements ``x`` [samples, dofs] relative to the ground."""
    x = np.asarray(x, dtype=float)
    up = x[:, list(storeys.upper)]
    low = np.column_stack([x[:, i] if i >= 0 else np.zeros(x.shape[0]) for i in storeys.lower])
    return (up - low) / np.asarray(storeys.heights, dtype=float)


def _peak(y):
    return np.max(np.abs(y), axis=0) if y.shape[0] else np.full(y.shape[1], math.nan)


def _rms(y):
    return np.sqrt(np.mean(y * y, axis=0)) if y.shape[0] else np.full(y.shape[1], math.nan)


def time_numbers(time, x, *, storeys=None, ground=None, residual_window: float | None = None) -> dict:
    """Peak and RMS of every dof's absolute acceleration (:func:`floor_accelerations`) over the record
    ``time`` [s] (uniform), ``x`` [samples, dofs] relative to the ground (``ground``: its acceleration
    at ``time``); with ``storeys`` each storey's drift ratio's peak, RMS and residual (the mean over the
    last ``residual_window`` [s], at most half the record; default the last tenth). Lists, SI."""
    x = np.asarray(x, dtype=float)
    _, a = floor_accelerations(time, x, ground)
    out = {"acceleration_peak_m_s2": _peak(a).tolist(), "acceleration_rms_m_s2": _rms(a).tolist()}
    if storeys is not None:
        t = np.asarray(time, dtype=float)
        d = storey_drift_ratios(x, storeys)
        span = t[-1] - t[0]
        window = 0.1 * span if residual_window is None else min(float(residual_window), 0.5 * span)
        tail = t >= t[-1] - window - 1e-12
        out.update(drift_ratio_peak=_peak(d).tolist(), drift_ratio_rms=_rms(d).tolist(),
                   drift_ratio_residual=np.mean(d[tail], axis=0).tolist(), residual_window_s=float(window))
    return out


def harmonic_numbers(frequencies, phasors, *, storeys=None) -> dict:
    """The same numbers as :func:`time_numbers` of steady harmonic responses: ``phasors``
    [frequencies, dofs] the dofs' complex amplitudes [m] at ``frequencies`` [Hz] (no ground
    motion); per frequency (lists over the dofs of lists over the frequencies) the acceleration amplitude (2 pi f)^2 |x^|
    and its RMS, with ``storeys`` the drift ratio's amplitude |x^_j - x^_{j-1}| / h_j and RMS."""
    f = np.asarray(frequencies, dtype=float)
    z = np.asarray(phasors, dtype=complex).reshape(f.size, -1)
    acc = (2.0 * math.pi * f[:, None]) ** 2 * np.abs(z)
    out = {"acceleration_peak_m_s2": acc.T.tolist(), "acceleration_rms_m_s2": (acc / math.sqrt(2.0)).T.tolist()}
    if storeys is not None:
        up = z[:, list(storeys.upper)]
        low = np.column_stack([z[:, i] if i >= 0 else np.zeros(f.size, dtype=complex) for i in storeys.lower])
        d = np.abs(up - low) / np.asarray(storeys.heights, dtype=float)
        out.update(drift_ratio_peak=d.T.tolist(), drift_ratio_rms=(d / math.sqrt(2.0)).T.tolist())
    return out


def worst(per_frequency: dict, frequencies) -> dict:
    """Of numbers per dof and frequency (lists over the dofs of lists over the frequencies, NaN for a failed point), each
    dof's largest over the frequencies and the frequency [Hz] where (``..._at_hz``)."""
    f = np.asarray(frequencies, dtype=float)
    out = {}
    for key, rows in per_frequency.items():
        if not isinstance(rows, list) or not rows or not isinstance(rows[0], list):
            continue
        arr = np.asarray(rows, dtype=float)
        ok = np.isfinite(arr)
        k = np.where(ok.any(axis=1), np.argmax(np.where(ok, arr, -np.inf), axis=1), 0)
        vals = np.where(ok.any(axis=1), arr[np.arange(arr.shape[0]), k], math.nan)
        out[key] = vals.tolist()
        out[f"{key}_at_hz"] = [float(f[j]) if math.isfinite(v) else math.nan for j, v in zip(k, vals)]
    return out


_UNITS = ("_m_s2",)


def bare_key(key: str) -> str:
    """The key of a number without the damper: ``_bare`` before the unit
    (``acceleration_peak_m_s2`` -> ``acceleration_peak_bare_m_s2``, ``drift_ratio_peak`` ->
    ``drift_ratio_peak_bare``)."""
    for u in _UNITS:
        if key.endswith(u):
            return key[:-len(u)] + "_bare" + u
    return key + "_bare"


def reduction_key(key: str) -> str:
    """The key of a number's ratio with / without the damper (``acceleration_peak_reduction``)."""
    for u in _UNITS:
        if key.endswith(u):
            return key[:-len(u)] + "_reduction"
    return key + "_reduction"


def _ratio(a, b) -> list:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(np.abs(b) > 0, a / b, math.nan).tolist()


def _verdict(values, limit: float) -> list:
    return ["n/a" if not math.isfinite(v) else ("pass" if abs(v) <= limit else "exceed") for v in values]


def verdicts(damped: dict, bare: dict, limits: Limits | None, *, dofs, storeys=None) -> dict:
    """Each limit given against the numbers with (``damped``) and without (``bare``) the damper
    (keys of :func:`time_numbers`): quantity -> {limit, what, labels (dofs or storeys), value,
    value_bare, verdict, verdict_bare ("pass", "exceed", "n/a"), met, met_bare (every dof or storey
    passes)}. A drift limit without storeys, or a residual drift without a record in time, says so
    in ``note``."""
    out = {}
    for key, limit in (limits.given() if limits is not None else {}).items():
        _, what, number, _ = LIMITS[key]
        entry = {"limit": limit, "what": what}
        if number not in damped:
            entry["note"] = ("no storeys: give [structure] storey_heights (or storey_height) and storey_dofs"
                             if number.startswith("drift") and storeys is None
                             else "not measured by this study (a steady harmonic response has no residual drift)")
            out[key] = entry
            continue
        v, vb = damped[number], bare.get(number, [math.nan] * len(damped[number]))
        vd, vdb = _verdict(v, limit), _verdict(vb, limit)
        entry.update(labels=list(storeys.labels) if number.startswith("drift") else list(dofs), value=list(v),
                     value_bare=list(vb), verdict=vd, verdict_bare=vdb,
                     met=all(x == "pass" for x in vd), met_bare=all(x == "pass" for x in vdb))
        out[key] = entry
    return out


def code_summary(damped: dict, bare: dict, *, dofs, storeys=None, limits: Limits | None = None,
                 ground: bool = False, method: str = "") -> dict:
    """The JSON ``codes`` object: the numbers with the damper (``damped``) and without (``bare``),
    keys of :func:`time_numbers` (per dof in ``dofs``' order, per storey of ``storeys``), each with
    ``_bare`` and ``_reduction`` (with / without) beside it, the storeys, how the accelerations were
    taken (``method``) and the limits' :func:`verdicts`."""
    out = {"dofs": list(dofs), "acceleration_absolute": True,
           "acceleration_note": ("absolute: relative to the ground plus the ground's acceleration" if ground
                                 else "absolute (the ground at rest)") + (f"; {method}" if method else "")}
    for key, v in damped.items():
        out[key] = v
        if isinstance(v, list) and key in bare:
            out[bare_key(key)] = bare[key]
            if "residual" not in key and not key.endswith("_at_hz"):  # a residual near 0 has no useful ratio
                out[reduction_key(key)] = _ratio(v, bare[key])
    if storeys is not None:
        out.update(storeys.to_dict())
    else:
        out["storeys"] = None
        out["storeys_note"] = ("no drift ratios: give [structure] storey_heights = ['3m', ...] (or storey_height) "
                               "and storey_dofs = [...] (docs/config.md)")
    out["limits"] = verdicts(damped, bare, limits, dofs=dofs, storeys=storeys)
    return out
