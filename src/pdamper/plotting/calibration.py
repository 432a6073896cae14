"""The figure of a calibration (:mod:`pdamper.studies.calibrate`): (a) measured eta*(X) with its error
bars beside the DEM at the best parameters (the surrogate) and at the evaluated point nearest them;
(b) the misfit of every evaluated point against the fitted parameter, with the smooth misfit of the
surrogate and the best value with its uncertainty (two parameters: the points coloured by misfit)."""

from __future__ import annotations

import numpy as np

from ..analysis.surrogate import poly_basis
from .figure import check_path, save, stroke_axis

__all__ = ["calibration_figure"]


def calibration_figure(cal, path=None, *, title=None, dpi: int = 150):
    from matplotlib.figure import Figure

    target = check_path(path)
    keys = list(cal.best)
    fig = Figure(figsize=(11.0, 4.6), layout="constrained")
    ax, bx = fig.subplots(1, 2)
    x = np.asarray(cal.strokes_m) * 1e3
    ax.errorbar(x, cal.measured, yerr=cal.measured_error, fmt="o", color="black", mfc="white", capsize=3,
                label="measured", zorder=5)
    ax.plot(x, cal.dem_at_best, "s--", color="tab:blue", ms=4,
            label="DEM, evaluated point nearest the best (mean over seeds)")
    sur = cal.surrogate
    if sur:
        lo, hi = np.asarray(sur["low_u"]), np.asarray(sur["high_u"])
        u = np.array([np.log10(cal.best[k]) if lg else cal.best[k] for k, lg in zip(keys, sur["log"])])
        z = (u - lo) / (hi - lo)
        pred = poly_basis(z[None, :]) @ np.asarray(sur["coefficients"])
        ax.plot(x, pred[0], "-", color="tab:red", label="DEM surrogate at the best value")
    ax.set_xscale("log")
    stroke_axis(ax, np.asarray(cal.strokes_m, dtype=float))
    ax.set_xlabel("stroke X [mm]")
    ax.set_ylabel("reduced loss factor η* [-]")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small")
    best_txt = ", ".join(f"{k} = {cal.best[k]:.4g} ± {cal.uncertainty[k]:.2g}" for k in keys)
    ax.set_title(f"(a) {best_txt}", fontsize="medium")
    pts = cal.points
    if len(keys) == 1:
        k = keys[0]
        v = np.array([p[k] for p in pts])
        m = np.array([p["misfit"] for p in pts])
        bx.plot(v, m, "o", color="tab:blue", ms=4, label="evaluated (DEM mean over seeds)")
        if sur:
            zz = np.linspace(0, 1, 400)
            pred = poly_basis(zz[:, None]) @ np.asarray(sur["coefficients"])
            meas, s2 = np.asarray(cal.measured), np.asarray(cal.measured_error) ** 2 + np.asarray(sur["scatter"]) ** 2
            chi = ((pred - meas) ** 2 / s2).sum(axis=1)
            uu = lo[0] + zz * (hi[0] - lo[0])
            vv = 10 ** uu if sur["log"][0] else uu
            bx.plot(vv, chi, "-", color="tab:red", label="misfit of the surrogate")
        bx.axvline(cal.best[k], color="black", lw=1)
        bx.axvspan(cal.best[k] - cal.uncertainty[k], cal.best[k] + cal.uncertainty[k], color="0.8", alpha=0.6,
                   label="best ± uncertainty")
        if sur and sur["log"][0]:
            bx.set_xscale("log")
        bx.set_yscale("log")
        bx.set_xlabel(k)
        bx.set_ylabel("misfit χ²")
        bx.legend(fontsize="small")
    else:
        v0, v1 = (np.array([p[k] for p in pts]) for k in keys[:2])
        m = np.array([p["misfit"] for p in pts])
        sc = bx.scatter(v0, v1, c=np.log10(np.maximum(m, 1e-3)), cmap="viridis_r")
        fig.colorbar(sc, ax=bx, label="log10 misfit χ²")
        bx.errorbar([cal.best[keys[0]]], [cal.best[keys[1]]], xerr=[cal.uncertainty[keys[0]]],
                    yerr=[cal.uncertainty[keys[1]]], fmt="*", color="tab:red", ms=12, capsize=3)
        bx.set_xlabel(keys[0])
        bx.set_ylabel(keys[1])
    bx.grid(True, alpha=0.3)
    bx.set_title("(b) misfit of the evaluated points", fontsize="medium")
    if title:
        fig.suptitle(title)
    if target is not None:
        save(fig, target, dpi)
    return fig
