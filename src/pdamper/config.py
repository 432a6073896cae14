"""Case configuration files (TOML): read one into a :class:`pdamper.params.Case`, write one back.

A config file has the sections below; every section and key is optional and defaults to the
paper's values (the :class:`~pdamper.params.Case` defaults), except ``[particles] count``.
Quantities are written as a person types them (``"120mm"``, ``"2Hz"``, ``"0.1deg"``,
``"208GPa"``, ``"7900kg/m^3"``) or as plain SI numbers (m, s, Hz, kg, rad, Pa, kg/m^3, m/s)::

    [container]
    shape = "cuboid"            # or "cylinder"
    length = "120mm"            # cuboid: length (along the drive), width, height
    width = "40.4mm"
    height = "40mm"             # cylinder: radius, height
    material = "pvc"            # a name from pdamper.materials.LIBRARY, or an inline table
                                # {name=..., youngs_modulus=..., poisson_ratio=..., density=...}
    tilt = ["0.1deg", "0.1deg", "0.1deg"]   # about x, y, z (applied in that order); one value: all three
    mass = "0kg"

    [particles]                 # one species; [[particles]] tables for a mixed bed
    count = 36                  # required
    radius = "5mm"
    material = "steel"

    [drive]                     # harmonic x_c = X sin(2 pi f t) ...
    stroke = "12mm"
    frequency = "2Hz"
    angle = "0deg"
    # ... or a sampled motion: samples = "motion.csv" (columns time, position[, velocity],
    # units in brackets, path relative to the config file), or inline arrays
    # time = [...], position = [...][, velocity = [...]]; frequency is then optional.
    # ... or a container at rest: kind = "still", duration = "1s".

    [contact]
    friction = 0.1
    restitution = 0.9           # or {law = "table", speeds = [...], values = [...]}
                                # or {law = "thornton", yield_pressure = "1.5GPa"}
    tau = 1000                  # friction smoothing [s/m]
    v_in_floor = "1mm/s"
    damping = "calibrated"      # or "gonthier" (the paper's d as written)
    [[contact.pair]]            # optional, per material pair
    materials = ["steel", "pvc"]
    friction = 0.2
    restitution = 0.8

    [numerics]                  # integrator, time_step ("auto" or a time), steps_per_contact,
                                # max_impact_speed ("auto" or a speed), max_time_step,
                                # gear_tolerance, neighbour_search, skin ("auto" or a length),
                                # overlap_limit
    [recording]                 # sample_rate, trajectory_fps
    [initial]                   # arrangement, jitter, seed, settle_time, layers, and optional
                                # per-sphere rows [x, y, z]: positions, velocities, spins [rad/s]
    [run]                       # cycles, drop_cycles, gravity

    [structure]                 # instead of [drive]: the container rides on a structure
    mass = "7kg"                # modal mass incl. the empty container (see docs/structure.md)
    natural_frequency = "2Hz"   # or stiffness = 1105 (N/m)
    damping_ratio = 0.005
    displacement = "12mm"       # initial; and/or force_amplitude = "0.5N", force_frequency = "2Hz"

:func:`load_case` reads a file (with optional overrides such as ``{"drive.stroke": "3mm"}``, the
command line's ``--set``, applied to the file's tables before they are read);
:func:`case_to_dict` / :func:`dump_case` write a case back in plain SI numbers, so that
``load_case(dump_case(case, p)) == case`` exactly. Every problem raises
:class:`pdamper.errors.InputError` naming the file, the section and the key.
A case in hand is changed by config keys with :func:`pdamper.schema.replace` (also
:func:`with_overrides`), which reads each value as this module does.

The keys are the parameter dataclasses' own fields, read and written from the spec each field
carries (:mod:`pdamper.schema`); this module adds only what no field can say (which class a
section builds, keys that are not fields, the restitution-law tables).
"""

from __future__ import annotations

import csv
import dataclasses
import difflib
import math
import tomllib
from collections.abc import Mapping
from pathlib import Path

from .contact import read_restitution
from .contact.cor_constant import ConstantRestitution
from .contact.cor_table import TabulatedRestitution
from .contact.cor_thornton import ThorntonRestitution
from .errors import InputError
from .io.files import atomic_write
from .excitation import DRIVES
from .geometry import SHAPES
from .materials import LIBRARY, Material, read_material
from .params import (Case, Container, ContactModel, InitialState, Numerics, ParticleSet, Recording, read_baffles,
                     read_tilt, read_wall_materials, read_with_material)
from .schema import (Spec, _choice, _grammar, _quoted, check_keys, config_keys, plain_fields, read_fields,
                     read_number, read_quantity, replace, spec_of, suggest)
from .units import unit_factor

__all__ = ["load_case", "loads_case", "case_from_dict", "case_to_dict", "dump_case", "dumps_case",
           "with_overrides", "key_spec", "SECTIONS"]

# The sections are read from the parameter dataclasses' own fields (pdamper.schema): a field's
# spec says its dimension, allowed values and key. What is written here by hand is only the
# structure no field can say: which class a section builds (a container shape, a drive kind),
# and keys that are not fields (a samples file, a natural frequency instead of a stiffness,
# per-material-pair tables).
_GEOMETRIES = SHAPES
_DRIVES = {kind: cls for kind, cls in DRIVES.items() if cls.config_section == "drive"}
#: The drives the [structure] section builds: the single mode (mass, stiffness) first, then the
#: modal structure (modes or matrices); the reader decides from the keys.
_STRUCTURES = tuple(cls for cls in DRIVES.values() if cls.config_section == "structure")
_STRUCTURE = _STRUCTURES[0]
_MODAL = next(cls for cls in _STRUCTURES if "modes" in config_keys(cls))


def _shape_keys() -> dict:
    """The config keys of each registered shape (read when asked: a shape may register later)."""
    return {shape: config_keys(cls) for shape, cls in _GEOMETRIES.items()}


#: Keys that only one kind of drive has (a key of another kind is an error).
_DRIVE_OWN = {kind: tuple(k for k in config_keys(cls)
                          if not any(k in config_keys(o) for o in _DRIVES.values() if o is not cls))
              for kind, cls in _DRIVES.items()}
_DRIVE_OWN["samples"] = ("samples",) + _DRIVE_OWN["samples"]
_SAMPLED_KEYS = _DRIVE_OWN["samples"]


def _union(*groups) -> tuple:
    return tuple(dict.fromkeys(k for g in groups for k in g))


class _Sections(Mapping):
    """Allowed keys of each section, derived from the dataclasses' fields (the container's from
    the shapes registered when asked)."""

    def __init__(self, fixed: dict):
        self._fixed = fixed

    def _container(self) -> tuple:
        return _union(("shape",), *_shape_keys().values(), config_keys(Container, drop=("geometry",)))

    def __getitem__(self, section):
        return self._container() if section == "container" else self._fixed[section]

    def __iter__(self):
        return iter(("container", *self._fixed))

    def __len__(self):
        return len(self._fixed) + 1


#: Allowed keys of each section, derived from the dataclasses' fields.
SECTIONS = _Sections({
    "particles": config_keys(ParticleSet),
    "drive": _union(("kind",), *(config_keys(cls) for cls in _DRIVES.values()), ("samples",)),
    "contact": config_keys(ContactModel, drop=("pair_friction", "pair_restitution")) + ("pair",),
    "numerics": config_keys(Numerics),
    "recording": config_keys(Recording),
    "initial": config_keys(InitialState),
    "run": tuple(s.key or f.name for f, s in plain_fields(Case)),
    "structure": _union(config_keys(_STRUCTURE), ("natural_frequency",), config_keys(_MODAL)),
})
_PAIR_KEYS = ("materials", "friction", "restitution")


# --------------------------------------------------------------------------- reading

def load_case(path, overrides: dict | None = None) -> Case:
    """Read the TOML config file ``path`` into a :class:`~pdamper.params.Case`.

    ``overrides`` maps dotted keys to values that replace (or add to) the file's, e.g.
    ``{"drive.stroke": 0.012, "drive.frequency": "2Hz", "run.cycles": 20, "initial.seed": 3}``;
    values are read exactly like the file's (SI numbers or strings with units).
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"config file not found: {path}")
    if path.is_dir():
        raise InputError(f"{path} is a directory; give a .toml config file")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"cannot read config file {path}: {exc}") from None
    return loads_case(text, overrides, source=str(path), base_dir=path.parent)


def loads_case(text: str, overrides: dict | None = None, *, source: str = "<config>",
               base_dir=None) -> Case:
    """Like :func:`load_case` for TOML ``text``; ``base_dir`` resolves relative sample files."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source}: invalid TOML: {exc}; check the syntax (key = value, "
                         "strings in quotes, [section] headers)") from None
    return case_from_dict(data, overrides, source=source, base_dir=base_dir)


def case_from_dict(data: dict, overrides: dict | None = None, *, source: str | None = None,
                   base_dir=None) -> Case:
    """Build a :class:`~pdamper.params.Case` from a parsed config ``data`` (see the module docstring)."""
    data = _apply_overrides(_copy(data), overrides or {})
    try:
        return _Reader(Path(base_dir) if base_dir is not None else Path.cwd()).case(data)
    except InputError as exc:
        if source is None:
            raise
        raise InputError(f"{source}: {exc}") from None


def _copy(obj):
    if isinstance(obj, dict):
        return {k: _copy(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_copy(v) for v in obj]
    return obj


#: The parameter classes whose fields make each section's keys.
_SECTION_CLASSES = {
    "container": (Container,), "particles": (ParticleSet,), "drive": tuple(_DRIVES.values()),
    "contact": (ContactModel,), "numerics": (Numerics,), "recording": (Recording,), "initial": (InitialState,),
    "run": (Case,), "structure": _STRUCTURES,
}
#: Specs of the structured keys that also take one plain value (a constant COR; one tilt angle for all axes).
_VALUE_SPECS = {"contact.restitution": Spec(kind="number"), "container.tilt": Spec(kind="number", dimension="angle")}


def key_spec(dotted: str) -> Spec:
    """The :class:`~pdamper.schema.Spec` of a config key written ``section.key`` (what a sweep axis
    over it holds), or an :class:`InputError` naming the allowed keys."""
    section, _, key = str(dotted).partition(".")
    if section not in SECTIONS:
        raise InputError(f"{dotted!r}: unknown section [{section}]; " + suggest(section, SECTIONS, "[{}]"))
    if key not in SECTIONS[section]:
        raise InputError(f"{dotted!r}: unknown key {key!r} in [{section}]; " + _quoted(key, SECTIONS[section]))
    if dotted in _VALUE_SPECS:
        return _VALUE_SPECS[dotted]
    classes = (*_GEOMETRIES.values(), *_SECTION_CLASSES[section]) if section == "container" else _SECTION_CLASSES[section]
    for cls in classes:
        for f, s in plain_fields(cls):
            if (s.key or f.name) == key:
                return s
    raise InputError(f"{dotted!r} is not a single value (a table or a list); it cannot be a sweep axis")


def with_overrides(case: Case, overrides: dict) -> Case:
    """``case`` with the dotted keys of ``overrides`` replaced, e.g. ``{"contact.friction": 1.0,
    "drive.stroke": "3mm", "particles.material": Material(...)}``: :func:`pdamper.schema.replace`
    (values read exactly like a config file's, with the same messages; parameter objects as they
    are; keys not given keep their values, the same objects). A parameter class's message names
    the key as a config file has it (``[run] gravity``)."""
    try:
        return replace(case, overrides)
    except InputError as exc:
        raise InputError(_as_key(str(exc))) from None


def _apply_overrides(data: dict, overrides: dict) -> dict:
    for dotted, value in overrides.items():
        parts = str(dotted).split(".")
        if len(parts) != 2 or not all(parts):
            raise InputError(f"override {dotted!r}: write it as 'section.key', e.g. 'drive.stroke'")
        section, key = parts
        if section not in SECTIONS:
            raise InputError(f"override {dotted!r}: unknown section [{section}]; "
                             + suggest(section, SECTIONS, "[{}]"))
        if key not in SECTIONS[section]:
            raise InputError(f"override {dotted!r}: unknown key {key!r} in [{section}]; "
                             + _quoted(key, SECTIONS[section]))
        table = data.setdefault(section, {})
        if isinstance(table, list):
            if len(table) != 1:
                raise InputError(f"override {dotted!r}: the config has {len(table)} [[{section}]] tables; "
                                 "edit the file to change one of them")
            table = table[0]
        if not isinstance(table, dict):
            raise InputError(f"[{section}] must be a table (a [{section}] header with key = value lines)")
        if section == "drive" and key in ("stroke",) and any(k in table for k in _SAMPLED_KEYS):
            raise InputError(f"override {dotted!r}: the drive is given as samples; a stroke applies to a "
                             "harmonic drive only")
        table[key] = value
    return data


class _Reader:
    """Turns the parsed TOML tables into parameter objects, one section at a time; every plain key
    is read by its field's spec (:func:`pdamper.schema.read_fields`), a material, a restitution law
    and a tilt by their fields' readers."""

    fields = staticmethod(read_fields)

    def __init__(self, base_dir: Path):
        self.base_dir = base_dir

    @staticmethod
    def _table(data, section):
        t = data.get(section, {})
        if not isinstance(t, dict):
            raise InputError(f"[{section}] must be a table (a [{section}] header with key = value lines), "
                             f"got {t!r}")
        return t

    @staticmethod
    def _choice(table, section, key, choices, default):
        return _choice(table[key], f"[{section}] {key}", choices) if key in table else default

    # ---- sections
    def case(self, data: dict) -> Case:
        for section in data:
            if section not in SECTIONS:
                raise InputError(f"unknown section [{section}]; " + suggest(section, SECTIONS, "[{}]"))
        with _context("container"):
            container = self.container(self._table(data, "container"))
        with _context("particles"):
            particles = self.particles(data.get("particles"))
        if "structure" in data:
            with _context("structure"):
                drive = self.structure(self._table(data, "structure"), self._table(data, "drive"))
        else:
            with _context("drive"):
                drive = self.drive(self._table(data, "drive"))
        mats = [p.material for p in particles] + [container.material]
        for m in mats:
            if any(o.name == m.name and o != m for o in mats):
                raise InputError(f"two different materials are both named {m.name!r}; contacts are looked up by "
                                 "material name, so give each inline material its own name = '...'")
        names = [m.name for m in mats]
        with _context("contact"):
            contact = self.contact(self._table(data, "contact"), names)
        sections = {}
        for section, cls in (("numerics", Numerics), ("recording", Recording), ("initial", InitialState)):
            with _context(section):
                sections[section] = self.flat(self._table(data, section), section, cls)
        with _context("run"):
            run = self._table(data, "run")
            check_keys(run, "run", SECTIONS["run"])
            return Case(particles=particles, container=container, drive=drive, contact=contact, **sections,
                        **read_fields(run, "run", Case))

    def container(self, t) -> Container:
        check_keys(t, "container", SECTIONS["container"])
        shape = self._choice(t, "container", "shape", tuple(_GEOMETRIES), "cuboid")
        shape_keys = _shape_keys()
        for key in t:
            owners = [s for s, keys in shape_keys.items() if key in keys]
            if owners and shape not in owners:
                raise InputError(f"[container] {key} applies to shape = {owners[0]!r}, but shape = {shape!r} "
                                 f"(give {', '.join(shape_keys[shape])})")
        kw = {"geometry": _GEOMETRIES[shape](**read_fields(t, "container", _GEOMETRIES[shape]))}
        if "material" in t:
            kw["material"] = read_material(t["material"], "container")
        if "baffles" in t:
            kw["baffles"] = read_baffles(t["baffles"], "container")
        if "wall_materials" in t:
            kw["wall_materials"] = read_wall_materials(t["wall_materials"], "container")
        if "tilt" in t:
            kw["tilt"] = read_tilt(t["tilt"], "container")
        kw.update(read_fields(t, "container", Container))
        return Container(**kw)

    def particles(self, value) -> tuple:
        if value is None:
            raise InputError("missing section [particles]; give at least the number of spheres, e.g. "
                             "[particles] count = 36")
        tables = value if isinstance(value, list) else [value]
        if not tables:
            raise InputError("[[particles]] is empty; give at least one table with count = ...")
        out = []
        for k, t in enumerate(tables):
            label = "particles" if len(tables) == 1 else f"particles #{k + 1}"
            if not isinstance(t, dict):
                raise InputError(f"[{label}] must be a table, got {t!r}")
            out.append(read_with_material(t, label, ParticleSet, required="count",
                                          hint="; give the number of spheres, e.g. count = 36"))
        return tuple(out)

    def drive(self, t):
        check_keys(t, "drive", SECTIONS["drive"])
        sampled = [k for k in _SAMPLED_KEYS if k in t]
        kind = self._choice(t, "drive", "kind", tuple(_DRIVES),
                           "samples" if sampled else ("still" if "duration" in t else "harmonic"))
        for other, keys in _DRIVE_OWN.items():
            given = [k for k in keys if k in t]
            if other != kind and given:
                raise InputError(f"[drive] {', '.join(given)} belongs to a {other!r} drive but this drive is "
                                 f"{kind!r}; give stroke (harmonic), samples or time/position (sampled) "
                                 "or duration (still), not a mix")
        cls = _DRIVES[kind]
        foreign = [k for k in t if k not in config_keys(cls) and k not in ("kind", "samples")]
        if foreign:
            raise InputError(f"[drive] {', '.join(foreign)} does not apply to a {kind!r} drive (give "
                             f"{', '.join(config_keys(cls))})")
        if isinstance(t.get("direction"), str):
            t = {**t}
            words = t.pop("direction")
            kw = {**read_fields(t, "drive", cls), "direction": words}
        else:
            kw = read_fields(t, "drive", cls)
        kw = {**cls.config_defaults, **kw}
        if "samples" in t:
            extra = [k for k in _SAMPLED_KEYS[1:] if k in t]
            if extra:
                raise InputError(f"[drive] give either samples = 'file.csv' or inline {', '.join(extra)}, not both")
            kw.update(self._samples_file(t["samples"]))
        missing = [k for k in cls.config_required if k not in kw]
        if missing:
            raise InputError(f"[drive] a {kind!r} drive needs {', '.join(repr(k) for k in missing)}: {cls.config_hint}")
        return cls(**kw)

    def structure(self, t, drive_table):
        """[structure]: the container rides on a coupled oscillator (replaces [drive])."""
        if drive_table:
            raise InputError(f"[drive] {', '.join(drive_table)} cannot be combined with [structure]: the "
                             "structure moves the container; remove [drive] (the direction is [structure] angle)")
        check_keys(t, "structure", SECTIONS["structure"])
        if "modes" in t or "matrices" in t:
            return self._modal_structure(t)
        modal = [k for k in t if k not in config_keys(_STRUCTURE) and k != "natural_frequency"]
        if modal:
            raise InputError(f"[structure] {modal[0]} is a key of a structure of several modes; give modes = "
                             "[{frequency, damping_ratio, modal_mass, damper, force, response}, ...] or matrices = "
                             "'frame.npz' with it, or leave it out")
        for req in ("mass",):
            if req not in t:
                raise InputError("[structure] mass is missing: give the structure's modal mass including the "
                                 "empty container, e.g. mass = '7kg'")
        if ("stiffness" in t) == ("natural_frequency" in t):
            raise InputError("[structure] give exactly one of stiffness (N/m, e.g. 1105) or natural_frequency "
                             "(e.g. '2Hz')")
        kw = read_fields(t, "structure", _STRUCTURE)
        if "natural_frequency" in t:
            fn = read_quantity(t["natural_frequency"], "[structure] natural_frequency", "frequency")
            if not (fn > 0 and math.isfinite(fn)):
                raise InputError(f"[structure] natural_frequency = {t['natural_frequency']!r}; must be > 0, e.g. '2Hz'")
            if not (kw["mass"] > 0 and math.isfinite(kw["mass"])):
                raise InputError(f"[structure] mass = {t['mass']!r}; must be > 0, e.g. '7kg'")
            w = 2.0 * math.pi * fn
            kw["stiffness"] = kw["mass"] * w * w
            if not (0 < kw["stiffness"] < math.inf):
                raise InputError(f"[structure] natural_frequency = {t['natural_frequency']!r} gives a stiffness of "
                                 f"{kw['stiffness']:g} N/m with mass = {kw['mass']:g} kg; give a natural frequency "
                                 "a damper test can have, e.g. '2Hz'")
        return _STRUCTURE(**kw)

    def _modal_structure(self, t):
        """[structure] with modes = [...] or matrices = ...: a structure of N modes."""
        single = [k for k in ("mass", "stiffness", "natural_frequency") if k in t]
        if single:
            raise InputError(f"[structure] {single[0]} is a key of the single-mode structure; with "
                             f"{'modes' if 'modes' in t else 'matrices'} the modes carry their own masses and "
                             "frequencies: remove it")
        kw = read_fields(t, "structure", _MODAL)
        if "modes" in t:
            kw["modes"] = t["modes"]
        if "matrices" in t:
            m = t["matrices"]
            if isinstance(m, str):
                m = self._path(m)
            elif isinstance(m, dict):
                m = {k: (self._path(v) if isinstance(v, str) else v) for k, v in m.items()}
            kw["matrices"] = m
        return _MODAL(**kw)

    def _path(self, value: str) -> str:
        """A file named in the config, absolute (a case written elsewhere, e.g. into a run
        directory, still finds it)."""
        path = Path(value)
        return str((path if path.is_absolute() else self.base_dir / path).resolve())

    def _samples_file(self, value) -> dict:
        if not isinstance(value, str) or not value.strip():
            raise InputError(f"[drive] samples = {value!r} must be the path of a CSV file")
        path = Path(value)
        if not path.is_absolute():
            path = self.base_dir / path
        return read_motion_csv(path)

    def contact(self, t, material_names) -> ContactModel:
        check_keys(t, "contact", SECTIONS["contact"])
        kw = read_fields(t, "contact", ContactModel)
        if "restitution" in t:
            kw["restitution"] = read_restitution(t["restitution"], "contact")
        pairs = t.get("pair", [])
        if isinstance(pairs, dict):
            pairs = [pairs]
        if not isinstance(pairs, list):
            raise InputError("[[contact.pair]] must be tables with materials = ['a', 'b'] and friction and/or "
                             "restitution")
        pf, pr = {}, {}
        known = list(dict.fromkeys(material_names))
        for k, p in enumerate(pairs):
            label = f"contact.pair #{k + 1}"
            if not isinstance(p, dict):
                raise InputError(f"[[contact.pair]] #{k + 1} must be a table, got {p!r}")
            check_keys(p, label, _PAIR_KEYS)
            mats = p.get("materials")
            if not (isinstance(mats, list) and len(mats) == 2 and all(isinstance(m, str) for m in mats)):
                raise InputError(f"[{label}] materials = {mats!r}: give two material names, e.g. ['steel', 'pvc']")
            for m in mats:
                if m not in known:
                    near = difflib.get_close_matches(m, known, n=1, cutoff=0.5)
                    hint = f"did you mean {near[0]!r}?" if near else "this case has " + ", ".join(map(repr, known))
                    raise InputError(f"[{label}] materials: {m!r} is not a material of this case; {hint}")
            key = (mats[0], mats[1])
            if "friction" not in p and "restitution" not in p:
                raise InputError(f"[{label}] sets nothing; give friction and/or restitution")
            for store, field_ in ((pf, "friction"), (pr, "restitution")):
                if field_ in p:
                    if key in store or key[::-1] in store:
                        raise InputError(f"[{label}] {field_} for {key[0]!r}-{key[1]!r} is given twice")
                    store[key] = (read_number(p["friction"], f"[{label}] friction") if field_ == "friction"
                                  else read_restitution(p["restitution"], label))
        if pf:
            kw["pair_friction"] = pf
        if pr:
            kw["pair_restitution"] = pr
        return ContactModel(**kw)

    def flat(self, t, section, cls):
        """A section whose every key is a plain field of ``cls``."""
        check_keys(t, section, SECTIONS[section])
        return cls(**read_fields(t, section, cls))


class _context:
    """Prefix ``[section]`` to an InputError raised by a parameter class that does not name it."""

    def __init__(self, section: str):
        self.section = section

    def __enter__(self):
        return self

    def __exit__(self, kind, exc, tb):
        if isinstance(exc, InputError):
            msg = _as_key(_grammar(str(exc)))
            if self.section not in msg.lower():
                msg = f"[{self.section}] {msg}"
            raise InputError(msg) from None
        return False


def _as_key(msg: str) -> str:
    """A message of a parameter class that starts ``section.key`` (``contact.v_in_floor = 0.0; ...``) with the
    key as the config file has it (``[contact] v_in_floor = 0.0; ...``)."""
    head, dot, rest = msg.partition(".")
    if dot and head in SECTIONS:
        key = rest.split(" ", 1)[0].rstrip(":;,")
        if key in SECTIONS[head]:
            return f"[{head}] {rest}"
    return msg


def read_motion_csv(path) -> dict:
    """Read a prescribed motion from a CSV file: columns ``time``, ``position`` and optionally
    ``velocity`` (units in brackets, e.g. ``time [s],position [mm]``; without a unit SI).

    Returns ``{"time": tuple, "position": tuple[, "velocity": tuple]}`` in SI.
    """
    path = Path(path)
    if not path.exists():
        raise InputError(f"[drive] samples: file not found: {path}")
    if path.is_dir():
        raise InputError(f"[drive] samples: {path} is a directory; give a CSV file")
    try:
        text = path.read_text(encoding="utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InputError(f"[drive] samples: {path} is not a text (CSV) file: byte {exc.start} is not UTF-8") from None
    except OSError as exc:
        raise InputError(f"[drive] samples: cannot read {path}: {exc.strerror or exc}") from None
    lines = [(no, ln) for no, ln in enumerate(text.splitlines(), start=1)
             if ln.strip() and not ln.lstrip().startswith("#")]
    if len(lines) < 2:
        raise InputError(f"{path}: expected a header row (time, position[, velocity]) and data rows")
    header = lines[0][1]
    delim = max((",", ";", "\t"), key=header.count)
    rows = []
    for no, ln in lines:
        try:
            rows.append(next(csv.reader([ln], delimiter=delim)))
        except csv.Error as exc:  # a field over 128 kB, a stray quote
            raise InputError(f"{path}, line {no}: not a CSV row ({exc}); the samples are numbers in columns "
                             "time, position[, velocity]") from None
    names, units = [], []
    for h in rows[0]:
        h = h.strip()
        unit = ""
        for o, c in (("[", "]"), ("(", ")")):
            if h.endswith(c) and o in h:
                h, unit = h[:h.rindex(o)].strip(), h[h.rindex(o) + 1:-1].strip()
                break
        names.append(h.lower())
        units.append(unit)
    dims = {"time": "time", "position": "length", "velocity": "velocity"}
    out = {}
    for role, dim in dims.items():
        if role not in names:
            if role == "velocity":
                continue
            raise InputError(f"{path}: no {role!r} column; the header has {rows[0]!r} "
                             "(need time, position[, velocity], units in brackets)")
        i = names.index(role)
        factor = unit_factor(units[i], dim, name=f"{path}: column {role!r}") if units[i] else 1.0
        col = []
        for (no, _), row in zip(lines[1:], rows[1:]):
            try:
                v = float(row[i].strip().replace(",", ".") if delim != "," else row[i])
            except (ValueError, IndexError):
                cell = row[i] if i < len(row) else ""
                shown = repr(cell) if len(cell) <= 60 else f"{cell[:60]!r}... ({len(cell)} characters)"
                raise InputError(f"{path}, line {no}, column {role!r}: cannot read {shown} as a number") from None
            if not math.isfinite(v):
                raise InputError(f"{path}, line {no}, column {role!r}: {v!r} is not a finite number")
            col.append(v * factor)
        out[role] = tuple(col)
    return out


# --------------------------------------------------------------------------- writing

def _material_to(m: Material):
    if LIBRARY.get(m.name) == m:
        return m.name
    return _fields_to(m)


def _law_to(law):
    if isinstance(law, ConstantRestitution):
        return float(law.value)
    if isinstance(law, TabulatedRestitution):
        return {"law": "table", "speeds": [float(v) for v in law.speeds], "values": [float(v) for v in law.values]}
    if isinstance(law, ThorntonRestitution):
        return {"law": "thornton", "yield_pressure": float(law.yield_pressure)}
    raise InputError(f"cannot write restitution law {law!r} to a config file")


def _num(v):
    """Keep ints as ints (TOML integer), everything else a float."""
    if isinstance(v, bool):
        return v
    if isinstance(v, int):
        return v
    return float(v)


def _fields_to(obj) -> dict:
    """The plain fields of ``obj`` as config keys, type tags first (the inverse of ``_Reader.fields``)."""
    out = {}
    for f in dataclasses.fields(obj):
        s = spec_of(f)
        if s.kind == "tag":
            out[s.key or f.name] = getattr(obj, f.name)
    for f, s in plain_fields(type(obj)):
        v = getattr(obj, f.name)
        key = s.key or f.name
        if not s.write_default and v == f.default:
            continue
        if v is None:
            if s.auto:
                out[key] = "auto"
        elif s.kind == "flag":
            out[key] = bool(v)
        elif s.kind == "text":
            out[key] = v
        elif s.kind == "whole":
            out[key] = int(v)
        elif s.kind == "list":
            out[key] = [float(x) for x in v]
        elif s.kind == "rows":
            out[key] = [[float(x) for x in row] for row in v]
        else:
            out[key] = float(v) if s.dimension is not None else _num(v)
    return out


def case_to_dict(case: Case) -> dict:
    """The full config of ``case`` as a TOML-ready dict, every quantity in plain SI units.

    Written from the same field specs the reader uses (:mod:`pdamper.schema`), so that
    ``case_from_dict(case_to_dict(case)) == case``.
    """
    c = case.container
    container = {**_fields_to(c.geometry), "material": _material_to(c.material), "tilt": [float(a) for a in c.tilt],
                 **_fields_to(c)}
    parts = [{**_fields_to(p), "material": _material_to(p.material)} for p in case.particles]

    ct = case.contact
    plain = _fields_to(ct)
    # friction, restitution, then the rest: the order of the text a store's fingerprint was taken of
    contact = {"friction": plain.pop("friction"), "restitution": _law_to(ct.restitution), **plain}
    pairs = []
    for key, mu in ct.pair_friction.items():
        pairs.append({"materials": list(key), "friction": _num(mu)})
    for key, law in ct.pair_restitution.items():
        for p in pairs:
            if tuple(p["materials"]) == tuple(key) and "restitution" not in p:
                p["restitution"] = _law_to(law)
                break
        else:
            pairs.append({"materials": list(key), "restitution": _law_to(law)})
    if pairs:
        contact["pair"] = pairs

    out = {"container": container, "particles": parts[0] if len(parts) == 1 else parts}
    if c.baffles:
        container["baffles"] = [{**_fields_to(b), **({"material": _material_to(b.material)} if b.material else {})}
                                for b in c.baffles]
    if c.wall_materials:
        container["wall_materials"] = {w: _material_to(m) for w, m in c.wall_materials.items()}
    d = case.drive
    drive_key = d.config_section
    if type(d) is not DRIVES.get(d.kind):
        raise InputError(f"cannot write drive {type(d).__name__} to a config file")
    drive = {**_fields_to(d), **d.config_extra()}
    if drive_key == "structure":
        del drive["kind"]
    out.update({"contact": contact, "numerics": _fields_to(case.numerics), "recording": _fields_to(case.recording),
                "initial": _fields_to(case.initial), "run": _fields_to(case)})
    # [drive] after [particles], [structure] last: the order of the text a store's fingerprint was taken of
    if drive_key == "structure":
        return {**out, "structure": drive}
    return {**{k: out[k] for k in ("container", "particles")}, "drive": drive,
            **{k: v for k, v in out.items() if k not in ("container", "particles")}}


_HEADER = ("# pdamper case configuration (written by pdamper {version}).\n"
           "# All quantities in SI units: m, s, Hz, kg, rad, Pa, kg/m^3, m/s, m/s^2.\n"
           "# Re-run with: pdamper run {name}\n\n")


def dumps_case(case: Case, *, name: str = "config.toml") -> str:
    """``case`` as TOML text (see :func:`case_to_dict`), with a comment header."""
    import tomli_w

    from ._version import __version__

    return _HEADER.format(version=__version__, name=name) + tomli_w.dumps(case_to_dict(case))


def dump_case(case: Case, path) -> Path:
    """Write ``case`` to the TOML file ``path`` atomically (temporary file + rename); returns the path."""
    path = Path(path)
    atomic_write(path, dumps_case(case, name=path.name))
    return path
