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

:func:`load_case` reads a file (with optional overrides such as ``{"drive.stroke": "3mm"}``);
:func:`case_to_dict` / :func:`dump_case` write a case back in plain SI numbers, so that
``load_case(dump_case(case, p)) == case`` exactly. Every problem raises
:class:`pdamper.errors.InputError` naming the file, the section and the key.
:func:`with_overrides` applies the same dotted overrides to a case in hand.

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
from pathlib import Path

from .contact.cor_constant import ConstantRestitution
from .contact.cor_table import TabulatedRestitution
from .contact.cor_thornton import ThorntonRestitution
from .errors import InputError
from .io.files import atomic_write
from .excitation import CoupledStructure, HarmonicDrive, SampledDrive, Still
from .geometry.cuboid import Cuboid
from .geometry.cylinder import Cylinder
from .materials import LIBRARY, Material
from .params import Case, Container, ContactModel, InitialState, Numerics, ParticleSet, Recording
from .schema import Spec, config_keys, plain_fields, spec_of
from .units import parse_quantity, unit_factor

__all__ = ["load_case", "loads_case", "case_from_dict", "case_to_dict", "dump_case", "dumps_case",
           "with_overrides", "key_spec", "SECTIONS"]

# The sections are read from the parameter dataclasses' own fields (pdamper.schema): a field's
# spec says its dimension, allowed values and key. What is written here by hand is only the
# structure no field can say: which class a section builds (a container shape, a drive kind),
# and keys that are not fields (a samples file, a natural frequency instead of a stiffness,
# per-material-pair tables).
_GEOMETRIES = {cls.shape: cls for cls in (Cuboid, Cylinder)}
_DRIVES = {cls.kind: cls for cls in (HarmonicDrive, SampledDrive, Still)}
_SHAPE_KEYS = {shape: config_keys(cls) for shape, cls in _GEOMETRIES.items()}
#: Keys that only one kind of drive has (a key of another kind is an error).
_DRIVE_OWN = {kind: tuple(k for k in config_keys(cls)
                          if not any(k in config_keys(o) for o in _DRIVES.values() if o is not cls))
              for kind, cls in _DRIVES.items()}
_DRIVE_OWN["samples"] = ("samples",) + _DRIVE_OWN["samples"]
_SAMPLED_KEYS = _DRIVE_OWN["samples"]


def _union(*groups) -> tuple:
    return tuple(dict.fromkeys(k for g in groups for k in g))


#: Allowed keys of each section, derived from the dataclasses' fields.
SECTIONS = {
    "container": _union(("shape",), *_SHAPE_KEYS.values(), config_keys(Container, drop=("geometry",))),
    "particles": config_keys(ParticleSet),
    "drive": _union(("kind",), *(config_keys(cls) for cls in _DRIVES.values()), ("samples",)),
    "contact": config_keys(ContactModel, drop=("pair_friction", "pair_restitution")) + ("pair",),
    "numerics": config_keys(Numerics),
    "recording": config_keys(Recording),
    "initial": config_keys(InitialState),
    "run": tuple(s.key or f.name for f, s in plain_fields(Case)),
    "structure": _union(config_keys(CoupledStructure), ("natural_frequency",)),
}
_MATERIAL_KEYS = config_keys(Material)
_PAIR_KEYS = ("materials", "friction", "restitution")
_LAW_KEYS = {"constant": ("law", "value"), "table": ("law", "speeds", "values"),
             "thornton": ("law", "yield_pressure")}


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


def _suggest(word: str, allowed, what: str) -> str:
    near = difflib.get_close_matches(word, list(allowed), n=1, cutoff=0.6)
    if near:
        return f"did you mean {what.format(near[0])}?"
    return "allowed: " + ", ".join(what.format(a) for a in allowed)


def _quoted(key, allowed) -> str:
    near = difflib.get_close_matches(key, list(allowed), n=1, cutoff=0.6)
    if near:
        return f"did you mean {near[0]!r}?"
    return "allowed keys: " + ", ".join(allowed)


#: The parameter classes whose fields make each section's keys.
_SECTION_CLASSES = {
    "container": (Cuboid, Cylinder, Container), "particles": (ParticleSet,), "drive": tuple(_DRIVES.values()),
    "contact": (ContactModel,), "numerics": (Numerics,), "recording": (Recording,), "initial": (InitialState,),
    "run": (Case,), "structure": (CoupledStructure,),
}
#: Specs of the structured keys that also take one plain value (a constant COR; one tilt angle for all axes).
_VALUE_SPECS = {"contact.restitution": Spec(kind="number"), "container.tilt": Spec(kind="number", dimension="angle")}


def key_spec(dotted: str) -> Spec:
    """The :class:`~pdamper.schema.Spec` of a config key written ``section.key`` (what a sweep axis
    over it holds), or an :class:`InputError` naming the allowed keys."""
    section, _, key = str(dotted).partition(".")
    if section not in SECTIONS:
        raise InputError(f"{dotted!r}: unknown section [{section}]; " + _suggest(section, SECTIONS, "[{}]"))
    if key not in SECTIONS[section]:
        raise InputError(f"{dotted!r}: unknown key {key!r} in [{section}]; " + _quoted(key, SECTIONS[section]))
    if dotted in _VALUE_SPECS:
        return _VALUE_SPECS[dotted]
    for cls in _SECTION_CLASSES[section]:
        for f, s in plain_fields(cls):
            if (s.key or f.name) == key:
                return s
    raise InputError(f"{dotted!r} is not a single value (a table or a list); it cannot be a sweep axis")


def with_overrides(case: Case, overrides: dict) -> Case:
    """``case`` with the dotted keys of ``overrides`` replaced, e.g. ``{"contact.friction": 1.0,
    "drive.stroke": "3mm", "particles.material": Material(...)}``.

    The one override mechanism of pdamper: the case is written as its config (:func:`case_to_dict`),
    the overrides are applied as for :func:`load_case` (values read exactly like a config file's,
    with the same messages) and the config is read back. Values may also be parameter objects
    (a :class:`~pdamper.materials.Material`, a restitution law) or tuples; they are written as a
    config would hold them. Round trips are exact, so keys not overridden keep their values bit
    for bit.
    """
    return case_from_dict(case_to_dict(case), {k: _to_config(v) for k, v in overrides.items()})


def _to_config(value):
    """A parameter value as a config file holds it."""
    if value is None:  # the value of an optional field: "auto" in a config file
        return "auto"
    if isinstance(value, Material):
        return _material_to(value)
    if isinstance(value, (ConstantRestitution, TabulatedRestitution, ThorntonRestitution)):
        return _law_to(value)
    if isinstance(value, (tuple, list)):
        return [_to_config(v) for v in value]
    if hasattr(value, "item") and not isinstance(value, (str, bytes)):  # numpy scalar
        return value.item()
    return value


def _apply_overrides(data: dict, overrides: dict) -> dict:
    for dotted, value in overrides.items():
        parts = str(dotted).split(".")
        if len(parts) != 2 or not all(parts):
            raise InputError(f"override {dotted!r}: write it as 'section.key', e.g. 'drive.stroke'")
        section, key = parts
        if section not in SECTIONS:
            raise InputError(f"override {dotted!r}: unknown section [{section}]; "
                             + _suggest(section, SECTIONS, "[{}]"))
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
    """Turns the parsed TOML tables into parameter objects, one section at a time."""

    def __init__(self, base_dir: Path):
        self.base_dir = base_dir

    # ---- helpers
    @staticmethod
    def _table(data, section):
        t = data.get(section, {})
        if not isinstance(t, dict):
            raise InputError(f"[{section}] must be a table (a [{section}] header with key = value lines), "
                             f"got {t!r}")
        return t

    @staticmethod
    def _check_keys(table, section, allowed):
        for key in table:
            if key not in allowed:
                raise InputError(f"unknown key {key!r} in [{section}]; {_quoted(key, allowed)}")

    @staticmethod
    def quantity(table, section, key, dimension, default=None):
        if key not in table:
            return default
        return _parse(table[key], f"[{section}] {key}", dimension)

    @staticmethod
    def number(table, section, key, default=None):
        if key not in table:
            return default
        v = table[key]
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            return v
        return _dimless(v, f"[{section}] {key}")

    @staticmethod
    def integer(table, section, key, default=None):
        if key not in table:
            return default
        v = table[key]
        if isinstance(v, float) and v.is_integer():
            return int(v)
        if isinstance(v, bool) or not isinstance(v, int):
            raise InputError(f"[{section}] {key} = {v!r} must be a whole number")
        return v

    @staticmethod
    def choice(table, section, key, choices, default):
        if key not in table:
            return default
        v = table[key]
        if not isinstance(v, str):
            raise InputError(f"[{section}] {key} = {v!r} must be a string: one of "
                             + ", ".join(repr(c) for c in choices))
        if v not in choices:
            near = difflib.get_close_matches(v, choices, n=1, cutoff=0.5)
            hint = f"did you mean {near[0]!r}? " if near else ""
            raise InputError(f"[{section}] {key} = {v!r} is not allowed; {hint}choose one of "
                             + ", ".join(repr(c) for c in choices))
        return v

    def fields(self, t, section, cls) -> dict:
        """Keyword arguments for ``cls`` from table ``t``: each plain field present, read by its spec."""
        kw = {}
        for f, s in plain_fields(cls):
            key = s.key or f.name
            if key in t:
                try:
                    kw[f.name] = self.value(t, section, key, s)
                except InputError as exc:
                    if s.paper is None or "paper" in str(exc):
                        raise
                    raise InputError(f"{exc} (paper: {s.paper})") from None
        return kw

    def value(self, t, section, key, s):
        """The value of ``t[key]`` read as the :class:`~pdamper.schema.Spec` ``s`` says."""
        v = t[key]
        if s.choices is not None:
            return self.choice(t, section, key, s.choices, None)
        if s.kind == "text":
            if not isinstance(v, str):
                raise InputError(f"[{section}] {key} = {v!r} must be a string")
            return v
        if s.kind == "whole":
            return self.integer(t, section, key)
        if s.kind == "list":
            return self.quantity_list(v, f"[{section}] {key}", s.dimension or "dimensionless")
        if s.kind == "rows":
            return self.vectors(v, f"[{section}] {key}", s.dimension, s.example)
        if s.auto and isinstance(v, str) and v.strip().lower() == "auto":
            return None
        if s.dimension is not None:
            return self.quantity(t, section, key, s.dimension)
        return self.number(t, section, key)

    def quantity_list(self, value, name, dimension):
        if not isinstance(value, list):
            raise InputError(f"{name} = {value!r} must be a list of {dimension}s, e.g. [1, 2, 3]")
        return tuple(_q(v, name, k, dimension) for k, v in enumerate(value))

    def vectors(self, rows, name, dimension, example):
        """A list of [x, y, z] rows as a tuple of 3-tuples (SI)."""
        if not isinstance(rows, list) or not all(isinstance(r, list) and len(r) == 3 for r in rows):
            raise InputError(f"{name} must be a list of [x, y, z] rows (one per sphere, container frame), "
                             f"e.g. [[0, {example}, 0], [{example}, 0, 0]]")
        return tuple(tuple(_q(v, f"{name}[{i}]", k, dimension) for k, v in enumerate(r)) for i, r in enumerate(rows))

    # ---- sections
    def case(self, data: dict) -> Case:
        for section in data:
            if section not in SECTIONS:
                raise InputError(f"unknown section [{section}]; " + _suggest(section, SECTIONS, "[{}]"))
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
        with _context("numerics"):
            numerics = self.numerics(self._table(data, "numerics"))
        with _context("recording"):
            recording = self.recording(self._table(data, "recording"))
        with _context("initial"):
            initial = self.initial(self._table(data, "initial"))
        with _context("run"):
            run = self._table(data, "run")
            self._check_keys(run, "run", SECTIONS["run"])
            kw = self.fields(run, "run", Case)
            return Case(particles=particles, container=container, drive=drive, contact=contact,
                        numerics=numerics, recording=recording, initial=initial, **kw)

    def material(self, value, section, default_name):
        """A material from a library name or an inline table ``{name, youngs_modulus, poisson_ratio, density}``."""
        name = f"[{section}] material"
        if isinstance(value, str):
            key = value.strip().lower()
            if key in LIBRARY:
                return LIBRARY[key]
            near = difflib.get_close_matches(key, list(LIBRARY), n=1, cutoff=0.5)
            hint = f"did you mean {near[0]!r}? " if near else ""
            raise InputError(f"{name} = {value!r} is not a known material; {hint}known: "
                             + ", ".join(map(repr, LIBRARY)) + " (or give an inline table {name = ..., "
                             "youngs_modulus = ..., poisson_ratio = ..., density = ...})")
        if not isinstance(value, dict):
            raise InputError(f"{name} = {value!r}: give a material name such as 'steel' or an inline table "
                             "{youngs_modulus = '208GPa', poisson_ratio = 0.3, density = '7900kg/m^3'}")
        sub = f"{section}.material"
        self._check_keys(value, sub, _MATERIAL_KEYS)
        for req in _MATERIAL_KEYS[1:]:
            if req not in value:
                raise InputError(f"[{sub}] {req} is missing; an inline material needs youngs_modulus, "
                                 "poisson_ratio and density")
        mname = value.get("name", default_name)
        if not isinstance(mname, str) or not mname:
            raise InputError(f"[{sub}] name = {mname!r} must be a non-empty string")
        return Material(**{**self.fields(value, sub, Material), "name": mname})

    def container(self, t) -> Container:
        self._check_keys(t, "container", SECTIONS["container"])
        shape = self.choice(t, "container", "shape", tuple(_GEOMETRIES), "cuboid")
        for key in ("length", "width", "height", "radius"):
            if key in t and key not in _SHAPE_KEYS[shape]:
                other = "cylinder" if shape == "cuboid" else "cuboid"
                raise InputError(f"[container] {key} applies to shape = {other!r}, but shape = {shape!r} "
                                 f"(give {', '.join(_SHAPE_KEYS[shape])})")
        kw = {"geometry": _GEOMETRIES[shape](**self.fields(t, "container", _GEOMETRIES[shape]))}
        if "material" in t:
            kw["material"] = self.material(t["material"], "container", "container")
        if "tilt" in t:
            tilt = t["tilt"]
            if isinstance(tilt, list):
                if len(tilt) != 3:
                    raise InputError(f"[container] tilt = {tilt!r}: give three angles about x, y, z, "
                                     "e.g. ['0.1deg', '0.1deg', '0.1deg'] (or one angle for all three)")
                kw["tilt"] = tuple(_q(a, "[container] tilt", k, "angle") for k, a in enumerate(tilt))
            else:
                a = self.quantity(t, "container", "tilt", "angle")
                kw["tilt"] = (a, a, a)
        kw.update(self.fields(t, "container", Container))
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
            self._check_keys(t, label, SECTIONS["particles"])
            if "count" not in t:
                raise InputError(f"[{label}] count is missing; give the number of spheres, e.g. count = 36")
            kw = self.fields(t, label, ParticleSet)
            if "material" in t:
                default = "particles" if len(tables) == 1 else f"particles-{k + 1}"
                kw["material"] = self.material(t["material"], label, default)
            out.append(ParticleSet(**kw))
        return tuple(out)

    def drive(self, t):
        self._check_keys(t, "drive", SECTIONS["drive"])
        sampled = [k for k in _SAMPLED_KEYS if k in t]
        kind = self.choice(t, "drive", "kind", tuple(_DRIVES),
                           "samples" if sampled else ("still" if "duration" in t else "harmonic"))
        for other, keys in _DRIVE_OWN.items():
            given = [k for k in keys if k in t]
            if other != kind and given:
                raise InputError(f"[drive] {', '.join(given)} belongs to a {other!r} drive but this drive is "
                                 f"{kind!r}; give stroke (harmonic), samples or time/position (sampled) "
                                 "or duration (still), not a mix")
        if kind == "still" and "frequency" in t:
            raise InputError("[drive] frequency does not apply to a still container (kind = 'still')")
        kw = self.fields(t, "drive", _DRIVES[kind])
        if kind == "harmonic":
            kw.setdefault("stroke", 0.012)
        elif kind == "samples":
            if "samples" in t:
                extra = [k for k in _SAMPLED_KEYS[1:] if k in t]
                if extra:
                    raise InputError(f"[drive] give either samples = 'file.csv' or inline {', '.join(extra)}, not both")
                kw.update(self._samples_file(t["samples"]))
            else:
                for req in ("time", "position"):
                    if req not in t:
                        raise InputError(f"[drive] a sampled motion needs {req!r}: give time = [...] and "
                                         "position = [...] (optionally velocity = [...]) or samples = 'motion.csv'")
        return _DRIVES[kind](**kw)

    def structure(self, t, drive_table) -> CoupledStructure:
        """[structure]: the container rides on a coupled oscillator (replaces [drive])."""
        if drive_table:
            raise InputError(f"[drive] {', '.join(drive_table)} cannot be combined with [structure]: the "
                             "structure moves the container; remove [drive] (the direction is [structure] angle)")
        self._check_keys(t, "structure", SECTIONS["structure"])
        for req in ("mass",):
            if req not in t:
                raise InputError("[structure] mass is missing: give the structure's modal mass including the "
                                 "empty container, e.g. mass = '7kg'")
        if ("stiffness" in t) == ("natural_frequency" in t):
            raise InputError("[structure] give exactly one of stiffness (N/m, e.g. 1105) or natural_frequency "
                             "(e.g. '2Hz')")
        kw = self.fields(t, "structure", CoupledStructure)
        if "natural_frequency" in t:
            fn = self.quantity(t, "structure", "natural_frequency", "frequency")
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
        return CoupledStructure(**kw)

    def _samples_file(self, value) -> dict:
        if not isinstance(value, str) or not value.strip():
            raise InputError(f"[drive] samples = {value!r} must be the path of a CSV file")
        path = Path(value)
        if not path.is_absolute():
            path = self.base_dir / path
        return read_motion_csv(path)

    def restitution(self, value, section, key="restitution"):
        """A COR law from a number (constant) or a table with ``law = ...``."""
        name = f"[{section}] {key}"
        try:
            return self._law(value, section, key)
        except InputError as exc:
            msg = str(exc)
            if msg.startswith("["):
                raise
            if msg.startswith("restitution = ") and ": " in msg:
                raise InputError(f"{name} = {value!r}: {msg.split(': ', 1)[1]}") from None
            raise InputError(f"[{section}] {msg}") from None

    def _law(self, value, section, key):
        name = f"[{section}] {key}"
        if isinstance(value, (bool, int, float, str)):
            return ConstantRestitution(value=_dimless(value, name))
        if not isinstance(value, dict):
            raise InputError(f"{name} = {value!r}: give a number such as 0.9 or a table "
                             "{law = 'table', speeds = [...], values = [...]} or {law = 'thornton', "
                             "yield_pressure = '1.5GPa'}")
        law = value.get("law")
        if law is None:
            raise InputError(f"{name}: the table needs law = 'constant', 'table' or 'thornton'")
        if law not in _LAW_KEYS:
            near = difflib.get_close_matches(str(law), list(_LAW_KEYS), n=1, cutoff=0.5)
            hint = f"did you mean {near[0]!r}? " if near else ""
            raise InputError(f"{name}: law = {law!r} is unknown; {hint}choose 'constant', 'table' or 'thornton'")
        sub = f"{section}.{key}"
        self._check_keys(value, sub, _LAW_KEYS[law])
        for req in _LAW_KEYS[law][1:]:
            if req not in value:
                raise InputError(f"{name}: law = {law!r} needs {req!r}")
        if law == "constant":
            return ConstantRestitution(value=_dimless(value["value"], f"[{sub}] value"))
        if law == "thornton":
            return ThorntonRestitution(yield_pressure=self.quantity(value, sub, "yield_pressure", "pressure"))
        speeds = self.quantity_list(value["speeds"], f"[{sub}] speeds", "velocity")
        vals = value["values"]
        if not isinstance(vals, list):
            raise InputError(f"[{sub}] values = {vals!r} must be a list of numbers in (0, 1]")
        values = tuple(_dimless(v, f"[{sub}] values[{k}]") for k, v in enumerate(vals))
        return TabulatedRestitution(speeds=speeds, values=values)

    def contact(self, t, material_names) -> ContactModel:
        self._check_keys(t, "contact", SECTIONS["contact"])
        kw = self.fields(t, "contact", ContactModel)
        if "restitution" in t:
            kw["restitution"] = self.restitution(t["restitution"], "contact")
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
            self._check_keys(p, label, _PAIR_KEYS)
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
                    store[key] = (self.number(p, label, "friction") if field_ == "friction"
                                  else self.restitution(p["restitution"], label))
        if pf:
            kw["pair_friction"] = pf
        if pr:
            kw["pair_restitution"] = pr
        return ContactModel(**kw)

    def flat(self, t, section, cls):
        """A section whose every key is a plain field of ``cls``."""
        self._check_keys(t, section, SECTIONS[section])
        return cls(**self.fields(t, section, cls))

    def numerics(self, t) -> Numerics:
        return self.flat(t, "numerics", Numerics)

    def recording(self, t) -> Recording:
        return self.flat(t, "recording", Recording)

    def initial(self, t) -> InitialState:
        return self.flat(t, "initial", InitialState)


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


def _q(value, name, index, dimension) -> float:
    label = f"{name}[{index}]"
    if isinstance(value, (dict, list)):
        raise InputError(f"{label} = {value!r}: expected a {dimension} such as {_example(dimension)}")
    return _parse(value, label, dimension)


def _parse(value, label, dimension) -> float:
    if isinstance(value, (dict, list)):
        kind = "table" if isinstance(value, dict) else "list"
        raise InputError(f"{label} = {value!r}: expected {_a(dimension)} such as {_example(dimension)}, not a {kind}")
    try:
        return parse_quantity(value, dimension, name=label)
    except InputError as exc:
        msg = _grammar(str(exc))
        rest = msg[len(label) + 2:] if msg.startswith(label + ": ") else msg
        raise InputError(f"{label} = {rest}" if rest.startswith(("'", '"')) else f"{label}: {rest}") from None


def _a(word: str) -> str:
    return ("an " if word[:1] in "aeiou" else "a ") + word


def _grammar(msg: str) -> str:
    for word in ("angle", "acceleration"):
        msg = msg.replace(f" a {word}", f" an {word}")
    return msg


def _dimless(value, label) -> float:
    if isinstance(value, bool) or isinstance(value, (dict, list)):
        raise InputError(f"{label} = {value!r} must be a number")
    return _parse(value, label, "dimensionless")


def _example(dimension: str) -> str:
    from .units import _example as ex

    return ex(dimension)


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
        if v is None:
            if s.auto:
                out[key] = "auto"
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
    d = case.drive
    if isinstance(d, CoupledStructure):
        drive_key, drive = "structure", _fields_to(d)
        del drive["kind"]
    elif isinstance(d, tuple(_DRIVES.values())):
        drive_key, drive = "drive", _fields_to(d)
    else:
        raise InputError(f"cannot write drive {type(d).__name__} to a config file")
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
