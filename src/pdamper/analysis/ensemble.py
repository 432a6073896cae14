"""What an ensemble says: percentiles, the share of samples that meet a target with its interval,
and which unknowns matter. Pure functions of arrays (:mod:`pdamper.studies.ensemble` runs the
samples; docs/ensembles.md).

- :func:`percentiles` -- the 5th, 50th and 95th percentiles over the samples (linear
  interpolation between order statistics, numpy's default), a failed sample (NaN) left out;
- :func:`share_meeting` -- the share of samples whose value is at most a target, with its
  **Wilson score interval** (:meth:`scipy.stats.binomtest`'s ``proportion_ci(method="wilson")``):
  near 0 or 1 and at a few dozen samples its coverage stays close to the nominal one, where the
  normal (Wald) interval collapses to a point and Clopper-Pearson's exact interval is wider than
  it needs to be (Brown, Cai & DasGupta, "Interval estimation for a binomial proportion",
  Statistical Science 16 (2001) 101-133);
- :func:`rank_importance` -- Spearman's rank correlation of each unknown with the result
  (:func:`scipy.stats.spearmanr`): the sign says which way the unknown moves it, ``|rho|`` how
  strongly and how monotonically; ranked by ``|rho|``. A choice is ranked by the place of its
  value in the list (numbers sorted): meaningful for ordered choices only.

**Why no Sobol indices.** Variance-based (Sobol) indices need their own design (Saltelli's, N (2 d
+ 2) runs: 768 DEM runs for 5 unknowns at N = 64, twelve times the ensemble); the estimators that
work on given samples such as ours (RBD-FAST, the delta index, in SALib) carry at 64 samples an
error of the order of the indices they estimate. The unknowns of a damper move its ratios mostly
one way each (softer frame, lower ratio), which a rank correlation captures; it misses an effect
that rises and falls over the range (a tilt around 0), which the tornado chart's companion, the
scatter of the ratio against each unknown, shows (:func:`pdamper.plotting.ensemble.tornado_figure`).
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["PERCENTILES", "CONFIDENCE", "percentiles", "share_meeting", "rank_importance"]

#: The percentiles an ensemble reports.
PERCENTILES = (5, 50, 95)
#: The confidence of the share's interval.
CONFIDENCE = 0.95


def percentiles(values, q=PERCENTILES, axis: int = 0) -> dict:
    """``{"p05": ..., "p50": ..., "p95": ...}`` of ``values`` over ``axis`` (the samples), NaN left
    out (a quantity per dof: an array per percentile); NaN where no finite value is left."""
    import warnings

    x = np.asarray(values, dtype=float)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # an all-NaN column: NaN, which says it
        return {f"p{p:02d}": np.nanpercentile(x, p, axis=axis) for p in q}


def share_meeting(values, target: float, *, confidence: float = CONFIDENCE) -> dict:
    """The share of the samples ``values`` that meet ``target`` (value <= target; a failed sample,
    NaN, counts as not meeting it) with its Wilson score interval at ``confidence``:
    ``{"met", "samples", "share", "low", "high", "confidence", "method"}``."""
    from scipy.stats import binomtest

    x = np.asarray(values, dtype=float).ravel()
    n = int(x.size)
    k = int(np.sum(np.isfinite(x) & (x <= target)))
    if n == 0:
        return {"met": 0, "samples": 0, "share": math.nan, "low": math.nan, "high": math.nan,
                "confidence": confidence, "method": "wilson", "target": float(target)}
    ci = binomtest(k, n).proportion_ci(confidence_level=confidence, method="wilson")
    return {"met": k, "samples": n, "share": k / n, "low": float(ci.low), "high": float(ci.high),
            "confidence": float(confidence), "method": "wilson", "target": float(target)}


def _ranks_of(column) -> np.ndarray:
    """A column of values as numbers to rank: numbers as they are, a choice of texts by their first
    appearance (the caller passes them in the list's order)."""
    vals = list(column)
    if all(isinstance(v, (int, float, np.integer, np.floating)) and not isinstance(v, bool) for v in vals):
        return np.asarray(vals, dtype=float)
    order = {v: i for i, v in enumerate(dict.fromkeys(vals))}
    return np.asarray([order[v] for v in vals], dtype=float)


def rank_importance(inputs: dict, output, *, order: dict | None = None) -> list:
    """Which unknowns matter for ``output`` (one value per sample, NaN where a sample failed):
    ``[{"key", "rho", "p_value", "samples"}, ...]``, Spearman's rho of each unknown's column of
    ``inputs`` (``{key: values per sample}``) with the output, largest ``|rho|`` first; an unknown
    whose values do not vary, or an output with fewer than 3 finite samples, has rho NaN (last).
    ``order``: for a choice of texts, ``{key: the listed values}`` (ranked in that order)."""
    from scipy.stats import spearmanr

    y = np.asarray(output, dtype=float).ravel()
    ok = np.isfinite(y)
    out = []
    for key, column in inputs.items():
        col = list(column)
        if order and key in order and not all(isinstance(v, (int, float)) for v in col):
            place = {v: i for i, v in enumerate(order[key])}
            x = np.asarray([place.get(v, np.nan) for v in col], dtype=float)
        else:
            x = _ranks_of(col)
        use = ok & np.isfinite(x)
        rho = p = math.nan
        if use.sum() >= 3 and np.ptp(x[use]) > 0 and np.ptp(y[use]) > 0:
            r = spearmanr(x[use], y[use])
            rho, p = float(r.statistic), float(r.pvalue)
        out.append({"key": key, "rho": rho, "p_value": p, "samples": int(use.sum())})
    out.sort(key=lambda r: (not math.isfinite(r["rho"]), -abs(r["rho"]) if math.isfinite(r["rho"]) else 0.0))
    return out
