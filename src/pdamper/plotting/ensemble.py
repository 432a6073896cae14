"""Figures of an ensemble over the unknowns, drawn from its dataset
(:func:`pdamper.studies.ensemble.run_ensemble`).

* :func:`cdf_figure` -- the ratio's empirical CDF over the samples (one step curve per dof: the
  share of samples at or below each value) against the target, the share meeting it with its
  Wilson interval; for a run ensemble eta*'s (the share at or above the target);
* :func:`tornado_figure` -- which unknowns matter: for each unknown, the median of the quantity
  over the samples in its lowest and its highest third, as bars from the median of all (the
  longest on top), with Spearman's rho beside; beside it, the quantity against the unknown that
  matters most (what a rank correlation cannot tell: an effect that rises and falls).
"""

from __future__ import annotations

import json

import numpy as np

from .figure import check_path, save

__all__ = ["cdf_figure", "tornado_figure", "ensemble_quantity"]

_WORDS = {"peak_ratio": "peak ratio (with / without the damper)", "rms_ratio": "RMS ratio (with / without the damper)",
          "eta_star": "eta*"}


def ensemble_quantity(ds, quantity: str | None = None) -> str:
    """The quantity an ensemble's figure draws: ``quantity``, or ``peak_ratio`` where the dataset
    has it, else ``eta_star``."""
    if quantity is not None:
        if quantity not in ds:
            from ..errors import InputError

            raise InputError(f"the ensemble has no {quantity!r}; it has "
                             + ", ".join(q for q in _WORDS if q in ds))
        return quantity
    return "peak_ratio" if "peak_ratio" in ds else "eta_star"


def _decisive(ds, quantity: str) -> np.ndarray:
    """One value per sample: a ratio's largest over the dofs (NaN where one is missing), eta*'s best
    over a sweep's grid."""
    x = ds[quantity]
    other = [d for d in x.dims if d != "sample"]
    if not other:
        return x.values.astype(float)
    v = x.transpose("sample", *other).values.reshape(x.sizes["sample"], -1)
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        if quantity == "eta_star":
            return np.nanmax(v, axis=1)
        return np.where(np.isfinite(v).all(axis=1), np.nanmax(v, axis=1), np.nan)


def cdf_figure(ds, path=None, *, quantity: str | None = None, target: float | None = None, dpi: int = 150):
    """The empirical CDF of ``quantity`` (module docstring) over the samples of ``ds``, the
    ``target`` drawn with the share meeting it."""
    from matplotlib.figure import Figure

    from ..analysis.ensemble import share_meeting

    target_path = check_path(path)
    q = ensemble_quantity(ds, quantity)
    fig = Figure(figsize=(7.0, 4.6), layout="constrained")
    ax = fig.subplots()
    x = ds[q]
    n = int(ds.sizes["sample"])
    curves = []
    if "dof" in x.dims:
        for k, d in enumerate(ds.dof.values):
            curves.append((f"dof {d}", x.isel(dof=k).values))
        if len(curves) > 1:
            curves.append(("largest over the dofs", _decisive(ds, q)))
    else:
        curves.append((_WORDS[q], _decisive(ds, q)))
    colors = ["#1f77b4", "#2ca02c", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"]
    for k, (label, v) in enumerate(curves):
        v = np.sort(v[np.isfinite(v)])
        if v.size == 0:
            continue
        share = np.arange(1, v.size + 1) / n  # a failed sample never meets a target: it tops the curve off below 1
        last = k == len(curves) - 1 and len(curves) > 1
        ax.step(np.r_[v[0], v], np.r_[0.0, share], where="post", lw=2.0 if last else 1.2,
                color="black" if last else colors[k % len(colors)], label=label)
    if target is not None:
        decisive = _decisive(ds, q)
        if q == "eta_star":
            s = share_meeting(-decisive, -target)
            said = f"eta* >= {target:g}"
        else:
            s = share_meeting(decisive, target)
            said = f"{q.replace('_', ' ')} <= {target:g}"
        ax.axvline(target, color="#d62728", lw=1.4, ls="--")
        ax.text(target, 0.02, f"  target: {said}\n  met by {s['met']} of {s['samples']} samples: "
                f"{100 * s['share']:.3g} %\n  95 % interval {100 * s['low']:.3g}-{100 * s['high']:.3g} % (Wilson)",
                color="#d62728", fontsize=8, va="bottom")
    ax.set_xlabel(_WORDS[q])
    ax.set_ylabel("share of the samples at or below")
    ax.set_ylim(0, 1.02)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title(f"{ds.attrs.get('study', '')} ensemble: {n} samples (Latin hypercube) of "
                 f"{len(json.loads(ds.attrs.get('unknowns', '[]')))} unknowns", fontsize=9)
    if target_path is not None:
        save(fig, target_path, dpi=dpi)
    return fig


def _thirds(x: np.ndarray, y: np.ndarray):
    """Median of ``y`` over the samples in the lowest and in the highest third of ``x``."""
    ok = np.isfinite(y) & np.isfinite(x)
    x, y = x[ok], y[ok]
    if x.size < 3 or np.ptp(x) == 0:
        return np.nan, np.nan
    order = np.argsort(x, kind="stable")
    k = max(1, x.size // 3)
    return float(np.median(y[order[:k]])), float(np.median(y[order[-k:]]))


def tornado_figure(ds, path=None, *, quantity: str | None = None, dpi: int = 150):
    """Which unknowns move ``quantity`` (module docstring): the tornado and the scatter beside it."""
    from matplotlib.figure import Figure

    from ..analysis.ensemble import rank_importance

    target_path = check_path(path)
    q = ensemble_quantity(ds, quantity)
    y = _decisive(ds, q)
    names = ds.attrs.get("unknown_variables", "").split()
    cols = {ds[v].attrs["config_key"]: ds[v].values for v in names if v in ds}
    listed = {u["key"]: u.get("values") for u in json.loads(ds.attrs.get("unknowns", "[]"))
              if u.get("distribution") == "choice"}
    ranks = rank_importance({k: list(v) for k, v in cols.items()}, y,
                            order={k: [str(x).rsplit("/", 1)[-1] for x in v] for k, v in listed.items()})

    def numeric(key):
        v = cols[key]
        if v.dtype.kind in "iuf":
            return v.astype(float)
        order = {s: i for i, s in enumerate(dict.fromkeys(str(x).rsplit("/", 1)[-1]
                                                           for x in (listed.get(key) or v)))}
        return np.array([order.get(str(s), np.nan) for s in v], dtype=float)

    fig = Figure(figsize=(10.0, max(3.2, 0.55 * len(ranks) + 1.6)), layout="constrained")
    ax, ax_s = fig.subplots(1, 2, width_ratios=[1.5, 1.0])
    mid = float(np.nanmedian(y)) if np.isfinite(y).any() else np.nan
    rows = list(reversed(ranks))  # the largest on top
    for j, r in enumerate(rows):
        lo, hi = _thirds(numeric(r["key"]), y)
        for value, color, label in ((lo, "#1f77b4", "lowest third of the unknown"),
                                    (hi, "#d62728", "highest third of the unknown")):
            if np.isfinite(value):
                ax.barh(j, value - mid, left=mid, height=0.6, color=color, alpha=0.8,
                        label=label if j == len(rows) - 1 else None)
        rho = r["rho"]
        ax.text(1.01, j, f"rho {rho:+.2f}" if np.isfinite(rho) else "rho n/a", transform=ax.get_yaxis_transform(),
                va="center", fontsize=8)
    ax.set_yticks(range(len(rows)), [r["key"] for r in rows], fontsize=8)
    if np.isfinite(mid):
        ax.axvline(mid, color="black", lw=0.8)
    ax.set_xlabel(f"median {_WORDS[q]}" + (" (largest over the dofs)" if "dof" in ds[q].dims and ds.sizes["dof"] > 1
                                            else ""))
    ax.grid(True, axis="x", alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")
    ax.set_title(f"(a) what moves it: the median of the samples in each unknown's\nlowest and highest third "
                 f"(black: the median of all {np.isfinite(y).sum()}, {mid:.3g})", fontsize=9)
    if ranks and np.isfinite(ranks[0]["rho"]):
        top = ranks[0]["key"]
        x = numeric(top)
        ax_s.plot(x, y, "o", ms=4, color="#444444")
        ax_s.set_xlabel(top + ("" if cols[top].dtype.kind in "iuf" else " (listed order)"))
        ax_s.set_ylabel(_WORDS[q])
        ax_s.grid(True, alpha=0.3)
        ax_s.set_title(f"(b) against {top},\nthe unknown that matters most", fontsize=9)
    else:
        ax_s.set_axis_off()
    if target_path is not None:
        save(fig, target_path, dpi=dpi)
    return fig
