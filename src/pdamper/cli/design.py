"""``pdamper design``: the filling that puts a structure's stroke at the damper's optimum, or the
damper for a structure's mode (:mod:`pdamper.design`); options and printing only."""

from __future__ import annotations

import functools

import click

from ..errors import shown, shown_path
from .codes import mode_lines
from .common import Quantity, ShapeChoice, echo_json, main, parse_sizes, renamed, size_option, user_errors
from .ensemble import uncertain_options

__all__ = ["design_command", "design_option"]

#: The options of ``pdamper design`` by the design's parameters (:func:`pdamper.design.naming`).
_OPTIONS = {"force": "--force", "mode": "--mode", "target_ratio": "--target-ratio", "margin": "--margin",
            "length": "--length", "length_range": "--length", "width": "--width",
            "container_radius": "--container-radius", "sphere_radius": "--sphere-radius", "particles": "--particles",
            "max_bed_mass": "--max-bed-mass", "max_mass_ratio": "--max-mass-ratio", "strokes": "--verify-strokes",
            "cycles": "--verify-cycles", "verify": "--verify", "target_peak_ratio": "--target-peak-ratio",
            "target_rms_ratio": "--target-rms-ratio", "checks": "--checks", "dofs": "--dofs", "load": "--load",
            "robust": "--robust", "samples": "--samples", "unknowns": "--uncertain"}


def _in_its_options(func):
    """The command ``func`` with the design's messages in its options (:func:`pdamper.design.naming`)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        from ..design import naming

        with naming(design_option):
            return func(*args, **kwargs)

    return wrapper


def design_option(key: str) -> str:
    """The option of ``pdamper design`` that sets the design's parameter ``key`` (``sizes.KEY``,
    another [container] key: ``--size KEY=VALUE``)."""
    if key.startswith("sizes."):
        return size_option(key[len("sizes."):], {})
    return _OPTIONS.get(key, key)


class _LengthOrRange(Quantity):
    """A length, or a range of them written LOW:HIGH (a tuple of two SI floats)."""

    def __init__(self):
        super().__init__("length")

    def convert(self, value, param, ctx):
        if isinstance(value, str) and ":" in value:
            parts = value.split(":")
            if len(parts) != 2:
                raise click.UsageError(f"--{param.name} {shown(value)}: write one length or LOW:HIGH, e.g. 80mm:160mm", ctx)
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
        raise InputError(f"--particles {shown(text)}: give a number of spheres or LOW:HIGH, e.g. 36 or 20:60")
    return values[0] if len(values) == 1 else tuple(values)


@main.command("design")
@click.option("--structure", "structure_file", type=click.Path(dir_okay=False), metavar="STRUCT.toml",
              help="Design for a structure: a config whose [structure] section gives the mode(s) "
                   "(the stroke is then the design's answer; give --force, not --frequency/--stroke).")
@click.option("--mode", "mode_number", type=int, multiple=True,
              help="With --structure: the mode to damp (1 = the lowest) [default: 1]; repeat it for a damper per mode "
                   "(--mode 1 --mode 2: the structure's damper points, damper_dof = [..] / damper_nodes = [..], one "
                   "a mode, in that order).")
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
@click.option("--target-peak-ratio", type=float, metavar="R",
              help="With --structure and a [load] (or --load): the lightest filling whose coupled DEM transient cuts "
                   "the peak to this fraction of the bare structure's, e.g. 0.7 (at the damper point, or every --dofs).")
@click.option("--target-rms-ratio", type=float, metavar="R",
              help="With --structure and a [load]: the same for the RMS over the run, e.g. 0.6.")
@click.option("--dofs", "judged_dofs", metavar="DOFS",
              help="With --target-peak-ratio/--target-rms-ratio: the dofs the targets hold at, e.g. 2 or 0,2 (labels "
                   "and ranges as pdamper transient takes them; default: the damper point).")
@click.option("--load", "load_file", type=click.Path(dir_okay=False), metavar="FILE",
              help="With the targets: design against this load instead of the file's [load]: a record (.AT2, .csv: "
                   "a ground acceleration) or a TOML file with a [load] section (a suite: files = [...]).")
@click.option("--checks", type=click.IntRange(min=1), default=3, show_default=True,
              help="With the targets: the most coupled DEM transients (one per candidate; a suite: one a record each).")
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
@click.option("--robust", metavar="SHARE",
              help="With the targets and --uncertain U.toml: the lightest filling whose targets hold in at least this "
                   "share of --samples samples of the unknowns, e.g. 0.9 (each candidate's DEM ensemble at the same "
                   "samples; the share with its Wilson interval).")
@click.option("--plot", type=click.Path(dir_okay=False),
              help="With --robust: write the CDF of the design's peak ratio (RMS ratio with only its target) over the "
                   "samples against the target (png, svg, pdf).")
@click.option("--workers", type=click.IntRange(min=1),
              help="Local worker processes for --verify and --robust (default: all cores).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units).")
@uncertain_options(executor=False, store_default="<structure file's name>_robust, a store a candidate")
@user_errors
@_in_its_options
def design_command(structure_file, mode_number, force, frequency, stroke, shape, length, length_range, width,
                   container_radius, sizes, sphere_radius, radius, density, max_particles, particles, max_bed_mass,
                   max_mass_ratio, target_ratio, target_peak_ratio, target_rms_ratio, judged_dofs, load_file, checks,
                   margin, write_case, tilt, verify, verify_cycles, verify_strokes, seeds, robust, plot, workers,
                   as_json, ensemble):
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

    Against a load in time (--structure CASE with a [load], or --load FILE; --target-peak-ratio
    and/or --target-rms-ratio, at the damper point or every --dofs): candidates screened by the
    closed-form fields in the structure's equations in time, the lightest expected to meet the
    targets checked by coupled DEM transients (at most --checks), the lightest that meets them
    written by --write-case; a target no filling within the bounds meets is said so, with the
    best achievable and the reasons measured on its run.

    Example: pdamper design --structure examples/frame_3hz.toml --force 1.5N --target-ratio 0.5 --length 80mm:160mm
    --write-case frame_design.toml

    Example: pdamper design --structure examples/frame_quake.toml --target-peak-ratio 0.97 --target-rms-ratio 0.93
    --length 80mm:200mm --write-case quake_design.toml

    Robust (--robust SHARE --uncertain U.toml --samples N, with the targets): the lightest filling
    whose targets hold in at least SHARE of N Latin hypercube samples of the unknowns: the
    candidates screened at every sample, the lightest expected to reach the share run as DEM
    ensembles at the same samples (at most --checks), each a resumable store under --store; the
    share with its Wilson interval, the ratios' percentiles, and unmet the best share and the
    unknowns that drive the failures (docs/structure.md, "A robust design").

    Example: pdamper design --structure examples/frame_quake.toml --target-rms-ratio 0.97 --robust 0.8
    --uncertain examples/unknowns/frame_quake.toml --samples 16 --length 120mm:140mm
    """
    from ..design import design_filling, verify_filling
    from ..errors import InputError
    from ..params import Container

    radius = renamed(sphere_radius, radius, new="--sphere-radius", old="--radius")
    sizes = {"width": width, "radius": container_radius, **parse_sizes(sizes)}
    modes = tuple(mode_number) or (1,)
    if robust is not None or ensemble is not None:
        robust = _check_robust(robust, ensemble, (target_peak_ratio, target_rms_ratio))
    elif plot is not None:
        raise InputError("--plot belongs to the robust design (the CDF of its ratio over the samples): give --robust "
                         "SHARE and --uncertain U.toml with it")
    if target_peak_ratio is not None or target_rms_ratio is not None:
        if len(modes) > 1:
            raise InputError("--mode once with --target-peak-ratio / --target-rms-ratio: the design against a load in "
                             "time is for one damper (a damper per mode: --mode 1 --mode 2 --force F)")
        return _design_load(structure_file, dict(
            force=force, frequency=frequency, stroke=stroke, target_ratio=target_ratio, verify=verify or None,
            max_particles=max_particles, tilt=tilt, margin=margin, mode=modes[0] if mode_number else None),
            dict(target_peak_ratio=target_peak_ratio, target_rms_ratio=target_rms_ratio, dofs=judged_dofs,
                 shape=shape, sizes=sizes, sphere_radius=radius, density=density, length=length,
                 length_range=length_range, particles=particles, max_bed_mass=max_bed_mass,
                 max_mass_ratio=max_mass_ratio, checks=checks), load_file, write_case, as_json,
            robust=(robust, ensemble, plot, workers) if robust is not None else None)
    for name, value in (("--dofs", judged_dofs), ("--load", load_file)):
        if value is not None:
            raise InputError(f"{name} belongs to the design against a load in time: give --target-peak-ratio and/or "
                             "--target-rms-ratio with it")
    if structure_file is not None:
        if len(modes) > 1:
            return _design_several(structure_file, modes, force, write_case, as_json, dict(
                shape=shape, length=length, length_range=length_range, sizes=sizes, radius=radius, density=density,
                particles=particles, max_bed_mass=max_bed_mass, max_mass_ratio=max_mass_ratio,
                target_ratio=target_ratio, margin=margin), verify)
        return _design_structure(structure_file, dict(
            mode=modes[0], force=force, frequency=frequency, stroke=stroke, shape=shape, length=length,
            length_range=length_range, sizes=sizes, radius=radius, density=density, max_particles=max_particles,
            particles=particles, max_bed_mass=max_bed_mass, max_mass_ratio=max_mass_ratio, target_ratio=target_ratio,
            margin=margin, write_case=write_case, tilt=tilt), verify, verify_cycles, verify_strokes, seeds, workers,
            as_json)
    if len(modes) > 1 or mode_number:
        raise InputError("--mode belongs to the design for a structure: give --structure STRUCT.toml with it")
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
        out["verify"] = verify_filling(d, cycles=verify_cycles, workers=workers,
                                       progress=False if as_json else None).to_dict()
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


def _design_structure(structure_file, o: dict, verify, verify_cycles, verify_strokes, seeds, workers, as_json):
    """``pdamper design --structure``: the filling for a structure mode (the options ``o``), its
    report, the DEM check and the written case."""
    from ..design import design_case, design_case_text, design_for_case, load_structure, verify_design
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
    sd = design_for_case(case, force=force, shape=o["shape"], sizes=o["sizes"], sphere_radius=o["radius"],
                         density=o["density"], mode=o["mode"], length=length, length_range=rng,
                         particles=_particles_option(o["particles"]) if o["particles"] is not None else None,
                         max_bed_mass=o["max_bed_mass"], max_mass_ratio=o["max_mass_ratio"],
                         target_ratio=o["target_ratio"], margin=o["margin"])
    out = sd.to_dict()
    out["structure_file"] = str(structure_file)
    checked = None
    if verify:
        checked = verify_design(sd, case, cycles=verify_cycles, strokes=verify_strokes, seeds=seeds, workers=workers,
                                progress=False if as_json else None)
        out["verify"] = checked.to_dict()
    if o["write_case"] is not None:
        from pathlib import Path

        path = Path(o["write_case"])
        text = design_case_text(sd, design_case(sd, case), command=_command_line(structure_file, o), name=path.name,
                                verify=checked, dropped_load=case.drive.load)
        atomic_write(path, text)
        out["case_file"] = str(path)
    from ..studies.structure_base import mode_table

    out["mode_table"] = mode_table(case.running_drive)
    if as_json:
        echo_json(out)
        return
    lines = _design_structure_lines(sd, out, structure_file)
    lines[1:1] = mode_lines(out["mode_table"])
    click.echo("\n".join(lines))



def _design_several(structure_file, modes, force, write_case, as_json, o: dict, verify) -> None:
    """``pdamper design --structure S --mode 1 --mode 2``: a damper per mode at the structure's damper
    points (:func:`pdamper.design.design_for_modes`), printed, and written as one case."""
    from ..design import design_case_several, design_for_modes, load_structure
    from ..config import dumps_case
    from ..errors import InputError
    from ..io.files import atomic_write

    if verify:
        raise InputError("--verify checks one damper: run pdamper design --mode K --verify for each mode, or "
                         "pdamper response / transient on the case --write-case writes")
    if force is None or not force > 0:
        raise InputError("--force: give the force amplitude on the structure at each mode's resonance, > 0, e.g. "
                         "--force 1.5N")
    if write_case is not None:
        _check_case_path(write_case)
    length, rng = o["length"], _length_range(o["length_range"]) if o["length_range"] is not None else None
    if isinstance(length, tuple):
        length, rng = None, length
    case = load_structure(structure_file)
    sd = design_for_modes(case, force=force, modes=modes, shape=o["shape"], sizes=o["sizes"],
                          sphere_radius=o["radius"], density=o["density"], length=length, length_range=rng,
                          particles=_particles_option(o["particles"]) if o["particles"] is not None else None,
                          max_bed_mass=o["max_bed_mass"], max_mass_ratio=o["max_mass_ratio"],
                          target_ratio=o["target_ratio"], margin=o["margin"])
    out = dict(sd.to_dict(), structure_file=str(structure_file))
    lines = [f"pdamper design --structure {structure_file}: a damper per mode ({', '.join(map(str, modes))}), "
             f"F = {force:.4g} N at each mode's resonance, each designed for its mode alone at its damper point"]
    for k, d in enumerate(sd.designs):
        f = d.filling
        lines.append(f"  mode {d.mode} ({d.natural_frequency_hz:.4g} Hz) at damper point {k + 1}: {f.particles} "
                     f"spheres ({1e3 * f.bed_mass_kg:.4g} g, {100 * d.mass_ratio:.3g} % of the mode's mass there) in a "
                     f"{f.describe_container()}; stroke {1e3 * d.damper_stroke_m:.4g} mm, ratio {d.reduction:.3g}")
    if write_case is not None:
        from pathlib import Path

        path = Path(write_case)
        head = (f"# pdamper design: a damper per mode ({', '.join(map(str, modes))}) of {structure_file}, "
                f"F = {force:.6g} N; each [[damper]] designed for its mode alone.\n# Run it: pdamper response "
                f"{path.name} --frequencies {sd.designs[0].frequency_hz:.5g}Hz, pdamper transient {path.name}\n")
        atomic_write(path, head + dumps_case(design_case_several(sd, case), name=path.name))
        out["case_file"] = str(path)
        lines.append(f"  wrote {path}")
    if as_json:
        echo_json(out)
        return
    click.echo("\n".join(lines))


def _check_case_path(path) -> None:
    """``--write-case`` names a .toml file in a folder that exists."""
    from pathlib import Path

    from ..errors import InputError

    p = Path(path)
    if p.suffix.lower() != ".toml":
        raise InputError(f"--write-case {path}: give a .toml file name, e.g. frame_design.toml")
    if not p.parent.is_dir():
        raise InputError(f"--write-case {path}: folder {shown_path(p.parent)} does not exist; create it or choose another "
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
        raise InputError(f"--length-range {shown(text)}: write LOW:HIGH, e.g. 80mm:200mm")
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
                     "fields, response, transient run it)")
    return lines


def _check_robust(robust, ensemble, targets) -> float:
    """The robust design's options go together: --robust (the share, returned as a number),
    --uncertain and a target."""
    import math

    from ..errors import InputError

    if robust is None:
        raise InputError("--uncertain with design belongs to the robust design: give --robust SHARE and "
                         "--target-peak-ratio and/or --target-rms-ratio with it (the lightest filling whose targets "
                         "hold in that share of the samples); a design for a harmonic force is checked over the "
                         "unknowns by pdamper response on its --write-case: pdamper response DESIGN.toml "
                         "--uncertain U.toml")
    try:
        share = float(robust)
    except ValueError:
        share = math.nan
    if not 0 < share <= 1:
        raise InputError(f"--robust {robust}: give the share of the samples in which the targets must hold, above 0 "
                         "and at most 1 (e.g. 0.9: in 90 % of them)")
    if ensemble is None:
        raise InputError(f"--robust {robust} is a share of the samples of the unknowns: give --uncertain U.toml (the "
                         "unknowns) and --samples N with it")
    if all(t is None for t in targets):
        raise InputError(f"--robust {robust} is the share of the samples in which the targets hold: give "
                         "--target-peak-ratio and/or --target-rms-ratio with it (e.g. 0.7 and 0.6)")
    return share


def _design_load(structure_file, refused: dict, o: dict, load_file, write_case, as_json, robust=None):
    """``pdamper design --structure CASE --target-peak-ratio R --target-rms-ratio R``: the design
    against the case's load in time (:func:`pdamper.design.design_for_load`), printed, its case
    written."""
    from ..design import design_for_load, load_design_text, load_structure
    from ..errors import InputError
    from ..io.files import atomic_write
    from ..studies.transient import parse_dofs

    if structure_file is None:
        raise InputError("--target-peak-ratio / --target-rms-ratio design against a load in time: give --structure "
                         "CASE.toml (a [structure] with a [load], or --load FILE)")
    words = {"force": "--force", "frequency": "--frequency", "stroke": "--stroke", "target_ratio": "--target-ratio",
             "verify": "--verify", "max_particles": "--max-particles", "tilt": "--tilt", "margin": "--margin",
             "mode": "--mode"}
    for key, value in refused.items():
        if value is not None:
            raise InputError(f"{words[key]} does not apply to the design against a load in time (the targets are "
                             "judged on coupled DEM transients under the [load]); leave it out")
    if write_case is not None:
        _check_case_path(write_case)
    given = dict(o)
    length, rng = o.pop("length"), o.pop("length_range")
    rng = _length_range(rng) if rng is not None else None
    if isinstance(length, tuple):
        if rng is not None:
            raise InputError("give --length LOW:HIGH or --length-range LOW:HIGH, not both")
        length, rng = None, length
    case = load_structure(structure_file, load=load_file)
    o["dofs"] = parse_dofs(o["dofs"])
    o["particles"] = _particles_option(o["particles"]) if o["particles"] is not None else None
    if robust is not None:
        return _design_robust(structure_file, case, o, length, rng, given, load_file, write_case, as_json, *robust)
    td = design_for_load(case, length=length, length_range=rng, **o)
    out = td.to_dict()
    out["structure_file"] = str(structure_file)
    if write_case is not None:
        from pathlib import Path

        path = Path(write_case)
        command = _load_command_line(structure_file, td, given, load_file)
        atomic_write(path, load_design_text(td, case, command=command, name=path.name))
        out["case_file"] = str(path)
    if as_json:
        echo_json(out)
        return
    click.echo("\n".join(design_load_lines(td, out, structure_file)))


def _load_command_line(structure_file, td, o: dict, load_file) -> str:
    """The design's command with the options given (for the written case's header)."""
    import shlex

    mm = lambda x: f"{x * 1e3:.6g}mm"  # noqa: E731
    words = ["pdamper design --structure", shlex.quote(str(structure_file))]
    for name, value in (("--target-peak-ratio", td.target_peak_ratio), ("--target-rms-ratio", td.target_rms_ratio)):
        if value is not None:
            words.append(f"{name} {value:g}")
    if o["dofs"] is not None:
        words.append(f"--dofs {shlex.quote(str(o['dofs']))}")
    if load_file:
        words.append(f"--load {shlex.quote(str(load_file))}")
    length = o["length"] if o["length"] is not None else o["length_range"]
    if length is not None:
        words.append("--length " + (":".join(mm(v) for v in length) if isinstance(length, tuple)
                                    else length if isinstance(length, str) else mm(length)))
    for key, value in (o["sizes"] or {}).items():
        if value is not None:
            words.append(f"--size {key}={value if isinstance(value, str) else mm(value)}")
    for name, key, fmt in (("--shape", "shape", "{}"), ("--particles", "particles", "{}"),
                           ("--max-mass-ratio", "max_mass_ratio", "{:g}"), ("--density", "density", "{:g}kg/m^3")):
        if o[key] is not None:
            words.append(f"{name} {fmt.format(o[key])}")
    if o["sphere_radius"] is not None:
        words.append(f"--sphere-radius {mm(o['sphere_radius'])}")
    if o["max_bed_mass"] is not None:
        words.append(f"--max-bed-mass {o['max_bed_mass'] * 1e3:.6g}g")
    words.append(f"--checks {o['checks']}")
    return " ".join(words)


def _verdict_lines(met: bool, chosen, verdict: str, reasons: list) -> list:
    """The design's line (its bed, then ``verdict``), or unmet the reasons."""
    if met:
        return [f"  design                {chosen.particles} of {chosen.max_particles} spheres, "
                f"{chosen.bed_mass_kg * 1e3:.4g} g, in a {chosen.container} (X_opt = {1e3 * chosen.x_opt_m:.4g} mm): "
                + verdict]
    return ["  not met: " + reasons[0]] + [f"    why: {r}" for r in reasons[1:]]


def design_load_lines(td, out, structure_file) -> list:
    """The report of a design against a load in time (``td``: :class:`pdamper.design.TransientDesign`)."""
    words = lambda rs: ", ".join(f"{r:.3g}" for r in rs)  # noqa: E731
    aims = [f"peak ratio <= {td.target_peak_ratio:g}" if td.target_peak_ratio is not None else "",
            f"RMS ratio <= {td.target_rms_ratio:g}" if td.target_rms_ratio is not None else ""]
    b = td.search
    lines = [f"pdamper design --structure {structure_file}: against a load in time, {' and '.join(a for a in aims if a)} "
             f"(with / without the damper) at {', '.join(map(str, td.dofs))}",
             f"  load                  {td.load}" + (f" ({td.records} records: the ratio of the means)"
                                                     if td.records > 1 else ""),
             f"  structure             first mode {td.natural_frequency_hz:.5g} Hz, {td.mass_at_damper_kg:.4g} kg at the "
             "damper",
             f"  screened              {td.candidates} fillings (lengths {b['lengths_m'][0] * 1e3:.4g}-"
             f"{b['lengths_m'][1] * 1e3:.4g} mm" + "".join(f", {k} {v * 1e3:.4g} g" for k, v in
                                                            b["max_bed_mass_kg"].items())
             + f"): {td.screen_met} expected to meet the targets (closed-form fields in the structure's equations in "
             "time)",
             f"  DEM checks            {len(td.checks)} (at most {b['checks']}), lightest expected first:"]
    for c in td.checks:
        lines.append(f"    {c.particles:>4} of {c.max_particles:<4} {c.bed_mass_kg * 1e3:8.4g} g in {c.length_m * 1e3:6.4g} mm"
                     f"  peak {words(c.peak_ratio)} (screen {words(c.screen_peak_ratio)})  RMS {words(c.rms_ratio)} "
                     f"(screen {words(c.screen_rms_ratio)})  {'meets' if c.met else 'misses'}")
    chosen = td.design if td.met else td.best
    lines += _verdict_lines(td.met, chosen, f"peak ratio {words(chosen.peak_ratio)}, RMS ratio "
                            f"{words(chosen.rms_ratio)} (DEM): met", td.reasons)
    lines += [f"warning: {w}" for w in td.warnings]
    if "case_file" in out:
        lines.append(f"  wrote {out['case_file']} (the {'design' if td.met else 'best achievable'} with the [load]: "
                     "pdamper transient runs it)")
    return lines


def _design_robust(structure_file, case, o, length, rng, given, load_file, write_case, as_json, robust, ensemble, plot,
                   workers):
    """``pdamper design ... --robust SHARE --uncertain U.toml``: the robust design
    (:func:`pdamper.design.design_robust`), printed, its figures drawn, its case written."""
    import sys
    import warnings
    from pathlib import Path

    from ..design import design_robust, robust_design_text
    from ..io.files import atomic_write
    from ..plotting.figure import check_path
    from ..studies.ensemble import summary_lines

    check_path(plot)
    check_path(ensemble.tornado)
    store = Path(ensemble.store or f"{Path(structure_file).stem}_robust")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        rd = design_robust(case, ensemble.uncertain, robust=robust, samples=ensemble.samples,
                           sample_seed=ensemble.sample_seed, store=store, length=length, length_range=rng,
                           workers=workers, progress=False if as_json else None,
                           history="pdamper " + " ".join(sys.argv[1:]), **o)
    said = []
    for w in caught:
        if str(w.message) not in said:
            said.append(str(w.message))
            click.echo(f"warning: {w.message}", err=True)
    out = rd.to_dict()
    out["structure_file"] = str(structure_file)
    out["uncertain"] = str(ensemble.uncertain)
    chosen = rd.chosen
    if plot or ensemble.tornado:
        ds = chosen.dataset()
        if plot:
            from ..plotting.ensemble import cdf_figure

            q = "peak_ratio" if rd.target_peak_ratio is not None else "rms_ratio"
            cdf_figure(ds, plot, quantity=q, target=rd.target_peak_ratio if q == "peak_ratio" else rd.target_rms_ratio)
        if ensemble.tornado:
            from ..plotting.ensemble import tornado_figure

            q = chosen.drivers[0]["ratio"] if chosen.drivers else None
            tornado_figure(ds, ensemble.tornado, quantity=q)
    out["plot"], out["tornado"] = plot, ensemble.tornado
    if write_case is not None:
        path = Path(write_case)
        command = (_load_command_line(structure_file, rd, given, load_file)
                   + f" --robust {robust:g} --uncertain {ensemble.uncertain} --samples {ensemble.samples}"
                   + (f" --sample-seed {ensemble.sample_seed}" if ensemble.sample_seed else ""))
        atomic_write(path, robust_design_text(rd, case, command=command, name=path.name, uncertain=ensemble.uncertain))
        out["case_file"] = str(path)
    if as_json:
        echo_json(out)
        return
    click.echo("\n".join(design_robust_lines(rd, out, structure_file, summary_lines(chosen.summary))))


def design_robust_lines(rd, out, structure_file, ensemble_lines) -> list:
    """The report of a robust design (``rd``: :class:`pdamper.design.RobustDesign`); ``ensemble_lines``
    the chosen candidate's ensemble summary (:func:`pdamper.studies.ensemble.summary_lines`)."""
    pct = lambda x: f"{100 * x:.3g} %"  # noqa: E731
    aims = [f"peak ratio <= {rd.target_peak_ratio:g}" if rd.target_peak_ratio is not None else "",
            f"RMS ratio <= {rd.target_rms_ratio:g}" if rd.target_rms_ratio is not None else ""]
    b = rd.search
    lines = [f"pdamper design --structure {structure_file}: a robust design against a load in time, "
             f"{' and '.join(a for a in aims if a)} (with / without the damper) at {', '.join(map(str, rd.dofs))} in "
             f"at least {pct(rd.robust)} of {rd.samples} samples of {len(rd.unknowns)} unknown"
             f"{'s' if len(rd.unknowns) != 1 else ''} ({out['uncertain']})",
             f"  load                  {rd.load}",
             f"  structure             first mode {rd.natural_frequency_hz:.5g} Hz, {rd.mass_at_damper_kg:.4g} kg at "
             "the damper",
             f"  screened              {rd.candidates} fillings (lengths {b['lengths_m'][0] * 1e3:.4g}-"
             f"{b['lengths_m'][1] * 1e3:.4g} mm" + "".join(f", {k} {v * 1e3:.4g} g" for k, v in
                                                            b["max_bed_mass_kg"].items())
             + f") at each sample: {rd.screen_met} expected to meet the targets in {pct(rd.robust)} of them",
             f"  DEM ensembles         {len(rd.checks)} (at most {b['checks']}), lightest expected first, the same "
             f"{rd.samples} samples each:"]
    for c in rd.checks:
        lines.append(f"    {c.particles:>4} of {c.max_particles:<4} {c.bed_mass_kg * 1e3:8.4g} g in "
                     f"{c.length_m * 1e3:6.4g} mm  meets the targets in {c.met_samples:>3} of {c.samples}: "
                     f"{pct(c.share):>7} ({100 * c.confidence:.0f} % interval {pct(c.low)}-{pct(c.high)}; screen "
                     f"{pct(c.screen_share)})  {'reaches' if c.met else 'misses'} {pct(rd.robust)}")
    c = rd.chosen
    lines += _verdict_lines(rd.met, c, f"the targets hold in {pct(c.share)} of the samples ({100 * c.confidence:.0f} % "
                            f"interval {pct(c.low)}-{pct(c.high)}, Wilson): met", rd.reasons)
    lines.append(f"  the {'design' if rd.met else 'best achievable'}'s ensemble ({c.store}):")
    lines += ["  " + ln for ln in ensemble_lines]
    lines += [f"warning: {w}" for w in rd.warnings]
    figures = [p for p in (out.get("plot"), out.get("tornado")) if p]
    lines.append(f"  ensembles             {rd.store} (one store a candidate; a rerun resumes them)"
                 + "".join(f"; figure: {p}" for p in figures))
    if "case_file" in out:
        lines.append(f"  wrote {out['case_file']} (the {'design' if rd.met else 'best achievable'} with the [load]: "
                     "pdamper transient runs it)")
    return lines
