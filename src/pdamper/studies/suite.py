"""A suite of records: one coupled transient per record, and what engineers report over them.

Seismic codes ask for a suite of ground motions (ASCE 7 and Eurocode 8: seven or more) and judge
the **mean** response over it; the **84th percentile** says how far one record may carry the
structure beyond it. A ``[load]`` with ``files = [...]`` (or a folder) is such a suite
(:meth:`pdamper.structure.loads.base.LoadBase.records`: one load a record, each scaled by its own
factor to a PGA or a spectral acceleration, or by the common ``scale``). :func:`run_suite` runs
:func:`pdamper.studies.transient.run_transient` on each and reports, per dof and at the damper
point, the peak and RMS with and without the damper over the records:

- ``mean``: the arithmetic mean over the records (the codes' design value);
- ``p84``: the 84th percentile of a lognormal fitted to them, ``exp(mean(ln x) + std(ln x))``
  (the median times e^beta, beta the logarithmic standard deviation, ddof = 1: the usual
  description of record-to-record variability); None for fewer than two records;
- ``peak_ratio`` / ``rms_ratio``: the mean with the damper over the mean without (the ratio of
  the design values), beside the mean and the 84th percentile of each record's own ratio.

Under ground accelerations each record's 5 %-damped pseudo-acceleration spectrum
(:func:`pdamper.structure.spectrum.response_spectrum`, as scaled) and its value at the
structure's first period are reported too, with the suite's mean spectrum.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..params import Case
from .transient import TransientResult, in_time, run_transient

__all__ = ["SuiteResult", "run_suite", "suite_statistics", "suite_spectra", "is_suite"]

#: The quantities of a transient's summary that the suite's statistics are taken of.
_PER_DOF = ("peak_m", "peak_bare_m", "rms_m", "rms_bare_m", "peak_reduction", "rms_reduction")
_DAMPER = ("damper_peak_m", "damper_peak_bare_m", "damper_rms_m", "damper_rms_bare_m", "damper_peak_reduction",
           "damper_rms_reduction")


def is_suite(case: Case) -> bool:
    """Whether the case's structure runs a suite of records (a ``[load]`` of several ``files``)."""
    drive = case.drive
    return bool(drive.coupled and drive.load is not None and len(drive.load.records()) > 1)


def suite_statistics(values) -> dict:
    """Over the records (axis 0 of ``values``, [records] or [records, dofs]): ``mean``, ``median``,
    ``p84`` (lognormal, module docstring; None for fewer than two records or a value <= 0) and
    ``beta`` (the log standard deviation), as plain numbers or lists.

    >>> s = suite_statistics([1.0, 2.0, 4.0])
    >>> round(s["mean"], 4), round(s["median"], 4), round(s["p84"], 4)
    (2.3333, 2.0, 4.0)
    """
    x = np.asarray(values, dtype=float)
    mean = np.mean(x, axis=0)
    out = {"mean": mean, "median": np.median(x, axis=0), "p84": None, "beta": None}
    if x.shape[0] >= 2 and np.all(np.isfinite(x)) and np.all(x > 0):
        ln = np.log(x)
        beta = np.std(ln, axis=0, ddof=1)
        out["p84"] = np.exp(np.mean(ln, axis=0) + beta)
        out["beta"] = beta
    return {k: (None if v is None else np.asarray(v).tolist()) for k, v in out.items()}


def suite_spectra(loads, period: float, periods=None) -> dict | None:
    """The records' 5 %-damped pseudo-acceleration spectra as scaled (``periods`` [s], default
    :data:`~pdamper.structure.spectrum.DEFAULT_PERIODS` with ``period``), each record's PSA at
    ``period`` [s] (the structure's first) and the mean spectrum; None unless every load is a
    ground acceleration (a force has no spectrum)."""
    from ..structure.spectrum import DEFAULT_PERIODS, SPECTRUM_DAMPING, response_spectrum

    if not all(load.ground for load in loads):
        return None
    grid = np.unique(np.concatenate([np.asarray(periods if periods is not None else DEFAULT_PERIODS), [period]]))
    psa, at = [], []
    for load in loads:
        t = np.asarray(load.time, dtype=float)
        a = load.values(t)
        s = response_spectrum(t, a, grid, damping=SPECTRUM_DAMPING)
        psa.append(s.psa)
        at.append(s.at(period))
    psa = np.array(psa)
    return {"periods_s": grid.tolist(), "damping": SPECTRUM_DAMPING, "psa_m_s2": psa.tolist(),
            "mean_psa_m_s2": psa.mean(axis=0).tolist(), "first_period_s": float(period),
            "psa_at_first_period_m_s2": at, "method": "Nigam-Jennings piecewise-exact recurrence"}


@dataclass(frozen=True, kw_only=True)
class SuiteResult:
    """One coupled transient a record (``runs``, :class:`~pdamper.studies.transient.TransientResult`,
    in the suite's order; ``names`` the records' files), the statistics over them and, under
    ground accelerations, the records' spectra; ``summary`` plain numbers for JSON."""

    case: Case
    runs: list
    names: list
    spectra: dict | None = None
    summary: dict = field(default_factory=dict)


def run_suite(case: Case, *, dofs=None, progress=None, limits=None) -> SuiteResult:
    """One coupled DEM transient (:func:`~pdamper.studies.transient.run_transient`) for each record
    of the case's suite (``[load] files``; a load of one record runs once), in turn, and the
    statistics over them (module docstring). ``progress(fraction)`` over the whole suite; ``limits``
    each record's codes limits (:func:`~pdamper.studies.transient.run_transient`)."""
    case = in_time(case)
    s = case.drive
    loads = s.load.records()
    runs: list[TransientResult] = []
    total = sum(load.duration for load in loads)
    done = 0.0
    for load in loads:
        one = dataclasses.replace(case, drive=dataclasses.replace(s, load=load))

        def step(fraction, _start=done, _length=load.duration):
            if progress is not None:
                progress((_start + fraction * _length) / total)

        try:
            runs.append(run_transient(one, dofs=dofs, progress=step if progress is not None else None, limits=limits))
        except InputError as exc:
            raise InputError(f"record {len(runs) + 1} of {len(loads)} ({_name(load)}): {exc}") from None
        done += load.duration
    names = [_name(load) for load in loads]
    first = 1.0 / float(np.min(case.running_drive.mode_frequencies))
    spectra = suite_spectra(loads, first)
    summary = _summary(runs, names, spectra)
    return SuiteResult(case=case, runs=runs, names=names, spectra=spectra, summary=summary)


def _name(load) -> str:
    return Path(load.file).name if load.file else "inline samples"


def _summary(runs, names, spectra) -> dict:
    per = [r.summary for r in runs]
    first = per[0]
    stats = {}
    for key in _PER_DOF + _DAMPER:
        stats[key] = suite_statistics([p[key] for p in per])
    mean = lambda key: np.asarray(stats[key]["mean"], dtype=float)  # noqa: E731
    with np.errstate(divide="ignore", invalid="ignore"):
        peak_ratio = np.where(mean("peak_bare_m") > 0, mean("peak_m") / mean("peak_bare_m"), np.nan)
        rms_ratio = np.where(mean("rms_bare_m") > 0, mean("rms_m") / mean("rms_bare_m"), np.nan)
    out = {
        "records": len(runs), "record_names": list(names), "dofs": first["dofs"],
        "ground": first["ground"], "relative_to_ground": first["relative_to_ground"],
        "particles": first["particles"], "bed_mass_kg": first["bed_mass_kg"], "mass_ratio": first["mass_ratio"],
        "load": [p["load"] for p in per], "statistics": stats,
        "peak_ratio": peak_ratio.tolist(), "rms_ratio": rms_ratio.tolist(),
        "damper_peak_ratio": float(mean("damper_peak_m") / mean("damper_peak_bare_m")),
        "damper_rms_ratio": float(mean("damper_rms_m") / mean("damper_rms_bare_m")),
        "p84_note": "84th percentile of a lognormal over the records: exp(mean ln x + std ln x), ddof 1",
        "runs": per, "wall_time_s": float(sum(p["wall_time_s"] for p in per)),
        "steps": int(sum(p["steps"] for p in per)),
    }
    if spectra is not None:
        out["spectra"] = spectra
    return out
