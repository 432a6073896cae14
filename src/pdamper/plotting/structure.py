"""Figures of the damper on a structure: free decay and frequency response, with and without it.

* :func:`decay_figure` -- (a) the structure's displacement over time with the damper and
  without (its envelope of extremes, and the closed form), (b) the equivalent damping ratio
  against amplitude from the logarithmic decrement, with and without the damper; each legend
  below its axes, over no curve.
* :func:`response_figure` -- steady amplitude against forcing frequency: with the damper
  (DEM), without it (closed form, and the bare structure run the same way) and with the bed as
  a rigid mass (closed form).

Built on :class:`matplotlib.figure.Figure` (no pyplot); saved to png, svg or pdf.
"""

from __future__ import annotations

import numpy as np

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
    """Frequency response: a DEM :class:`pdamper.studies.structure.ResponseResult` (``fields``: a
    :class:`~pdamper.studies.structure.FieldsResponseResult` drawn beside it) or a
    ``FieldsResponseResult`` alone (its stable branches, the unstable solutions, the jumps)."""
    from matplotlib.figure import Figure

    target = check_path(path)
    s = result.summary
    case = result.case
    st = case.drive
    f = result.frequencies
    lo, hi = float(f.min()), float(f.max())
    pad = 0.05 * max(hi - lo, 0.1 * hi)
    fine = np.linspace(max(lo - pad, 1e-3), hi + pad, 600)
    fig = Figure(figsize=(8.0, 5.2), layout="constrained")
    ax = fig.subplots()
    F0 = result.force_amplitude
    bare = st.steady_amplitude(fine, F0)
    solid = st.steady_amplitude(fine, F0, added_mass=case.bed_mass)
    ax.plot(fine, bare * _MM, color=_C_BARE, lw=1.3, label="without damper (closed form, steady state)")
    dem = s.get("method", "dem") == "dem"
    if dem:
        ax.plot(f, result.bare_run * _MM, "s", mfc="none", color=_C_BARE, ms=5,
                label=f"without damper, run as the DEM ({s['measure_cycles']} of {s['cycles']:g} cycles)")
    ax.plot(fine, solid * _MM, "--", color=_C_SOLID, lw=1.1, label=f"bed as a solid mass (+{case.bed_mass * 1e3:.3g} g)")
    if dem:
        steady = np.asarray(s.get("steady", [True] * f.size), dtype=bool)
        ax.plot(f, result.damped * _MM, "-", color=_C_DAMPED, lw=1.3)
        ax.plot(f[steady], result.damped[steady] * _MM, "o", color=_C_DAMPED, ms=5,
                label=f"with damper (DEM, {s['particles']} spheres, from {s.get('start', 'rest')})")
        if not steady.all():
            ax.plot(f[~steady], result.damped[~steady] * _MM, "o", mfc="white", color=_C_DAMPED, ms=5,
                    label="with damper (DEM), not steady (a transient)")
    for fr in ([result] if not dem else [] if fields is None else [fields]):
        _draw_fields(ax, fr)
    x_opt = s.get("x_opt_m")
    if x_opt:
        ax.axhline(x_opt * _MM, color="gray", ls=":", lw=1.0, label=f"$X_{{opt}}$ = {x_opt * _MM:.3g} mm")
    ax.set_ylim(bottom=0)
    ax.set_xlabel("forcing frequency f [Hz]")
    ax.set_ylabel("steady amplitude at the damper |X| [mm]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, framealpha=0.9)
    ax.set_title(f"frequency response, F$_0$ = {F0:.3g} N: M = {st.mass:.3g} kg, f$_n$ = {st.natural_frequency:.3g} Hz, "
                 f"ζ = {100 * st.modal_damping_ratio:.3g} %", fontsize=10)
    if title:
        fig.suptitle(title, fontsize=11)
    if target is not None:
        save(fig, target, dpi)
    return fig


_C_FIELDS = ("tab:purple", "tab:green", "tab:orange")
#: What a fields solution's mode family means on the figure.
_FAMILY_WORDS = {"other": "scattered or swaying bed", "collide": "rolling collect-and-collide bed",
                 "other/collide": "held at the mode change"}


def _draw_fields(ax, result):
    """The fields' stable branches (a line per mode family, or per rank where no family is known),
    the unstable solutions (crosses) and the jump frequencies (dotted verticals)."""
    groups: dict = {}
    unstable = []
    order = np.argsort(result.frequencies)
    for i, j in enumerate(order):
        f, sols = result.frequencies[j], result.solution.solutions[j]
        stable = [x for x in sols if x.stable]
        for rank, x in enumerate(stable):
            pts = groups.setdefault(x.family or f"branch {rank + 1}", [])
            if pts and pts[-1][2] != i - 1:  # the branch was absent in between: no line across
                pts.append((np.nan, np.nan, i - 1))
            pts.append((f, x.damper_amplitude_m, i))
        unstable += [(f, x.damper_amplitude_m) for x in sols if not x.stable]
    for k, (name, pts) in enumerate(sorted(groups.items())):
        p = np.array(pts)
        ax.plot(p[:, 0], p[:, 1] * _MM, ".-", color=_C_FIELDS[k % len(_C_FIELDS)], lw=1.6, ms=4,
                label=f"with damper, from the fields ({_FAMILY_WORDS.get(name, name)})")
    if unstable:
        p = np.array(unstable)
        ax.plot(p[:, 0], p[:, 1] * _MM, "x", color="black", ms=5, label="from the fields, unstable (slope criterion)")
    for j, fj in enumerate(result.summary.get("jump_frequencies_hz", [])):
        ax.axvline(fj, color="black", ls=":", lw=1.0, label="jump (a branch ends)" if j == 0 else None)
