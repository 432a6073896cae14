"""Measured next to simulated: the paper's Fig. 4 with experiment.

:func:`compare_figure` draws a campaign (:mod:`pdamper.studies.campaign`: measured eta* with error
bars, one marker per record) over the DEM of one or more sweeps (mean line, seed band, single
seeds) and the paper's laws for the sweeps' clearance.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .figure import check_path, save, stroke_axis
from .sweep import _sweep_into

__all__ = ["compare_figure"]


def compare_figure(campaign, sweeps=(), path=None, *, title=None, figsize=(7.8, 5.2), dpi: int = 150):
    """eta*(X) measured (``campaign``, error bars) and simulated (``sweeps``: results datasets with a
    stroke dimension), with the laws. Returns the figure; saved to ``path`` if given."""
    from matplotlib.figure import Figure

    target = check_path(path)
    if "eta_star" not in campaign or "stroke" not in campaign.dims:
        raise InputError("the measured results must be a campaign dataset (pdamper campaign), with eta_star over stroke")
    fig = Figure(figsize=figsize, layout="constrained")
    sweeps = list(sweeps)
    if sweeps:
        import xarray as xr

        dem = sweeps[0] if len(sweeps) == 1 else xr.concat(
            [s.assign_coords(setting=s.attrs.get("title", f"DEM {k + 1}")).expand_dims("setting")
             for k, s in enumerate(sweeps)], dim="setting", combine_attrs="drop_conflicts")
        _sweep_into(fig, dem, title=title or "measured and simulated", theory=True)
        ax = fig.axes[0]
    else:
        ax = fig.add_subplot()
        ax.set_xscale("log")
        ax.set_xlabel("stroke X [mm]")
        ax.set_ylabel("reduced loss factor η* [-]")
        ax.grid(True, alpha=0.3)
        ax.set_title(title or campaign.attrs.get("title", "test campaign"), fontsize="medium")
    eta = campaign["eta_star"]
    err = campaign["eta_star_error"] if "eta_star_error" in campaign else None
    other = [d for d in eta.dims if d not in ("stroke", "seed")]
    groups = [({}, "measured")] if not other else [
        ({other[0]: v}, f"measured, {other[0]} = {float(v):g}") for v in campaign[other[0]].values]
    measured = []
    for k, (sel, label) in enumerate(groups):
        e = eta.sel(sel).transpose("stroke", "seed").values
        s = err.sel(sel).transpose("stroke", "seed").values if err is not None else np.full_like(e, np.nan)
        x = np.repeat(campaign["stroke"].values[:, None] * 1e3, e.shape[1], axis=1)
        ok = np.isfinite(e)
        measured.append(ax.errorbar(x[ok], e[ok], yerr=np.where(np.isfinite(s[ok]), s[ok], 0.0), fmt=("o", "s", "^", "D")[k % 4],
                    ms=5, color="black", mfc="white", capsize=2.5, lw=1.0, zorder=5, label=label))
    if not sweeps:
        stroke_axis(ax, np.asarray(campaign["stroke"].values, dtype=float))
        ax.set_ylim(bottom=0)
        ax.legend(fontsize="small")
    else:  # the figure's legend holds the DEM and the laws; the measured points get their own
        ax.legend(handles=measured, loc="upper left", fontsize="small")
    if target is not None:
        save(fig, target, dpi)
    return fig
