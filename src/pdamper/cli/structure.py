"""``pdamper decay`` and ``pdamper response``: the damper on a structure, with and without it
(:mod:`pdamper.studies.structure`, :mod:`pdamper.studies.transient`); options and printing only."""

from __future__ import annotations

import math
import sys

import click

from .codes import codes_lines, limit_option, settings_line
from .common import Quantity, echo_json, fraction_bar, main, user_errors
from .ensemble import uncertain_options
from .run import parse_set
from .structure_text import _codes_text, _dem_lines, _dof_lines, _fields_lines, _sweep_lines

__all__ = ["decay_command", "response_command"]


def _load(config, settings, cycles, seed, force=None):
    """The case of CONFIG.toml with the command's overrides, forced by ``force`` [N] (``--force``;
    :func:`pdamper.studies.structure.load_forced`)."""
    from ..studies.structure import load_forced

    overrides = parse_set(settings)
    if cycles is not None:
        overrides["run.cycles"] = int(cycles) if float(cycles).is_integer() else cycles
    if seed is not None:
        overrides["initial.seed"] = seed
    return load_forced(config, overrides, force=force)


def _report(res, case, config, plot, figure, as_json):
    """Add X_opt to the summary, draw the figure, print JSON (then return None) or return the summary."""
    from ..studies.structure_base import bed_x_opt

    res.summary["x_opt_m"] = bed_x_opt(case)
    if plot:
        figure(res, plot)
    s = dict(res.summary, config=str(config), plot=plot)
    if as_json:
        echo_json(s)
        return None
    return s


_COMMON = [
    click.argument("config", metavar="CONFIG.toml"),
    click.option("--cycles", type=click.FloatRange(min=0, min_open=True),
                 help="Cycles to simulate (natural periods for decay, forcing periods for response)."),
    click.option("--seed", type=click.IntRange(min=0), help="Seed of the initial jitter/scatter."),
    click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE",
                 help="Override any config key, e.g. --set structure.displacement=15mm (repeatable)."),
    click.option("--plot", type=click.Path(dir_okay=False), help="Write the figure (png, svg or pdf)."),
    click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units)."),
]


def _common(func):
    for deco in reversed(_COMMON):
        func = deco(func)
    return func


@main.command("decay")
@_common
@click.option("--fields", "fields_path", type=click.Path(dir_okay=False),
              help="Also the envelope from the damper's fields (pdamper fields --out F.nc), by averaging.")
@click.option("--extrapolate", is_flag=True, help="With --fields: continue the fields below their smallest amplitude.")
@user_errors
def decay_command(config, cycles, seed, settings, plot, as_json, fields_path, extrapolate):
    """Free decay of the structure of CONFIG.toml ([structure]) with and without the damper.

    Releases the structure from [structure] displacement; prints the equivalent damping ratio
    with and without the bed and writes the envelope and damping-vs-amplitude figure.

    Example: pdamper decay examples/structure_36.toml --plot decay.png
    """
    from ..plotting.structure import decay_figure
    from ..plotting.figure import check_path
    from ..studies.structure import run_decay

    case = _load(config, settings, cycles, seed)
    check_path(plot)
    with fraction_bar("pdamper decay", round(case.duration, 3), "s", not as_json and sys.stderr.isatty()) as progress:
        fields = None
        if fields_path:
            from ..studies.fields import load_fields

            fields = load_fields(fields_path)
        res = run_decay(case, progress=progress, fields=fields, extrapolate=extrapolate)
    s = _report(res, case, config, plot, decay_figure, as_json)
    if s is None:
        return
    pct = lambda z: "n/a" if not math.isfinite(z) else f"{100 * z:.3g} %"  # noqa: E731
    mm = lambda x: "n/a" if x is None or not math.isfinite(x) else f"{1e3 * x:.3g} mm"  # noqa: E731
    lines = [
        f"pdamper decay {config}",
        *settings_line(settings),
        f"  structure             M = {s['mass_kg']:.4g} kg, f_n = {s['natural_frequency_hz']:.4g} Hz, "
        f"zeta = {pct(s['damping_ratio'])}, from {mm(s['initial_displacement_m'])}",
        *([f"  modes                 {s['modes_kept']}: " + ", ".join(f"{f:.4g}" for f in s["mode_frequencies_hz"])
           + " Hz (M, f_n, zeta: the first mode's, M at the damper)"
           + (f"; truncation error {s['truncation_error']:.2g}" if "truncation_error" in s else ""),
           "  mode damping ratios   " + ", ".join(f"{100 * z:.3g}" for z in s["mode_damping_ratios"]) + " %"]
          if s.get("modes_kept", 1) > 1 else []),
        f"  damper                {s['particles']} spheres, {1e3 * s['bed_mass_kg']:.4g} g "
        f"({100 * s['mass_ratio']:.3g} % of M), X_opt = {mm(s['x_opt_m'])}",
        f"  zeta without damper   {pct(s['zeta_bare_mean'])}        (bare run vs closed form: "
        f"max error {s['bare_vs_closed_form_max_error']:.2g} of X0)",
        f"  zeta with damper      {pct(s['zeta_damped_upper_half'])} above X0/2, "
        f"{pct(s['zeta_damped_lower_half'])} below; largest {pct(s['zeta_damped_max'])} "
        f"at {mm(s['amplitude_at_zeta_max_m'])}",
        f"  after {s['duration_s']:.3g} s           {mm(s['final_amplitude_damped_m'])} with damper, "
        f"{mm(s['final_amplitude_bare_m'])} without",
        *([f"  from the fields       {mm(s['final_amplitude_fields_m'])} after {s['fields_decay_end_s']:.3g} s; "
           f"largest difference to the direct envelope {100 * s['fields_vs_direct_envelope_max_error']:.3g} %"]
          if "final_amplitude_fields_m" in s else []),
        f"  energy balance error  {s['energy_balance_error']:.2g}          (structure + bed)",
        f"  wall time             {s['wall_time_s']:.3g} s, {s['steps']:,} steps of {1e6 * s['time_step_s']:.3g} us",
    ]
    if plot:
        lines.append(f"  wrote {plot}")
    click.echo("\n".join(lines))


@main.command("response")
@_common
@click.option("--frequencies", help="LOW:HIGH:N (linear, both ends) or a list 1.9Hz,2Hz,2.1Hz "
              "[default: 9 points over +-10 % around the natural frequency of --mode].")
@click.option("--mode", "mode", type=click.IntRange(min=1), default=1, show_default=True,
              help="The mode whose resonance the default grid is centred on (and the warning checks).")
@click.option("--force", "force", type=Quantity("force"), multiple=True,
              help="Force amplitude F0 on the structure, e.g. 0.4N (default: [structure] force_amplitude); repeat it "
                   "for several forces, overlaid in the figure (|X|/F0 panel).")
@click.option("--fields", "fields_path", type=click.Path(dir_okay=False), multiple=True,
              help="The damper's fields (pdamper fields --out F.nc): the response by harmonic balance, in "
                   "milliseconds, instead of DEM runs (with --start: the DEM runs, and the fields' prediction beside). "
                   "Several dampers ([[damper]], damper_dof = [..]): one --fields a damper, in their order (or one "
                   "for all).")
@click.option("--extrapolate", is_flag=True,
              help="With --fields: continue the fields' end values where the solution lies outside their box "
                   "(default: refuse).")
@click.option("--start", type=click.Choice(["rest", "bare", "fields"]),
              help="DEM runs: start from rest (default), on the bare structure's steady orbit, or on the fields' "
                   "prediction (needs --fields).")
@click.option("--measure-cycles", type=click.IntRange(min=1), default=8, show_default=True,
              help="Last cycles of each run over which the steady amplitude is measured.")
@click.option("--workers", type=click.IntRange(min=1),
              help="Local worker processes (>1: the sweep executor, Dask; default 1, with --uncertain all cores).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on an existing Dask cluster.")
@click.option("--sweep", type=click.Choice(["up", "down", "both"]),
              help="A stepped sine over the frequencies instead of a run per frequency: one DEM run, --cycles "
                   "periods a step, the state carried from step to step (both: up, then down from rest); with "
                   "--fields drawn over the fields' branches.")
@click.option("--dofs", help="The dofs whose amplitudes to report: labels and ranges START:STOP[:STEP] (0-based, "
              "STOP excluded), e.g. 0,18,38 or 0:40:2 (default: every dof, in the JSON).")
@limit_option
@uncertain_options(executor=False, ratios=True)
@user_errors
def response_command(config, cycles, seed, settings, plot, as_json, frequencies, mode, force, fields_path,
                     extrapolate, start, measure_cycles, workers, scheduler, sweep, dofs, limits, ensemble):
    """Frequency response of the structure of CONFIG.toml with and without the damper.

    DEM (default): at each frequency the structure runs under F0 sin(2 pi f t) for the config's
    [run] cycles (of the forcing), from rest or on an orbit (--start); the steady amplitude is
    the Fourier amplitude over the last --measure-cycles, and each point says whether it is
    steady (the last two periods' amplitudes within 2 %, and the two halves of the measured
    ones). Without the damper: closed form (and
    the bare structure run the same way); the bed as a solid mass: closed form.

    With --fields F.nc (and no --start): harmonic balance of the modal model with the damper as
    its fields' mass and dashpot at its node, every solution branch per frequency with its
    stability and the jump frequencies (docs/structure.md).

    With --sweep up|down|both: the stepped sine (one DEM run over the frequencies in the sweep's
    order, [run] cycles a step, the last --measure-cycles fitted), with the bare structure's own
    stepped sine (exact) and its steady closed form; with --fields drawn over the fields'
    branches, so a jump is seen to follow one branch.

    Also what codes ask for (not with --sweep): every dof's absolute floor acceleration and,
    with [structure] storey_heights, every storey's drift ratio, each dof's largest over the
    frequencies with and without the damper, judged by --limit (JSON ``codes``); and the damper
    as an equivalent TMD at the damped peak (JSON ``tmd_equivalent``).

    Every dof's amplitude is in the JSON (``dofs``, ``response_amplitude_m`` per dof); --dofs
    chooses and prints them.

    With --uncertain U.toml --samples N: the DEM response at N samples of the unknowns
    (docs/ensembles.md), each on its own grid around its mode unless --frequencies is given: the
    peak ratio per dof (the largest amplitude over the grid with the damper over without), the share
    meeting --target-peak-ratio, which unknowns matter; --plot draws the ratio's CDF.

    Examples: pdamper response examples/structure_36.toml --force 0.4N --plot response.png;
    pdamper response examples/mast_modal.toml --force 0.3N --fields fields_36.nc --plot r.png;
    pdamper response examples/structure_36.toml --force 0.4N --sweep both --fields fields_36.nc --plot sweep.png
    """
    import numpy as np

    from ..errors import InputError
    from ..plotting.figure import check_path
    from ..plotting.structure import response_figure
    from ..studies.structure import (default_frequencies, grid_warnings, parse_frequencies, run_response,
                                     run_response_fields)

    forces = [float(f) for f in force or ()]
    case = _load(config, settings, cycles, seed, force=forces[0] if forces else None)
    check_path(plot)
    if frequencies is None:
        freqs = default_frequencies(case, mode)
        warnings = []
    else:
        freqs = parse_frequencies(frequencies)
        warnings = grid_warnings(case, freqs, mode)
    if not forces:
        forces = [case.drive.force_amplitude if case.drive.coupled else 0.0]
    if not all(f0 > 0 for f0 in forces):
        raise InputError("--force: give the force amplitude on the structure, e.g. --force 0.4N "
                         "([structure] force_amplitude is 0)")
    fields = None
    if fields_path:
        from ..studies.fields import load_fields

        fields = [load_fields(p) for p in fields_path]
        if len(fields) > 1 and (start is not None or sweep is not None):
            raise InputError("several --fields are the several dampers' harmonic balance; --start and --sweep take one")
        fields = fields[0] if len(fields) == 1 else fields
        fields_path = ", ".join(fields_path)
    elif start == "fields":
        raise InputError("--start fields needs the damper's fields: --fields F.nc")
    elif extrapolate:
        raise InputError("--extrapolate belongs to --fields F.nc")
    from ..studies.structure_base import bed_x_opt, parse_dofs

    wanted = parse_dofs(dofs)
    from ..analysis.codes import parse_limits

    wanted_limits = parse_limits(limits)
    if ensemble is not None:
        if limits:
            raise InputError("--limit judges one response; an ensemble reports its ratios' percentiles and shares: "
                             "leave --limit out or --uncertain out")
        return _response_ensemble(ensemble, case, config, frequencies, freqs, forces, fields_path, sweep, start,
                                  measure_cycles, mode, workers, scheduler, wanted, plot, as_json)
    workers = workers or 1
    if not as_json:
        for w in warnings:
            click.echo(f"warning: {w}", err=True)
    if sweep is not None:
        return _sweep(case, config, freqs, forces, sweep, fields, extrapolate, measure_cycles, start, workers,
                      scheduler, wanted, plot, as_json, warnings, settings, wanted_limits)
    results, beside, text = [], [], []
    x_opt = bed_x_opt(case)
    for f0 in forces:
        if fields is not None and start is None:
            res = run_response_fields(case, freqs, fields, force_amplitude=f0, extrapolate=extrapolate, dofs=wanted,
                                      limits=wanted_limits)
            res.summary.update(warnings=warnings, x_opt_m=x_opt)
            results.append(res)
            beside.append(None)
            text += _fields_lines(dict(res.summary, config=str(config)), config, f0, fields_path, None)
            if wanted is not None:
                text += _dof_lines(res.summary)
            text += _codes_text(res.summary)
            continue
        res = run_response(case, freqs, force_amplitude=f0, measure_cycles=measure_cycles, workers=workers,
                           scheduler=scheduler, progress=None if not as_json else False, start=start or "rest",
                           fields=fields, extrapolate=extrapolate, dofs=wanted, limits=wanted_limits)
        res.summary.update(warnings=warnings, x_opt_m=x_opt)
        prediction = curve = None
        if fields is not None:
            prediction = run_response_fields(case, freqs, fields, force_amplitude=f0, extrapolate=extrapolate)
            res.summary["fields_prediction"] = {k: prediction.summary[k] for k in (
                "damper_amplitude_m", "dofs", "response_amplitude_m", "response_point_amplitude_m",
                "jump_frequencies_hz", "peak_damped_m", "peak_damped_frequency_hz", "solve_time_median_s")}
            if plot and freqs.size > 1:  # the figure: the fields' curve on a fine grid over the DEM's
                curve = run_response_fields(case, np.linspace(freqs.min(), freqs.max(), 81), fields,
                                            force_amplitude=f0, extrapolate=extrapolate)
        results.append(res)
        beside.append(curve or prediction)
        text += _dem_lines(res.summary, config, f0, prediction is not None)
        if wanted is not None:
            text += _dof_lines(res.summary)
        text += _codes_text(res.summary)
    if plot:
        response_figure(results if len(results) > 1 else results[0], plot,
                        fields=(beside if len(beside) > 1 else beside[0]) if any(b is not None for b in beside)
                        else None)
    summaries = [dict(r.summary) for r in results]
    if as_json:
        if len(summaries) == 1:
            echo_json(dict(summaries[0], config=str(config), plot=plot))
        else:
            echo_json({"forces_N": forces, "responses": summaries, "config": str(config), "plot": plot})
        return
    if plot:
        text.append(f"  wrote {plot}")
    text[1:1] = settings_line(settings)
    click.echo("\n".join(text))


def _response_ensemble(ensemble, case, config, frequencies, freqs, forces, fields_path, sweep, start, measure_cycles,
                       mode, workers, scheduler, wanted, plot, as_json):
    """``response --uncertain``: the DEM response at every sample (:func:`pdamper.cli.ensemble.run_uncertain`)."""
    from ..errors import InputError
    from .ensemble import run_uncertain

    for flag, given in (("--fields", fields_path), ("--sweep", sweep), ("--start", start),
                        ("a second --force", len(forces) > 1)):
        if given:
            raise InputError(f"{flag} does not apply to an ensemble (one DEM response per sample, from rest)")
    run_uncertain(ensemble, case, config, study="response", as_json=as_json, plot=plot, dofs=wanted,
                  frequencies=freqs if frequencies is not None else None, force_amplitude=forces[0],
                  measure_cycles=measure_cycles, mode=mode, workers=workers, scheduler=scheduler)


def _sweep(case, config, freqs, forces, sweep, fields, extrapolate, measure_cycles, start, workers, scheduler,
           wanted, plot, as_json, warnings, settings=(), limits=None):
    """``pdamper response --sweep``: the stepped sines, their tables and the numbers codes ask for
    (against ``limits``), the figure over the fields."""
    import numpy as np

    from ..errors import InputError
    from ..studies.structure import run_response_fields
    from ..studies.structure_base import bed_x_opt
    from ..studies.transient import APART, SWEEPS, run_stepped_sine, sweeps_apart

    if len(forces) != 1:
        raise InputError("--sweep takes one force: give --force once")
    for name, value in (("--start", start), ("--workers", workers if workers != 1 else None),
                        ("--scheduler", scheduler)):
        if value is not None:
            raise InputError(f"{name} does not apply to --sweep (one run carries the state from step to step)")
    if freqs.size < 2:
        raise InputError("--sweep needs two or more frequencies, e.g. --frequencies 1.9Hz:2.1Hz:9")
    f0 = forces[0]
    directions = SWEEPS if sweep == "both" else (sweep,)
    results = []
    for d in directions:
        res = run_stepped_sine(case, freqs, force_amplitude=f0, direction=d, measure_cycles=measure_cycles,
                               dofs=wanted, progress=None, limits=limits)
        res.summary.update(warnings=warnings, x_opt_m=bed_x_opt(case))
        results.append(res)
    curve = None
    if fields is not None:
        curve = run_response_fields(case, np.linspace(freqs.min(), freqs.max(), 81), fields, force_amplitude=f0,
                                    extrapolate=extrapolate, dofs=wanted)
        for r in results:
            r.summary["fields_jump_frequencies_hz"] = curve.summary["jump_frequencies_hz"]
    if plot:
        from ..plotting.transient import sweep_figure

        sweep_figure(results, plot, fields=curve)
    if as_json:
        out = [dict(r.summary) for r in results]
        echo_json(dict(out[0], config=str(config), plot=plot) if len(out) == 1 else
                  {"sweeps": out, "config": str(config), "plot": plot})
        return
    text = []
    for r in results:
        text += _sweep_lines(r.summary, config)
        if wanted is not None:
            text += _dof_lines(r.summary)
        text += codes_lines(r.summary["codes"], over="(the largest over the steps)")
    if len(results) == 2:  # up and down at the same frequencies: where they part, the branches differ
        apart = sweeps_apart(*results)
        text.append(f"  up and down differ by more than {100 * APART:g} % at " + (", ".join(
            f"{f:.5g} Hz ({1e3 * a:.4g} / {1e3 * b:.4g} mm)" for f, a, b in apart) if apart else "no frequency"))
    if curve is not None and curve.summary["jump_frequencies_hz"]:
        text.append("  the fields' jumps at " + ", ".join(f"{f:.5g} Hz" for f in curve.summary["jump_frequencies_hz"]))
    if plot:
        text.append(f"  wrote {plot}")
    text[1:1] = settings_line(settings)
    click.echo("\n".join(text))


