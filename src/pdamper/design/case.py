"""The case: a structure file read for the design, and the design written as one runnable case.

- :func:`load_structure` -- a case file with a ``[structure]`` section, read by
  :func:`pdamper.config.load_case` with the design's defaults (the paper's spheres and cuboid);
- :func:`design_container` -- the container the search starts from (the file's, sizes over it);
- :func:`design_for_case` -- :func:`~pdamper.design.search.design_for_structure` of a case's
  structure with its container and spheres;
- :func:`design_case`, :func:`design_case_text` -- the design as a :class:`~pdamper.params.Case`
  (the damper on its rig and the structure forced at the design's resonance) and as its TOML
  text with a header that says how it was designed.
"""

from __future__ import annotations

import dataclasses
import math

from ..errors import InputError, shown_path
from ..geometry import shape_from_keys
from .filling import Design, size_name
from . import names
from .search import StructureDesign, design_for_structure

__all__ = ["load_structure", "design_container", "design_for_case", "design_case", "design_case_text"]


def load_structure(path, overrides: dict | None = None, *, load=None):
    """The :class:`~pdamper.params.Case` of a structure file for the design: a config with a
    ``[structure]`` section (one mode: mass with stiffness or natural_frequency; or ``modes =
    [...]``; or ``matrices = ...``), read by :func:`pdamper.config.load_case`. A file with
    only ``[structure]`` is enough: ``[particles]`` defaults to the paper's 5 mm steel spheres
    (their count is the design's), ``[container]`` to the paper's cuboid, and a structure given
    without motion (no displacement, velocity or force) gets a nominal 1 mm start (the design
    does not use it; a ``force_amplitude`` of 0 N moves nothing either).

    ``load``: the load in time to design against instead of the file's ``[load]``: a record file
    (a ground acceleration: a PEER ``.AT2`` file, a CSV of ``time`` and ``acceleration``) or a TOML
    file whose ``[load]`` section is taken (its files relative to it)."""
    from ..config import load_case

    if load is None:
        return load_case(path, overrides, prepare=_structure_defaults)
    table = _load_table(load)

    def prepare(data):
        data = {**data, "load": table}
        if isinstance(data.get("structure"), dict):  # the load in time moves it, not the file's harmonic force
            data["structure"] = {k: v for k, v in data["structure"].items()
                                 if k not in ("force_amplitude", "force_frequency")}
        return _structure_defaults(data)

    return load_case(path, overrides, prepare=prepare)


def _load_table(path) -> dict:
    """The ``[load]`` table of ``path`` (:func:`load_structure`'s ``load``), its files absolute."""
    import tomllib
    from pathlib import Path

    p = Path(path)
    if not p.is_file():
        raise InputError(f"{names.name('load')} {shown_path(path)}: no such file; give a record (.AT2, .csv) or a TOML file "
                         "with a [load] section")
    if p.suffix.lower() != ".toml":
        return {"kind": "ground_acceleration", "file": str(p.resolve())}
    try:
        table = tomllib.loads(p.read_text(encoding="utf-8")).get("load")
    except (tomllib.TOMLDecodeError, UnicodeDecodeError, OSError) as exc:
        raise InputError(f"{names.name('load')} {shown_path(path)}: cannot be read as TOML ({exc})") from None
    if not isinstance(table, dict):
        raise InputError(f"{names.name('load')} {shown_path(path)}: the file has no [load] section")
    root = p.resolve().parent
    out = dict(table)
    for key in ("file", "files"):
        v = out.get(key)
        if isinstance(v, str) and v.strip():
            out[key] = str(Path(v) if Path(v).is_absolute() else root / v)
        elif key == "files" and isinstance(v, list):
            out[key] = [str(Path(x) if Path(x).is_absolute() else root / x) if isinstance(x, str) else x for x in v]
    return out


def _structure_defaults(data: dict) -> dict:
    """The tables of a structure file with the design's defaults (:func:`load_structure`)."""
    t = data.get("structure")
    if not isinstance(t, dict):
        raise InputError("no [structure] section; give the structure's mode, e.g. [structure] mass = '25kg', "
                         "natural_frequency = '3Hz', damping_ratio = 0.003 (or modes = [...], or matrices = "
                         "'frame.npz'; docs/structure.md)")
    data.setdefault("particles", {"count": 1})
    if "load" not in data and not any(_nonzero(t.get(k), k, dim) for k, dim in _MOVES):
        t["displacement"] = "1mm"  # nothing moves it (a 0 N force counts as none): the design's nominal start
    return data


#: The [structure] keys that move a structure, and their dimensions.
_MOVES = (("displacement", "length"), ("velocity", "velocity"), ("force_amplitude", "force"))


def _nonzero(value, key: str, dimension: str) -> bool:
    """Does the [structure] ``key``'s ``value`` move the structure? (Not given or 0: no; a value the
    reader will refuse: yes, so the reader says what is wrong with it.)"""
    if value is None:
        return False
    from ..schema import read_quantity

    try:
        return read_quantity(value, f"[structure] {key}", dimension) != 0
    except InputError:
        return True


def design_container(case, *, shape: str | None = None, sizes: dict | None = None):
    """The container a design for a structure starts from: the case's (``[container]`` of the
    structure file) with the given [container] ``sizes`` over it (None: not given), or, for another
    registered ``shape``, that shape with the sizes given. Its length along the drive is the
    design's to choose (its ``length`` or ``length_range``)."""
    from ..schema import config_keys

    geo = case.container.geometry
    if shape is None or shape == geo.shape:
        current = {k: getattr(geo, k) for k in config_keys(type(geo))}
        return shape_from_keys(geo.shape, {**current, **(sizes or {})}, option=size_name)
    return shape_from_keys(shape, sizes or {}, option=size_name, require=False)



def design_for_case(case, *, force: float, shape: str | None = None, sizes: dict | None = None,
                    sphere_radius: float | None = None, density: float | None = None, **search) -> StructureDesign:
    """The design for the structure of ``case`` (a structure file, :func:`load_structure`):
    :func:`~pdamper.design.search.design_for_structure` of its structure under ``force`` [N], in its
    container (another ``shape`` or ``sizes`` over it: :func:`design_container`) with the empty
    container's mass, with the case's spheres (their radius and density unless ``sphere_radius``
    [m] or ``density`` [kg/m^3] are given); ``search``: the search's other parameters (``mode``,
    ``length``, ``length_range``, ``particles``, ``max_bed_mass``, ``max_mass_ratio``,
    ``target_ratio``, ``margin``, ``kappa``, ``gravity``).

    >>> sd = design_for_case(load_structure("examples/frame_3hz.toml"), force=1.5)
    >>> sd.filling.particles, round(sd.reduction, 3)
    (36, 0.535)
    """
    geo = design_container(case, shape=shape, sizes=sizes)
    sphere = case.particles[0]
    return design_for_structure(case.drive, force=force,
                                sphere_radius=sphere_radius if sphere_radius is not None else sphere.radius,
                                container=geo, container_mass=case.container.mass,
                                density=density if density is not None else sphere.material.density, **search)


def _bed(case, d: Design) -> dict:
    """The fields of ``case`` that hold the design's bed ``d``: its spheres (the case's, in the
    design's count, radius and density) and its container (the design's)."""
    sphere = case.particles[0]
    mat = sphere.material
    if mat.density != d.density_kg_m3:
        mat = dataclasses.replace(mat, density=d.density_kg_m3)
    return {"particles": (dataclasses.replace(sphere, count=d.particles, radius=d.sphere_radius_m, material=mat),),
            "container": dataclasses.replace(case.container, geometry=d.container_geometry())}


def design_case(sd: StructureDesign, case, *, cycles: float | None = None):
    """The design ``sd`` as one runnable :class:`~pdamper.params.Case`: ``case`` (the structure
    file's: materials, contact, numerics) with the design's container (its length along the drive),
    filling and sphere density; its drive the structure forced by the design's force at the
    design's resonance, from rest; and the damper's rig drive beside it
    (:attr:`~pdamper.params.Case.rig`): the operating stroke at that frequency, along the
    structure's direction, which a sweep (and the fields made of it) runs. A load in time of the
    structure file (``[load]``) is dropped: the case is forced by the design's force, the load it
    was designed for (``pdamper transient`` runs that force from rest; :func:`design_case_text`
    says the ``[load]`` was left out).

    ``cycles`` (``[run] cycles``): forcing periods of a run; default five decay times of the
    damped mode, 5 / (2 pi zeta_total) rounded up to tens, so a response from rest is steady;
    ``drop_cycles`` the paper's 2 (what a sweep's analysis drops; a response measures its last cycles).
    """
    from ..excitation import HarmonicDrive

    f = round(sd.frequency_hz, 4)
    s = case.drive
    structure = dataclasses.replace(s, force_amplitude=sd.force_N, force_frequency=f, displacement=0.0, velocity=0.0,
                                    load=None)
    rig = HarmonicDrive(stroke=round(sd.damper_stroke_m, 7), frequency=f, angle=s.angle, direction=s.direction)
    if cycles is None:
        cycles = 10 * math.ceil(5.0 / (2 * math.pi * sd.zeta_total) / 10)
    return dataclasses.replace(case, **_bed(case, sd.filling), drive=structure, rig=rig, cycles=cycles, drop_cycles=2)


def design_case_text(sd: StructureDesign, case, *, command: str, name: str = "design.toml",
                     verify=None, dropped_load=None) -> str:
    """The TOML text of :func:`design_case` (``case``: that case) with a header that says how it
    was designed (``command``), the target, the predicted ratio, the margin, the DEM check's
    verdict (``verify``, a :class:`~pdamper.design.verify.Verification`, if run), the structure file's load in time left out (``dropped_load``,
    if it had one) and the commands it is meant for."""
    from .._version import __version__
    from ..config import dumps_case

    d = sd.filling
    mm = lambda x: f"{x * 1e3:.4g} mm"  # noqa: E731
    aim = (f"the lightest filling whose resonant amplitude is at most {sd.target_ratio:g} times the bare "
           "structure's" if sd.target_ratio is not None else "the filling with the smallest resonant amplitude")
    lines = [
        f"pdamper design (pdamper {__version__}): a particle damper and the structure it was designed for, in one "
        "case.",
        "",
        f"Designed by:  {command}",
        f"Aim:          {aim} (mode {sd.mode} of {sd.modes}, F = {sd.force_N:.4g} N at resonance)",
        f"Predicted:    ratio {sd.reduction:.3g}: the damper point swings {mm(sd.amplitude_damper_m)} at "
        f"{sd.frequency_hz:.5g} Hz, the bare structure {mm(sd.amplitude_damper_bare_m)} at "
        f"{sd.natural_frequency_hz:.5g} Hz (energy balance at resonance with the paper's closed forms)",
        f"The damper:   {d.particles} of {d.max_particles} spheres r = {mm(d.sphere_radius_m)} "
        f"({d.bed_mass_kg * 1e3:.4g} g, {100 * sd.mass_ratio:.3g} % of the mode's {sd.mass_at_damper_kg:.4g} kg at "
        f"the damper) in a {d.describe_container()}"
        + (f"; one sphere fewer gives at best ratio {sd.lighter_ratio:.3g}" if sd.lighter_ratio is not None else ""),
        f"Margin:       the operating stroke {mm(sd.damper_stroke_m)} is {sd.stroke_over_x_opt:.3g} X_opt "
        f"(X_opt = {mm(d.x_opt_m)}), kept >= {sd.margin:.3g} X_opt ("
        + (names.name("margin") if sd.margin_given else f"the default for a bed {100 * d.particles / d.max_particles:.3g} % "
           "filled, above the strokes at which the DEM checks saw such beds sway")
        + "; docs/structure.md, \"The margin\")",
    ]
    if verify is not None:
        lines.append(f"DEM check:    {verify.verdict}: {verify.reason}")
    else:
        lines.append("DEM check:    not run (pdamper design ... --verify)")
    if dropped_load is not None:
        lines += [f"Left out:     the structure file's [load] ({dropped_load.describe()}): this case is forced by F, the "
                  "load it was designed for;", "              to run `pdamper transient` under that load, set "
                  "[structure] force_amplitude = 0 and add the [load] back"]
    lo, hi = 0.4 * sd.damper_stroke_m, 1.6 * sd.damper_stroke_m
    f = case.drive.force_frequency
    stem = name[:-5] if name.endswith(".toml") else name
    lines += [
        "",
        "[drive] is the damper alone on its rig, at the operating stroke and the resonance: `pdamper sweep` runs",
        "it (the damper's eta* and fields). [structure] is the structure forced by F at the design's resonance,",
        "from rest: `pdamper response` and `pdamper transient` run it (and `pdamper decay` with --set",
        "structure.displacement=...). [run] cycles are forcing periods, about five decay times of the damped mode",
        "(a sweep takes --cycles of its own):",
        "",
        f"  pdamper response {name} --frequencies {f:.5g}Hz",
        f"  pdamper transient {name} --plot {stem}_transient.png",
        f"  pdamper sweep {name} --vary drive.stroke={lo * 1e3:.3g}mm:{hi * 1e3:.3g}mm:6 "
        f"--vary drive.frequency={0.97 * f:.4g}Hz,{f:.4g}Hz,{1.03 * f:.4g}Hz --seeds 2 --cycles 12 --out {stem}_sweep",
        f"  pdamper fields {stem}_sweep --out {stem}_fields.nc",
        f"  pdamper response {name} --fields {stem}_fields.nc --frequencies {0.99 * f:.4g}Hz:{1.01 * f:.4g}Hz:9",
        "",
    ]
    return "".join(f"# {line}".rstrip() + "\n" for line in lines) + "\n" + dumps_case(case, name=name)
