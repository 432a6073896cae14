"""The damper's fields drawn: eta*(X) and m_eff / m_bed (X), one curve per frequency.

:func:`fields_figure` draws a :class:`pdamper.analysis.fields.DamperFields`: per frequency node
the mean over seeds at the nodes (marker by the motion mode most seeds are in, hollow where the
seeds disagree), the interpolation the fields give (:meth:`DamperFields.at`) drawn within each
segment of one mode family only, the seeds' min-max as a band, and each jump interval (a change
of mode family between two nodes) as a shaded span with a dotted line where the single-valued
interpolation jumps; X_opt of the theory where the fields carry it.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .figure import MM, check_path, save, stroke_axis
from .mode_looks import mode_rank, mode_style

__all__ = ["fields_figure"]

_PANELS = (("eta_star", "reduced loss factor η* [-]", False),
           ("effective_mass", "effective mass of the bed m_eff / m_bed [-]", True))


def fields_figure(fields, path=None, *, title=None, figsize=(12.0, 4.6), dpi: int = 150):
    """The figure of ``fields`` (module docstring); saved to ``path`` (.png, .svg, .pdf) if given."""
    from matplotlib import colormaps
    from matplotlib.figure import Figure
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    target = check_path(path)
    ds = fields.dataset
    bed = fields.bed_mass
    if not (math.isfinite(bed) and bed > 0):
        raise InputError("these fields carry no bed mass (attribute bed_mass_kg); m_eff / m_bed cannot be drawn")
    fig = Figure(figsize=figsize, layout="constrained")
    axes = fig.subplots(1, 2, sharex=True)
    freqs = fields.frequencies
    cmap = colormaps["viridis"]
    colours = [cmap(0.85 * k / max(len(freqs) - 1, 1)) for k in range(len(freqs))]
    seen_modes = set()
    for j, f in enumerate(freqs):
        colour = colours[j]
        eta = ds["eta_star"].values[:, j]
        ok = np.isfinite(eta)
        if not ok.any():
            continue
        x = fields.amplitudes[ok]
        modes = ds["mode"].values[ok, j]
        mixed = ds["mode_mixed"].values[ok, j]
        jumps = fields.jumps(f)
        # segments: node ranges between jumps
        edges = [x[0]] + [v for jmp in jumps for v in (jmp["below_m"], jmp["above_m"])] + [x[-1]]
        spans = list(zip(edges[0::2], edges[1::2]))
        for ax, (name, _, per_bed) in zip(axes, _PANELS):
            scale = 1.0 / bed if per_bed else 1.0
            lo = ds[f"{name}_min"].values[ok, j] * scale
            hi = ds[f"{name}_max"].values[ok, j] * scale
            mean = ds[name].values[ok, j] * scale
            for a, b in spans:
                inside = (x >= a) & (x <= b)
                ax.fill_between(x[inside] * MM, lo[inside], hi[inside], color=colour, alpha=0.18, lw=0)
                if b > a:
                    xs = np.geomspace(a, b, 60)
                    ys = [getattr(fields.at(v, f), _attr(name)) * scale for v in xs]
                    ax.plot(xs * MM, ys, color=colour, lw=1.6)
            for jmp in jumps:
                ax.axvspan(jmp["below_m"] * MM, jmp["above_m"] * MM, color=colour, alpha=0.08, lw=0)
                ax.axvline(math.sqrt(jmp["below_m"] * jmp["above_m"]) * MM, color=colour, ls=":", lw=1.2)
            for xi, yi, m, mx in zip(x, mean, modes, mixed):
                st = mode_style(m or "unknown")
                ax.plot([xi * MM], [yi], ls="none", marker=st["marker"], ms=6, mec=colour,
                        mfc="white" if mx else colour, zorder=4)
                seen_modes.add(str(m or "unknown"))
    x_opt = float(ds.attrs.get("x_opt_m", math.nan))
    for ax, (_, label, _) in zip(axes, _PANELS):
        ax.set_xscale("log")
        stroke_axis(ax, fields.amplitudes)
        ax.set_xlabel("container amplitude X [mm]")
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.set_ylim(bottom=min(0.0, ax.get_ylim()[0]))
        if math.isfinite(x_opt):
            ax.axvline(x_opt * MM, color="0.3", ls="--", lw=1.0)
    handles = [Line2D([], [], color=c, lw=1.6, label=f"f = {f:g} Hz") for c, f in zip(colours, freqs)]
    handles.append(Patch(color="0.5", alpha=0.3, label="min-max over seeds"))
    handles += [Line2D([], [], ls="none", marker=mode_style(m)["marker"], color="0.3", label=m)
                for m in sorted(seen_modes, key=mode_rank)]
    handles.append(Line2D([], [], ls="none", marker="o", mfc="white", mec="0.3", label="seeds disagree"))
    handles.append(Line2D([], [], color="0.4", ls=":", lw=1.2, label="mode change (jump)"))
    if math.isfinite(x_opt):
        handles.append(Line2D([], [], color="0.3", ls="--", lw=1.0, label=f"X_opt = {x_opt * MM:.3g} mm"))
    fig.legend(handles=handles, fontsize="small", loc="outside right upper")
    fig.suptitle(title or _title(ds), fontsize="medium")
    if target is not None:
        save(fig, target, dpi)
    return fig


def _attr(name: str) -> str:
    from ..analysis.fields import FIELDS

    return FIELDS[name][0]


def _title(ds) -> str:
    kind = "measured" if ds.attrs.get("source_kind") == "campaign" else "DEM"
    seeds = int(np.nanmax(ds["seeds"].values)) if ds["seeds"].size else 0
    bed = float(ds.attrs.get("bed_mass_kg", math.nan))
    return f"damper fields ({kind}, up to {seeds} seed(s) a point); bed {bed * 1e3:.4g} g"
