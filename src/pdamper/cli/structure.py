"""``pdamper decay``, ``pdamper response`` and ``pdamper design``: the damper on a structure,
and the filling that puts a structure's stroke at the damper's optimum."""

from __future__ import annotations

import math
import sys
import tempfile

import click

from .common import Quantity, echo_json, fraction_bar, main, renamed, user_errors
from .run import parse_set

__all__ = ["decay_command", "response_command", "design_command"]


def _load(config, settings, cycles, seed):
    from ..config import load_case

    overrides = parse_set(settings)
    if cycles is not None:
        overrides["run.cycles"] = int(cycles) if float(cycles).is_integer() else cycles
    if seed is not None:
        overrides["initial.seed"] = seed
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
@user_errors
def decay_command(config, cycles, seed, settings, plot, as_json):
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
        res = run_decay(case, progress=progress)
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
           + (f"; truncation error {s['truncation_error']:.2g}" if "truncation_error" in s else "")]
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
        f"  energy balance error  {s['energy_balance_error']:.2g}          (structure + bed)",
        f"  wall time             {s['wall_time_s']:.3g} s, {s['steps']:,} steps of {1e6 * s['time_step_s']:.3g} us",
    ]
    if plot:
        lines.append(f"  wrote {plot}")
    click.echo("\n".join(lines))


@main.command("response")
@_common
@click.option("--frequencies", default="1.8Hz:2.2Hz:9", show_default=True,
              help="LOW:HIGH:N (linear, both ends) or a list 1.9Hz,2Hz,2.1Hz.")
@click.option("--force", "force", type=Quantity("force"),
              help="Force amplitude F0 on the structure, e.g. 0.4N (default: [structure] force_amplitude).")
@click.option("--measure-cycles", type=click.IntRange(min=1), default=8, show_default=True,
              help="Last cycles of each run over which the steady amplitude is measured.")
@click.option("--workers", type=click.IntRange(min=1), default=1, show_default=True,
              help="Local worker processes (>1: the sweep executor, Dask).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on an existing Dask cluster.")
@user_errors
def response_command(config, cycles, seed, settings, plot, as_json, frequencies, force, measure_cycles,
                     workers, scheduler):
    """Frequency response of the structure of CONFIG.toml with and without the damper.

    At each frequency the structure starts from rest under F0 sin(2 pi f t) for the config's
    [run] cycles (of the forcing); the steady amplitude is the Fourier amplitude over the last
    --measure-cycles. Without the damper: closed form (and the bare structure run the same way);
    the bed as a solid mass: closed form.

    Example: pdamper response examples/structure_36.toml --force 0.4N --plot response.png
    """
    from ..errors import InputError
    from ..plotting.structure import response_figure
    from ..plotting.figure import check_path
    from ..studies.structure import parse_frequencies, run_response

    case = _load(config, settings, cycles, seed)
    check_path(plot)
    freqs = parse_frequencies(frequencies)
    f0 = force if force is not None else (case.drive.force_amplitude if case.drive.coupled else 0.0)
    if not f0 > 0:
        raise InputError("--force: give the force amplitude on the structure, e.g. --force 0.4N "
                         "([structure] force_amplitude is 0)")
    res = run_response(case, freqs, force_amplitude=f0, measure_cycles=measure_cycles, workers=workers,
                       scheduler=scheduler, progress=None if not as_json else False)
    s = _report(res, case, config, plot, response_figure, as_json)
    if s is None:
        return
    lines = [f"pdamper response {config}  (F0 = {f0:.4g} N, {s['particles']} spheres, "
             f"{100 * s['mass_ratio']:.3g} % of M; {s['measure_cycles']} of {s['cycles']:g} cycles measured)",
             f"  {'f [Hz]':>8}  {'damper [mm]':>12}  {'bare [mm]':>10}  {'bare run [mm]':>13}  {'solid mass [mm]':>15}"]
    for k, f in enumerate(s["frequencies_hz"]):
        lines.append(f"  {f:8.4g}  {1e3 * s['amplitude_damped_m'][k]:12.4g}  {1e3 * s['amplitude_bare_m'][k]:10.4g}  "
                     f"{1e3 * s['amplitude_bare_run_m'][k]:13.4g}  {1e3 * s['amplitude_solid_mass_m'][k]:15.4g}")
    lines.append(f"  peak with damper {1e3 * s['peak_damped_m']:.4g} mm at {s['peak_damped_frequency_hz']:.4g} Hz; "
                 f"without {1e3 * s['peak_bare_m']:.4g} mm on this grid (resonance {1e3 * s['resonance_bare_m']:.4g} mm): "
                 f"ratio {s['peak_reduction']:.3g}")
    lines.append(f"  energy balance error (worst point) {s['energy_balance_error_max']:.2g}; "
                 f"DEM time {s['wall_time_s']:.3g} s")
    for f, msg in s["failed"].items():
        lines.append(f"  failed at {f} Hz: {msg}")
    if plot:
        lines.append(f"  wrote {plot}")
    click.echo("\n".join(lines))


@main.command("design")
@click.option("--frequency", type=Quantity("frequency"), required=True, help="Structure's frequency, e.g. 2Hz.")
@click.option("--stroke", type=Quantity("length"), required=True,
              help="Stroke (amplitude) of the structure where the damper sits, e.g. 10mm.")
@click.option("--shape", type=click.Choice(["cuboid", "cylinder"]), default="cuboid", show_default=True)
@click.option("--length", type=Quantity("length"), help="Cuboid: inner length along the motion, e.g. 120mm.")
@click.option("--width", type=Quantity("length"), help="Cuboid: inner width, e.g. 40.4mm.")
@click.option("--container-radius", type=Quantity("length"), help="Cylinder: inner radius R, e.g. 39mm.")
@click.option("--sphere-radius", type=Quantity("length"), help="Sphere radius r, e.g. 5mm (required).")
@click.option("--radius", type=Quantity("length"), hidden=True, help="Old name of --sphere-radius.")
@click.option("--density", type=Quantity("density"), default=7900.0, show_default=True,
              help="Sphere density [kg/m^3] (steel).")
@click.option("--max-particles", type=click.IntRange(min=2),
              help="Spheres covering the floor in one layer (default: the floor packing of the container).")
@click.option("--tilt", type=Quantity("angle"), help="Expected mounting tilt, e.g. 1deg.")
@click.option("--verify", is_flag=True, help="Run a short DEM sweep around the stroke with the proposed filling.")
@click.option("--verify-cycles", type=click.IntRange(min=3), default=8, show_default=True,
              help="Drive cycles per verification case (the first 2 dropped).")
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes for --verify (default: all cores).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units).")
@user_errors
def design_command(frequency, stroke, shape, length, width, container_radius, sphere_radius, radius, density,
                   max_particles, tilt, verify, verify_cycles, workers, as_json):
    """The filling (N_p of N_p,max) that puts the structure's stroke at the damper's optimum X_opt.

    Inverts eqs. (6), (17): h = X / 0.4075, N_p = N_p,max (1 - h/L), rounded up so that X is at
    or just above X_opt (the largest eta* of the paper's laws). Reports the expected eta*,
    energy per cycle and bed mass, and warns about lift-off, tilt sensitivity and thin beds.

    Example: pdamper design --frequency 2Hz --stroke 10mm --length 120mm --width 40.4mm --sphere-radius 5mm
    """
    from ..design import design_filling
    from ..errors import InputError

    radius = renamed(sphere_radius, radius, new="--sphere-radius", old="--radius")
    if radius is None:
        raise InputError("missing --sphere-radius (the sphere radius r, e.g. 5mm)")

    d = design_filling(frequency=frequency, stroke=stroke, sphere_radius=radius, shape=shape, length=length,
                       width=width, container_radius=container_radius, max_particles=max_particles, tilt=tilt,
                       density=density)
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
