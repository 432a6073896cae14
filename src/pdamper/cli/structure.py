"""``pdamper decay``, ``pdamper response`` and ``pdamper design``: the damper on a structure,
and the filling that puts a structure's stroke at the damper's optimum."""

from __future__ import annotations

import math
import sys
import tempfile

import click

from .common import Quantity, ShapeChoice, echo_json, fraction_bar, main, parse_sizes, renamed, user_errors
from .run import parse_set

__all__ = ["decay_command", "response_command", "design_command"]


def _load(config, settings, cycles, seed, force=None):
    """The case of CONFIG.toml with the command's overrides. ``force`` [N] (``--force``): the
    structure is forced (its ``force_amplitude``), at its ``force_frequency`` or, where the file
    gives none, at its first mode's natural frequency; a file whose structure nothing moves
    (``force_amplitude = 0``, no start) is then read as forced, not refused."""
    from ..config import load_case

    overrides = parse_set(settings)
    if cycles is not None:
        overrides["run.cycles"] = int(cycles) if float(cycles).is_integer() else cycles
    if seed is not None:
        overrides["initial.seed"] = seed
    if force is not None and force > 0 and "structure.force_amplitude" not in overrides:
        # the file as it stands may have nothing that moves it: read it once with a nominal start
        probe = load_case(config, {**overrides, "structure.displacement": "1mm", "structure.force_amplitude": 0.0})
        if not probe.drive.coupled:
            return probe  # not a structure: the command says so
        overrides["structure.force_amplitude"] = force
        overrides.setdefault("structure.force_frequency",
                             probe.drive.force_frequency or probe.drive.natural_frequency)
    return load_case(config, overrides)


def _x_opt(case) -> float | None:
    """X_opt [m] of the case's bed (one species, one layer), else None."""
    from .. import theory as th

    if len(case.particles) != 1:
        return None
    g = case.container.geometry
    n, n_max = case.particles[0].count, g.clearance_capacity(case.particles[0].radius)
    if not 1 <= n < n_max:
        return None
    return th.optimal_stroke(th.clearance(g.drive_length, n, n_max))


def _report(res, case, config, plot, figure, as_json):
    """Add X_opt to the summary, draw the figure, print JSON (then return None) or return the summary."""
    res.summary["x_opt_m"] = _x_opt(case)
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
@click.option("--fields", "fields_path", type=click.Path(dir_okay=False),
              help="The damper's fields (pdamper fields --out F.nc): the response by harmonic balance, in "
                   "milliseconds, instead of DEM runs (with --start: the DEM runs, and the fields' prediction beside).")
@click.option("--extrapolate", is_flag=True,
              help="With --fields: continue the fields' end values where the solution lies outside their box "
                   "(default: refuse).")
@click.option("--start", type=click.Choice(["rest", "bare", "fields"]),
              help="DEM runs: start from rest (default), on the bare structure's steady orbit, or on the fields' "
                   "prediction (needs --fields).")
@click.option("--measure-cycles", type=click.IntRange(min=1), default=8, show_default=True,
              help="Last cycles of each run over which the steady amplitude is measured.")
@click.option("--workers", type=click.IntRange(min=1), default=1, show_default=True,
              help="Local worker processes (>1: the sweep executor, Dask).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on an existing Dask cluster.")
@user_errors
def response_command(config, cycles, seed, settings, plot, as_json, frequencies, mode, force, fields_path,
                     extrapolate, start, measure_cycles, workers, scheduler):
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

    Examples: pdamper response examples/structure_36.toml --force 0.4N --plot response.png;
    pdamper response examples/mast_modal.toml --force 0.3N --fields fields_36.nc --plot r.png
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

        fields = load_fields(fields_path)
    elif start == "fields":
        raise InputError("--start fields needs the damper's fields: --fields F.nc")
    elif extrapolate:
        raise InputError("--extrapolate belongs to --fields F.nc")
    if not as_json:
        for w in warnings:
            click.echo(f"warning: {w}", err=True)
    results, beside, text = [], [], []
    x_opt = _x_opt(case)
    for f0 in forces:
        if fields is not None and start is None:
            res = run_response_fields(case, freqs, fields, force_amplitude=f0, extrapolate=extrapolate)
            res.summary.update(warnings=warnings, x_opt_m=x_opt)
            results.append(res)
            beside.append(None)
            text += _fields_lines(dict(res.summary, config=str(config)), config, f0, fields_path, None)
            continue
        res = run_response(case, freqs, force_amplitude=f0, measure_cycles=measure_cycles, workers=workers,
                           scheduler=scheduler, progress=None if not as_json else False, start=start or "rest",
                           fields=fields, extrapolate=extrapolate)
        res.summary.update(warnings=warnings, x_opt_m=x_opt)
        prediction = curve = None
        if fields is not None:
            prediction = run_response_fields(case, freqs, fields, force_amplitude=f0, extrapolate=extrapolate)
            res.summary["fields_prediction"] = {k: prediction.summary[k] for k in (
                "damper_amplitude_m", "response_amplitude_m", "jump_frequencies_hz", "peak_damped_m",
                "peak_damped_frequency_hz", "solve_time_median_s")}
            if plot and freqs.size > 1:  # the figure: the fields' curve on a fine grid over the DEM's
                curve = run_response_fields(case, np.linspace(freqs.min(), freqs.max(), 81), fields,
                                            force_amplitude=f0, extrapolate=extrapolate)
        results.append(res)
        beside.append(curve or prediction)
        text += _dem_lines(res.summary, config, f0, prediction is not None)
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
    click.echo("\n".join(text))


def _dem_lines(s: dict, config, f0: float, prediction: bool) -> list[str]:
    """The table of a DEM response (``s``: its summary)."""
    from ..studies.structure import frequency_format

    mark = lambda k: "" if s["steady"][k] else " *"  # noqa: E731
    hz = frequency_format(s["frequencies_hz"])
    lines = [f"pdamper response {config}  (F0 = {f0:.4g} N, {s['particles']} spheres, "
             f"{100 * s['mass_ratio']:.3g} % of M; {s['measure_cycles']} of {s['cycles']:g} cycles measured, "
             f"from {s['start']})",
             f"  {'f [Hz]':>8}  {'damper [mm]':>12}  {'bare [mm]':>10}  {'bare run [mm]':>13}  {'solid mass [mm]':>15}"
             + ("  fields [mm]" if prediction else "")]
    for k, f in enumerate(s["frequencies_hz"]):
        line = (f"  {hz(f):>8}  {1e3 * s['amplitude_damped_m'][k]:10.4g}{mark(k):2}  {1e3 * s['amplitude_bare_m'][k]:10.4g}  "
                f"{1e3 * s['amplitude_bare_run_m'][k]:11.4g}{'' if s['bare_run_steady'][k] else ' *':2}  "
                f"{1e3 * s['amplitude_solid_mass_m'][k]:15.4g}")
        if prediction:
            line += "  " + _branches_mm(s["fields_prediction"]["damper_amplitude_m"][k])
        lines.append(line)
    ratio = (f"ratio {s['peak_reduction']:.3g}" if s["peak_steady"]
             else f"no ratio: the damped peak is a transient ({transient_words(s)})")
    lines.append(_peak_line(s, hz) + ratio)
    if not all(s["steady"]) or not all(s["bare_run_steady"]):
        lines.append(f"  * not steady: the amplitude over the last period (or the last half of the measured ones) "
                     f"differs from the one before by more than {100 * s['steady_tolerance']:g} %; a bare run: "
                     "more than that from its steady closed form (a transient; run more --cycles or --start bare|fields)")
    lines.append(f"  energy balance error (worst point) {s['energy_balance_error_max']:.2g}; "
                 f"DEM time {s['wall_time_s']:.3g} s")
    for f, msg in s["failed"].items():
        lines.append(f"  failed at {f} Hz: {msg}")
    return lines


def transient_words(s: dict) -> str:
    """Why the damped peak of a DEM response ``s`` is not steady: the checks that failed, with
    their numbers and the limit (:func:`pdamper.studies.structure.steadiness`)."""
    k = s["frequencies_hz"].index(s["peak_damped_frequency_hz"])
    tol = s["steady_tolerance"]
    checks = [("over the last period", s["last_period_change"][k]),
              ("between the two halves of the measured periods", s["window_change"][k])]
    failed = [f"changed {100 * v:.2g} % {what}" for what, v in checks if not v <= tol]
    return "; ".join(failed or ["its run failed"]) + f", beyond the {100 * tol:g} % limit"


def _peak_line(s: dict, hz) -> str:
    """The damped peak against the bare structure's resonance (its closed-form peak, not the grid's
    largest bare value)."""
    return (f"  peak with damper {1e3 * s['peak_damped_m']:.4g} mm at {hz(s['peak_damped_frequency_hz'])} Hz; without "
            f"{1e3 * s['resonance_bare_m']:.4g} mm at its resonance {s['resonance_bare_frequency_hz']:.5g} Hz "
            f"({1e3 * s['peak_bare_m']:.4g} mm on this grid): ")


def _branches_mm(v) -> str:
    """A frequency's stable amplitudes in mm: one number, or the branches joined by ' / '."""
    vals = v if isinstance(v, list) else [v]
    return " / ".join(f"{1e3 * x:.4g}" for x in vals) if vals else "none"


def _fields_lines(s, config, f0, fields_path, plot) -> list[str]:
    lines = [f"pdamper response {config} --fields {fields_path}  (F0 = {f0:.4g} N, {s['particles']} spheres, "
             f"{100 * s['mass_ratio']:.3g} % of M; harmonic balance, stable branches)",
             f"  {'f [Hz]':>8}  {'damper [mm]':>16}  {'response [mm]':>16}  {'bare [mm]':>10}  {'solid mass [mm]':>15}"]
    from ..studies.structure import frequency_format

    hz = frequency_format(s["frequencies_hz"])
    for k, f in enumerate(s["frequencies_hz"]):
        lines.append(f"  {hz(f):>8}  {_branches_mm(s['damper_amplitude_m'][k]):>16}  "
                     f"{_branches_mm(s['response_amplitude_m'][k]):>16}  {1e3 * s['amplitude_bare_m'][k]:10.4g}  "
                     f"{1e3 * s['amplitude_solid_mass_m'][k]:15.4g}")
    lines.append(_peak_line(s, hz) + f"ratio {s['peak_reduction']:.3g}")
    if s["jump_frequencies_hz"]:
        lines.append("  jumps (the stable branches change) at " +
                     ", ".join(f"{f:.5g} Hz" for f in s["jump_frequencies_hz"]))
    if s["extrapolated"]:
        lines.append("  warning: some solutions lie outside the fields' box (--extrapolate: end values continued)")
    lines.append(f"  solve time {1e3 * s['solve_time_median_s']:.3g} ms per frequency (median); fields {s['fields_box']}")
    if plot:
        lines.append(f"  wrote {plot}")
    return lines


class _LengthOrRange(Quantity):
    """A length, or a range of them written LOW:HIGH (a tuple of two SI floats)."""

    def __init__(self):
        super().__init__("length")

    def convert(self, value, param, ctx):
        if isinstance(value, str) and ":" in value:
            parts = value.split(":")
            if len(parts) != 2:
                raise click.UsageError(f"--{param.name} {value!r}: write one length or LOW:HIGH, e.g. 80mm:160mm", ctx)
            return tuple(super(_LengthOrRange, self).convert(p, param, ctx) for p in parts)
        return super().convert(value, param, ctx)

    def get_metavar(self, param, ctx=None):  # noqa: D401 - click API
        return "LENGTH|LOW:HIGH"


def _particles_option(text):
    """``--particles N`` or ``LOW:HIGH`` as an int or a (LOW, HIGH) pair."""
    from ..errors import InputError

    parts = str(text).split(":")
    try:
        values = [int(p) for p in parts]
    except ValueError:
        values = []
    if len(parts) > 2 or not values:
        raise InputError(f"--particles {text!r}: give a number of spheres or LOW:HIGH, e.g. 36 or 20:60")
    return values[0] if len(values) == 1 else tuple(values)


@main.command("design")
@click.option("--structure", "structure_file", type=click.Path(dir_okay=False), metavar="STRUCT.toml",
              help="Design for a structure: a config whose [structure] section gives the mode(s) "
                   "(the stroke is then the design's answer; give --force, not --frequency/--stroke).")
@click.option("--mode", "mode_number", type=int, default=1, show_default=True,
              help="With --structure: the mode to damp (1 = the lowest).")
@click.option("--force", type=Quantity("force"), help="With --structure: force amplitude at the mode's resonance, "
              "e.g. 1.5N.")
@click.option("--frequency", type=Quantity("frequency"), help="Structure's frequency, e.g. 2Hz (without --structure).")
@click.option("--stroke", type=Quantity("length"),
              help="Stroke (amplitude) of the structure where the damper sits, e.g. 10mm (without --structure).")
@click.option("--shape", type=ShapeChoice(),
              help="Container shape (any registered shape) [default: cuboid; with --structure the file's container].")
@click.option("--length", type=_LengthOrRange(), help="Cuboid: inner length along the motion, e.g. 120mm; with "
              "--structure also a range to choose from, LOW:HIGH, e.g. 80mm:160mm (1 mm steps, at most 121).")
@click.option("--length-range", metavar="LOW:HIGH",
              help="With --structure: the same as --length LOW:HIGH.")
@click.option("--width", type=Quantity("length"), help="Cuboid: inner width, e.g. 40.4mm.")
@click.option("--container-radius", type=Quantity("length"), help="Cylinder: inner radius R, e.g. 39mm.")
@click.option("--size", "sizes", multiple=True, metavar="KEY=VALUE",
              help="Another [container] key of the shape, e.g. --size height=30mm (repeatable).")
@click.option("--sphere-radius", type=Quantity("length"),
              help="Sphere radius r, e.g. 5mm (required without --structure; with it the config's, else 5 mm).")
@click.option("--radius", type=Quantity("length"), hidden=True, help="Old name of --sphere-radius.")
@click.option("--density", type=Quantity("density"),
              help="Sphere density [kg/m^3] (default: 7900, steel; with --structure the config's spheres).")
@click.option("--max-particles", type=click.IntRange(min=2),
              help="Spheres covering the floor in one layer (default: the floor packing of the container).")
@click.option("--particles", "particles", metavar="N|LOW:HIGH",
              help="With --structure: the fillings to choose from, e.g. 20:60 (default: every filling of the floor).")
@click.option("--max-bed-mass", type=Quantity("mass"), help="With --structure: largest bed mass, e.g. 200g.")
@click.option("--max-mass-ratio", type=click.FloatRange(min=0, min_open=True),
              help="With --structure: largest bed mass over the mode's mass at the damper, e.g. 0.01.")
@click.option("--target-ratio", type=click.FloatRange(min=0, max=1, min_open=True, max_open=True),
              help="With --structure: the lightest filling whose resonant amplitude is at most this fraction of the "
                   "bare structure's, e.g. 0.5 (default: the filling with the smallest amplitude).")
@click.option("--margin", type=click.FloatRange(min=1.0),
              help="With --structure: keep the operating stroke at least this factor above X_opt [default: by the "
                   "filling fraction N_p/N_p,max, 1.2 up to 75 % filled to 1.75 at 91 %, above the strokes at which "
                   "the DEM checks saw such beds sway; docs/structure.md, \"The margin\"].")
@click.option("--write-case", type=click.Path(dir_okay=False), metavar="OUT.toml",
              help="With --structure: write one runnable case of the design: the damper, its rig drive [drive] and "
                   "the structure forced at the design's resonance [structure] (for sweep, fields, response).")
@click.option("--tilt", type=Quantity("angle"), help="Expected mounting tilt, e.g. 1deg.")
@click.option("--verify", is_flag=True, help="Run a short DEM sweep around the stroke with the proposed filling.")
@click.option("--verify-cycles", type=click.IntRange(min=3), default=8, show_default=True,
              help="Drive cycles per verification case (the first 2 dropped; 1 below 5 cycles with --structure).")
@click.option("--verify-strokes", type=click.IntRange(min=1), default=3, show_default=True,
              help="With --structure: strokes of the DEM check (0.85 to 1.15 times the operating stroke).")
@click.option("--seeds", type=click.IntRange(min=1), default=2, show_default=True,
              help="With --structure: DEM seeds per stroke of the check.")
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes for --verify (default: all cores).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units).")
@user_errors
def design_command(structure_file, mode_number, force, frequency, stroke, shape, length, length_range, width,
                   container_radius, sizes, sphere_radius, radius, density, max_particles, particles, max_bed_mass,
                   max_mass_ratio, target_ratio, margin, write_case, tilt, verify, verify_cycles, verify_strokes, seeds,
                   workers, as_json):
    """The filling (N_p of N_p,max) that puts the structure's stroke at the damper's optimum X_opt.

    With a stroke (--frequency, --stroke): inverts eqs. (6), (17): h = X / 0.4075,
    N_p = N_p,max (1 - h/L), rounded up so that X is at or just above X_opt (the largest eta*
    of the paper's laws). Reports the expected eta*, energy per cycle and bed mass, and warns
    about lift-off, tilt sensitivity and thin beds.

    With a structure (--structure STRUCT.toml --mode 1 --force 1.5N): the stroke is the
    unknown. Sizes the filling (and the container's length within --length LOW:HIGH, the bed
    within --particles, --max-bed-mass / --max-mass-ratio) that minimises the mode's resonant
    amplitude, or with --target-ratio R the lightest one whose resonant amplitude is at most R
    times the bare structure's, from the energy balance at resonance with the paper's laws,
    keeping the operating stroke >= --margin X_opt; --verify checks it with a short DEM sweep
    and gives a verdict (against the target, with one); --write-case OUT.toml writes the design
    as one case that sweep, fields and response run.

    Example: pdamper design --frequency 2Hz --stroke 10mm --length 120mm --width 40.4mm --sphere-radius 5mm

    Example: pdamper design --structure examples/frame_3hz.toml --mode 1 --force 1.5N

    Example: pdamper design --structure examples/frame_3hz.toml --force 1.5N --target-ratio 0.5 --length 80mm:160mm
    --write-case frame_design.toml
    """
    from ..design import design_filling
    from ..errors import InputError
    from ..params import Container

    radius = renamed(sphere_radius, radius, new="--sphere-radius", old="--radius")
    sizes = {"width": width, "radius": container_radius, **parse_sizes(sizes)}
    if structure_file is not None:
        return _design_structure(structure_file, dict(
            mode=mode_number, force=force, frequency=frequency, stroke=stroke, shape=shape, length=length,
            length_range=length_range, sizes=sizes, radius=radius, density=density, max_particles=max_particles,
            particles=particles, max_bed_mass=max_bed_mass, max_mass_ratio=max_mass_ratio, target_ratio=target_ratio,
            margin=margin, write_case=write_case, tilt=tilt), verify, verify_cycles, verify_strokes, seeds, workers,
            as_json)
    for name, value in (("--force", force), ("--length-range", length_range), ("--max-bed-mass", max_bed_mass),
                        ("--max-mass-ratio", max_mass_ratio), ("--particles", particles),
                        ("--target-ratio", target_ratio), ("--write-case", write_case)):
        if value is not None:
            raise InputError(f"{name} belongs to the design for a structure: give --structure STRUCT.toml with it "
                             "(or --frequency and --stroke without it)")
    if isinstance(length, tuple):
        raise InputError("--length LOW:HIGH (a range) belongs to the design for a structure: give --structure "
                         "STRUCT.toml with it, or one length, e.g. --length 120mm")
    for name, value in (("--frequency", frequency), ("--stroke", stroke)):
        if value is None:
            raise InputError(f"Missing option '{name}' (or give --structure STRUCT.toml --force F).")
    if radius is None:
        raise InputError("missing --sphere-radius (the sphere radius r, e.g. 5mm)")

    d = design_filling(frequency=frequency, stroke=stroke, sphere_radius=radius,
                       shape=shape if shape is not None else Container().geometry.shape, length=length,
                       sizes=sizes, max_particles=max_particles, tilt=tilt,
                       density=7900.0 if density is None else density)
    out = d.to_dict()
    if verify:
        out["verify"] = _verify(d, verify_cycles, workers, quiet=as_json)
    if as_json:
        echo_json(out)
        return
    mm = lambda x: f"{1e3 * x:.4g} mm"  # noqa: E731
    box = d.describe_container()
    rows = [
        ("filling", f"{d.particles} of {d.max_particles}", f"spheres, {d.rows} rows (exact {d.exact_particles:.3f})"),
        ("clearance h", mm(d.clearance_m), "eq. (6)"),
        ("X_opt", mm(d.x_opt_m), f"eq. (17); X/X_opt = {d.stroke_over_x_opt:.3f}"),
        ("expected eta*", f"{d.eta_star:.3f}", f"{d.regime} (eqs. 8/14)"),
        ("energy per cycle", f"{1e3 * d.energy_per_cycle_J:.4g} mJ", "pi eta* m_bed (X Omega)^2, eqs. (4), (5)"),
        ("bed mass", f"{1e3 * d.bed_mass_kg:.4g} g", f"{d.particles} x {1e3 * d.sphere_mass_kg:.3g} g"),
        ("acceleration", f"{d.acceleration_amplitude_m_s2:.3g} m/s^2",
         f"A = X Omega^2 (lift-off above {mm(d.max_stroke_no_liftoff_m)})"),
    ]
    lines = [f"pdamper design: X = {mm(d.stroke_m)} at f = {d.frequency_hz:.4g} Hz, {box}, "
             f"spheres r = {mm(d.sphere_radius_m)}"]
    lines += [f"  {name:<20}{value:<14}{note}" for name, value, note in rows]
    lines += [f"warning: {w}" for w in d.warnings]
    if verify:
        v = out["verify"]
        lines.append(f"  DEM check ({v['cycles']} cycles, {len(v['seeds'])} seeds):")
        for x, e, t in zip(v["strokes_m"], v["eta_star_mean"], v["eta_theory"]):
            lines.append(f"    X = {mm(x):>9}   eta* DEM {e:.3f}   theory {t:.3f}")
    click.echo("\n".join(lines))


def _verify(d, cycles, workers, quiet):
    """A short DEM sweep of the proposed filling at 0.9, 1, 1.1, 1.25 x the stroke (2 seeds)."""
    import numpy as np

    from .. import theory as th
    from ..excitation import HarmonicDrive
    from ..materials import STEEL_S235, Material
    from ..params import Case, Container, ParticleSet
    from ..studies import SweepSpec, run_sweep

    geo = d.container_geometry()
    mat = STEEL_S235 if d.density_kg_m3 == STEEL_S235.density else Material(
        name="spheres", youngs_modulus=STEEL_S235.youngs_modulus, poisson_ratio=STEEL_S235.poisson_ratio,
        density=d.density_kg_m3)
    paper = np.radians(0.1)
    tilt = (paper, paper, d.tilt_rad if d.tilt_rad is not None else paper)  # the given tilt as a pitch
    base = Case(particles=(ParticleSet(count=d.particles, radius=d.sphere_radius_m, material=mat),),
                container=Container(geometry=geo, tilt=tilt),
                drive=HarmonicDrive(stroke=d.stroke_m, frequency=d.frequency_hz), cycles=cycles, drop_cycles=2)
    strokes = d.stroke_m * np.array([0.9, 1.0, 1.1, 1.25])
    spec = SweepSpec(base=base, strokes=tuple(strokes), seeds=(0, 1))
    with tempfile.TemporaryDirectory(prefix="pdamper-design-") as tmp:
        ds = run_sweep(spec, f"{tmp}/store", workers=workers, progress=False if quiet else None)
        eta = ds.eta_star.mean("seed", skipna=True).values
        xs = ds.stroke.values
    return {"strokes_m": xs.tolist(), "eta_star_mean": eta.tolist(), "seeds": [0, 1], "cycles": cycles,
            "eta_theory": [float(th.eta_theory(x, d.clearance_m)) for x in xs]}


def _design_structure(structure_file, o: dict, verify, verify_cycles, verify_strokes, seeds, workers, as_json):
    """``pdamper design --structure``: the filling for a structure mode (the options ``o``), its
    report, the DEM check and the written case."""
    from ..design import design_case, design_case_text, design_container, design_for_structure, load_structure
    from ..errors import InputError
    from ..io.files import atomic_write

    for name, key in (("--frequency", "frequency"), ("--stroke", "stroke"), ("--max-particles", "max_particles"),
                      ("--tilt", "tilt")):
        if o[key] is not None:
            raise InputError(f"{name} does not apply with --structure: the design finds the stroke at the mode's "
                             "resonance and sizes the container's length along the drive (give --length or "
                             "--length LOW:HIGH, the other sizes, --sphere-radius)")
    force = o["force"]
    if force is None or not force > 0:
        raise InputError(f"--force{'' if force is None else f' = {force:g} N'}: give the force amplitude on the "
                         "structure at the mode's resonance, > 0, e.g. --force 1.5N")
    length, rng = o["length"], _length_range(o["length_range"]) if o["length_range"] is not None else None
    if isinstance(length, tuple):
        if rng is not None:
            raise InputError("give --length LOW:HIGH or --length-range LOW:HIGH, not both")
        length, rng = None, length
    if o["write_case"] is not None:
        _check_case_path(o["write_case"])
    case = load_structure(structure_file)
    geo = design_container(case, shape=o["shape"], sizes=o["sizes"])
    sphere = case.particles[0]
    sd = design_for_structure(case.drive, force=force, mode=o["mode"],
                              sphere_radius=o["radius"] if o["radius"] is not None else sphere.radius,
                              length=length, length_range=rng, container=geo, container_mass=case.container.mass,
                              particles=_particles_option(o["particles"]) if o["particles"] is not None else None,
                              max_bed_mass=o["max_bed_mass"], max_mass_ratio=o["max_mass_ratio"],
                              target_ratio=o["target_ratio"],
                              density=o["density"] if o["density"] is not None else sphere.material.density,
                              margin=o["margin"])
    out = sd.to_dict()
    out["structure_file"] = str(structure_file)
    if verify:
        out["verify"] = _verify_structure(sd, case, verify_cycles, verify_strokes, seeds, workers, quiet=as_json)
    if o["write_case"] is not None:
        from pathlib import Path

        path = Path(o["write_case"])
        text = design_case_text(sd, design_case(sd, case), command=_command_line(structure_file, o), name=path.name,
                                verify=out.get("verify"))
        atomic_write(path, text)
        out["case_file"] = str(path)
    if as_json:
        echo_json(out)
        return
    click.echo("\n".join(_design_structure_lines(sd, out, structure_file)))


def _check_case_path(path) -> None:
    """``--write-case`` names a .toml file in a folder that exists."""
    from pathlib import Path

    from ..errors import InputError

    p = Path(path)
    if p.suffix.lower() != ".toml":
        raise InputError(f"--write-case {path}: give a .toml file name, e.g. frame_design.toml")
    if not p.parent.is_dir():
        raise InputError(f"--write-case {path}: folder {str(p.parent)!r} does not exist; create it or choose another "
                         "path")


def _command_line(structure_file, o: dict) -> str:
    """The design's command with the options given (for the written case's header), quantities in
    the units a person types."""
    import shlex

    mm = lambda x: f"{x * 1e3:.6g}mm"  # noqa: E731
    length = o["length"] if o["length"] is not None else o["length_range"]
    words = ["pdamper design --structure", shlex.quote(str(structure_file)), f"--mode {o['mode']}",
             f"--force {o['force']:.6g}N"]
    given = [("--target-ratio", o["target_ratio"], "{:g}"), ("--shape", o["shape"], "{}"),
             ("--sphere-radius", o["radius"], None), ("--density", o["density"], "{:g}kg/m^3"),
             ("--particles", o["particles"], "{}"), ("--max-bed-mass", o["max_bed_mass"], None),
             ("--max-mass-ratio", o["max_mass_ratio"], "{:g}")]
    for name, value, fmt in given:
        if value is None:
            continue
        words.append(f"{name} " + (fmt.format(value) if fmt else (f"{value * 1e3:.6g}g" if "mass" in name
                                                                    else mm(value))))
    if length is not None:
        words.append("--length " + (":".join(mm(v) for v in length) if isinstance(length, tuple)
                                    else length if isinstance(length, str) else mm(length)))
    for key, value in o["sizes"].items():
        if value is not None:
            words.append(f"--size {key}={value if isinstance(value, str) else mm(value)}")
    if o["margin"] is not None:
        words.append(f"--margin {o['margin']:g}")
    return " ".join(words)


def _length_range(text: str):
    from ..errors import InputError
    from ..units import parse_quantity

    parts = str(text).split(":")
    if len(parts) != 2:
        raise InputError(f"--length-range {text!r}: write LOW:HIGH, e.g. 80mm:200mm")
    return tuple(parse_quantity(p, "length", name="--length-range") for p in parts)


def _design_structure_lines(sd, out, structure_file) -> list:
    from ..design import margin_note

    mm = lambda x: f"{1e3 * x:.4g} mm"  # noqa: E731
    pct = lambda z: f"{100 * z:.3g} %"  # noqa: E731
    d = sd.filling
    shaped = sd.modes > 1 or sd.phi_damper != 1.0
    lines = [f"pdamper design --structure {structure_file}: mode {sd.mode} of {sd.modes}, "
             f"M = {sd.mass_at_damper_kg:.4g} kg at the damper"
             + (f" (m / phi_d^2: modal mass m = {sd.modal_mass_kg:.4g} kg in the mode's normalisation)" if shaped
                else "") + (f", the empty container's {1e3 * sd.container_mass_kg:.4g} g included"
                            if sd.container_mass_kg > 0 else "")
             + f", f = {sd.natural_frequency_hz:.5g} Hz, zeta = {pct(sd.damping_ratio)}, F = {sd.force_N:.4g} N at "
             "resonance" + (f" (mode shape: damper {sd.phi_damper:.4g}, force {sd.phi_force:.4g}, response "
                            f"{sd.phi_response:.4g})" if shaped else ""),
             "  masses are physical, at the damper (the mode's own normalisation only where it says so)"]
    if sd.target_ratio is not None:
        b = sd.search
        lines.append(f"  target: ratio <= {sd.target_ratio:g} (resonant amplitude with the damper over without); the "
                     f"lightest filling that meets it among lengths {b['lengths_m'][0] * 1e3:.4g}-"
                     f"{b['lengths_m'][1] * 1e3:.4g} mm" + (f", fillings {b['particles'][0]}-{b['particles'][1]}"
                                                            if b["particles"][1] is not None else "")
                     + "".join(f", {k} {v * 1e3:.4g} g" for k, v in b["max_bed_mass_kg"].items())
                     + (f"; one sphere fewer: at best ratio {sd.lighter_ratio:.3g}" if sd.lighter_ratio is not None
                        else "; no lighter filling keeps the margin"))
    rows = [
        ("container", d.describe_container(), f"{sd.candidates} fillings tried"),
        ("filling", f"{d.particles} of {d.max_particles}", f"spheres r = {mm(d.sphere_radius_m)}, {d.rows} rows"),
        ("bed mass", f"{1e3 * d.bed_mass_kg:.4g} g", f"{pct(sd.mass_ratio)} of the mode's mass at the damper"),
        ("clearance h", mm(d.clearance_m), "eq. (6)"),
        ("X_opt", mm(d.x_opt_m), "eq. (17)"),
        ("damper stroke X", mm(sd.damper_stroke_m), f"X/X_opt = {sd.stroke_over_x_opt:.3f} (kept >= {sd.margin:.3g}: "
         "rolling collect-and-collide)"),
        ("eta*", f"{sd.eta_star:.3f}", "rolling law, eq. (14)"),
        ("energy per cycle", f"{1e3 * sd.energy_per_cycle_J:.4g} mJ", "pi eta* m_bed (X Omega)^2"),
        ("added mass", f"{1e3 * sd.effective_mass_kg:.4g} g",
         f"at the damper: the rolling bed's m_eff = {sd.effective_mass_kg / d.bed_mass_kg:.3g} m_bed (eqs. 10-12)"
         + (f"; phi_d^2 m_eff = {1e3 * sd.added_modal_mass_kg:.4g} g in the mode's normalisation" if
            sd.phi_damper != 1.0 else "")),
        ("resonance", f"{sd.frequency_hz:.5g} Hz", f"without damper {sd.natural_frequency_hz:.5g} Hz"),
        ("modal damping", pct(sd.zeta_total),
         f"= {pct(sd.zeta_structure)} structure + {pct(sd.zeta_damper)} damper (without: {pct(sd.zeta_bare)})"),
        ("amplitude, damper", mm(sd.amplitude_damper_m), f"without damper {mm(sd.amplitude_damper_bare_m)}, bed as a "
         f"solid mass {mm(sd.amplitude_damper_solid_m)}: ratio {sd.reduction:.3g}"),
    ]
    if sd.modes > 1 or sd.phi_response != sd.phi_damper:
        rows.append(("amplitude, response", mm(sd.amplitude_response_m),
                     f"without damper {mm(sd.amplitude_response_bare_m)} (the response point)"))
    rows.append(("acceleration", f"{d.acceleration_amplitude_m_s2:.3g} m/s^2",
                 f"A = X Omega^2 (lift-off above {mm(d.max_stroke_no_liftoff_m)})"))
    wv = max(16, *(len(value) + 2 for _, value, _ in rows))
    lines += [f"  {name:<20}{value:<{wv}}{note}" for name, value, note in rows]
    lines.append(f"  {margin_note(sd.margin, sd.margin_given, d.particles / d.max_particles)}")
    lines += [f"warning: {w}" for w in sd.warnings]
    if "verify" in out:
        v = out["verify"]
        lines.append(f"  DEM check at {sd.frequency_hz:.5g} Hz ({v['cycles']} cycles, {len(v['seeds'])} seeds):")
        for x, s, e, t, m, fr in zip(v["strokes_m"], v["stroke_over_x_opt"], v["eta_star_dem"], v["eta_star_law"],
                                     v["modes"], v["force_required_N"]):
            lines.append(f"    X = {mm(x):>9} ({s:.3g} X_opt)  eta* DEM {e:.3f}  law {t:.3f}  force needed "
                         f"{fr:.3g} N  {m or 'mode n/a'}")
        lines.append(f"  verdict: {v['verdict']}: {v['reason']}" + (f"; {v['move']}" if v["move"] else ""))
    if "case_file" in out:
        lines.append(f"  wrote {out['case_file']} (the damper, its rig [drive] and the [structure]: pdamper sweep, "
                     "fields, response run it)")
    return lines


def _verify_structure(sd, case, cycles, n_strokes, n_seeds, workers, quiet) -> dict:
    """The DEM check of a structure design: a sweep of the design's filling, driven at the design's
    resonance with strokes around its operating stroke, and the verdict (:func:`pdamper.design.judge_verification`)."""
    import dataclasses

    import numpy as np

    from ..analysis.modes import majority_mode
    from ..design import judge_verification, verify_factors
    from ..excitation import HarmonicDrive
    from ..studies import SweepSpec, run_sweep

    d = sd.filling
    sphere = case.particles[0]
    mat = sphere.material
    if mat.density != d.density_kg_m3:
        mat = dataclasses.replace(mat, density=d.density_kg_m3)
    base = dataclasses.replace(
        case, particles=(dataclasses.replace(sphere, count=d.particles, radius=d.sphere_radius_m, material=mat),),
        container=dataclasses.replace(case.container, geometry=d.container_geometry()),
        drive=HarmonicDrive(stroke=sd.damper_stroke_m, frequency=sd.frequency_hz), cycles=cycles,
        drop_cycles=2 if cycles >= 5 else 1)  # the record's whole cycles: one fewer than asked at an odd frequency
    strokes = [sd.damper_stroke_m * f for f in verify_factors(n_strokes)]
    seeds = tuple(range(n_seeds))
    spec = SweepSpec(base=base, strokes=tuple(strokes), seeds=seeds)
    with tempfile.TemporaryDirectory(prefix="pdamper-design-") as tmp:
        ds = run_sweep(spec, f"{tmp}/store", workers=workers, progress=False if quiet else None)
        eta = ds.eta_star.mean("seed", skipna=True).values
        xs = ds.stroke.values
        modes = ([majority_mode(ds["mode"].sel(stroke=x).values.ravel())[0] for x in xs] if "mode" in ds
                 else [""] * len(xs))
    out = judge_verification(sd, xs, eta, modes)
    out.update(seeds=list(seeds), cycles=cycles, eta_star_seeds=np.asarray(ds.eta_star.values).tolist())
    return out
