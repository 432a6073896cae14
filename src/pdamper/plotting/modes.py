"""The motion-mode map of sweeps and studies: stroke x filling (or any study setting), beside η*.

:func:`mode_map_figure` takes one or more results datasets (a sweep's ``results.nc``: dimensions
``stroke`` and ``seed``; a study's ``study.nc``: also ``setting``) with the text variable
``mode`` (:mod:`pdamper.analysis.modes`) and draws

- top: η*(X), the mean over seeds, one line per row, X_opt of each row marked;
- bottom: the mode map, one row per sweep or setting, one cell per stroke coloured by the mode
  most seeds are in (a dot marks cells whose seeds disagree).
"""

from __future__ import annotations

import math
import numpy as np

from ..analysis.modes import majority_mode
from ..errors import InputError
from .sweep import _check_path, _save, _segments, _with_gaps, log_ticks

__all__ = ["mode_map_figure", "MODE_COLOURS", "MODE_MARKERS", "MODE_HATCHES", "mode_style", "mode_order",
           "mode_rows"]

# The one place where the motion modes get their look (the mode map, the sweep figure's markers, the
# design map's hatching). A mode of pdamper.analysis.modes.MODES that is not listed here still gets a
# colour, marker and hatch of its own from the spare ones below (see mode_style), so adding a mode to
# the classifier needs no change here; list it to choose its look.

#: Colour of each mode (cases without a mode: white, failed: black).
MODE_COLOURS = {
    "locked": "#636363",
    "scattered": "#9ecae1",
    "rolling-collect-and-collide": "#31a354",
    "swaying": "#c7e9c0",
    "single-sided": "#fd8d3c",
    "lift-off": "#de2d26",
    "unknown": "#ffffff",
    "failed": "#000000",
}
#: Marker of each mode on η*(X) curves.
MODE_MARKERS = {
    "locked": "p",
    "scattered": "o",
    "rolling-collect-and-collide": "s",
    "swaying": "v",
    "single-sided": "^",
    "lift-off": "D",
    "unknown": "o",
    "failed": "X",
}
#: Hatching of each mode on the design map (rolling collect-and-collide plain).
MODE_HATCHES = {
    "locked": "++",
    "scattered": "..",
    "rolling-collect-and-collide": "",
    "swaying": "--",
    "single-sided": "//",
    "lift-off": "oo",
    "unknown": "",
    "failed": "xx",
}
_SPARE_COLOURS = ("#756bb1", "#e7ba52", "#8c6d31", "#e377c2", "#17becf", "#bcbd22")
_SPARE_MARKERS = ("v", "P", "h", "<", ">", "*")
_SPARE_HATCHES = ("\\\\", "--", "++", "||", "oo..", "**")


def mode_order() -> list[str]:
    """Every mode with a look, in legend order: those of :data:`MODE_COLOURS`, then any of the
    classifier's modes (:data:`pdamper.analysis.modes.MODES`) it does not list, ``unknown`` and
    ``failed`` last."""
    from ..analysis.modes import MODES

    ends = ("unknown", "failed")
    order = [m for m in MODE_COLOURS if m not in ends] + [m for m in MODES if m not in MODE_COLOURS]
    return order + list(ends)


def mode_style(mode: str) -> dict:
    """``{"color", "marker", "hatch"}`` of a motion mode: from :data:`MODE_COLOURS`,
    :data:`MODE_MARKERS` and :data:`MODE_HATCHES`; a mode they do not list (e.g. one just added to
    :data:`pdamper.analysis.modes.MODES`) gets a spare colour, marker and hatch of its own, fixed by
    its place in the classifier's list (or its name).

    >>> mode_style("scattered")["marker"]
    'o'
    """
    mode = str(mode)
    if mode in MODE_COLOURS:
        return {"color": MODE_COLOURS[mode], "marker": MODE_MARKERS.get(mode, "o"),
                "hatch": MODE_HATCHES.get(mode, "")}
    unlisted = [m for m in mode_order() if m not in MODE_COLOURS]
    k = unlisted.index(mode) if mode in unlisted else len(unlisted) + sum(map(ord, mode))
    return {"color": _SPARE_COLOURS[k % len(_SPARE_COLOURS)], "marker": _SPARE_MARKERS[k % len(_SPARE_MARKERS)],
            "hatch": _SPARE_HATCHES[k % len(_SPARE_HATCHES)]}


def _mode_rank(mode: str) -> int:
    order = mode_order()
    return order.index(mode) if mode in order else len(order)


def _label(ds, default):
    n = ds.attrs.get("particles")
    return f"N_p = {int(n)}" if n is not None else default


def mode_rows(datasets, names=None, labels=None) -> list[dict]:
    """One dict per row (``label``, ``stroke`` [m], ``modes`` (strokes, seeds) text, ``eta`` mean
    over seeds, ``x_opt`` [m]) from sweep or study datasets; ``labels`` replace the row labels."""
    rows = []
    names = list(names) if names is not None else [f"results {k + 1}" for k in range(len(datasets))]
    for ds, name in zip(datasets, names):
        if "mode" not in ds or "stroke" not in ds.dims:
            raise InputError(f"{name}: no motion modes in these results (no 'mode' variable); they were made "
                             "by a pdamper without mode classification: re-run the sweep into a new --out")
        if "setting" in ds.dims:
            for k, lbl in enumerate(ds.setting.values.tolist()):
                sub = ds.isel(setting=k)
                x_opt = float(ds["x_opt"].values[k]) if "x_opt" in ds else math.nan
                rows.append(_row(sub, str(lbl), x_opt))
        else:
            rows.append(_row(ds, _label(ds, name), float(ds.attrs.get("x_opt_m", math.nan))))
    auto = [r["label"] for r in rows]
    if len(set(auto)) < len(auto):  # two sweeps of the same filling: tell them apart by file
        k = 0
        for ds, name in zip(datasets, names):
            count = ds.sizes.get("setting", 1)
            for _ in range(count):
                rows[k]["label"] = f"{rows[k]['label']} ({name})"
                k += 1
    if labels:
        if len(labels) != len(rows):
            raise InputError(f"{len(labels)} row label(s) given for {len(rows)} row(s) of the mode map; "
                             "give one per sweep or study setting")
        for r, lbl in zip(rows, labels):
            r["label"] = str(lbl)
    return rows


def _row(ds, label, x_opt):
    modes = np.asarray(ds["mode"].transpose("stroke", "seed").values).astype(str)
    eta = ds["eta_star"].transpose("stroke", "seed").values.astype(float) if "eta_star" in ds else None
    with np.errstate(all="ignore"):
        mean = np.nanmean(eta, axis=1) if eta is not None and np.isfinite(eta).any() else None
    return {"label": label, "stroke": np.asarray(ds.stroke.values, dtype=float), "modes": modes,
            "eta": mean, "x_opt": x_opt}


def _edges(x):
    """Cell edges around log-spaced strokes (geometric midpoints)."""
    x = np.asarray(x, dtype=float)
    if x.size == 1:
        return np.array([x[0] / 1.15, x[0] * 1.15])
    mid = np.sqrt(x[1:] * x[:-1])
    return np.concatenate([[x[0] ** 2 / mid[0]], mid, [x[-1] ** 2 / mid[-1]]])


def mode_map_figure(datasets, path=None, *, names=None, labels=None, title: str | None = None, figsize=None,
                    dpi: int = 150):
    """η*(X) and the mode map of sweep/study datasets (see the module docstring); returns the Figure."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch, Rectangle

    target = _check_path(path)
    rows = mode_rows(datasets, names, labels)
    if not rows:
        raise InputError("mode map: no results given")
    n = len(rows)
    fig = Figure(figsize=figsize or (7.8, 3.6 + 0.45 * n), layout="constrained")
    top, bottom = fig.subplots(2, 1, sharex=True, height_ratios=[2.2, max(0.8, 0.45 * n)])
    colours = [f"C{k}" for k in range(n)]
    for k, r in enumerate(rows):
        xs = r["stroke"] * 1e3
        if r["eta"] is not None:  # broken across X_opt and where the mode changes, as the sweep figure
            have = np.isfinite(r["eta"])
            cells = [majority_mode(c)[0] for c in r["modes"][have]]
            x_opt = r["x_opt"] * 1e3 if math.isfinite(r["x_opt"]) else None
            gx, gy = _with_gaps(xs[have], r["eta"][have], _segments(xs[have], cells, x_opt))
            top.plot(gx, gy, "o-", ms=3.5, lw=1.3, color=colours[k], label=r["label"])
        if math.isfinite(r["x_opt"]):
            top.axvline(r["x_opt"] * 1e3, color=colours[k], ls=":", lw=1.0)
            bottom.plot([r["x_opt"] * 1e3] * 2, [k - 0.5, k + 0.5], color="k", ls=":", lw=1.2)
        edges = _edges(r["stroke"]) * 1e3
        for i in range(len(xs)):
            mode, mixed = majority_mode(r["modes"][i])
            if not mode:
                continue
            bottom.add_patch(Rectangle((edges[i], k - 0.42), edges[i + 1] - edges[i], 0.84,
                                       facecolor=mode_style(mode)["color"], edgecolor="white", lw=0.5))
            if mixed:
                bottom.plot([xs[i]], [k], "o", ms=2.5, color="k")
    top.set_xscale("log")
    top.set_ylabel("η* (mean over seeds) [-]")
    top.grid(True, which="both", color="0.92", lw=0.5)
    top.legend(fontsize=8, frameon=False, loc="upper left")
    lo = min(_edges(r["stroke"])[0] for r in rows) * 1e3
    hi = max(_edges(r["stroke"])[-1] for r in rows) * 1e3
    bottom.set_xlim(lo, hi)
    bottom.set_ylim(-0.5, n - 0.5)
    bottom.set_yticks(range(n), [r["label"] for r in rows], fontsize=8.5)
    bottom.invert_yaxis()
    bottom.set_xlabel("stroke X [mm]   (dotted: X_opt, eq. 17)")
    log_ticks(bottom.xaxis, lo, hi)   # shared with the η* panel: at least 3 labelled strokes
    top.tick_params(labelbottom=True)
    present = sorted({majority_mode(c)[0] for r in rows for c in r["modes"]} - {""}, key=_mode_rank)
    handles = [Patch(facecolor=mode_style(m)["color"], edgecolor="0.5", label=m) for m in present]
    if any(majority_mode(c)[1] for r in rows for c in r["modes"]):
        from matplotlib.lines import Line2D

        handles.append(Line2D([], [], marker="o", ls="", color="k", ms=3, label="seeds disagree"))
    fig.legend(handles=handles, fontsize=8.5, frameon=False, loc="outside lower center",
               ncol=min(5, max(1, len(handles))))
    fig.suptitle(title or "Motion modes over the stroke (docs/motion.md)", fontsize=10.5)
    if target is not None:
        _save(fig, target, dpi)
    return fig
