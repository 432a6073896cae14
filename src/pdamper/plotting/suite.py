"""The figure of a suite of records (:func:`pdamper.studies.suite.run_suite`): the records'
response spectra, and the damper point's peaks and ratios record by record.

* (a) under ground accelerations: each record's 5 %-damped pseudo-acceleration spectrum as scaled
  (grey), the suite's mean (black), the structure's first period (dashed) and each record's value
  there (dots);
* (b) the damper point's peak with and without the damper, record by record, with their means;
* (c) the ratios (with / without) of the peak and the RMS, record by record, with the ratio of
  the means (the design value) and the 84th percentile of the records' ratios.

The colours are :mod:`.structure`'s (with the damper red, without blue).
"""

from __future__ import annotations

import numpy as np

from .figure import MM, check_path, save
from .structure import _C_BARE, _C_DAMPED

__all__ = ["suite_figure"]

_G = 9.80665


def suite_figure(result, path=None, *, title: str | None = None, dpi: int = 150):
    """A :class:`pdamper.studies.suite.SuiteResult` drawn (module docstring)."""
    from matplotlib.figure import Figure

    target = check_path(path)
    s = result.summary
    sp = result.spectra
    panels = 3 if sp is not None else 2
    fig = Figure(figsize=(9.0, 3.3 * panels + 0.6), layout="constrained")
    axes = fig.subplots(panels, 1)
    letters = iter("abc")
    if sp is not None:
        ax = axes[0]
        T = np.asarray(sp["periods_s"])
        for k, psa in enumerate(sp["psa_m_s2"]):
            ax.loglog(T, np.asarray(psa) / _G, color="0.6", lw=0.8, label="each record (as scaled)" if k == 0 else None)
        ax.loglog(T, np.asarray(sp["mean_psa_m_s2"]) / _G, color="black", lw=1.6, label="mean of the records")
        t1 = sp["first_period_s"]
        ax.axvline(t1, color="black", ls="--", lw=0.8, label=f"structure's first period {t1:.3g} s")
        ax.plot([t1] * len(sp["psa_at_first_period_m_s2"]), np.asarray(sp["psa_at_first_period_m_s2"]) / _G, "o",
                color=_C_DAMPED, ms=4, label="each record at the first period")
        ax.set_xlabel("period T [s]")
        ax.set_ylabel("pseudo-acceleration PSA [g]")
        ax.grid(True, which="both", alpha=0.3)
        ax.set_title(f"({next(letters)}) {100 * sp['damping']:g} %-damped response spectra of the {s['records']} records",
                     fontsize=9)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncols=2, frameon=False)
    names = s["record_names"]
    pos = np.arange(len(names))
    runs = s["runs"]
    ax_p, ax_r = axes[-2], axes[-1]
    w = 0.38
    bare = np.array([r["damper_peak_bare_m"] for r in runs]) * MM
    damped = np.array([r["damper_peak_m"] for r in runs]) * MM
    ax_p.bar(pos - w / 2, bare, w, color=_C_BARE, label="without damper (exact)")
    ax_p.bar(pos + w / 2, damped, w, color=_C_DAMPED, label="with damper (DEM)")
    ax_p.axhline(bare.mean(), color=_C_BARE, ls="--", lw=1.0, label=f"mean without {bare.mean():.3g} mm")
    ax_p.axhline(damped.mean(), color=_C_DAMPED, ls="--", lw=1.0, label=f"mean with {damped.mean():.3g} mm")
    ax_p.set_ylabel("damper point peak [mm]" + (" (relative)" if s["relative_to_ground"] else ""))
    ax_p.set_title(f"({next(letters)}) the damper point's peak, record by record", fontsize=9)
    stats = s["statistics"]
    for key, style, what in (("damper_peak_reduction", "o", "peak"), ("damper_rms_reduction", "s", "RMS")):
        ratios = [r[key] for r in runs]
        ax_r.plot(pos, ratios, style, color=_C_DAMPED if what == "peak" else "black", ms=5, label=f"{what} ratio")
    ax_r.axhline(s["damper_peak_ratio"], color=_C_DAMPED, ls="--", lw=1.0,
                 label=f"peak: ratio of the means {s['damper_peak_ratio']:.3g}")
    ax_r.axhline(s["damper_rms_ratio"], color="black", ls="--", lw=1.0,
                 label=f"RMS: ratio of the means {s['damper_rms_ratio']:.3g}")
    p84 = stats["damper_peak_reduction"]["p84"]
    if p84 is not None:
        ax_r.axhline(p84, color=_C_DAMPED, ls=":", lw=1.0, label=f"peak ratio, 84th percentile {p84:.3g}")
    ax_r.set_ylabel("with / without the damper")
    ax_r.ticklabel_format(axis="y", useOffset=False)
    ax_r.set_title(f"({next(letters)}) the ratios at the damper point (< 1: reduced)", fontsize=9)
    for ax in (ax_p, ax_r):
        ax.set_xticks(pos, names, fontsize=8, rotation=20 if len(names) > 4 else 0)
        ax.grid(True, axis="y", alpha=0.3)
        ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.22), ncols=2, frameon=False)
    if title:
        fig.suptitle(title, fontsize=10)
    if target is not None:
        save(fig, target, dpi=dpi)
    return fig
