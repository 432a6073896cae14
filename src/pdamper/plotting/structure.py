"""Figures of the damper on a structure: free decay and frequency response, with and without it.

* :func:`decay_figure` -- (a) the structure's displacement over time with the damper and
  without (its envelope of extremes, and the closed form), (b) the equivalent damping ratio
  against amplitude from the logarithmic decrement, with and without the damper; each legend
  below its axes, over no curve.
* :func:`response_figure` -- against forcing frequency, (a) the steady amplitude, (b) the
  amplitude over the force (responses to several forces overlaid) and (c) the phase against the
  force: with the damper (DEM points, joined only along a branch; the fields' branches, each
  motion family in its own colour in every figure), without it (closed form, and the bare
  structure run the same way) and with the bed as a rigid mass (closed form); the legend below
  the panels.

Built on :class:`matplotlib.figure.Figure` (no pyplot); saved to png, svg or pdf.
"""

from __future__ import annotations

import numpy as np

from ..analysis.decay import JUMP  # a jump between two DEM neighbours (the tables' too)
from .figure import MM as _MM, check_path, save

__all__ = ["decay_figure", "response_figure"]

_C_DAMPED = "tab:red"
_C_BARE = "tab:blue"
_C_SOLID = "tab:gray"


def decay_figure(result, path=None, *, title: str | None = None, dpi: int = 150):
    """Free decay with and without the damper (a :class:`pdamper.studies.structure.DecayResult`)."""
    from matplotlib.figure import Figure

    target = check_path(path)
    s = result.summary
    fig = Figure(figsize=(8.5, 8.0), layout="constrained")
    ax_t, ax_z = fig.subplots(2, 1, height_ratios=[1.1, 1.0])
    t = result.time
    ax_t.plot(t, result.bare * _MM, color=_C_BARE, lw=0.6, alpha=0.45)
    ax_t.plot(t, result.damped * _MM, color=_C_DAMPED, lw=0.6, alpha=0.6)
    te, ae = result.envelope_bare
    ax_t.plot(te, ae * _MM, "o-", color=_C_BARE, ms=2.5, lw=1.2, label="without damper (envelope)")
    ax_t.plot(t, _envelope_closed_form(result) * _MM, "--", color="black", lw=0.9,
              label=r"without damper, closed form $X_0 e^{-\zeta\omega t}$")
    te, ae = result.envelope_damped
    ax_t.plot(te, ae * _MM, "o-", color=_C_DAMPED, ms=2.5, lw=1.2,
              label=f"with damper, {s['particles']} spheres ({100 * s['mass_ratio']:.2g} % of M)")
    if getattr(result, "envelope_fields", None) is not None:
        tf, af = result.envelope_fields
        ax_t.plot(tf, af * _MM, "-", color="tab:purple", lw=1.6,
                  label="with damper, from the fields (averaging: energy balance per cycle)")
    ax_t.set_xlabel("time t [s]")
    ax_t.set_ylabel("structure displacement $x_s$ [mm]")
    ax_t.grid(True, alpha=0.3)
    _legend_below(ax_t)
    ax_t.set_title(f"(a) free decay from {s['initial_displacement_m'] * _MM:.3g} mm: M = {s['mass_kg']:.3g} kg, "
                   f"f$_n$ = {s['natural_frequency_hz']:.3g} Hz, ζ = {100 * s['damping_ratio']:.3g} %", fontsize=10)

    _, a, z = result.zeta_bare
    ax_z.plot(a * _MM, 100 * z, "s", color=_C_BARE, ms=3, label="without damper")
    _, a, z = result.zeta_damped
    ax_z.plot(a * _MM, 100 * z, "o-", color=_C_DAMPED, ms=3, lw=0.8, label="with damper")
    ax_z.axhline(100 * s["damping_ratio"], color="black", ls="--", lw=0.9, label="structure's own ζ")
    x_opt = s.get("x_opt_m")
    if x_opt:
        ax_z.axvline(x_opt * _MM, color="gray", ls=":", lw=1.0,
                     label=f"$X_{{opt}}$ = {x_opt * _MM:.3g} mm (rolling law, eq. 17)")
    ax_z.set_xlabel("amplitude [mm] (geometric mean of extremes one period apart)")
    ax_z.set_ylabel("equivalent damping ratio ζ$_{eq}$ [%]")
    ax_z.set_ylim(bottom=0)
    ax_z.grid(True, alpha=0.3)
    _legend_below(ax_z)
    ax_z.set_title("(b) damping from the logarithmic decrement, against amplitude", fontsize=10)
    if title:
        fig.suptitle(title, fontsize=11)
    if target is not None:
        save(fig, target, dpi)
    return fig


def _legend_below(ax):
    """The legend under the axes' x label, in two columns: over no curve (the decay's last peaks
    and the damping curve fill every corner of the axes)."""
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncols=2, frameon=False,
              columnspacing=1.8)


def _envelope_closed_form(result):
    s = result.summary
    w = 2 * np.pi * s["natural_frequency_hz"]
    return abs(s["initial_displacement_m"]) * np.exp(-s["damping_ratio"] * w * result.time)


def response_figure(result, path=None, *, fields=None, title: str | None = None, dpi: int = 150):
    """Frequency response: (a) the steady amplitude at the damper |X| [mm], (b) |X| / F0 [mm/N]
    (where responses to several forces overlay: a linear structure's curves coincide, the damper's
    do not) and (c) the phase of X against the force [deg]; with the damper (DEM points, or the
    fields' branches), without it (closed form; the bare structure run as the DEM) and with the bed
    as a rigid mass (closed form). The legend sits below the panels, over no data.

    ``result``: a DEM :class:`pdamper.studies.structure.ResponseResult` (``fields``: a
    :class:`~pdamper.studies.structure.FieldsResponseResult` drawn beside it) or a
    ``FieldsResponseResult`` alone, or a list of them (one per force, ``fields`` a list as long or
    None). DEM points are joined only between neighbours on one branch: not across a jump of the
    fields (when given) nor where the amplitude changes by more than a quarter (a jump seen by the
    DEM itself). A fields branch keeps its colour in every figure (by its motion family).
    """
    from matplotlib.figure import Figure

    target = check_path(path)
    results = list(result) if isinstance(result, (list, tuple)) else [result]
    extra = list(fields) if isinstance(fields, (list, tuple)) else [fields] * len(results)
    several = len(results) > 1
    fig = Figure(figsize=(9.0, 10.0), layout="constrained")
    ax_a, ax_n, ax_p = fig.subplots(3, 1, sharex=True, height_ratios=[1.2, 1.0, 0.8])
    lo = min(float(r.frequencies.min()) for r in results)
    hi = max(float(r.frequencies.max()) for r in results)
    pad = 0.05 * max(hi - lo, 0.1 * hi)
    fine = np.linspace(max(lo - pad, 1e-3), hi + pad, 600)
    for i, (res, fr) in enumerate(zip(results, extra)):
        _draw_response(ax_a, ax_n, ax_p, res, fr, fine, i, several)
    first = results[0]
    x_opt = first.summary.get("x_opt_m")
    if x_opt:
        ax_a.axhline(x_opt * _MM, color="gray", ls=":", lw=1.0, label=f"$X_{{opt}}$ = {x_opt * _MM:.3g} mm")
    ax_a.set_ylim(bottom=0)
    ax_n.set_ylim(bottom=0)
    ax_p.set_ylim(-185, 5)
    ax_p.set_yticks([-180, -135, -90, -45, 0])
    ax_a.set_ylabel("steady amplitude at the damper |X| [mm]")
    ax_n.set_ylabel("|X| / F$_0$ [mm/N]")
    ax_p.set_ylabel("phase of X against F [deg]")
    ax_p.set_xlabel("forcing frequency f [Hz]")
    for ax, tag in ((ax_a, "(a)"), (ax_n, "(b)"), (ax_p, "(c)")):
        ax.grid(True, alpha=0.3)
        ax.text(0.01, 0.97, tag, transform=ax.transAxes, va="top", fontsize=9)
    st = first.case.running_drive
    forces = ", ".join(f"{r.force_amplitude:.3g}" for r in results)
    ax_a.set_title(f"frequency response, F$_0$ = {forces} N: M = {st.mass:.3g} kg at the damper, f$_n$ = "
                   f"{st.natural_frequency:.4g} Hz, ζ = {100 * st.modal_damping_ratio:.3g} %", fontsize=10)
    handles, labels = legend_entries(ax_a, ax_n, ax_p)
    if several:  # a line style per force
        from matplotlib.lines import Line2D

        for i, r in enumerate(results):
            handles.append(Line2D([], [], color="black", ls=_DASHES[i % len(_DASHES)], lw=1.2))
            labels.append(f"F$_0$ = {r.force_amplitude:.3g} N (its line style)")
    fig.legend(handles, labels, loc="outside lower center", ncols=2, fontsize=7.5, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    if target is not None:
        save(fig, target, dpi)
    return fig


def legend_entries(*axes) -> tuple[list, list]:
    """(handles, labels) of the axes' curves, each label once (the first curve that has it)."""
    handles, labels = [], []
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    return handles, labels


#: A response's line style per force (the colours say what a curve is: bare, solid, DEM, a fields branch).
_DASHES = ("-", "--", "-.", ":")


def _draw_response(ax_a, ax_n, ax_p, result, fields, fine, i, several):
    """One force's curves on the three panels (``i``: its place among the forces)."""
    s = result.summary
    case = result.case
    st = case.running_drive
    F0 = result.force_amplitude
    f = result.frequencies
    dash = _DASHES[i % len(_DASHES)] if several else "-"
    solid_dash = dash if several else "--"
    bare = st.steady_phasor(fine, F0)
    solid = st.steady_phasor(fine, F0, added_mass=case.bed_mass)
    panels = ((ax_a, _MM, np.abs), (ax_n, _MM / F0, np.abs), (ax_p, 1.0, lambda z: np.degrees(np.angle(z))))
    for ax, scale, of in panels:
        ax.plot(fine, of(bare) * scale, dash, color=_C_BARE, lw=1.2, label="without damper (closed form, steady state)")
        ax.plot(fine, of(solid) * scale, solid_dash, color=_C_SOLID, lw=1.0,
                label=f"bed as a solid mass (+{case.bed_mass * 1e3:.3g} g)")
    if s.get("method", "dem") == "dem":
        _draw_dem(ax_a, ax_n, ax_p, result, fields, dash)
        if fields is not None:
            _draw_fields(ax_a, fields, scale=_MM, phase_ax=ax_p, dash=dash)
            _draw_fields(ax_n, fields, scale=_MM / F0, dash=dash)
    else:
        _draw_fields(ax_a, result, scale=_MM, phase_ax=ax_p, dash=dash)
        _draw_fields(ax_n, result, scale=_MM / F0, dash=dash)


def _segments(f, x, jumps):
    """Index runs of neighbours to join: not across a jump frequency, not across a change of more
    than :data:`JUMP` in amplitude."""
    runs, cur = [], [0]
    for k in range(1, len(f)):
        a, b = x[k - 1], x[k]
        crossing = any(f[k - 1] < fj < f[k] for fj in jumps)
        big = not (np.isfinite(a) and np.isfinite(b)) or abs(b - a) > JUMP * max(abs(a), abs(b))
        if crossing or big:
            runs.append(cur)
            cur = [k]
        else:
            cur.append(k)
    runs.append(cur)
    return runs


def _draw_dem(ax_a, ax_n, ax_p, result, fields, dash):
    s = result.summary
    f = result.frequencies
    F0 = result.force_amplitude
    colour = _C_DAMPED
    order = np.argsort(f)
    f, damped = f[order], np.asarray(result.damped, dtype=float)[order]
    steady = np.asarray(s.get("steady", [True] * f.size), dtype=bool)[order]
    phase = np.asarray(s.get("phase_damped_rad", [np.nan] * f.size), dtype=float)[order]
    jumps = fields.summary.get("jump_frequencies_hz", []) if fields is not None else []
    for ax, scale in ((ax_a, _MM), (ax_n, _MM / F0)):
        for run in _segments(f, damped, jumps):
            if len(run) > 1:
                ax.plot(f[run], damped[run] * scale, dash, color=colour, lw=1.2)
        if steady.any():
            ax.plot(f[steady], damped[steady] * scale, "o", color=colour, ms=5,
                    label=f"with damper (DEM, {s['particles']} spheres, from {s.get('start', 'rest')})")
        if not steady.all():
            ax.plot(f[~steady], damped[~steady] * scale, "o", mfc="white", color=colour, ms=5,
                    label="with damper (DEM), not steady (a transient)")
    if getattr(result, "bare_run", None) is not None:
        bare_run = np.asarray(result.bare_run, dtype=float)[order]
        ax_a.plot(f, bare_run * _MM, "s", mfc="none", color=_C_BARE, ms=5,
                  label=f"without damper, run as the DEM ({s['measure_cycles']} of {s['cycles']:g} cycles)")
    if np.any(np.isfinite(phase)):
        ax_p.plot(f[steady], np.degrees(phase[steady]), "o", color=colour, ms=5)
        if not steady.all():
            ax_p.plot(f[~steady], np.degrees(phase[~steady]), "o", mfc="white", color=colour, ms=5)


#: The colour of a fields branch by its motion family: the same in every figure.
_C_FAMILY = {"other": "tab:purple", "collide": "tab:green", "other/collide": "tab:orange"}
#: Branches without a known family, by rank.
_C_RANK = ("tab:gray", "tab:olive", "tab:cyan")
#: What a fields solution's mode family means on the figure.
_FAMILY_WORDS = {"other": "scattered or swaying bed", "collide": "rolling collect-and-collide bed",
                 "other/collide": "held at the mode change"}


def _draw_fields(ax, result, *, scale=_MM, phase_ax=None, dash="-"):
    """The fields' stable branches (a line per mode family, its colour fixed by the family, or per
    rank where no family is known), the unstable solutions (crosses) and the jump frequencies
    (dotted verticals); with ``phase_ax`` the stable branches' phases there too."""
    groups: dict = {}
    unstable = []
    order = np.argsort(result.frequencies)
    for i, j in enumerate(order):
        f, sols = result.frequencies[j], result.solution.solutions[j]
        stable = [x for x in sols if x.stable]
        for rank, x in enumerate(stable):
            pts = groups.setdefault(x.family or f"branch {rank + 1}", [])
            if pts and pts[-1][3] != i - 1:  # the branch was absent in between: no line across
                pts.append((np.nan, np.nan, np.nan, i - 1))
            pts.append((f, x.damper_amplitude_m, np.angle(x.damper_phasor), i))
        unstable += [(f, x.damper_amplitude_m) for x in sols if not x.stable]
    ranks = iter(_C_RANK)
    for name, pts in sorted(groups.items()):
        p = np.array(pts, dtype=float)
        colour = _C_FAMILY.get(name) or next(ranks, "black")
        label = f"with damper, from the fields ({_FAMILY_WORDS.get(name, name)})"
        ax.plot(p[:, 0], p[:, 1] * scale, dash, marker=".", color=colour, lw=1.6, ms=4, label=label)
        if phase_ax is not None:
            phase_ax.plot(p[:, 0], np.degrees(p[:, 2]), dash, marker=".", color=colour, lw=1.6, ms=4, label=label)
    if unstable:
        p = np.array(unstable)
        ax.plot(p[:, 0], p[:, 1] * scale, "x", color="black", ms=5, label="from the fields, unstable (slope criterion)")
    for j, fj in enumerate(result.summary.get("jump_frequencies_hz", [])):
        ax.axvline(fj, color="black", ls=":", lw=1.0, label="jump (a branch ends)" if j == 0 else None)
