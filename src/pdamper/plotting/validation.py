"""Figures of the validation report that are not study sweeps: the vertical drive against the
bouncing law."""

from __future__ import annotations

import math

import numpy as np

from .figure import MM, check_path, save

__all__ = ["bouncing_figure"]


def bouncing_figure(rows, clearance: float, path=None, *, title: str = "", dpi: int = 150):
    """eta*(X) of a vertically driven bed (``rows`` of :func:`pdamper.studies.validate.vertical_rows`:
    the seed mean with the seeds' range) against the bouncing law at ``clearance`` h [m], X_opt = h/pi
    marked; the top axis is the intensity X Omega^2 / g."""
    from matplotlib.figure import Figure

    from ..theory.bouncing import ETA_MAX_BOUNCING, eta_bouncing, optimal_stroke_bouncing

    target = check_path(path)
    x = np.array([r["stroke_m"] for r in rows])
    m = np.array([r["eta_dem"] for r in rows])
    lo = np.array([r["eta_min"] for r in rows])
    hi = np.array([r["eta_max"] for r in rows])
    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    ax = fig.subplots()
    xs = np.linspace(x.min() * 0.95, x.max() * 1.02, 400)
    law = eta_bouncing(xs, clearance)
    ax.plot(xs * MM, law, color="k", lw=1.6, label="bouncing law (one block, perfectly inelastic)")
    xo = float(optimal_stroke_bouncing(clearance))
    ax.axvline(xo * MM, color="0.5", ls=":", lw=1.0, label=f"X_opt = h/π = {xo * MM:.2f} mm")
    ax.axhline(ETA_MAX_BOUNCING, color="0.75", ls="--", lw=0.8, label="η*_max = 4/π")
    ax.errorbar(x * MM, m, yerr=[m - lo, hi - m], fmt="o", color="C0", ms=5, capsize=3,
                label=f"DEM (seed mean, range over {max(r['seeds'] for r in rows)} seeds)")
    ax.set_xlabel("stroke X [mm]")
    ax.set_ylabel("η* [-]")
    ax.set_ylim(0, max(1.4, float(np.nanmax(hi)) * 1.1))
    ax.grid(True, color="0.9", lw=0.6)
    ax.legend(loc="upper right", fontsize=8.5)
    if rows and all(math.isfinite(r["intensity"]) for r in rows):
        ratio = rows[0]["intensity"] / rows[0]["stroke_m"]
        top = ax.secondary_xaxis("top", functions=(lambda v: v / MM * ratio, lambda g: g / ratio * MM))
        top.set_xlabel("intensity Γ = X Ω² / g [-]")
    ax.set_title(title or f"Vertical drive, h = {clearance * MM:.1f} mm", fontsize=10)
    if target is not None:
        save(fig, target, dpi)
    return fig
