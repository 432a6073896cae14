"""``pdamper run``: simulate one case from a TOML config file and report eta* and the energies."""

from __future__ import annotations

import math
import sys

import click

from ..errors import InputError
from .common import (Quantity, device_option, echo_json, fraction_bar, main, parse_set, until_steady_option,
                     user_errors)
from .ensemble import uncertain_options

__all__ = ["run_command", "parse_set", "DEFAULT_FPS"]

#: Trajectory frames per second of ``--trajectory`` without ``--fps``.
DEFAULT_FPS = 100.0


@main.command("run")
@click.argument("config", metavar="CONFIG.toml")
@click.option("--stroke", type=Quantity("length"), help="Stroke X of the harmonic drive, e.g. 12mm.")
@click.option("--frequency", type=Quantity("frequency"), help="Drive frequency f, e.g. 2Hz.")
@click.option("--cycles", type=click.FloatRange(min=0, min_open=True),
              help="Drive cycles to simulate (the first [run] drop_cycles are not analysed).")
@click.option("--seed", type=click.IntRange(min=0), help="Seed of the initial jitter/scatter.")
@click.option("--integrator", type=click.Choice(["verlet", "gear"]), help="Time integrator.")
@click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE",
              help="Override any config key, e.g. --set particles.count=8 --set numerics.time_step=2us "
                   "(repeatable).")
@click.option("--trajectory", is_flag=True,
              help="Record particle trajectories (positions, velocities, spins) for pdamper animate/export.")
@click.option("--fps", type=Quantity("frequency"),
              help="Trajectory frames per second with --trajectory (default 100; a bare number is frames/s).")
@until_steady_option
@device_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units) instead of the table.")
@click.option("--out", "out_dir", type=click.Path(file_okay=False),
              help="Write the run directory (config.toml, signals.csv, energy.csv, result.json).")
@uncertain_options(eta=True)
@user_errors
def run_command(config, stroke, frequency, cycles, seed, integrator, settings, trajectory, fps, until_steady, device,
                as_json, out_dir, ensemble):
    """Simulate the particle damper of CONFIG.toml and print eta* and the energy per cycle.

    Options override the file's values; quantities take units (12mm, 2Hz). See
    examples/cuboid_36.toml for the config format.

    Every run also reports the bed's motion mode (docs/motion.md), measured on the recorded
    trajectory (a coarse one at 50 frames/s, 25 frames a cycle above 2 Hz, is recorded
    for it if none is asked for).

    With --uncertain U.toml --samples N: the case at N samples of the unknowns of U.toml
    (docs/ensembles.md): eta*'s percentiles, the share meeting --target-eta-star, which unknowns
    matter.

    Example: pdamper run examples/cuboid_36.toml --stroke 20mm --trajectory --out runs/x20
    """
    from ..config import load_case
    from ..rundir import check_run_dir, write_run
    from ..run import check_device, on_device, run_case

    overrides = parse_set(settings)
    for key, value in (("drive.stroke", stroke), ("drive.frequency", frequency), ("run.cycles", cycles),
                       ("initial.seed", seed), ("numerics.integrator", integrator)):
        if value is not None:
            if key == "run.cycles" and float(value).is_integer():
                value = int(value)
            overrides[key] = value
    if fps is not None and not trajectory:
        raise InputError("--fps sets the frame rate of --trajectory; add --trajectory")
    if fps is not None and not fps > 0:
        raise InputError(f"--fps {fps:g}: give a positive frame rate, e.g. 100 (frames per second)")
    if trajectory:
        overrides["recording.trajectory_fps"] = fps if fps is not None else DEFAULT_FPS
    case = load_case(config, overrides)
    if device is not None:
        case = on_device(case, device)
    check_device(case.numerics.device)  # no GPU: one line now, not after the setup
    if ensemble is not None:
        return _run_ensemble(ensemble, case, config, trajectory, out_dir, until_steady, as_json)
    if out_dir is not None:
        check_run_dir(out_dir)  # fail before a long run, not after it

    cycles = case.drive.counts_cycles
    total = float(case.cycles) if cycles else round(case.duration, 3)
    with fraction_bar("pdamper run", total, "cycle" if cycles else "s",
                      not as_json and sys.stderr.isatty()) as progress:
        result = run_case(case, progress=progress, until_steady=until_steady)
    written = write_run(result, out_dir) if out_dir is not None else None

    summary = result.summary()
    if as_json:
        echo_json({**summary, "config": str(config), "run_dir": str(written) if written else None})
        return
    click.echo(_table(config, case, summary, written, settings))


def _run_ensemble(ensemble, case, config, trajectory, out_dir, until_steady, as_json):
    """``run --uncertain``: the case at every sample (:func:`pdamper.cli.ensemble.run_uncertain`)."""
    from .ensemble import run_uncertain

    if trajectory or out_dir is not None:
        raise InputError(f"{'--trajectory' if trajectory else '--out'} belongs to one run; an ensemble keeps its "
                         "samples in its --store")
    run_uncertain(ensemble, case, config, study="run", as_json=as_json, until_steady=until_steady)


def _fmt(v, digits=4) -> str:
    if v is None or (isinstance(v, float) and not math.isfinite(v)):
        return "n/a"
    return f"{v:.{digits}g}"


def _describe(case) -> str:
    beds = " + ".join(f"{p.count} {p.material.name} r = {p.radius * 1e3:g} mm" for p in case.particles)
    d = case.drive
    if d.periodic:
        drive = f"{d.describe()}; {case.cycles:g} cycles, first {case.drop_cycles} dropped"
    else:
        drive = f"{d.describe()}, {case.duration:g} s"
    return f"{beds} in {case.container.describe()}; {drive}"


def _table(config, case, s, written, settings=()) -> str:
    from .codes import settings_line

    rows = [
        ("case", _describe(case), "", ""),
        ("eta*", _fmt(s["eta_star"]), "[-]", "reduced loss factor, eq. (5)"),
        ("", "", "", f"+- {_fmt(s.get('eta_star_error'), 2)} standard error over the cycles, "
                     f"{'steady' if s.get('steady') else 'NOT steady: run more cycles'}"
                     + (f"; stopped after {s['cycles_run']:g} cycles (--until-steady)"
                        if s.get("cycles_run", case.cycles) < case.cycles else "")),
        ("energy per cycle", _fmt(s["energy_per_cycle_J"] * 1e3), "[mJ]", "complex power, eq. (4)"),
        ("effective mass", _fmt(s.get("effective_mass_kg", math.nan) * 1e3), "[g]",
         f"of the bed, Im(P) / (1/2 Omega |V*|^2) - m_c; m_bed = {_fmt(s['bed_mass_kg'] * 1e3)} g, "
         f"container m_c = {_fmt(s.get('container_mass_kg', 0.0) * 1e3)} g"),
        ("equivalent damping", _fmt(s.get("equivalent_damping_N_s_per_m", math.nan)), "[N s/m]", "2 Re(P) / |V*|^2"),
        ("ledger dissipation", _fmt(s["ledger_dissipated_per_cycle_J"] * 1e3), "[mJ]",
         "per cycle, normal damping + friction"),
        ("energy balance error", _fmt(s["energy_balance_error"], 2), "[-]",
         "max |residual| / energy exchanged"),
        ("steps", f"{s['steps']:,}", "",
         f"{s['integrator']}, {'mean ' if s['integrator'] == 'gear' else ''}dt = {s['time_step_s'] * 1e6:.3g} us, "
         f"{s['neighbour_search']} search"),
        ("speed", _fmt(s["us_per_step"], 3), "[us/step]", f"{s['particles']} spheres"),
        ("wall time", _fmt(s["wall_time_s"], 3), "[s]", ""),
    ]
    at = 3  # where the motion mode goes: after eta* and its steadiness line
    if "damper_stroke_m" in s:
        # a coupled structure: no eta* (the complex power is for a prescribed harmonic drive)
        rows[1:6] = [
            ("structure amplitude", _fmt(s["structure_amplitude_m"] * 1e3), "[mm]",
             "response point, half peak-to-peak over the last period"),
            ("damper stroke", _fmt(s["damper_stroke_m"] * 1e3), "[mm]",
             f"the container, last period; largest {_fmt(s['damper_stroke_max_m'] * 1e3)} mm"),
            ("coupled ledger error", _fmt(s["coupled_energy_balance_error"], 2), "[-]",
             "structure + bed ledger, max |residual| / energy put in"),
        ]
        if s.get("truncation_error") is not None and math.isfinite(s["truncation_error"]):
            rows.insert(4, ("truncation error", _fmt(s["truncation_error"], 2), "[-]",
                            f"static compliance at the damper from the {s['modes_kept']} kept modes vs K^-1"))
        if s.get("modes_kept", 1) > 1:
            rows.insert(4, ("modes", str(s["modes_kept"]), "",
                            "f = " + ", ".join(f"{f:.4g}" for f in s["mode_frequencies_hz"]) + " Hz; zeta = "
                            + ", ".join(f"{100 * z:.3g}" for z in s["mode_damping_ratios"]) + " %"))
        at = 4 + ("truncation_error" in s) + (s.get("modes_kept", 1) > 1)
    if s.get("mode"):
        from ..analysis.modes import describe_features

        f = s.get("mode_features") or {}
        # after eta* and its steadiness line (which is about eta*, not about the mode)
        rows.insert(at, ("motion mode", s["mode"], "", ""))
        rows.insert(at + 1, ("", "", "", f"{describe_features(f)}; docs/motion.md"))
    if written is not None:
        rows.append(("run directory", str(written), "", ""))
    lines = [f"pdamper run {config}", *settings_line(settings)]
    for name, value, unit, note in rows:
        if name in ("case", "run directory", "motion mode"):
            lines.append(f"  {name:<21}{value}")
        elif not name:
            lines.append(f"  {'':<21}{note}")
        else:
            lines.append(f"  {name:<21}{value:<12}{unit:<11}{note}".rstrip())
    return "\n".join(lines)
