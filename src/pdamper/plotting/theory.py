"""Figures of the closed-form laws: the η*(X) curves (paper Fig. 4 overlay) and Fig. 5.

* :func:`draw_theory_curves` draws the laws onto a given axes, so DEM or measured η* can be
  plotted on the same axes (strokes in **mm** on a log axis: plot your data as ``X * 1e3``).
* :func:`theory_figure` is a complete η*(X) figure for one clearance.
* :func:`rolling_phase_figure` is the paper's Fig. 5: positions (a) and velocities (b) of the
  rolling bed over Ωt.

Figures are built with :class:`matplotlib.figure.Figure` (no pyplot, no display needed) and
saved to the format the file name says (png, svg, pdf, ...).

Reference: "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities", Nonlinear Dynamics, Figs. 4 and 5.
"""

from __future__ import annotations

import math

import numpy as np

from .. import theory
from ..errors import InputError, shown
from .figure import MM as _MM, check_path, save

__all__ = ["draw_theory_curves", "theory_figure", "rolling_phase_figure"]



def draw_theory_curves(ax, clearance: float, strokes=None, *, kappa: float = 1.0,
                       bouncing: bool = True, color: str = "black", label: str = "",
                       mark_x_opt: bool = True):
    """Draw the η*(X) laws for clearance h onto ``ax`` (stroke axis in mm, log scale).

    The scattered law (8) is drawn below X_opt and the rolling law (14) from X_opt up, as the
    paper's "ana. formulas" in Fig. 4; the bouncing law (no rolling) dashed for comparison;
    X_opt (17) as a dotted vertical line.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        Axes to draw on. Its x axis is set to log scale and its data are strokes in mm.
    clearance : float
        Clearance h [m].
    strokes : array_like, optional
        Strokes [m] whose range the curves should span (e.g. the strokes of a DEM sweep).
        Default: X_opt/30 to 10 X_opt.
    kappa : float
        Scaling factor κ of the scattered law.
    bouncing : bool
        Also draw the bouncing collect-and-collide law.
    color : str
        Colour of the paper's laws (the bouncing law is drawn in grey).
    label : str
        Text appended to the legend entries, e.g. ``", h = 30 mm"`` when several clearances
        share one axes.
    mark_x_opt : bool
        Draw X_opt as a vertical line.

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``.
    """
    x_opt = theory.optimal_stroke(clearance)
    if strokes is None:
        lo, hi = x_opt / 30.0, 10.0 * x_opt
    else:
        s = np.asarray(strokes, dtype=float)
        if s.size == 0 or not np.all(np.isfinite(s) & (s > 0)):
            raise InputError("strokes: give a non-empty array of finite strokes > 0 in m")
        lo, hi = float(s.min()), float(s.max())
        if hi <= lo:
            lo, hi = lo / 2.0, hi * 2.0
    x = np.geomspace(lo, hi, 400)
    below, above = x[x < x_opt], x[x >= x_opt]
    if lo <= x_opt <= hi:  # both branches end exactly at X_opt, where the curve jumps
        below, above = np.append(below, x_opt), np.insert(above, 0, x_opt)
    if below.size:
        ax.plot(below * _MM, theory.eta_scattered(below, clearance, kappa), color=color,
                lw=1.5, ls="-.", label=f"scattered, eq. (8), κ = {kappa:g}{label}")
    if above.size:
        ax.plot(above * _MM, theory.eta_rolling(above, clearance), color=color, lw=1.8,
                label=f"rolling collect-and-collide, eq. (14){label}")
    if bouncing:
        xb = x[x >= theory.optimal_stroke_bouncing(clearance)]
        if xb.size:
            ax.plot(xb * _MM, theory.eta_bouncing(xb, clearance), color="0.55", lw=1.3,
                    ls="--", label=f"bouncing collect-and-collide (no rolling){label}")
    if mark_x_opt and lo <= x_opt <= hi:
        ax.axvline(x_opt * _MM, color=color, lw=1.0, ls=":",
                   label=f"$X_{{opt}}$ = {x_opt * _MM:.3g} mm, eq. (17){label}")
    ax.set_xscale("log")
    _format_stroke_axis(ax)
    ax.set_xlabel("stroke X [mm]")
    ax.set_ylabel("reduced loss factor η* [-]")
    return ax


def theory_figure(clearance: float, strokes=None, *, kappa: float = 1.0, bouncing: bool = True,
                  operating_stroke: float | None = None, liftoff_stroke: float | None = None,
                  tilt_stroke: float | None = None, title: str | None = None, path=None, figsize=(6.4, 4.2)):
    """The η*(X) figure of the laws for one clearance, like the paper's Fig. 4.

    Parameters
    ----------
    clearance : float
        Clearance h [m].
    strokes, kappa, bouncing
        As in :func:`draw_theory_curves`.
    operating_stroke : float, optional
        A stroke [m] to mark (e.g. the damper's operating point).
    liftoff_stroke : float, optional
        The stroke [m] above which A = X Omega^2 >= g: the strokes beyond it are shaded (the bed lifts
        off; the laws assume it stays on the floor).
    tilt_stroke : float, optional
        The tilt bound [m] (A = g tan(tilt)): the strokes below it are shaded (the tilt keeps the bed
        at the low wall, Sect. 6.2).
    title : str, optional
        Figure title; default names h and X_opt.
    path : str or path-like, optional
        Save the figure there; the extension picks the format (png, svg, pdf, ...).
    figsize : tuple of float
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    target = check_path(path)
    x_opt = theory.optimal_stroke(clearance)
    span = [x_opt / 30.0, 10.0 * x_opt] if strokes is None else list(np.ravel(strokes))
    for name, value in (("operating_stroke", operating_stroke), ("liftoff_stroke", liftoff_stroke),
                        ("tilt_stroke", tilt_stroke)):
        if value is not None and (not isinstance(value, (int, float)) or not 0 < value < math.inf):
            raise InputError(f"{name} = {shown(value)} is not allowed: give a finite stroke > 0 in m, e.g. 0.015 (15 mm)")
    if operating_stroke is not None:
        span.append(operating_stroke)
    fig = Figure(figsize=figsize, layout="constrained")
    ax = fig.add_subplot()
    draw_theory_curves(ax, clearance, span, kappa=kappa, bouncing=bouncing)
    if operating_stroke is not None:
        ax.axvline(operating_stroke * _MM, color="tab:red", lw=1.2,
                   label=f"operating stroke {operating_stroke * _MM:.3g} mm")
    ax.set_ylim(0.0, 1.1 * theory.ETA_MAX_BOUNCING if bouncing else 1.1)
    lo, hi = ax.get_xlim()
    if liftoff_stroke is not None and liftoff_stroke * _MM < hi:
        ax.axvspan(max(liftoff_stroke * _MM, lo), hi, color="0.6", alpha=0.25, hatch="//", lw=0,
                   label=f"lift-off: A $\\geq$ g above {liftoff_stroke * _MM:.3g} mm (laws do not hold)")
        ax.axvline(liftoff_stroke * _MM, color="0.35", lw=1.0, ls="-")
    if tilt_stroke is not None and tilt_stroke * _MM > lo:
        ax.axvspan(lo, min(tilt_stroke * _MM, hi), color="tab:orange", alpha=0.15, lw=0,
                   label=f"below the tilt bound {tilt_stroke * _MM:.3g} mm (A $\\leq$ g tan tilt)")
        ax.axvline(tilt_stroke * _MM, color="tab:orange", lw=1.0, ls="--")
    ax.set_xlim(lo, hi)
    ax.grid(True, which="major", alpha=0.3)
    ax.grid(True, which="minor", alpha=0.1)
    ax.legend(loc="upper left", fontsize="small", framealpha=0.9)
    ax.set_title(title if title is not None else
                 f"Analytical laws, clearance h = {clearance * _MM:.3g} mm "
                 f"($X_{{opt}}$ = {x_opt * _MM:.3g} mm)", fontsize="medium")
    if target is not None:
        save(fig, target)
    return fig


def rolling_phase_figure(stroke_over_clearance: float = 0.5, *, path=None, figsize=(6.4, 6.4)):
    """The paper's Fig. 5: the rolling bed between the walls over Ωt.

    (a) Bed position and the pushing (solid) and impacting (dashed) wall positions over X;
    (b) absolute bed velocity (10) and its velocity relative to the container (11) over V.
    The impacting wall depends on h/X; ``stroke_over_clearance`` X/h picks the configuration
    shown (the default 0.5 hits the wall before π; ``theory.X_OPT_OVER_H`` hits at π).

    Parameters
    ----------
    stroke_over_clearance : float
        X/h [-], at least ``X_OPT_OVER_H`` (below it the bed does not reach the far wall).
    path : str or path-like, optional
        Save the figure there; the extension picks the format.
    figsize : tuple of float
        Size in inches.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure

    ratio = stroke_over_clearance
    if not isinstance(ratio, (int, float)) or not theory.X_OPT_OVER_H <= ratio < math.inf:
        raise InputError(f"stroke_over_clearance = {shown(ratio)} is not allowed: the rolling bed "
                         "reaches the far wall by Ωt = π only for "
                         f"X/h >= X_opt/h = {theory.X_OPT_OVER_H:.5f}")
    target = check_path(path)
    theta_i = theory.impact_phase_rolling(ratio, 1.0)
    h_over_x = 1.0 / ratio
    th = np.linspace(0.0, math.pi, 400)
    th_bed = np.linspace(0.0, theta_i, 400)

    fig = Figure(figsize=figsize, layout="constrained")
    ax_a, ax_b = fig.subplots(2, 1, sharex=True)
    ax_a.plot(th, np.sin(th), color="black", lw=1.5, label="pushing wall $x_c/X$")
    ax_a.plot(th, np.sin(th) + h_over_x, color="black", lw=1.5, ls="--",
              label=f"impacting wall $(x_c + h)/X$, $h/X$ = {h_over_x:.3g}")
    ax_a.plot(th_bed, theory.bed_position(th_bed), color="tab:blue", lw=2.0,
              label="particle bed $x_p/X$")
    ax_a.plot([theta_i], [theory.bed_position(theta_i)], "o", color="tab:red", ms=5,
              label=f"impact, $Ωt_i$ = {theta_i / math.pi:.3f}π")
    ax_a.set_ylabel("position / X [-]")
    ax_a.set_title("(a) positions during the rolling phase", fontsize="medium", loc="left")

    ax_b.plot(th, np.cos(th), color="0.6", lw=1.2, label="container $\\dot{x}_c/V$")
    ax_b.plot(th, theory.bed_velocity(th), color="tab:blue", lw=2.0,
              label="particle bed $\\dot{x}_p/V$, eq. (10)")
    ax_b.plot(th, theory.relative_velocity(th), color="tab:orange", lw=2.0,
              label="relative $Δ\\dot{x}_{cp}/V$, eq. (11)")
    ax_b.set_ylabel("velocity / V [-]")
    ax_b.set_xlabel("drive phase Ωt [rad]")
    ax_b.set_title("(b) velocities", fontsize="medium", loc="left")

    for ax in (ax_a, ax_b):
        ax.axvline(theta_i, color="tab:red", lw=1.0, ls=":")
        ax.axhline(0.0, color="0.8", lw=0.8)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize="small", framealpha=0.9)
    ax_b.set_xlim(0.0, math.pi)
    ax_b.set_xticks([0, math.pi / 4, math.pi / 2, 3 * math.pi / 4, math.pi],
                    ["0", "π/4", "π/2", "3π/4", "π"])
    if target is not None:
        save(fig, target)
    return fig


def _format_stroke_axis(ax):
    from matplotlib.ticker import FuncFormatter, NullFormatter

    ax.xaxis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:g}"))
    ax.xaxis.set_minor_formatter(NullFormatter())
