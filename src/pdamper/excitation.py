"""Prescribed container motion behind one protocol: harmonic ``x_c = X sin(Omega t)``, a motion
given as samples, a container at rest. The same protocol serves the structures the container
rides on (:mod:`pdamper.structure`, two-way coupled): a drive is whatever moves the container.

A drive kind is one class registered with :func:`register_drive`; nothing outside its module
asks which kind a drive is: callers ask what it can do, and each kind reads its own config
table. What a drive answers (:class:`DriveBase` gives the defaults):

=============================  ======================================================================
``kind``, ``config_section``   its tag (``[drive] kind``) and the config section it is read from
config keys                    its dataclass fields, declared with :func:`pdamper.schema.param`, and
                               ``config_extra_keys`` (a samples file, a natural frequency)
``from_config(table, ...)``    the drive of a config table (its own keys, read and checked)
``config_table()``             the config table it is written as (the inverse)
``config_sections()``          sections written after its own (a structure's ``[load]``)
``config_marks``               keys that make a table without ``kind`` this kind's
``config_default``             the kind a section's table is when no key marks another
``kernel_drive()``             ``(kernel kind, par, table, state)`` for the kernels; the kernel kind
                               is the name of a compiled motion (:data:`pdamper.kernels.drive.DRIVE_KINDS`)
``kernel_load()``              the kernels' table of a load given in time (a structure's; none else)
``speed_bound()``              the container's largest speed [m/s] (the automatic time step)
``duration(cycles)``           the driven time [s]
``motion(t)``                  ``(x, v, a)`` at times t, as prescribed (without the bed)
``container_motion(t, s)``     ``(x, v, a)`` now, the kernels' drive state ``s`` included
``start_state(s)``             releases a coupled structure at t = 0 (None for a prescribed motion)
``carrying(mass)``             the drive with the empty container's ``mass`` [kg] on it (a prescribed
                               motion is unchanged; a structure carries it at the damper)
``lab_direction()``            the unit direction of the motion in the lab frame
``describe()``                 one line for people
``stroke``, ``frequency``      X [m] and f [Hz] where the drive has them, else None
=============================  ======================================================================

and what it can do (class attributes, all False on :class:`DriveBase`):

=================  ==================================================================================
``periodic``       harmonic, with whole cycles the analysis drops (``[run] drop_cycles``)
``sweepable``      its keys may be swept, fitted or stopped early (``drive.stroke``, ``drive.frequency``)
``analysable``     a prescribed motion whose force and velocity the complex-power analysis reads
``coupled``        moved by the bed's force (a structure): its motion is recorded
``counts_cycles``  the run lasts ``[run] cycles`` periods of ``frequency`` (else its own duration)
=================  ==================================================================================

**Direction.** The motion acts along ``direction`` (a 3-vector in the lab frame, whose y axis
points up against gravity: ``[0, 1, 0]`` or ``"vertical"`` is a vertical drive) or, as a
shorthand for a horizontal drive, along ``angle`` [rad] from the lab x axis (the container's
length when untilted) towards the lab z axis. A drive with a vertical part lifts the bed off
the floor above A = g: that is expected (the bouncing regime), not warned about.

The structures (``CoupledStructure``, ``ModalStructure``, ``read_structure_matrices``) live in
:mod:`pdamper.structure`; their old names here still work and warn.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .errors import InputError, checked_file, shown
from .schema import OwnTable, config_keys, convert_fields, param, read_fields, register_tagged, write_fields
from .units import thousandth_hint, unit_factor

__all__ = ["HarmonicDrive", "SampledDrive", "Still", "DriveBase", "DRIVES", "register_drive", "read_motion_csv"]

#: Registered drive kinds by tag (``[drive] kind``; the structures' ``structure`` and ``modal``).
DRIVES: dict[str, type] = {}

#: Words a config may give for ``direction``.
_DIRECTION_WORDS = {"vertical": (0.0, 1.0, 0.0), "up": (0.0, 1.0, 0.0), "x": (1.0, 0.0, 0.0), "z": (0.0, 0.0, 1.0)}


def register_drive(cls):
    """Class decorator: register a drive class under its ``kind`` tag. Returns the class. A drive
    registered at any time is read from config files from then on (the reader asks :data:`DRIVES`
    each time)."""
    return register_tagged(DRIVES, cls, "kind", "drive", needs=("kernel_drive", "motion", "duration", "from_config"))


class DriveBase(OwnTable):
    """The answers of the drive protocol that most drives share (see the module docstring)."""

    #: the config section the drive is read from (:func:`pdamper.schema.replace` reads it too)
    config_section = "drive"
    #: X [m] and f [Hz] where the drive has them
    stroke = None
    frequency = None
    #: what it can do (the module docstring)
    periodic = False
    sweepable = False
    analysable = False
    coupled = False
    counts_cycles = False
    #: the dampers a drive moves (a structure may carry several) and whether another code advances
    #: it (a co-simulated structure: :mod:`pdamper.cosim`)
    damper_count = 1
    cosimulated = False
    #: what a config file must give (its keys) and the values it may leave out
    config_required: tuple = ()
    config_defaults: dict = {}
    config_hint = ""
    #: config keys beyond the dataclass fields; keys that make a table without ``kind`` this
    #: kind's; whether this is the section's kind when nothing marks another
    config_extra_keys: tuple = ()
    config_marks: tuple = ()
    config_default = False
    #: the kind in words for messages ("a harmonic drive"), and the keys that say it ("stroke")
    config_label = ""
    config_summary = ""
    #: the written table carries ``kind`` (a [structure] tells its kind by its keys); the
    #: section it is written after (the order of the text a store's fingerprint was taken of)
    config_writes_kind = True
    config_after = "particles"

    # ---- reading and writing its own config table (label, table_keys: schema.OwnTable)
    @classmethod
    def from_config(cls, table: dict, *, base_dir=None):
        """The drive of the config ``table`` of its section (``base_dir`` resolves files named in
        it): each plain key read by its field's spec, the kind's own keys by
        :meth:`config_read_extra`; keys of no field of this kind are refused."""
        section = cls.config_section
        t = {k: v for k, v in table.items() if k != "kind"}
        foreign = [k for k in t if k not in cls.table_keys()]
        if foreign:
            raise InputError(f"[{section}] {', '.join(foreign)} does not apply to {cls.label()} (give "
                             f"{', '.join(config_keys(cls))})")
        words = t.pop("direction") if isinstance(t.get("direction"), str) else None
        kw = read_fields(t, section, cls)
        if words is not None:
            kw["direction"] = words
        kw = {**cls.config_defaults, **kw, **cls.config_read_extra(t, base_dir)}
        missing = [k for k in cls.config_required if k not in kw]
        if missing:
            raise InputError(f"[{section}] {cls.label()} needs {', '.join(repr(k) for k in missing)}: "
                             f"{cls.config_hint}")
        return cls(**kw)

    @classmethod
    def config_read_extra(cls, table: dict, base_dir) -> dict:
        """Keyword arguments from the table's keys that are not plain fields; none by default."""
        return {}

    def config_table(self) -> dict:
        """The config table of this drive, every quantity in plain SI (read back by
        :meth:`from_config`)."""
        out = {**write_fields(self), **self.config_extra()}
        if not self.config_writes_kind:
            del out["kind"]
        return out

    def config_extra(self) -> dict:
        """Config keys beyond the plain fields (a modal structure's ``modes``); none by default."""
        return {}

    def config_sections(self) -> dict:
        """Sections written after the drive's own (a structure's ``[load]``): section -> table;
        none by default."""
        return {}

    # ---- motion
    def _prepare(self) -> None:
        """First in ``__post_init__``: a direction given as a word becomes its vector, then the
        fields given with units are converted to SI."""
        d = self.direction
        if isinstance(d, str):
            if d.strip().lower() not in _DIRECTION_WORDS:
                raise InputError(f"{self.config_section}.direction = {shown(d)}; give three numbers [x, y, z] (lab frame, y up) "
                                 f"or one of {', '.join(repr(w) for w in _DIRECTION_WORDS)}")
            object.__setattr__(self, "direction", _DIRECTION_WORDS[d.strip().lower()])
        convert_fields(self, self.config_section)

    def _check_direction(self) -> None:
        """Validate ``angle`` and ``direction`` (called by each drive's ``__post_init__``)."""
        sec = self.config_section
        if not (isinstance(self.angle, (int, float)) and math.isfinite(self.angle)):
            raise InputError(f"{sec}.angle = {shown(self.angle)}; must be a finite angle")
        d = self.direction
        if d is None:
            return
        try:
            v = np.asarray(d, dtype=float)
        except (TypeError, ValueError):
            v = np.zeros(0)
        if v.shape != (3,) or not np.all(np.isfinite(v)) or not np.linalg.norm(v) > 0:
            raise InputError(f"{sec}.direction = {shown(self.direction)}; give three finite numbers, not all 0, e.g. "
                             "[0, 1, 0] for a vertical drive (lab frame: y up)")
        if self.angle != 0.0:
            raise InputError(f"{sec}.direction and {sec}.angle are both given; give either direction = "
                             f"[{', '.join(f'{c:g}' for c in v)}] or angle (the horizontal shorthand), not both")
        object.__setattr__(self, "direction", tuple(float(x) for x in v / np.linalg.norm(v)))

    def lab_direction(self) -> np.ndarray:
        """The unit direction of the motion in the lab frame (y up)."""
        if self.direction is not None:
            return np.asarray(self.direction, dtype=float)
        return np.array([np.cos(self.angle), 0.0, np.sin(self.angle)])

    @property
    def vertical_share(self) -> float:
        """|d_y|: the vertical part of the direction (0 for a horizontal drive)."""
        return abs(float(self.lab_direction()[1]))

    def speed_bound(self) -> float:
        """The container's largest speed [m/s] (for the automatic time step)."""
        _, v, _ = self.motion(np.linspace(0.0, self.duration(1.0), 2001))
        return float(np.max(np.abs(v)))

    def container_motion(self, t: float, state):
        """``(x, v, a)`` [m, m/s, m/s^2] of the container at time ``t`` (held at rest before 0)."""
        return self.motion(np.array([max(t, 0.0)]))

    def start_state(self, state):
        """Release at t = 0; a prescribed motion has nothing to release (None)."""
        return None

    def kernel_drive(self):
        """``(kernel kind, par, table, state)`` for :mod:`pdamper.kernels.drive`: the kernel kind
        is the name of a compiled motion (:data:`pdamper.kernels.drive.DRIVE_KINDS`)."""
        kind, par, tab = self.kernel_args()
        return kind, par, tab, np.zeros((2, 5))

    def kernel_load(self):
        """The kernels' load table (:attr:`pdamper.kernels.bundles.Drive.load`, rows (t_j, ...) of a
        load given in time, :mod:`pdamper.kernels.structure`): none for a prescribed motion (one
        row of zeros, never read)."""
        return np.zeros((1, 4))

    def carrying(self, mass: float):
        """The drive with the empty container's ``mass`` [kg] on it: a prescribed motion moves the
        container whatever its mass (the mass enters the driving force only), so itself."""
        return self

    def describe(self) -> str:
        return f"{self.kind} drive"

    def check_scale(self, length: float) -> None:
        """InputError when the drive moves the container absurdly far for its inner ``length`` [m]
        (a bare number read as metres); nothing to check by default."""



@register_drive
@dataclass(frozen=True, kw_only=True)
class HarmonicDrive(DriveBase):
    """``x_c = X sin(Omega t)``, Omega = 2 pi f (paper Sect. 2).

    Parameters
    ----------
    stroke : float
        X [m], > 0 (amplitude of the container motion).
    frequency : float
        f [Hz], > 0.
    angle : float
        Direction of the drive in the horizontal plane [rad] (0: along the container's length).
    direction : (x, y, z) or None
        Direction of the drive in the lab frame (y up; ``(0, 1, 0)``: vertical); instead of ``angle``.
    """

    stroke: float = param(dimension="length", paper="3-50 mm")
    frequency: float = param(2.0, dimension="frequency", paper="2 Hz")
    angle: float = param(0.0, dimension="angle")
    direction: tuple | None = param(None, kind="list")
    kind: str = param("harmonic", kind="tag")
    periodic = True
    sweepable = True
    analysable = True
    counts_cycles = True
    config_defaults = {"stroke": 0.012}
    config_default = True
    config_label = "a harmonic drive"
    config_summary = "stroke (harmonic)"

    def __post_init__(self):
        self._prepare()
        if not (self.stroke > 0 and math.isfinite(self.stroke)):
            raise InputError(f"drive.stroke = {shown(self.stroke)} m; must be > 0 (e.g. '12mm')")
        if not (self.frequency > 0 and math.isfinite(self.frequency)):
            raise InputError(f"drive.frequency = {shown(self.frequency)} Hz; must be > 0 (e.g. '2Hz')")
        self._check_direction()

    @property
    def omega(self) -> float:
        """Omega [rad/s]."""
        return 2.0 * math.pi * self.frequency

    @property
    def velocity_amplitude(self) -> float:
        """V = X Omega [m/s]."""
        return self.stroke * self.omega

    @property
    def acceleration_amplitude(self) -> float:
        """A = X Omega^2 [m/s^2]."""
        return self.stroke * self.omega**2

    def duration(self, cycles: float) -> float:
        """Time [s] of ``cycles`` periods."""
        return cycles / self.frequency

    def motion(self, t):
        """(x, v, a) of the container at times t [s] (t >= 0), vectorised."""
        t = np.asarray(t, dtype=float)
        w = self.omega
        s, c = np.sin(w * t), np.cos(w * t)
        return self.stroke * s, self.stroke * w * c, -self.stroke * w * w * s

    def kernel_args(self):
        """(kernel kind, par, tab) for :func:`pdamper.kernels.drive.drive_motion`."""
        return "harmonic", np.array([self.stroke, self.omega, 0.0]), np.zeros((1, 5))

    def speed_bound(self) -> float:
        """V = X Omega [m/s]."""
        return self.velocity_amplitude

    def check_scale(self, length: float) -> None:
        """A stroke beyond twice the container's length is a bare number meant in mm."""
        if self.stroke > 2 * length:
            raise InputError(f"drive.stroke = {self.stroke:g} m is {self.stroke / length:.3g} times the container's "
                             f"length {length:g} m (a number without a unit is metres){thousandth_hint(self.stroke, 2 * length)}")

    def describe(self) -> str:
        where = "" if self.direction is None and self.angle == 0.0 else (
            f" along [{', '.join(f'{c:.3g}' for c in self.lab_direction())}]" if self.direction is not None
            else f" at {math.degrees(self.angle):g} deg")
        return f"harmonic X = {self.stroke * 1e3:g} mm, f = {self.frequency:g} Hz{where}"


@register_drive
@dataclass(frozen=True, kw_only=True)
class SampledDrive(DriveBase):
    """A container motion given as samples (e.g. a measured displacement record).

    Position samples are interpolated by a C2 cubic spline (scipy ``CubicSpline``, not-a-knot);
    when velocities (and accelerations) are given too, a cubic Hermite spline through positions
    and velocities is used so the given velocities are honoured.

    Parameters
    ----------
    time : array [s], strictly increasing, starting at 0.
    position : array [m].
    velocity : array [m/s], optional.
    angle : float, drive direction [rad] as for :class:`HarmonicDrive`.
    frequency : float, optional drive frequency [Hz] for the analysis (detected if omitted).
    """

    # (the order of the fields is the order a config file is written in)
    angle: float = param(0.0, dimension="angle")
    frequency: float | None = param(None, dimension="frequency")
    time: tuple = param((), kind="list", dimension="time")
    position: tuple = param((), kind="list", dimension="length")
    velocity: tuple | None = param(None, kind="list", dimension="velocity")
    acceleration: tuple | None = param(None, kind="list", dimension="acceleration")
    direction: tuple | None = param(None, kind="list")
    kind: str = param("samples", kind="tag")
    analysable = True
    config_required = ("time", "position")
    config_hint = "give time = [...] and position = [...] (optionally velocity = [...]) or samples = 'motion.csv'"
    config_extra_keys = ("samples",)
    config_marks = ("samples", "time", "position", "velocity", "acceleration")
    config_label = "a sampled drive"
    config_summary = "samples or time/position (sampled)"

    @classmethod
    def config_read_extra(cls, table: dict, base_dir) -> dict:
        """``samples = "motion.csv"`` (relative to the config file): the columns of the file
        (:func:`read_motion_csv`), instead of inline arrays."""
        if "samples" not in table:
            return {}
        extra = [k for k in cls.config_marks[1:] if k in table]
        if extra:
            raise InputError(f"[drive] give either samples = 'file.csv' or inline {', '.join(extra)}, not both")
        value = table["samples"]
        if not isinstance(value, str) or not value.strip():
            raise InputError(f"[drive] samples = {shown(value)} must be the path of a CSV file")
        path = Path(value)
        if not path.is_absolute():
            path = Path(base_dir if base_dir is not None else Path.cwd()) / path
        return read_motion_csv(path)

    def __post_init__(self):
        self._prepare()
        self._check_direction()
        t = np.asarray(self.time, dtype=float)
        x = np.asarray(self.position, dtype=float)
        if t.ndim != 1 or t.size < 4 or x.shape != t.shape:
            raise InputError(f"drive samples: need >= 4 times and as many positions, got {t.size} and {x.size}")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(x))):
            raise InputError("drive samples: time and position must be finite numbers (found NaN or inf)")
        if np.any(np.diff(t) <= 0):
            k = int(np.argmax(np.diff(t) <= 0))
            raise InputError(f"drive samples: time must increase strictly; it does not at sample {k + 1} (t = {shown(t[k + 1])} s)")
        for name in ("velocity", "acceleration"):
            v = getattr(self, name)
            if v is not None and np.asarray(v, dtype=float).shape != t.shape:
                raise InputError(f"drive samples: {name} must have as many samples as time ({t.size})")
        object.__setattr__(self, "time", tuple((t - t[0]).tolist()))
        object.__setattr__(self, "position", tuple(x.tolist()))

    def duration(self, cycles: float | None = None) -> float:
        """Length of the record [s]."""
        return float(self.time[-1])

    def _spline(self):
        from scipy.interpolate import CubicHermiteSpline, CubicSpline

        t = np.asarray(self.time)
        x = np.asarray(self.position)
        if self.velocity is not None:
            return CubicHermiteSpline(t, x, np.asarray(self.velocity, dtype=float))
        return CubicSpline(t, x)

    def motion(self, t):
        """(x, v, a) at times t [s], vectorised."""
        sp = self._spline()
        t = np.asarray(t, dtype=float)
        return sp(t), sp(t, 1), sp(t, 2)

    def kernel_args(self):
        """(kernel kind, par, tab) for :func:`pdamper.kernels.drive.drive_motion`."""
        sp = self._spline()
        c = sp.c  # (4, n-1): highest power first
        tab = np.column_stack([sp.x[:-1], c[3], c[2], c[1], c[0]])
        # closing row holds the last knot so the kernel can find the end
        last = np.array([[sp.x[-1], float(sp(sp.x[-1])), 0.0, 0.0, 0.0]])
        return "spline", np.zeros(3), np.ascontiguousarray(np.vstack([tab, last]))

    def speed_bound(self) -> float:
        """The largest |v| [m/s] at the samples."""
        _, v, _ = self.motion(np.asarray(self.time))
        return float(np.max(np.abs(v)))

    def describe(self) -> str:
        return f"sampled motion, {len(self.time)} samples over {self.duration():g} s"


@register_drive
@dataclass(frozen=True, kw_only=True)
class Still(DriveBase):
    """A container at rest for ``duration`` [s] (settling, tests, free motion of the bed)."""

    duration_s: float = param(1.0, dimension="time", key="duration")
    angle: float = param(0.0, dimension="angle")
    direction: tuple | None = param(None, kind="list")
    kind: str = param("still", kind="tag")
    config_marks = ("duration",)
    config_label = "a drive at rest"
    config_summary = "duration (still)"

    def __post_init__(self):
        self._prepare()
        self._check_direction()
        if not (self.duration_s > 0 and math.isfinite(self.duration_s)):
            raise InputError(f"drive.duration = {shown(self.duration_s)} s; must be > 0")

    def duration(self, cycles: float | None = None) -> float:
        """Length of the run [s] (``cycles`` is ignored)."""
        return self.duration_s

    def motion(self, t):
        """(0, 0, 0) at every time."""
        z = np.zeros(np.shape(t))
        return z, z.copy(), z.copy()

    def speed_bound(self) -> float:
        """0: the container does not move."""
        return 0.0

    def describe(self) -> str:
        return f"container at rest for {self.duration_s:g} s"

    def kernel_args(self):
        """(kernel kind, par, tab) for :func:`pdamper.kernels.drive.drive_motion`."""
        return "rest", np.zeros(3), np.zeros((1, 5))


def read_motion_csv(path) -> dict:
    """Read a prescribed motion from a CSV file: columns ``time``, ``position`` and optionally
    ``velocity`` (units in brackets, e.g. ``time [s],position [mm]``; without a unit SI).

    Returns ``{"time": tuple, "position": tuple[, "velocity": tuple]}`` in SI.
    """
    try:
        path = checked_file(path, "motion file (CSV)", missing="file not found: {path}")
    except InputError as exc:
        raise InputError(f"[drive] samples: {exc}") from None
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
            raise InputError(f"{path}: no {shown(role)} column; the header has {shown(rows[0])} "
                             "(need time, position[, velocity], units in brackets)")
        i = names.index(role)
        factor = unit_factor(units[i], dim, name=f"{path}: column {role!r}") if units[i] else 1.0
        col = []
        for (no, _), row in zip(lines[1:], rows[1:]):
            try:
                v = float(row[i].strip().replace(",", ".") if delim != "," else row[i])
            except (ValueError, IndexError):
                cell = row[i] if i < len(row) else ""
                raise InputError(f"{path}, line {no}, column {shown(role)}: cannot read {shown(cell)} as a number") from None
            if not math.isfinite(v):
                raise InputError(f"{path}, line {no}, column {shown(role)}: {shown(v)} is not a finite number")
            col.append(v * factor)
        out[role] = tuple(col)
    return out


#: Old homes of the structures (now :mod:`pdamper.structure`): the name -> its new module.
_MOVED = {"CoupledStructure": "pdamper.structure", "ModalStructure": "pdamper.structure",
          "read_structure_matrices": "pdamper.structure"}


def __getattr__(name):
    """``from pdamper.excitation import CoupledStructure`` still works (warns): the structures moved
    to :mod:`pdamper.structure`. (Imported by name at run time: :mod:`pdamper.structure` is a
    layer above this module, which it builds on.)"""
    if name in _MOVED:
        import importlib

        from ._deprecated import warn_renamed

        warn_renamed(f"pdamper.excitation.{name}", f"{_MOVED[name]}.{name}")
        return getattr(importlib.import_module(_MOVED[name]), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
