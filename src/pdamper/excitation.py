"""Container motion behind one protocol: harmonic ``x_c = X sin(Omega t)``, a motion given as
samples, a container at rest, or the motion of a structure the container rides on
(:class:`CoupledStructure`, two-way coupled).

A drive kind is one class here, registered with :func:`register_drive`; nothing outside this
module asks which kind a drive is. What a drive answers (:class:`DriveBase` gives the defaults):

=========================  =========================================================================
``kind``, ``config_section``  its tag (``[drive] kind``) and the config section it is read from
config keys                its dataclass fields, declared with :func:`pdamper.schema.param`
``kernel_drive()``         ``(kind number, par, table, state)`` for the kernels
                           (:mod:`pdamper.kernels.drive`)
``speed_bound()``          the container's largest speed [m/s] (the automatic time step)
``duration(cycles)``       the driven time [s]
``motion(t)``              ``(x, v, a)`` at times t, as prescribed (without the bed)
``container_motion(t, s)`` ``(x, v, a)`` now, the kernels' drive state ``s`` included
``start_state(s)``         releases a coupled structure at t = 0 (None for a prescribed motion)
``lab_direction()``        the unit direction of the motion in the lab frame
``describe()``             one line for people
``stroke``, ``frequency``  X [m] and f [Hz] where the drive has them, else None
``periodic``, ``coupled``  harmonic with whole cycles to drop; moved by the bed's force
=========================  =========================================================================

**Direction.** The motion acts along ``direction`` (a 3-vector in the lab frame, whose y axis
points up against gravity: ``[0, 1, 0]`` or ``"vertical"`` is a vertical drive) or, as a
shorthand for a horizontal drive, along ``angle`` [rad] from the lab x axis (the container's
length when untilted) towards the lab z axis. A drive with a vertical part lifts the bed off
the floor above A = g: that is expected (the bouncing regime), not warned about.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .schema import convert_fields, param, register_tagged, registered

__all__ = ["HarmonicDrive", "SampledDrive", "Still", "CoupledStructure", "DriveBase", "DRIVES", "register_drive",
           "drive_class"]

#: Registered drive kinds by tag (``[drive] kind``, or ``structure`` for the ``[structure]`` section).
DRIVES: dict[str, type] = {}

#: Words a config may give for ``direction``.
_DIRECTION_WORDS = {"vertical": (0.0, 1.0, 0.0), "up": (0.0, 1.0, 0.0), "x": (1.0, 0.0, 0.0), "z": (0.0, 0.0, 1.0)}


def register_drive(cls):
    """Class decorator: register a drive class under its ``kind`` tag. Returns the class."""
    return register_tagged(DRIVES, cls, "kind", "drive", needs=("kernel_drive", "motion", "duration"))


def drive_class(tag: str) -> type:
    """The registered drive class of ``tag``."""
    return registered(DRIVES, tag, "drive.kind")


class DriveBase:
    """The answers of the drive protocol that most drives share (see the module docstring)."""

    #: the config section the drive is read from (:func:`pdamper.schema.replace` reads it too)
    config_section = "drive"
    #: X [m] and f [Hz] where the drive has them
    stroke = None
    frequency = None
    #: a harmonic motion whose first cycles the analysis drops
    periodic = False
    #: the container is moved by the bed's force (a structure): its motion is recorded
    coupled = False
    #: what a config file must give (``[drive]`` keys) and the values it may leave out
    config_required: tuple = ()
    config_defaults: dict = {}
    config_hint = ""

    def _prepare(self) -> None:
        """First in ``__post_init__``: a direction given as a word becomes its vector, then the
        fields given with units are converted to SI."""
        d = self.direction
        if isinstance(d, str):
            if d.strip().lower() not in _DIRECTION_WORDS:
                raise InputError(f"{self.config_section}.direction = {d!r}; give three numbers [x, y, z] (lab frame, y up) "
                                 f"or one of {', '.join(repr(w) for w in _DIRECTION_WORDS)}")
            object.__setattr__(self, "direction", _DIRECTION_WORDS[d.strip().lower()])
        convert_fields(self, self.config_section)

    def _check_direction(self) -> None:
        """Validate ``angle`` and ``direction`` (called by each drive's ``__post_init__``)."""
        sec = self.config_section
        if not (isinstance(self.angle, (int, float)) and math.isfinite(self.angle)):
            raise InputError(f"{sec}.angle = {self.angle!r}; must be a finite angle")
        d = self.direction
        if d is None:
            return
        try:
            v = np.asarray(d, dtype=float)
        except (TypeError, ValueError):
            v = np.zeros(0)
        if v.shape != (3,) or not np.all(np.isfinite(v)) or not np.linalg.norm(v) > 0:
            raise InputError(f"{sec}.direction = {self.direction!r}; give three finite numbers, not all 0, e.g. "
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
        """``(kind number, par, table, state)`` for :mod:`pdamper.kernels.drive`."""
        kind, par, tab = self.kernel_args()
        return kind, par, tab, np.zeros((2, 5))

    def describe(self) -> str:
        return f"{self.kind} drive"

    def check_scale(self, length: float) -> None:
        """InputError when the drive moves the container absurdly far for its inner ``length`` [m]
        (a bare number read as metres); nothing to check by default."""


def _mm_hint(value: float, upper: float, unit: str = "mm") -> str:
    """'; did you mean '13mm'?' when the number read in thousandths would be plausible."""
    return f"; did you mean '{value:g}{unit}'?" if 1e-3 * value <= upper else ""


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
    config_defaults = {"stroke": 0.012}

    def __post_init__(self):
        self._prepare()
        if not (self.stroke > 0 and math.isfinite(self.stroke)):
            raise InputError(f"drive.stroke = {self.stroke!r} m; must be > 0 (e.g. '12mm')")
        if not (self.frequency > 0 and math.isfinite(self.frequency)):
            raise InputError(f"drive.frequency = {self.frequency!r} Hz; must be > 0 (e.g. '2Hz')")
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
        """(kind, par, tab) for :func:`pdamper.kernels.drive.drive_motion`."""
        return 1, np.array([self.stroke, self.omega, 0.0]), np.zeros((1, 5))

    def speed_bound(self) -> float:
        """V = X Omega [m/s]."""
        return self.velocity_amplitude

    def check_scale(self, length: float) -> None:
        """A stroke beyond twice the container's length is a bare number meant in mm."""
        if self.stroke > 2 * length:
            raise InputError(f"drive.stroke = {self.stroke:g} m is {self.stroke / length:.3g} times the container's "
                             f"length {length:g} m (a number without a unit is metres){_mm_hint(self.stroke, 2 * length)}")

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
    config_required = ("time", "position")
    config_hint = "give time = [...] and position = [...] (optionally velocity = [...]) or samples = 'motion.csv'"

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
            raise InputError(f"drive samples: time must increase strictly; it does not at sample {k + 1} (t = {t[k + 1]!r} s)")
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
        """(kind, par, tab) for :func:`pdamper.kernels.drive.drive_motion`."""
        sp = self._spline()
        c = sp.c  # (4, n-1): highest power first
        tab = np.column_stack([sp.x[:-1], c[3], c[2], c[1], c[0]])
        # closing row holds the last knot so the kernel can find the end
        last = np.array([[sp.x[-1], float(sp(sp.x[-1])), 0.0, 0.0, 0.0]])
        return 2, np.zeros(3), np.ascontiguousarray(np.vstack([tab, last]))

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

    def __post_init__(self):
        self._prepare()
        self._check_direction()
        if not (self.duration_s > 0 and math.isfinite(self.duration_s)):
            raise InputError(f"drive.duration = {self.duration_s!r} s; must be > 0")

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
        """(kind, par, tab) for :func:`pdamper.kernels.drive.drive_motion`."""
        return 0, np.zeros(3), np.zeros((1, 5))


@register_drive
@dataclass(frozen=True, kw_only=True)
class CoupledStructure(DriveBase):
    """The container rides rigidly on a single-degree-of-freedom structure, two-way coupled.

    ``M x_s'' + c x_s' + K x_s = F0 sin(2 pi f_F t) - F_w`` with ``c = 2 zeta sqrt(K M)`` and F_w
    the force of the walls on the particles along the drive; the structure's motion is the
    container's (see :mod:`pdamper.kernels.structure` and docs/structure.md). Both integrators
    advance it with the same structure step (Gear and Verlet, docs/structure.md).

    Parameters
    ----------
    mass : float
        M [kg], > 0: the structure's modal mass *including the empty container*
        (``container.mass`` is then only reported, not added again).
    stiffness : float
        K [N/m], > 0.
    damping_ratio : float
        zeta [-], in [0, 1): the structure's own damping.
    force_amplitude : float
        F0 [N], >= 0 (0: free motion).
    force_frequency : float or None
        f_F [Hz], > 0, needed when F0 > 0.
    displacement, velocity : float
        Initial x_s [m] and v_s [m/s] when the drive starts (t = 0).
    angle : float
        Direction of the motion in the horizontal plane [rad], as for :class:`HarmonicDrive`.

    Examples
    --------
    >>> s = CoupledStructure(mass=7.0, stiffness=1105.0, damping_ratio=0.005, displacement=0.01)
    >>> round(s.natural_frequency, 3)
    2.0
    """

    mass: float = param(dimension="mass")
    stiffness: float = param(kind="number", unit="N/m")
    damping_ratio: float = 0.005
    force_amplitude: float = param(0.0, dimension="force")
    displacement: float = param(0.0, dimension="length")
    velocity: float = param(0.0, dimension="velocity")
    angle: float = param(0.0, dimension="angle")
    # last: the order a config file is written in (a store's fingerprint is taken of that text)
    force_frequency: float | None = param(None, dimension="frequency")
    direction: tuple | None = param(None, kind="list")
    kind: str = param("structure", kind="tag")
    config_section = "structure"
    coupled = True

    def __post_init__(self):
        self._prepare()
        for name, unit, ex in (("mass", "kg", "'7kg'"), ("stiffness", "N/m", "1105 (N/m)")):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (v > 0 and math.isfinite(v)):
                raise InputError(f"structure.{name} = {v!r} {unit}; must be > 0, e.g. {ex}")
        z = self.damping_ratio
        if isinstance(z, bool) or not isinstance(z, (int, float)) or not (0.0 <= z < 1.0):
            raise InputError(f"structure.damping_ratio = {z!r}; must be in [0, 1), e.g. 0.005 (0.5 %)")
        f0 = self.force_amplitude
        if isinstance(f0, bool) or not isinstance(f0, (int, float)) or not (f0 >= 0 and math.isfinite(f0)):
            raise InputError(f"structure.force_amplitude = {f0!r} N; must be >= 0 (0: free motion)")
        ff = self.force_frequency
        if ff is not None and not (isinstance(ff, (int, float)) and ff > 0 and math.isfinite(ff)):
            raise InputError(f"structure.force_frequency = {ff!r} Hz; must be > 0, e.g. '2Hz'")
        if f0 > 0 and ff is None:
            raise InputError("structure.force_frequency is missing: a force_amplitude > 0 needs its "
                             "frequency, e.g. force_frequency = '2Hz'")
        for name in ("displacement", "velocity"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise InputError(f"structure.{name} = {v!r}; must be a finite number")
        self._check_direction()
        if f0 == 0 and self.displacement == 0 and self.velocity == 0:
            raise InputError("structure: nothing moves it; give a displacement (free decay, e.g. '10mm') "
                             "or a force_amplitude with force_frequency (forced response)")

    @property
    def damping(self) -> float:
        """c = 2 zeta sqrt(K M) [N s/m]."""
        return 2.0 * self.damping_ratio * math.sqrt(self.stiffness * self.mass)

    @property
    def natural_frequency(self) -> float:
        """f_n = sqrt(K/M) / 2 pi [Hz] (without the bed)."""
        return math.sqrt(self.stiffness / self.mass) / (2.0 * math.pi)

    @property
    def frequency(self) -> float:
        """The frequency [Hz] that counts the run's cycles: f_F when forced, else f_n."""
        return self.force_frequency if self.force_amplitude > 0 else self.natural_frequency

    @property
    def velocity_bound(self) -> float:
        """An upper estimate [m/s] of |v_s| without the bed (for the time step)."""
        from .theory.oscillator import steady_amplitude

        w = 2.0 * math.pi * self.natural_frequency
        free = abs(self.velocity) + w * abs(self.displacement)
        forced = 0.0
        if self.force_amplitude > 0:
            wf = 2.0 * math.pi * self.force_frequency
            res = self.force_amplitude / self.stiffness / max(2.0 * self.damping_ratio, 0.02)
            forced = max(wf, w) * max(res, steady_amplitude(self.force_frequency, mass=self.mass,
                                                            stiffness=self.stiffness, damping_ratio=self.damping_ratio,
                                                            force_amplitude=self.force_amplitude))
        return free + 2.0 * forced

    def duration(self, cycles: float) -> float:
        """Time [s] of ``cycles`` periods of :attr:`frequency`."""
        return cycles / self.frequency

    def motion(self, t):
        """(x, v, a) at times t [s] of the structure *without* the bed (closed form); the
        coupled motion is recorded by the run."""
        from .theory.oscillator import oscillator_response

        return oscillator_response(t, mass=self.mass, stiffness=self.stiffness, damping_ratio=self.damping_ratio,
                                   force_amplitude=self.force_amplitude, force_frequency=self.force_frequency or 0.0,
                                   displacement=self.displacement, velocity=self.velocity)

    def kernel_drive(self):
        """(kind, par, table, state) for the kernels (:mod:`pdamper.kernels.structure`); the
        state starts at rest at the initial displacement (held during settling)."""
        om = 2.0 * math.pi * (self.force_frequency or 0.0)
        par = np.array([self.mass, self.stiffness, self.damping, self.force_amplitude, om])
        st = np.zeros((2, 5))
        st[0, 0] = self.displacement
        return 3, par, np.zeros((1, 5)), st

    def speed_bound(self) -> float:
        """An upper estimate [m/s] of |v_s| (:attr:`velocity_bound`)."""
        return self.velocity_bound

    def container_motion(self, t: float, state):
        """The structure's ``(x, v, a)`` now, from the kernels' state."""
        return state[0, 0], state[0, 1], state[0, 2]

    def check_scale(self, length: float) -> None:
        """A start or a resonant swing beyond twice the container's length is a bare number meant
        in thousandths (or a force far too large)."""
        for key in ("displacement", "velocity"):
            v = abs(getattr(self, key))
            limit = 2 * length if key == "displacement" else 2 * length * 2 * math.pi * self.natural_frequency
            if v > limit:
                unit = "m" if key == "displacement" else "m/s"
                raise InputError(f"structure.{key} = {getattr(self, key):g} {unit} moves the container {v / limit:.3g} "
                                 f"times further than twice its length {length:g} m (a number without a unit is SI)"
                                 f"{_mm_hint(v, limit, 'mm' if key == 'displacement' else 'mm/s')}")
        resonant = self.force_amplitude / self.stiffness / max(2.0 * self.damping_ratio, 0.02)
        if resonant > 2 * length:
            raise InputError(f"structure.force_amplitude = {self.force_amplitude:g} N would swing the structure by "
                             f"about {resonant:.3g} m at resonance (F0 / K / 2 zeta), beyond twice the container's "
                             f"length {length:g} m; give a smaller force (a number without a unit is N)")

    def describe(self) -> str:
        forced = (f"F0 = {self.force_amplitude:g} N at {self.force_frequency:g} Hz" if self.force_amplitude > 0
                  else f"free decay from {self.displacement * 1e3:g} mm")
        return f"structure M = {self.mass:g} kg, f_n = {self.natural_frequency:.4g} Hz, {forced}"

    def start_state(self, st, wall_force: float = 0.0) -> float:
        """Release the structure at t = 0: set (x0, v0, a0) in the kernel state ``st``, with
        ``wall_force`` [N] the bed's wall force along the drive at that moment; returns a0."""
        a0 = (-self.damping * self.velocity - self.stiffness * self.displacement - wall_force) / self.mass
        st[0, 0:4] = (self.displacement, self.velocity, a0, 0.0)
        st[1, :] = 0.0
        return a0
