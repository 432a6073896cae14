"""Figures of a structure under a load in time, with the damper and without it.

* :func:`transient_figure` -- (a) the load over time, (b) the damper point's displacement with
  the damper (DEM) and without (exact), (c) each dof's peak and RMS with and without, and for a
  random load (d) the FRF estimate H1 with and without the damper against the exact FRF at the
  dof that moves most.
* :func:`sweep_figure` -- stepped sines up and down (the steady amplitude of each step) over the
  fields' branches, the bare structure's closed form and its stepped sine, the bed as a solid mass.

The colours are :mod:`.structure`'s (with the damper red, without blue, the bed as a solid mass grey).
"""

from __future__ import annotations

import numpy as np

from .figure import MM, check_path, save
from .structure import _C_BARE, _C_DAMPED, _C_SOLID, _draw_fields, legend_entries

__all__ = ["transient_figure", "sweep_figure"]


def transient_figure(result, path=None, *, title: str | None = None, dpi: int = 150):
    """A :class:`pdamper.studies.transient.TransientResult` drawn (module docstring)."""
    from matplotlib.figure import Figure

    target = check_path(path)
    s = result.summary
    rnd = result.random
    fig = Figure(figsize=(9.0, 11.0 if rnd else 9.0), layout="constrained")
    axes = fig.subplots(4 if rnd else 3, 1, height_ratios=[0.6, 1.0, 0.9] + ([1.0] if rnd else []))
    ax_f, ax_x, ax_d = axes[:3]
    t = result.time
    ax_f.plot(t, result.load, color="black", lw=0.6)
    ax_f.set_ylabel("ground acceleration [m/s²]" if s["ground"] else "force [N]")
    ax_f.set_title(f"(a) {s['load']}", fontsize=9)
    ax_x.plot(t, result.damper_bare * MM, color=_C_BARE, lw=0.7, label="without damper (exact linear response)")
    ax_x.plot(t, result.damper * MM, color=_C_DAMPED, lw=0.7,
              label=f"with damper (DEM, {s['particles']} spheres, {100 * s['mass_ratio']:.2g} % of M)")
    ax_x.set_ylabel("damper point x [mm]" + (" (relative)" if s["relative_to_ground"] else ""))
    ax_x.set_xlabel("time t [s]")
    ax_x.set_title(f"(b) the damper point: peak ratio {s['damper_peak_reduction']:.3g}, RMS ratio "
                   f"{s['damper_rms_reduction']:.3g} (with / without)", fontsize=9)
    for ax in (ax_f, ax_x):
        ax.grid(True, alpha=0.3)
    ax_x.sharex(ax_f)
    ax_x.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.22), ncols=2, frameon=False)
    pos = np.arange(len(result.dofs))
    for key, style, what in (("peak", "o-", "peak"), ("rms", "s--", "RMS")):
        ax_d.plot(pos, np.asarray(s[f"{key}_bare_m"]) * MM, style, color=_C_BARE, ms=4, lw=1.0,
                  label=f"{what} without damper")
        ax_d.plot(pos, np.asarray(s[f"{key}_m"]) * MM, style, color=_C_DAMPED, ms=4, lw=1.0, label=f"{what} with damper")
    step = max(1, len(pos) // 20)
    ax_d.set_xticks(pos[::step], [str(d) for d in result.dofs][::step], fontsize=8)
    ax_d.set_xlabel("dof")
    ax_d.set_ylabel("displacement [mm]")
    ax_d.set_ylim(bottom=0)
    ax_d.grid(True, alpha=0.3)
    ax_d.set_title("(c) every dof" + (" (relative to the ground)" if s["relative_to_ground"] else ""), fontsize=9)
    ax_d.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncols=4, frameon=False)
    if rnd:
        ax_h = axes[3]
        k = int(np.argmax(s["peak_bare_m"]))
        from ..structure.linear import frequency_response

        fr = np.asarray(rnd["frequencies_hz"])
        fine = np.linspace(fr.min(), fr.max(), 2000)
        st = result.case.running_drive
        labels = st.dof_shapes()[0]
        ax_h.semilogy(fine, np.abs(frequency_response(st, fine)[:, labels.index(result.dofs[k])]), "-",
                      color="black", lw=1.0, label="without damper, exact")
        ax_h.semilogy(fr, np.asarray(rnd["h1_bare_abs"][k]), ".", color=_C_BARE, ms=3, label="without damper, H1")
        ax_h.semilogy(fr, np.asarray(rnd["h1_abs"][k]), ".-", color=_C_DAMPED, ms=3, lw=0.8, label="with damper, H1")
        unit = "m/(m/s²)" if s["ground"] else "m/N"
        ax_h.set_ylabel(f"|H| [{unit}]")
        ax_h.set_xlabel("frequency f [Hz]")
        ax_h.grid(True, alpha=0.3, which="both")
        ax_h.set_title(f"(d) FRF at dof {result.dofs[k]}: H1 = G_fx / G_ff (Welch, "
                       f"{rnd['frequency_resolution_hz']:.3g} Hz) against the exact FRF", fontsize=9)
        ax_h.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncols=3, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    if target is not None:
        save(fig, target, dpi)
    return fig


#: A sweep's marker and line style by direction.
_SWEEP_STYLE = {"up": ("^", "-", "sweep up"), "down": ("v", "--", "sweep down")}


def sweep_figure(sweeps, path=None, *, fields=None, title: str | None = None, dpi: int = 150):
    """Stepped sines (:class:`pdamper.studies.transient.SweepResult`, one or a list: up and down)
    against frequency: the steady amplitude of each step at the damper, joined in the sweep's
    order (a jump shows as a long step of the line), over the fields' stable branches (``fields``:
    a :class:`~pdamper.studies.structure.FieldsResponseResult`), the bare structure (closed form;
    its stepped sine: squares) and the bed as a solid mass."""
    from matplotlib.figure import Figure

    target = check_path(path)
    sweeps = list(sweeps) if isinstance(sweeps, (list, tuple)) else [sweeps]
    fig = Figure(figsize=(9.0, 6.5), layout="constrained")
    ax = fig.subplots(1, 1)
    first = sweeps[0]
    st = first.case.running_drive
    lo = min(float(r.frequencies.min()) for r in sweeps)
    hi = max(float(r.frequencies.max()) for r in sweeps)
    pad = 0.05 * max(hi - lo, 0.02 * hi)
    fine = np.linspace(lo - pad, hi + pad, 600)
    F0 = first.force_amplitude
    ax.plot(fine, st.steady_amplitude(fine, F0) * MM, "-", color=_C_BARE, lw=1.2,
            label="without damper (closed form, steady state)")
    ax.plot(fine, st.steady_amplitude(fine, F0, added_mass=first.case.bed_mass) * MM, "--", color=_C_SOLID,
            lw=1.0, label=f"bed as a solid mass (+{first.case.bed_mass * 1e3:.3g} g)")
    if fields is not None:
        _draw_fields(ax, fields, scale=MM)
    for r in sweeps:
        marker, ls, words = _SWEEP_STYLE.get(r.direction, ("o", "-", r.direction))
        ax.plot(r.frequencies, r.damped * MM, ls, marker=marker, color=_C_DAMPED, ms=6, lw=1.0,
                label=f"with damper, DEM {words} ({r.summary['cycles']:g} periods a step, the state carried)")
        ax.plot(r.frequencies, r.bare_sweep * MM, marker, mfc="none", color=_C_BARE, ms=6, ls="none",
                label=f"without damper, {words} (exact)")
    ax.set_xlabel("forcing frequency f [Hz]")
    ax.set_ylabel("steady amplitude at the damper |X| [mm]")
    ax.set_ylim(bottom=0)
    ax.grid(True, alpha=0.3)
    ax.set_title(f"stepped sine, F$_0$ = {F0:.3g} N: M = {st.mass:.3g} kg at the damper, f$_n$ = "
                 f"{st.natural_frequency:.4g} Hz, ζ = {100 * st.modal_damping_ratio:.3g} %", fontsize=10)
    fig.legend(*legend_entries(ax), loc="outside lower center", ncols=2, fontsize=7.5, frameon=False)
    if title:
        fig.suptitle(title, fontsize=11)
    if target is not None:
        save(fig, target, dpi)
    return fig
