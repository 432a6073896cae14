"""The check of an accelerogram on reading, and its optional baseline correction.

Every ground acceleration pdamper reads (a CSV, a PEER ``.AT2`` file, HDF5/MATLAB/TDMS channels,
inline samples, a Python caller's arrays) becomes a
:class:`~pdamper.structure.loads.ground.GroundAcceleration`, which checks it here once it is built:

- :func:`check_record` integrates it from rest (trapezoids) and measures what a processed record
  does not have: a **mean** (a one-sided record: ``|mean| > 0.2 RMS``, or fewer than two zero
  crossings), a **drifting velocity** (the least-squares straight line through the integrated
  velocity rises over the record by more than half the velocity's peak: a baseline error, which a
  real ground motion, ending at rest, does not have) and the displacement it leads to (the "table
  travel"). A one-sided or drifting record moves a structure quasi-statically, which no damper
  changes; :class:`RecordWarning` says so with the numbers (issue 39: a record of mean 0.14 g that
  never crossed zero, 261 m of travel when integrated, had run without a word).
- :func:`baseline_correct` (``[load] baseline = "constant" | "linear" | "quadratic" | "cubic"``) is
  the standard least-squares polynomial baseline of strong-motion processing fitted to the
  *velocity* (Boore, Stephens & Joyner 2002, BSSA 92(4) 1543-1560; Boore & Bommer 2005, Soil Dyn.
  Earthq. Eng. 25, 93-115, section 4): a polynomial q(t) of degree p + 1 is fitted by least
  squares to the velocity integrated from rest, and its derivative q'(t), a polynomial of degree p
  (the baseline's order: 0 a constant, 1 a line ...), is taken off the acceleration. Fitting the
  velocity rather than the acceleration weighs the long-period error that integration amplifies;
  correcting a corrected record changes nothing (the fit is a projection). It does not filter:
  the record's own content below the baseline's order is kept.

No physics of the structure is involved; these are pure functions of the samples (numpy only).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["RecordCheck", "RecordWarning", "check_record", "baseline_correct", "BASELINES"]

#: ``[load] baseline`` -> the order of the polynomial taken off the acceleration (None: none).
BASELINES = {"none": None, "constant": 0, "linear": 1, "quadratic": 2, "cubic": 3}
#: A record is one-sided when its mean exceeds this share of its RMS.
ONE_SIDED_MEAN = 0.2
#: A record drifts when the straight line through its velocity rises by this share of the peak velocity.
DRIFTING_TREND = 0.5
_G = 9.80665


class RecordWarning(UserWarning):
    """An accelerogram that is one-sided or drifts (:func:`check_record`): it moves a structure
    quasi-statically, which no damper changes."""


def _integral(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The running integral of ``y`` over ``t`` from 0 (trapezoids)."""
    out = np.zeros_like(y)
    np.cumsum(0.5 * (y[1:] + y[:-1]) * np.diff(t), out=out[1:])
    return out


@dataclass(frozen=True)
class RecordCheck:
    """What :func:`check_record` measured on an accelerogram (SI units), integrated from rest.

    Attributes
    ----------
    mean, rms, peak : float
        Of the acceleration [m/s^2].
    zero_crossings : int
        Sign changes of the acceleration.
    duration : float
        From the first sample to the last [s].
    end_velocity, peak_velocity : float
        The integrated velocity at the record's end and its largest magnitude [m/s].
    velocity_trend : float
        The rise over the record of the least-squares straight line through the velocity [m/s].
    end_displacement, peak_displacement : float
        The twice-integrated displacement at the end and its largest magnitude [m] (the table travel).
    """

    mean: float
    rms: float
    peak: float
    zero_crossings: int
    duration: float
    end_velocity: float
    peak_velocity: float
    velocity_trend: float
    end_displacement: float
    peak_displacement: float

    @property
    def one_sided(self) -> bool:
        """The record hardly changes sign: ``|mean| > 0.2 RMS`` or fewer than two zero crossings."""
        return self.rms > 0 and (abs(self.mean) > ONE_SIDED_MEAN * self.rms or self.zero_crossings < 2)

    @property
    def drifting(self) -> bool:
        """The velocity's straight-line trend exceeds half its peak: a baseline error."""
        return self.peak_velocity > 0 and abs(self.velocity_trend) > DRIFTING_TREND * self.peak_velocity

    def describe(self) -> str:
        """One line of the numbers, in g, m/s and m."""
        return (f"mean {self.mean / _G:.3g} g (RMS {self.rms / _G:.3g} g, {self.zero_crossings} zero crossings); "
                f"integrated from rest: velocity trend {self.velocity_trend:.3g} m/s (peak {self.peak_velocity:.3g} "
                f"m/s), displacement {self.end_displacement:.3g} m at the end (peak {self.peak_displacement:.3g} m)")

    def warning(self, source: str = "the accelerogram") -> str | None:
        """The warning's text for a one-sided or drifting record, else None."""
        what = [w for w, bad in (("one-sided", self.one_sided), ("drifting", self.drifting)) if bad]
        if not what:
            return None
        return (f"{source} is {' and '.join(what)}: {self.describe()}; a record that is not a shake moves the "
                "structure quasi-statically, which no damper changes: check its units and its baseline (a processed "
                "record ends at rest), or set [load] baseline = \"linear\" (a least-squares baseline fitted to the "
                "velocity, Boore et al. 2002)")


def check_record(time, acceleration) -> RecordCheck:
    """The :class:`RecordCheck` of an accelerogram: ``time`` [s] strictly increasing, ``acceleration``
    [m/s^2], finite (as a :class:`~pdamper.structure.loads.ground.GroundAcceleration` holds them)."""
    t = np.asarray(time, dtype=float)
    a = np.asarray(acceleration, dtype=float)
    t = t - t[0]
    with np.errstate(all="ignore"):  # a record of 1e300 m/s^2 integrates to inf: its numbers say so
        v = _integral(t, a)
        d = _integral(t, v)
        rms = float(np.sqrt(np.mean(a * a)))
        span = float(t[-1])
        fits = t.size > 2 and span > 0 and np.isfinite(v).all()
        slope = float(np.polyfit(t, v, 1)[0]) if fits else (0.0 if np.isfinite(v).all() else math.inf)
    signs = np.sign(a[a != 0.0])
    return RecordCheck(mean=float(np.mean(a)), rms=rms, peak=float(np.max(np.abs(a))),
                       zero_crossings=int(np.count_nonzero(signs[1:] != signs[:-1])), duration=span,
                       end_velocity=float(v[-1]), peak_velocity=float(np.max(np.abs(v))),
                       velocity_trend=slope * span, end_displacement=float(d[-1]),
                       peak_displacement=float(np.max(np.abs(d))))


def baseline_correct(time, acceleration, order: int) -> np.ndarray:
    """The acceleration [m/s^2] less its least-squares baseline of polynomial ``order`` (0 to 3),
    fitted to the velocity integrated from rest (module docstring): a polynomial of degree
    ``order + 1`` in ``t / duration`` through the velocity, its derivative taken off."""
    if order not in (0, 1, 2, 3):
        raise ValueError(f"baseline order {order!r}; choose 0 to 3")
    t = np.asarray(time, dtype=float)
    a = np.asarray(acceleration, dtype=float)
    t = t - t[0]
    span = float(t[-1])
    if t.size < order + 3 or not span > 0 or not math.isfinite(span):
        return a.copy()
    with np.errstate(all="ignore"):
        v = _integral(t, a)
        if not np.isfinite(v).all():  # beyond floats: nothing to fit
            return a.copy()
        s = t / span
        coef = np.polynomial.polynomial.polyfit(s, v, order + 1)
        slope = np.polynomial.polynomial.polyval(s, np.polynomial.polynomial.polyder(coef)) / span
    return a - slope
