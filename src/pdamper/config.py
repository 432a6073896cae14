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
    mass = "0kg"                # the empty container: on a [structure] it moves with it

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
                                # overlap_limit, device ("cpu" or "cuda": the GPU engine)
    [recording]                 # sample_rate, trajectory_fps
    [initial]                   # arrangement, jitter, seed, settle_time, layers, and optional
                                # per-sphere rows [x, y, z]: positions, velocities, spins [rad/s]
    [run]                       # cycles, drop_cycles, gravity

    [structure]                 # the container rides on a structure: the case's drive
    mass = "7kg"                # modal mass without the damper ([container] mass is added)
    natural_frequency = "2Hz"   # or stiffness = 1105 (N/m)
    damping_ratio = 0.005
    displacement = "12mm"       # initial; and/or force_amplitude = "0.5N", force_frequency = "2Hz"
    # A [drive] beside a [structure] is the damper's rig drive (Case.rig): a sweep runs the
    # damper on it (Case.on_rig), the structure's commands (decay, response) run the structure.

    [load]                      # with [structure]: a load in time (pdamper transient), its own keys
    kind = "ground_acceleration"  # or harmonic, force_history, random, stepped_sine
    file = "quake.csv"          # time [s], acceleration [g]; or a PEER .AT2 file

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

import difflib
import re
import tomllib
from collections.abc import Mapping
from pathlib import Path

from .contact import read_restitution, restitution_value
from .errors import InputError, read_text_file, shown_path, shown
from .io.files import atomic_write
from . import structure as _structures  # noqa: F401  (registers the structure models as drives)
from .excitation import DRIVES, read_motion_csv
from .io.records import read_signal
from .structure.loads import LOADS
from .geometry import SHAPES
from .materials import LIBRARY, Material, read_material
from .params import (Case, Container, ContactModel, Damper, InitialState, Numerics, ParticleSet, Recording,
                     read_baffles, read_tilt, read_wall_materials, read_with_material)
from .schema import (Spec, _choice, _grammar, _num, _quoted, check_keys, config_keys, plain_fields, read_fields,
                     read_list, read_number, read_quantity, replace, suggest, write_fields)

__all__ = ["load_case", "loads_case", "parse_toml", "case_from_dict", "case_to_dict", "case_with_keys", "dump_case", "dumps_case",
           "with_overrides", "key_spec", "SECTIONS"]

# The sections are read from the parameter dataclasses' own fields (pdamper.schema): a field's
# spec says its dimension, allowed values and key. A container shape and a drive kind read their
# own keys (a shape's fields; a drive's from_config); what is written here by hand is only the
# structure no field can say (per-material-pair tables, the restitution laws). The registries
# (SHAPES, DRIVES) are asked each time: a shape or drive registered later is read too.
_GEOMETRIES = SHAPES


def _shape_keys() -> dict:
    """The config keys of each registered shape (read when asked: a shape may register later)."""
    return {shape: config_keys(cls) for shape, cls in _GEOMETRIES.items()}


def _union(*groups) -> tuple:
    return tuple(dict.fromkeys(k for g in groups for k in g))


def _drive_sections() -> tuple:
    """The config sections drives are read from (``drive``, ``structure``), in registration order."""
    return tuple(dict.fromkeys(cls.config_section for cls in DRIVES.values()))


def _kinds(section: str) -> dict:
    """The registered drive kinds of ``section``: tag -> class."""
    return {kind: cls for kind, cls in DRIVES.items() if cls.config_section == section}


def _own_keys(section: str) -> dict:
    """Keys that only one kind of ``section`` has (a key of another kind is an error): tag -> keys."""
    kinds = _kinds(section)
    return {kind: tuple(k for k in cls.table_keys()
                        if not any(k in o.table_keys() for o in kinds.values() if o is not cls))
            for kind, cls in kinds.items()}


def _load_keys() -> tuple:
    """The keys a ``[load]`` section may hold: ``kind`` and every key of the registered load kinds
    (read when asked: a load kind may register later)."""
    return _union(("kind",), *(cls.table_keys() for cls in LOADS.values()))


def _section_keys(section: str) -> tuple:
    """The keys a drive section may hold: every key of its kinds (and ``kind`` where written)."""
    kinds = _kinds(section).values()
    tag = ("kind",) if any(cls.config_writes_kind for cls in kinds) else ()
    return _union(tag, *(cls.table_keys() for cls in kinds))


def _kind_of(table: dict, section: str):
    """The drive class a table of ``section`` is read by: its ``kind``, else the kind whose
    marking keys it has (a samples file: sampled), else the section's default kind."""
    kinds = _kinds(section)
    if "kind" in table:
        return kinds[_choice(table["kind"], f"[{section}] kind", tuple(kinds))]
    marked = {kind: [k for k in cls.config_marks if k in table] for kind, cls in kinds.items()}
    marked = {kind: keys for kind, keys in marked.items() if keys}
    if len(marked) > 1:
        said = " and ".join(f"{', '.join(keys)} ({kinds[kind].label()})" for kind, keys in marked.items())
        raise InputError(f"[{section}] {said} are given together; give the keys of one kind: "
                         + " or ".join(cls.config_summary for cls in kinds.values()) + ", not a mix")
    if marked:
        return kinds[next(iter(marked))]
    return next(cls for cls in kinds.values() if cls.config_default)


class _Sections(Mapping):
    """Allowed keys of each section, derived from the dataclasses' fields (the container's from
    the shapes registered when asked, a drive section's from its kinds registered when asked)."""

    def __init__(self, fixed: dict):
        self._fixed = fixed

    def _container(self) -> tuple:
        return _union(("shape",), *_shape_keys().values(), config_keys(Container, drop=("geometry",)))

    def __getitem__(self, section):
        if section == "container":
            return self._container()
        if section == "load":
            return _load_keys()
        if section in self._fixed:
            return self._fixed[section]
        if section in _drive_sections():
            return _section_keys(section)
        raise KeyError(section)

    def __iter__(self):
        fixed = list(self._fixed)
        drives = [s for s in _drive_sections() if s not in self._fixed]
        return iter(("container", fixed[0], *drives[:1], *fixed[1:], *drives[1:], "load"))

    def __len__(self):
        return len(self._fixed) + 2 + len([s for s in _drive_sections() if s not in self._fixed])


#: Allowed keys of each section, derived from the dataclasses' fields.
SECTIONS = _Sections({
    "particles": config_keys(ParticleSet),
    "contact": config_keys(ContactModel, drop=("pair_friction", "pair_restitution")) + ("pair",),
    "numerics": config_keys(Numerics),
    "recording": config_keys(Recording),
    "initial": config_keys(InitialState),
    "run": tuple(s.key or f.name for f, s in plain_fields(Case)),
    # [[damper]]: one of several dampers on the structure (pdamper.params.Damper)
    "damper": ("dof", "node", "angle", "direction", "container", "particles"),
})
_PAIR_KEYS = ("materials", "friction", "restitution")


# --------------------------------------------------------------------------- reading

def load_case(path, overrides: dict | None = None, *, prepare=None) -> Case:
    """Read the TOML config file ``path`` into a :class:`~pdamper.params.Case`.

    ``overrides`` maps dotted keys to values that replace (or add to) the file's, e.g.
    ``{"drive.stroke": 0.012, "drive.frequency": "2Hz", "run.cycles": 20, "initial.seed": 3}``;
    values are read exactly like the file's (SI numbers or strings with units). ``prepare``: a
    function of the file's parsed tables that returns them as the case is to be read (a reader's
    defaults, e.g. :func:`pdamper.design.load_structure`'s), before the overrides; its
    :class:`InputError` is prefixed by the file's name like the file's own.

    Every case file pdamper reads goes through here (the commands, the studies, the design).
    """
    path, text = read_text_file(path, "config file")
    return loads_case(text, overrides, source=shown_path(path), base_dir=path.parent, prepare=prepare)


def loads_case(text: str, overrides: dict | None = None, *, source: str = "<config>",
               base_dir=None, prepare=None) -> Case:
    """Like :func:`load_case` for TOML ``text``; ``base_dir`` resolves relative sample files."""
    return case_from_dict(parse_toml(text, source=source), overrides, source=source, base_dir=base_dir,
                          prepare=prepare)


#: Whole numbers of more digits than this are refused by Python's int() (sys.get_int_max_str_digits).
_INT_DIGITS = 4300
_LONG_NUMERAL = re.compile(r"(?<![\w.])[+-]?[0-9][0-9_]{%d,}" % _INT_DIGITS)


def parse_toml(text: str, *, source: str = "<config>") -> dict:
    """The tables of TOML ``text`` (a config file, a study file, a structure file), or an
    :class:`InputError` naming ``source`` and the line: invalid TOML, and also a whole number of
    more than 4,300 digits, which Python's ``int()`` refuses (``tomllib`` lets that ``ValueError``
    through)."""
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source}: invalid TOML: {' '.join(str(exc).split())}; check the syntax (key = value, "
                         "strings in quotes, [section] headers)") from None
    except ValueError:  # int(): "Exceeds the limit (4300 digits) for integer string conversion"
        m = _LONG_NUMERAL.search(text)
        where = f", line {text.count(chr(10), 0, m.start()) + 1}" if m else ""
        digits = len(m.group().replace("_", "").lstrip("+-")) if m else _INT_DIGITS + 1
        raise InputError(f"{source}{where}: a whole number of {digits} digits; a number is read with at most "
                         f"{_INT_DIGITS} digits: write it with an exponent (1e{digits - 1}) or, for a name, in "
                         "quotes") from None


def case_from_dict(data: dict, overrides: dict | None = None, *, source: str | None = None,
                   base_dir=None, prepare=None) -> Case:
    """Build a :class:`~pdamper.params.Case` from a parsed config ``data`` (see the module docstring);
    ``prepare`` as in :func:`load_case`."""
    data = _copy(data)
    if prepare is not None:
        data = _sourced(prepare, data, source)
    data = _apply_overrides(data, overrides or {})
    return _sourced(_Reader(Path(base_dir) if base_dir is not None else Path.cwd()).case, data, source)


def _sourced(read, data: dict, source: str | None):
    """``read(data)``, its :class:`InputError` prefixed by ``source`` (the file's name; None: as it is)."""
    try:
        return read(data)
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


#: The parameter classes whose fields make each section's keys (a drive section's: its kinds').
_SECTION_CLASSES = {
    "container": (Container,), "particles": (ParticleSet,), "contact": (ContactModel,), "numerics": (Numerics,),
    "recording": (Recording,), "initial": (InitialState,), "run": (Case,),
}


def _section_classes(section: str) -> tuple:
    if section in _SECTION_CLASSES:
        return _SECTION_CLASSES[section]
    return tuple(_kinds(section).values())
#: Specs of the structured keys that also take one plain value (a constant COR; one tilt angle for all axes).
_VALUE_SPECS = {"contact.restitution": Spec(kind="number"), "container.tilt": Spec(kind="number", dimension="angle")}


def key_spec(dotted: str) -> Spec:
    """The :class:`~pdamper.schema.Spec` of a config key written ``section.key`` (what a sweep axis
    over it holds), or an :class:`InputError` naming the allowed keys."""
    section, _, key = str(dotted).partition(".")
    if section not in SECTIONS:
        raise InputError(f"{shown(dotted)}: unknown section [{section}]; " + suggest(section, SECTIONS, "[{}]"))
    if key not in SECTIONS[section]:
        raise InputError(f"{shown(dotted)}: unknown key {shown(key)} in [{section}]; " + _quoted(key, SECTIONS[section]))
    if dotted in _VALUE_SPECS:
        return _VALUE_SPECS[dotted]
    classes = _section_classes(section)
    if section == "container":
        classes = (*_GEOMETRIES.values(), *classes)
    for cls in classes:
        for f, s in plain_fields(cls):
            if (s.key or f.name) == key:
                return s
    raise InputError(f"{shown(dotted)} is not a single value (a table or a list); it cannot be a sweep axis")


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
            raise InputError(f"override {shown(dotted)}: write it as 'section.key', e.g. 'drive.stroke'")
        section, key = parts
        if section not in SECTIONS:
            raise InputError(f"override {shown(dotted)}: unknown section [{section}]; "
                             + suggest(section, SECTIONS, "[{}]"))
        if key not in SECTIONS[section]:
            raise InputError(f"override {shown(dotted)}: unknown key {shown(key)} in [{section}]; "
                             + _quoted(key, SECTIONS[section]))
        if section in _drive_sections() and section not in data:
            there = next((sec for sec in _drive_sections() if sec in data), None)
            if there is not None:
                raise InputError(f"override {shown(dotted)}: this file's drive is its [{there}]; a [{section}] beside it "
                                 f"(the damper's rig beside a structure) is written in the file, not made by an "
                                 f"override; give [{there}] keys")
        table = data.setdefault(section, {})
        if isinstance(table, list):
            if len(table) != 1:
                raise InputError(f"override {shown(dotted)}: the config has {len(table)} [[{section}]] tables; "
                                 "edit the file to change one of them")
            table = table[0]
        if not isinstance(table, dict):
            raise InputError(f"[{section}] must be a table (a [{section}] header with key = value lines)")
        if section in _drive_sections() and "kind" not in table and table:
            _check_override_kind(dotted, section, key, table)
        table[key] = value
    return data


def _check_override_kind(dotted: str, section: str, key: str, table: dict) -> None:
    """An override of a key that only another kind of drive has than the file's: refused with the
    kind each belongs to (``drive.stroke`` on a sampled drive)."""
    try:
        cls = _kind_of(table, section)
    except InputError:
        return  # the reader says what is wrong with the file's table
    owner = next((kind for kind, keys in _own_keys(section).items() if key in keys), None)
    if owner is not None and key not in cls.table_keys():
        raise InputError(f"override {shown(dotted)}: the file's [{section}] is {cls.label()}; {key} applies to "
                         f"{_kinds(section)[owner].label()} only")


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
                             f"got {shown(t)}")
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
        tables = self._damper_tables(data)
        with _context("particles"):
            own = data.get("particles")
            if own is None and tables and all("particles" in t for t in tables):
                own = tables[0]["particles"]  # the first damper's filling is the case's
            particles = self.particles(own)
        with _context("damper"):
            dampers = tuple(self.damper(t, k, len(tables), data, container, particles) for k, t in enumerate(tables))
            data = self._damper_points(data, tables)
        if len(dampers) == 1:  # one damper: the case's own container and filling
            container, particles, dampers = dampers[0].container, dampers[0].particles, ()
        drive, rig = self.drive(data)
        if tables and not drive.coupled:
            raise InputError("[[damper]] tables put dampers on a structure; this case has no [structure] (its drive "
                             "moves one container): remove [[damper]] or give a [structure]")
        mats = [p.material for p in particles] + [container.material]
        for m in mats:
            if any(o.name == m.name and o != m for o in mats):
                raise InputError(f"two different materials are both named {shown(m.name)}; contacts are looked up by "
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
                        **read_fields(run, "run", Case), **({"rig": rig} if rig is not None else {}),
                        **({"dampers": dampers} if dampers else {}))

    # ---- several dampers ([[damper]])
    def _damper_tables(self, data: dict) -> list:
        value = data.get("damper")
        if value is None:
            return []
        tables = value if isinstance(value, list) else [value]
        if not tables or not all(isinstance(t, dict) for t in tables):
            raise InputError("[[damper]] must be tables, each a damper on the structure: [[damper]] dof = 3 (or node = "
                             "4), with its own [damper.container] and [damper.particles] where they differ")
        for k, t in enumerate(tables):
            try:
                check_keys(t, "damper", SECTIONS["damper"])
            except InputError as exc:
                if len(tables) == 1:
                    raise
                raise InputError(f"{exc} (in [[damper]] table #{k + 1})") from None
        return tables

    def damper(self, t: dict, k: int, n: int, data: dict, container: Container, particles: tuple) -> Damper:
        """Damper ``k`` of ``n`` of the ``[[damper]]`` table ``t``: its container (the ``[container]``
        section's keys with its own over them; its own alone when it names another shape), its
        filling (else the case's), its direction (else the structure's)."""
        label = "damper" if n == 1 else f"damper #{k + 1}"
        box = container
        if "container" in t:
            own = t["container"]
            if not isinstance(own, dict):
                raise InputError(f"[{label}] container = {shown(own)}: give a table, [damper.container] with the "
                                 "[container] keys")
            base = self._table(data, "container")
            merged = own if own.get("shape", base.get("shape", "cuboid")) != base.get("shape", "cuboid") \
                else {**base, **own}
            with _context(f"{label} container"):
                box = self.container(merged)
        fill = particles
        if "particles" in t:
            with _context(f"{label} particles"):
                fill = self.particles(t["particles"])
        kw = {}
        if "angle" in t:
            kw["angle"] = read_quantity(t["angle"], f"[{label}] angle", "angle")
        if "direction" in t:
            v = t["direction"]
            if isinstance(v, str):
                from .excitation import _DIRECTION_WORDS

                if v.strip().lower() not in _DIRECTION_WORDS:
                    raise InputError(f"[{label}] direction = {shown(v)}; give three numbers [x, y, z] (lab frame, y up) or "
                                     + ", ".join(repr(w) for w in _DIRECTION_WORDS))
                v = list(_DIRECTION_WORDS[v.strip().lower()])
            kw["direction"] = read_list(v, f"[{label}] direction", "dimensionless")
        if n == 1 and kw:
            raise InputError(f"[{label}] {', '.join(kw)}: one damper moves along the structure's direction; give "
                             "[structure] angle or direction")
        return Damper(container=box, particles=fill, **kw)

    def _damper_points(self, data: dict, tables: list) -> dict:
        """``data`` with the structure's damper points set from the tables' ``dof`` / ``node`` (the
        structure's key, :attr:`~pdamper.structure.StructureBase.damper_points_key`), checked
        against what ``[structure]`` gives."""
        named = [k for k in ("dof", "node") if any(k in t for t in tables)]
        if not named:
            return data
        if "structure" not in data:
            raise InputError(f"[[damper]] {named[0]} puts the dampers on a structure; give a [structure] section")
        st = self._table(data, "structure")
        cls = _kind_of(st, "structure")
        table_key, structure_key = cls.damper_points_key
        if table_key is None:
            raise InputError(f"[[damper]] {named[0]}: {cls.label()} has one point the dampers sit on; leave "
                             f"{named[0]} out")
        wrong = [k for k in named if k != table_key]
        if wrong:
            raise InputError(f"[[damper]] {wrong[0]}: the dampers of {cls.label()} are placed by {table_key} = ...")
        missing = [k + 1 for k, t in enumerate(tables) if table_key not in t]
        if missing:
            raise InputError(f"[[damper]] #{missing[0]} has no {table_key}; give each damper its {table_key} (or none, "
                             f"and the structure's {structure_key} = [...])")
        points = [t[table_key] for t in tables]
        given = st.get(structure_key)
        if given is not None and list(given if isinstance(given, list) else [given]) != points:
            raise InputError(f"[structure] {structure_key} = {shown(given)} and the [[damper]] tables' {table_key} "
                             f"{shown(points)} differ; give the points in one place")
        data = dict(data)
        data["structure"] = {**st, structure_key: points if len(points) > 1 else points[0]}
        return data

    def container(self, t) -> Container:
        check_keys(t, "container", SECTIONS["container"])
        shape = self._choice(t, "container", "shape", tuple(_GEOMETRIES), "cuboid")
        shape_keys = _shape_keys()
        for key in t:
            owners = [s for s, keys in shape_keys.items() if key in keys]
            if owners and shape not in owners:
                raise InputError(f"[container] {key} applies to shape = {shown(owners[0])}, but shape = {shown(shape)} "
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
                raise InputError(f"[{label}] must be a table, got {shown(t)}")
            out.append(read_with_material(t, label, ParticleSet, required="count",
                                          hint="; give the number of spheres, e.g. count = 36"))
        return tuple(out)

    def drive(self, data: dict) -> tuple:
        """The case's drive and the damper's rig drive (:attr:`pdamper.params.Case.rig`, or None):
        the last drive section the file has (``[drive]``, or the ``[structure]`` the container rides
        on) is the case's drive; an earlier one beside a coupled drive (a ``[drive]`` beside a
        ``[structure]``) is the damper's rig; each read by its kind (:func:`_kind_of`,
        :meth:`pdamper.excitation.DriveBase.from_config`); none: the default ``[drive]``."""
        sections = _drive_sections()
        present = [sec for sec in sections if sec in data]
        section = present[-1] if present else sections[0]
        others = [sec for sec in present[:-1] if self._table(data, sec)]
        drive = self._drive(data, section, self.load(data))
        rig = self._drive(data, others[0]) if others else None
        if len(others) > 1 or (rig is not None and (rig.coupled or not drive.coupled)):
            raise InputError(f"[{others[0]}] {', '.join(self._table(data, others[0]))} cannot be combined with "
                             f"[{section}]: a case has one drive (the [{section}] moves the container); remove "
                             f"[{others[0]}] (the direction is [{section}] angle)")
        return drive, rig

    def _drive(self, data: dict, section: str, load=None):
        """The drive of the table of drive ``section``, loaded by ``load`` (the ``[load]`` section's,
        which only a coupled drive takes) where one is given."""
        with _context(section):
            t = self._table(data, section)
            check_keys(t, section, SECTIONS[section])
            cls = _kind_of(t, section)
            if load is not None:
                if not cls.coupled:
                    raise InputError(f"[load] loads a structure; this case's [{section}] is {cls.label()}: give a "
                                     "[structure] section (the container riding on it) or remove [load]")
                # the [structure]'s own force may be there, 0 (a file made for free decay and response)
                forced = ("force_amplitude" in t and
                          read_quantity(t["force_amplitude"], f"[{section}] force_amplitude", "force") != 0)
                if forced or "load" in t:
                    raise InputError(f"[load] and [{section}] {'force_amplitude' if forced else 'load'} both load the "
                                     f"structure; give the load in one place (force_amplitude = 0 with a [load])")
                t = {**t, **load.structure_keys()}
            for other, keys in _own_keys(section).items():
                found = [k for k in keys if k in t]
                if found and _kinds(section)[other] is not cls:
                    raise InputError(f"[{section}] {', '.join(found)} {'is a key' if len(found) == 1 else 'are keys'} "
                                     f"of {_kinds(section)[other].label()}, but this [{section}] is {cls.label()}; "
                                     "give " + " or ".join(c.config_summary for c in _kinds(section).values())
                                     + ", not a mix")
            return cls.from_config(t, base_dir=self.base_dir)

    def load(self, data: dict):
        """The ``[load]`` section's load (:mod:`pdamper.structure.loads`), read by its ``kind``
        (a file named in it relative to the config file, read by
        :func:`pdamper.io.records.read_signal`), or None without one."""
        if "load" not in data:
            return None
        with _context("load"):
            t = self._table(data, "load")
            check_keys(t, "load", SECTIONS["load"])
            if "kind" not in t:
                raise InputError("[load] kind is missing: give one of " + ", ".join(repr(k) for k in LOADS))
            cls = LOADS[_choice(t["kind"], "[load] kind", tuple(LOADS))]
            return cls.from_config(t, base_dir=self.base_dir, read_signal=read_signal)

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
                raise InputError(f"[[contact.pair]] #{k + 1} must be a table, got {shown(p)}")
            check_keys(p, label, _PAIR_KEYS)
            mats = p.get("materials")
            if not (isinstance(mats, list) and len(mats) == 2 and all(isinstance(m, str) for m in mats)):
                raise InputError(f"[{label}] materials = {shown(mats)}: give two material names, e.g. ['steel', 'pvc']")
            for m in mats:
                if m not in known:
                    near = difflib.get_close_matches(m, known, n=1, cutoff=0.5)
                    hint = f"did you mean {near[0]!r}?" if near else "this case has " + ", ".join(map(repr, known))
                    raise InputError(f"[{label}] materials: {shown(m)} is not a material of this case; {hint}")
            key = (mats[0], mats[1])
            if "friction" not in p and "restitution" not in p:
                raise InputError(f"[{label}] sets nothing; give friction and/or restitution")
            for store, field_ in ((pf, "friction"), (pr, "restitution")):
                if field_ in p:
                    if key in store or key[::-1] in store:
                        raise InputError(f"[{label}] {field_} for {shown(key[0])}-{shown(key[1])} is given twice")
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


# --------------------------------------------------------------------------- writing

def _material_to(m: Material):
    if LIBRARY.get(m.name) == m:
        return m.name
    return _fields_to(m)


#: The plain fields of an object as config keys (:func:`pdamper.schema.write_fields`).
_fields_to = write_fields




def case_to_dict(case: Case) -> dict:
    """The full config of ``case`` as a TOML-ready dict, every quantity in plain SI units.

    Written from the same field specs the reader uses (:mod:`pdamper.schema`), so that
    ``case_from_dict(case_to_dict(case)) == case``.
    """
    c = case.container
    container = _container_to(c, baffles=False)
    parts = [{**_fields_to(p), "material": _material_to(p.material)} for p in case.particles]

    ct = case.contact
    plain = _fields_to(ct)
    # friction, restitution, then the rest: the order of the text a store's fingerprint was taken of
    contact = {"friction": plain.pop("friction"), "restitution": restitution_value(ct.restitution), **plain}
    pairs = []
    for key, mu in ct.pair_friction.items():
        pairs.append({"materials": list(key), "friction": _num(mu)})
    for key, law in ct.pair_restitution.items():
        for p in pairs:
            if tuple(p["materials"]) == tuple(key) and "restitution" not in p:
                p["restitution"] = restitution_value(law)
                break
        else:
            pairs.append({"materials": list(key), "restitution": restitution_value(law)})
    if pairs:
        contact["pair"] = pairs

    out = {"container": container, "particles": parts[0] if len(parts) == 1 else parts}
    container.update(_container_to(c, baffles=True, only=True))
    out.update({"contact": contact, "numerics": _fields_to(case.numerics), "recording": _fields_to(case.recording),
                "initial": _fields_to(case.initial), "run": _fields_to(case)})
    # each drive's table after the section it names ([drive] after [particles], [structure] last):
    # the order of the text a store's fingerprint was taken of; the damper's rig ([drive]) beside
    # a structure the same way; and the sections a drive writes after its own (a structure's [load])
    for d in (case.rig, case.drive):
        if d is None:
            continue
        if type(d) is not DRIVES.get(d.kind):
            raise InputError(f"cannot write drive {type(d).__name__} to a config file")
        at = list(out).index(d.config_after) + 1
        items = list(out.items())
        out = dict(items[:at] + [(d.config_section, d.config_table()), *d.config_sections().items()] + items[at:])
    if case.dampers:
        out["damper"] = [_damper_to(d) for d in case.dampers]
    return out


def _container_to(c: Container, *, baffles: bool, only: bool = False) -> dict:
    """The ``[container]`` table of ``c``: its shape's keys, material, tilt and own keys (``only``: none
    of those), then (``baffles``) its baffles and wall materials where it has them (the order of the
    text a store's fingerprint was taken of: those come after the [contact] section is made)."""
    out = {} if only else {**_fields_to(c.geometry), "material": _material_to(c.material),
                           "tilt": [float(a) for a in c.tilt], **_fields_to(c)}
    if baffles and c.baffles:
        out["baffles"] = [{**_fields_to(b), **({"material": _material_to(b.material)} if b.material else {})}
                          for b in c.baffles]
    if baffles and c.wall_materials:
        out["wall_materials"] = {w: _material_to(m) for w, m in c.wall_materials.items()}
    return out


def _damper_to(d: Damper) -> dict:
    """A ``[[damper]]`` table: its container and filling (its place is the structure's, in order)."""
    box = {**_container_to(d.container, baffles=False), **_container_to(d.container, baffles=True, only=True)}
    parts = [{**_fields_to(p), "material": _material_to(p.material)} for p in d.particles]
    out = {"container": box, "particles": parts[0] if len(parts) == 1 else parts}
    if d.angle is not None:
        out["angle"] = float(d.angle)
    if d.direction is not None:
        out["direction"] = [float(x) for x in d.direction]
    return out


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


# -- a case at config keys' values, tables' entries included (an ensemble's sample) ------------------
#: ``contact.pair[a, b].friction`` / ``.restitution``: a material pair's value in its [[contact.pair]] table
PAIR_KEY = re.compile(r"^contact\.pair\[\s*([^\],]+?)\s*,\s*([^\],]+?)\s*\]\.(friction|restitution)$")
#: ``structure.modes[k].<key>``: a key of mode k of the modes given as data
MODE_KEY = re.compile(r"^structure\.modes\[\s*(\d+)\s*\]\.(\w+)$")


def _set_pair(data: dict, a: str, b: str, what: str, value) -> None:
    contact = data.setdefault("contact", {})
    pairs = contact.setdefault("pair", [])
    if isinstance(pairs, dict):
        pairs = contact["pair"] = [pairs]
    for p in pairs:
        if isinstance(p, dict) and sorted(map(str, p.get("materials", ()))) == sorted((a, b)):
            p[what] = value
            return
    pairs.append({"materials": [a, b], what: value})


def _set_mode(data: dict, k: int, what: str, value, key: str) -> None:
    table = data.get("structure")
    modes = table.get("modes") if isinstance(table, dict) else None
    if not isinstance(modes, list):
        raise InputError(f"{key}: this case's structure has no modes given as data (structure.modes = [...]); an "
                         "FE structure's modes follow from its matrices: give structure.stiffness_scale or "
                         "structure.mass_scale, or structure.damping_ratio")
    if not 0 <= k < len(modes):
        raise InputError(f"{key}: the structure has {len(modes)} mode{'s' if len(modes) != 1 else ''} "
                         f"(structure.modes[0] to [{len(modes) - 1}])")
    modes[k][what] = value


def case_with_keys(base, values: dict, *, label: str = "sample"):
    """The case ``base`` with config keys' ``values`` (``{key: value}``, SI; an ensemble's sample,
    :mod:`pdamper.studies.unknowns`) set: written as its config (:func:`case_to_dict`), the values set there as ``--set`` sets them (a
    material pair's or a mode's in its table), and read back, so every value is read and checked
    as in a config file. An error names ``label`` (which sample) and the key."""
    try:
        data = case_to_dict(base)
    except InputError as exc:
        raise InputError(f"the ensemble's base case cannot be written as a config: {exc}") from None
    overrides = {}
    for key, v in values.items():
        v = v.item() if hasattr(v, "item") else v
        m, mm = PAIR_KEY.match(key), MODE_KEY.match(key)
        if m:
            _set_pair(data, m.group(1), m.group(2), m.group(3), v)
        elif mm:
            _set_mode(data, int(mm.group(1)), mm.group(2), v, key)
        else:
            overrides[key] = v
    try:
        return case_from_dict(data, overrides)
    except InputError as exc:
        said = ", ".join(f"{k} = {v:.6g}" if isinstance(v, float) else f"{k} = {shown(v)}" for k, v in values.items())
        raise InputError(f"{label} ({said}) is not a valid case: {' '.join(str(exc).split())}; narrow the "
                         "distribution (e.g. distribution = \"truncated\" with low/high, or a uniform)") from None

