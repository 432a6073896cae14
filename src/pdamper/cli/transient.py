"""``pdamper transient``: the damper on a structure under a load in time (``[load]``), with and
without it, at every dof."""

from __future__ import annotations

import math
import sys

import click

from ..errors import InputError
from .codes import codes_lines, limit_option, mode_lines, settings_line, tmd_lines
from .common import echo_json, fraction_bar, main, user_errors
from .ensemble import uncertain_options
from .run import parse_set

__all__ = ["transient_command"]


@main.command("transient")
@click.argument("config", metavar="CONFIG.toml")
@click.option("--dofs", help="The dofs to report: labels and ranges START:STOP[:STEP] (0-based, STOP excluded), "
              "e.g. 0,18,38 or 0:40:2 (default: every dof; modes given as data: damper,force,response).")
@click.option("--seed", type=click.IntRange(min=0), help="Seed of the initial jitter/scatter.")
@click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE",
              help="Override any config key, e.g. --set load.scale=2 (repeatable).")
@click.option("--plot", type=click.Path(dir_okay=False), help="Write the figure (png, svg or pdf).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units).")
@limit_option
@uncertain_options(ratios=True)
@user_errors
def transient_command(config, dofs, seed, settings, plot, as_json, limits, ensemble):
    """The structure of CONFIG.toml under its [load] in time, with and without the damper.

    Runs the coupled DEM for the load's duration (a force history, a ground acceleration, a
    random load, a stepped sine; without a [load], the [structure]'s harmonic force from rest
    for [run] cycles periods, as in a case written by pdamper design --write-case) and the structure without the bed by its exact linear response
    (modal superposition, piecewise-exact in the load); prints each dof's peak and RMS with and
    without the damper and their ratios (damped / bare). Under a ground acceleration the
    displacements are relative to the ground. For a random load also the response PSD and the
    FRF estimate H1 (Welch) against the exact FRF (JSON ``random``). Also what codes ask for:
    every dof's absolute floor acceleration and, with [structure] storey_heights, every storey's
    drift ratio (peak, RMS, residual), each against --limit (JSON ``codes``), and the damper as
    an equivalent TMD mode by mode (JSON ``tmd_equivalent``). Nothing is written when a run fails.

    With --uncertain U.toml --samples N: the transient at N samples of the unknowns (docs/ensembles.md):
    the peak and RMS ratios' percentiles per dof, the share meeting --target-peak-ratio and
    --target-rms-ratio with its interval, which unknowns matter; --plot draws the ratio's CDF.

    Examples: pdamper transient examples/frame_quake.toml --plot quake.png;
    pdamper transient examples/mast_hammer.toml --dofs 0:40:2 --json
    """
    from ..analysis.codes import parse_limits
    from ..config import load_case
    from ..plotting.figure import check_path
    from ..studies.transient import parse_dofs, run_transient

    wanted_limits = parse_limits(limits)
    overrides = parse_set(settings)
    if seed is not None:
        overrides["initial.seed"] = seed
    case = load_case(config, overrides)
    wanted = parse_dofs(dofs)
    if ensemble is not None:
        from .ensemble import run_uncertain

        if limits:
            raise InputError("--limit judges one transient; an ensemble reports its ratios' percentiles and shares: "
                             "leave --limit out or --uncertain out")
        return run_uncertain(ensemble, case, config, study="transient", as_json=as_json, plot=plot, dofs=wanted)
    check_path(plot)
    from ..studies.suite import is_suite

    if is_suite(case):  # [load] files = [...]: one transient a record
        from .suite import transient_suite

        return transient_suite(case, config, wanted, plot, as_json, limits=wanted_limits)
    from ..plotting.transient import transient_figure

    def printed(s, config):
        lines = transient_lines(s, config)
        lines[1:1] = settings_line(settings) + mode_lines(s["mode_table"])
        at = next(k for k, line in enumerate(lines) if line.startswith("  energy balance error"))
        lines[at:at] = codes_lines(s["codes"]) + tmd_lines(s["tmd_equivalent"])
        return lines

    shown_run("pdamper transient", case.duration,
              lambda progress: run_transient(case, dofs=wanted, progress=progress, limits=wanted_limits),
              transient_figure, printed, config, plot, as_json)


def shown_run(desc: str, total: float, run, figure, lines, config, plot, as_json) -> None:
    """``run(progress)`` under a bar of ``total`` seconds (on a terminal, not with ``as_json``), its
    ``figure(result, plot)`` written, its summary printed as JSON or as ``lines(summary, config)``."""
    with fraction_bar(desc, round(total, 3), "s", not as_json and sys.stderr.isatty()) as progress:
        res = run(progress)
    if plot:
        figure(res, plot)
    s = dict(res.summary, config=str(config), plot=plot)
    if as_json:
        echo_json(s)
        return
    click.echo("\n".join(lines(s, config)))


def transient_lines(s: dict, config) -> list[str]:
    """The table of a transient run (``s``: its summary)."""
    unit = "m/s^2" if s["ground"] else "N"
    ratio = lambda r: "n/a" if r is None or not math.isfinite(r) else f"{r:.3g}"  # noqa: E731
    lines = [f"pdamper transient {config}",
             f"  load                  {s['load']}",
             f"                        peak {s['load_peak']:.4g} {unit}, rms {s['load_rms']:.4g} {unit}",
             f"  damper                {s['particles']} spheres, {1e3 * s['bed_mass_kg']:.4g} g "
             f"({100 * s['mass_ratio']:.3g} % of M)",
             f"  damper point          peak {1e3 * s['damper_peak_m']:.4g} mm (without {1e3 * s['damper_peak_bare_m']:.4g}"
             f" mm: ratio {ratio(s['damper_peak_reduction'])}), rms {1e3 * s['damper_rms_m']:.4g} mm (without "
             f"{1e3 * s['damper_rms_bare_m']:.4g} mm: ratio {ratio(s['damper_rms_reduction'])})",
             *([f"  damper points         {s['dampers']} dampers: peak "
                + ", ".join(f"{1e3 * a:.4g}" for a in s["damper_points_peak_m"]) + " mm (without "
                + ", ".join(f"{1e3 * a:.4g}" for a in s["damper_points_peak_bare_m"]) + " mm); beds "
                + ", ".join(f"{1e3 * m:.4g}" for m in s["bed_masses_kg"]) + " g"] if s.get("dampers") else []),
             "  every dof" + (" (relative to the ground)" if s["relative_to_ground"] else "")
             + "; ratio = with / without the damper (< 1: reduced):",
             f"  {'dof':>9}  {'peak [mm]':>10}  {'bare [mm]':>10}  {'ratio':>6}  {'rms [mm]':>10}  {'bare [mm]':>10}"
             f"  {'ratio':>6}"]
    residual = bool(s.get("nonlinear"))
    if residual:
        lines[-1] += f"  {'residual [mm]':>13}  {'bare [mm]':>10}"
    for k, d in enumerate(s["dofs"]):
        lines.append(f"  {str(d):>9}  {1e3 * s['peak_m'][k]:10.4g}  {1e3 * s['peak_bare_m'][k]:10.4g}  "
                     f"{ratio(s['peak_reduction'][k]):>6}  {1e3 * s['rms_m'][k]:10.4g}  {1e3 * s['rms_bare_m'][k]:10.4g}  "
                     f"{ratio(s['rms_reduction'][k]):>6}"
                     + (f"  {1e3 * s['residual_m'][k]:13.4g}  {1e3 * s['residual_bare_m'][k]:10.4g}" if residual else ""))
    if "random" in s:
        r = s["random"]
        lines.append(f"  random load           variance {r['load_variance']:.4g} (target {r['load_variance_target']:.4g}); "
                     f"H1 without the damper against the exact FRF: median error {100 * r['h1_bare_vs_exact_median_error']:.3g} "
                     f"% ({r['frequency_resolution_hz']:.3g} Hz resolution, JSON: random)")
    c = s.get("coupling")
    if c:
        how = "OpenSees co-simulation" if c["coupling"] == "opensees" else "coupling loop"
        lines.append(f"  coupling              {how}, step {1e3 * c['coupling_step_s']:.3g} ms; interface energy "
                     f"error {c['interface_energy_error']:.2g} (of the work through the walls)")
    err = s["energy_balance_error"]
    lines.append("  energy balance error  " + (f"{err:.2g}" if err is not None else "n/a (" + s.get(
        "energy_balance_note", "") + ")"))
    step = f" of {1e6 * s['time_step_s']:.3g} us" if math.isfinite(s["time_step_s"]) else ""
    lines.append(f"  DEM                   {s['duration_s']:.4g} s simulated in {s['wall_time_s']:.3g} s, "
                 f"{s['steps']:,} steps{step}")
    if s.get("plot"):
        lines.append(f"  wrote {s['plot']}")
    return lines
