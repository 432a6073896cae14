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
from .schema import convert_fields, param, register_tagged
from .units import thousandth_hint

__all__ = ["HarmonicDrive", "SampledDrive", "Still", "CoupledStructure", "ModalStructure", "DriveBase", "DRIVES",
           "register_drive", "read_structure_matrices"]

#: Registered drive kinds by tag (``[drive] kind``, or ``structure`` for the ``[structure]`` section).
DRIVES: dict[str, type] = {}

#: Words a config may give for ``direction``.
_DIRECTION_WORDS = {"vertical": (0.0, 1.0, 0.0), "up": (0.0, 1.0, 0.0), "x": (1.0, 0.0, 0.0), "z": (0.0, 0.0, 1.0)}


def register_drive(cls):
    """Class decorator: register a drive class under its ``kind`` tag. Returns the class."""
    return register_tagged(DRIVES, cls, "kind", "drive", needs=("kernel_drive", "motion", "duration"))



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

    def config_extra(self) -> dict:
        """Config keys beyond the plain fields (a modal structure's ``modes``); none by default."""
        return {}


#: Highest natural or forcing frequency of a structure [Hz].
_MAX_STRUCTURE_HZ = 1000.0


def _check_structure_scale(s, length: float, damping_ratio: float) -> None:
    """A structure's start (``displacement``, ``velocity``) or resonant swing (F0 / K / 2 zeta, of
    its first mode) beyond twice the container's ``length`` [m], or a frequency beyond 1 kHz (no
    damper test; the time step would vanish): an InputError with the fix."""
    if not s.natural_frequency <= _MAX_STRUCTURE_HZ:
        raise InputError(f"structure: a natural frequency of {s.natural_frequency:.3g} Hz (structure.mass = {s.mass:g} kg, "
                         f"stiffness {s.stiffness:.3g} N/m) is beyond {_MAX_STRUCTURE_HZ:g} Hz; check structure.mass and "
                         "structure.stiffness / natural_frequency (a number without a unit is SI)")
    ff = s.force_frequency
    if ff is not None and not ff <= _MAX_STRUCTURE_HZ:
        raise InputError(f"structure.force_frequency = {ff:g} Hz is beyond {_MAX_STRUCTURE_HZ:g} Hz, no damper test; "
                         "give the forcing frequency, e.g. '2Hz'")
    for key in ("displacement", "velocity"):
        v = abs(getattr(s, key))
        limit = 2 * length if key == "displacement" else 2 * length * 2 * math.pi * s.natural_frequency
        if v > limit:
            unit = "m" if key == "displacement" else "m/s"
            raise InputError(f"structure.{key} = {getattr(s, key):g} {unit} moves the container {v / limit:.3g} "
                             f"times further than twice its length {length:g} m (a number without a unit is SI)"
                             f"{thousandth_hint(v, limit, 'mm' if key == 'displacement' else 'mm/s')}")
    resonant = s.force_amplitude / s.stiffness / max(2.0 * damping_ratio, 0.02)
    if resonant > 2 * length:
        raise InputError(f"structure.force_amplitude = {s.force_amplitude:g} N would swing the structure "
                         f"(structure.mass = {s.mass:g} kg, stiffness {s.stiffness:.3g} N/m) by about {resonant:.3g} m "
                         f"at resonance (F0 / K / 2 zeta), beyond twice the container's length {length:g} m; give a "
                         "smaller force or check the mass (a number without a unit is SI)")


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


def _check_structure_motion(s) -> None:
    """Validate what moves a structure (``force_amplitude``, ``force_frequency``, ``displacement``,
    ``velocity``) and its direction; something must move it."""
    f0 = s.force_amplitude
    if isinstance(f0, bool) or not isinstance(f0, (int, float)) or not (f0 >= 0 and math.isfinite(f0)):
        raise InputError(f"structure.force_amplitude = {f0!r} N; must be >= 0 (0: free motion)")
    ff = s.force_frequency
    if ff is not None and not (isinstance(ff, (int, float)) and ff > 0 and math.isfinite(ff)):
        raise InputError(f"structure.force_frequency = {ff!r} Hz; must be > 0, e.g. '2Hz'")
    if f0 > 0 and ff is None:
        raise InputError("structure.force_frequency is missing: a force_amplitude > 0 needs its "
                         "frequency, e.g. force_frequency = '2Hz'")
    for name in ("displacement", "velocity"):
        v = getattr(s, name)
        if not (isinstance(v, (int, float)) and math.isfinite(v)):
            raise InputError(f"structure.{name} = {v!r}; must be a finite number")
    s._check_direction()
    if f0 == 0 and s.displacement == 0 and s.velocity == 0:
        raise InputError("structure: nothing moves it; give a displacement (free decay, e.g. '10mm') "
                         "or a force_amplitude with force_frequency (forced response)")


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
        _check_structure_motion(self)

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
        _check_structure_scale(self, length, self.damping_ratio)

    def describe(self) -> str:
        forced = (f"F0 = {self.force_amplitude:g} N at {self.force_frequency:g} Hz" if self.force_amplitude > 0
                  else f"free decay from {self.displacement * 1e3:g} mm")
        return f"structure M = {self.mass:g} kg, f_n = {self.natural_frequency:.4g} Hz, {forced}"

    @property
    def highest_frequency(self) -> float:
        """The highest frequency of the structure's motion without the bed [Hz] (for time steps)."""
        return max(self.natural_frequency, self.force_frequency or 0.0)

    @property
    def modal_damping_ratio(self) -> float:
        """zeta [-] (the one mode's)."""
        return self.damping_ratio

    def response_motion(self, t):
        """Displacement [m] of the response point (the structure itself) without the bed."""
        return self.motion(t)[0]

    def steady_amplitude(self, frequencies, force_amplitude: float, added_mass: float = 0.0, point: str = "damper"):
        """Steady amplitude [m] under ``force_amplitude`` sin(2 pi f t) at ``frequencies`` [Hz]
        without the bed, with ``added_mass`` [kg] rigidly on the structure (the same K and c)."""
        from .theory.oscillator import steady_amplitude

        if added_mass == 0.0:
            return np.asarray(steady_amplitude(frequencies, mass=self.mass, stiffness=self.stiffness,
                                               damping_ratio=self.damping_ratio, force_amplitude=force_amplitude))
        m2 = self.mass + added_mass
        zeta2 = self.damping / (2.0 * math.sqrt(self.stiffness * m2))
        return np.asarray(steady_amplitude(frequencies, mass=m2, stiffness=self.stiffness, damping_ratio=zeta2,
                                           force_amplitude=force_amplitude))

    def modal_arrays(self):
        """(modal masses [kg], stiffnesses [N/m], dampings [N s/m], mode shape at the damper, at the
        force, at the response point): the structure as its one mode, every shape 1."""
        one = np.ones(1)
        return (np.array([self.mass]), np.array([self.stiffness]), np.array([self.damping]), one, one.copy(),
                one.copy())

    def record_info(self) -> dict:
        """What :class:`pdamper.recorders.structure.StructureRecord` keeps of the structure."""
        return {"mass_kg": self.mass, "stiffness_N_m": self.stiffness, "x0_m": self.displacement,
                "v0_m_s": self.velocity}

    def structure_summary(self) -> dict:
        """Plain numbers about the structure for a run's summary."""
        return {"modes_kept": 1, "mode_frequencies_hz": [self.natural_frequency]}

    def start_state(self, st, wall_force: float = 0.0) -> float:
        """Release the structure at t = 0: set (x0, v0, a0) in the kernel state ``st``, with
        ``wall_force`` [N] the bed's wall force along the drive at that moment; returns a0."""
        a0 = (-self.damping * self.velocity - self.stiffness * self.displacement - wall_force) / self.mass
        st[0, 0:4] = (self.displacement, self.velocity, a0, 0.0)
        st[1, :] = 0.0
        return a0


# --------------------------------------------------------------------------- modal structures

#: Keys of one entry of ``[structure] modes``: (unit dimension, example).
_MODE_KEYS = {"frequency": ("frequency", "'2Hz'"), "damping_ratio": ("dimensionless", "0.005"),
              "modal_mass": ("mass", "'7kg'"), "damper": ("dimensionless", "1.0"),
              "force": ("dimensionless", "1.0"), "response": ("dimensionless", "1.0")}
#: The highest mode a modal structure may carry [Hz]: omega h = 0.31 at a 50 us step (the
#: velocity-Verlet step of each mode is stable for omega h < 2); modes this high do not take part
#: in a damper's few-Hz motion.
_MODE_LIMIT_HZ = 1000.0
_GEAR_STEP_BOUND = 50e-6
#: File endings of a matrix that scipy reads: Matrix Market and Harwell-Boeing (and numpy's own).
_MATRIX_READERS = {".mtx": "mmread", ".mm": "mmread", ".rb": "hb_read", ".rua": "hb_read", ".rsa": "hb_read",
                   ".hb": "hb_read", ".npy": "npy"}


def _read_mode(entry, k: int) -> dict:
    """One ``modes`` entry as SI floats (``frequency`` [Hz], ``modal_mass`` [kg], the rest plain)."""
    from .units import to_si

    label = f"structure.modes[{k}]"
    if not isinstance(entry, dict):
        raise InputError(f"{label} = {entry!r}; give a table {{frequency = '2Hz', damping_ratio = 0.005, "
                         "modal_mass = '7kg', damper = 1.0, force = 1.0, response = 1.0}")
    unknown = [key for key in entry if key not in _MODE_KEYS]
    if unknown:
        raise InputError(f"{label}: unknown key {unknown[0]!r}; a mode has {', '.join(_MODE_KEYS)}")
    out = {}
    for key, (dim, ex) in _MODE_KEYS.items():
        if key not in entry:
            if key in ("force", "response"):
                out[key] = out.get("damper", 1.0)
                continue
            raise InputError(f"{label}.{key} is missing, e.g. {key} = {ex}")
        v = entry[key]
        if isinstance(v, bool):
            raise InputError(f"{label}.{key} = {v!r}; must be a number, e.g. {ex}")
        v = to_si(v, dim, name=f"{label}.{key}") if isinstance(v, str) or hasattr(v, "magnitude") else v
        if not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InputError(f"{label}.{key} = {entry[key]!r}; must be a finite number, e.g. {ex}")
        out[key] = float(v)
    if not out["frequency"] > 0:
        raise InputError(f"{label}.frequency = {entry['frequency']!r}; must be > 0, e.g. '2Hz'")
    if not out["modal_mass"] > 0:
        raise InputError(f"{label}.modal_mass = {entry['modal_mass']!r}; must be > 0, e.g. '7kg'")
    if not 0.0 <= out["damping_ratio"] < 1.0:
        raise InputError(f"{label}.damping_ratio = {entry['damping_ratio']!r}; must be in [0, 1), e.g. 0.005")
    if out["damper"] == 0.0:
        raise InputError(f"{label}.damper = 0: the mode shape is zero at the damper, so the damper cannot act "
                         "on this mode; leave the mode out or give its value at the damper (e.g. damper = 1.0)")
    return out


def _load_matrix(path, name: str):
    """A matrix [SI] from ``path`` (Matrix Market, Harwell-Boeing or .npy), dense."""
    from pathlib import Path

    import scipy.io

    p = Path(path)
    reader = _MATRIX_READERS.get(p.suffix.lower())
    if reader is None:
        raise InputError(f"structure.matrices.{name} = {str(path)!r}: unknown file type {p.suffix!r}; give a Matrix "
                         f"Market (.mtx), Harwell-Boeing ({', '.join(k for k, r in _MATRIX_READERS.items() if r == 'hb_read')}) "
                         "or .npy file, or one .npz with arrays M, K (and C)")
    if not p.is_file():
        raise InputError(f"structure.matrices.{name}: file not found: {p}")
    try:
        a = np.load(p) if reader == "npy" else getattr(scipy.io, reader)(str(p))
    except Exception as exc:  # the readers raise many kinds of error on a bad file
        raise InputError(f"structure.matrices.{name}: cannot read {p}: {exc}") from None
    return np.asarray(a.toarray() if hasattr(a, "toarray") else a, dtype=float)


def read_structure_matrices(matrices) -> dict:
    """``{"M": ..., "K": ..., "C": ... or None}`` from ``matrices``: the path of an .npz with arrays
    ``M``, ``K`` (and optionally ``C``), or a table ``{M = path, K = path, C = path}`` of Matrix
    Market / Harwell-Boeing / .npy files (read by scipy)."""
    from pathlib import Path

    if isinstance(matrices, (str, Path)):
        p = Path(matrices)
        if p.suffix.lower() != ".npz":
            raise InputError(f"structure.matrices = {str(matrices)!r}; one file must be an .npz with arrays M, K "
                             "(and C); for Matrix Market or Harwell-Boeing files give a table, "
                             "matrices = {M = 'frame_M.mtx', K = 'frame_K.mtx'}")
        if not p.is_file():
            raise InputError(f"structure.matrices: file not found: {p}")
        with np.load(p) as z:
            missing = [k for k in ("M", "K") if k not in z.files]
            if missing:
                raise InputError(f"structure.matrices = {str(matrices)!r} has no array {missing[0]!r} (it has "
                                 f"{', '.join(z.files) or 'none'}); it needs M and K, optionally C")
            return {k: (np.asarray(z[k], dtype=float) if k in z.files else None) for k in ("M", "K", "C")}
    if isinstance(matrices, dict):
        unknown = [k for k in matrices if k not in ("M", "K", "C")]
        if unknown:
            raise InputError(f"structure.matrices: unknown key {unknown[0]!r}; give M, K and optionally C")
        for k in ("M", "K"):
            if k not in matrices:
                raise InputError(f"structure.matrices.{k} is missing; give M = 'file' and K = 'file' (and C)")
        return {k: (_load_matrix(matrices[k], k) if k in matrices else None) for k in ("M", "K", "C")}
    raise InputError(f"structure.matrices = {matrices!r}; give the path of an .npz file (arrays M, K, C) or a "
                     "table {M = 'M.mtx', K = 'K.mtx'}")


def _check_matrices(mats: dict) -> int:
    """Shapes, symmetry and definiteness of M, K (and C); returns the number of dofs."""
    M, K, C = mats["M"], mats["K"], mats["C"]
    if M.ndim != 2 or M.shape[0] != M.shape[1] or M.shape[0] == 0:
        raise InputError(f"structure.matrices: M must be square, got shape {M.shape}")
    n = M.shape[0]
    for name, A in (("K", K), ("C", C)):
        if A is not None and A.shape != (n, n):
            raise InputError(f"structure.matrices: {name} has shape {A.shape}; M is {n} x {n}, they must match")
    for name, A in (("M", M), ("K", K), ("C", C)):
        if A is None:
            continue
        if not np.all(np.isfinite(A)):
            raise InputError(f"structure.matrices: {name} has NaN or infinite entries")
        asym = float(np.max(np.abs(A - A.T))) / max(float(np.max(np.abs(A))), 1e-300)
        if asym > 1e-9:
            raise InputError(f"structure.matrices: {name} is not symmetric (largest |{name} - {name}^T| is {asym:.2g} "
                             f"of its largest entry); give the symmetric {name} of the FE model")
    for name, A, what in (("M", M, "a mass matrix"),
                          ("K", K, "a supported structure (one with rigid-body modes has a singular K: clamp it)")):
        try:
            np.linalg.cholesky(A)
        except np.linalg.LinAlgError:
            raise InputError(f"structure.matrices: {name} is not positive definite; {what} must be") from None
    return n


@register_drive
@dataclass(frozen=True, kw_only=True)
class ModalStructure(DriveBase):
    """The container rides on a structure of N modes, two-way coupled (docs/structure.md).

    Each mode k (modal mass m_k, natural frequency f_k, damping ratio zeta_k, mode shape phi_k at
    the damper, the force and the response point, along the drive direction) obeys

        m_k q_k'' + c_k q_k' + k_k q_k = phi_k(force) F0 sin(2 pi f_F t) - phi_k(damper) F_w,

    ``k_k = m_k (2 pi f_k)^2``, ``c_k = 2 zeta_k sqrt(k_k m_k)``; the container moves with the damper
    point, ``x_c = sum_k phi_k(damper) q_k``; the response point with ``sum_k phi_k(response) q_k``.

    The modes are given either as ``modes`` (a list of tables ``{frequency, damping_ratio,
    modal_mass, damper, force, response}``) or computed from FE matrices ``matrices`` (an .npz with
    arrays ``M``, ``K`` and optionally ``C``, or a table of Matrix Market / Harwell-Boeing files)
    with ``damper_dof``, ``force_dof``, ``response_dof`` (0-based indices), the damping as
    ``rayleigh = [alpha, beta]`` (C = alpha M + beta K), ``damping_ratio`` (every mode) or the
    file's ``C`` (its modal projection's diagonal), and ``modes_kept`` (the lowest modes of the
    generalised problem K phi = omega^2 M phi, mass-normalised; default all).

    The truncation error (:attr:`truncation_error`) is the relative error of the static compliance
    at the damper dof from the kept modes, ``sum_k phi_k(d)^2 / omega_k^2``, against ``(K^-1)_dd``.

    ``displacement`` and ``velocity`` are the damper point's at t = 0, taken in the static shape of
    a load at the damper (``q_k proportional to phi_k(damper) / k_k``: the structure pulled at the
    damper and released).

    Examples
    --------
    >>> s = ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.005, "modal_mass": 7.0,
    ...                            "damper": 1.0, "force": 1.0, "response": 1.0},), displacement=0.01)
    >>> round(s.natural_frequency, 3), s.n_modes
    (2.0, 1)
    """

    modes: tuple = param((), kind="custom")
    matrices: object = param(None, kind="custom")
    damper_dof: int | None = param(None, kind="whole")
    force_dof: int | None = param(None, kind="whole")
    response_dof: int | None = param(None, kind="whole")
    rayleigh: tuple | None = param(None, kind="list")
    damping_ratio: float | None = param(None, kind="number")
    modes_kept: int | None = param(None, kind="whole")
    force_amplitude: float = param(0.0, dimension="force")
    displacement: float = param(0.0, dimension="length")
    velocity: float = param(0.0, dimension="velocity")
    angle: float = param(0.0, dimension="angle")
    force_frequency: float | None = param(None, dimension="frequency")
    direction: tuple | None = param(None, kind="list")
    kind: str = param("modal", kind="tag")
    config_section = "structure"
    coupled = True

    def __post_init__(self):
        self._prepare()
        given = [k for k in ("modes", "matrices") if getattr(self, k)]
        if len(given) != 1:
            raise InputError("structure: give exactly one of modes = [{frequency, damping_ratio, modal_mass, damper, "
                             "force, response}, ...] or matrices = 'frame.npz'" +
                             (" (both are given)" if len(given) == 2 else ""))
        fe_keys = ("damper_dof", "force_dof", "response_dof", "rayleigh", "modes_kept")
        if self.modes:
            extra = [k for k in fe_keys if getattr(self, k) is not None]
            if extra or self.damping_ratio is not None:
                k = extra[0] if extra else "damping_ratio"
                raise InputError(f"structure.{k} belongs to matrices = ...; with modes each mode has its own "
                                 "damping_ratio and mode shape values (damper, force, response)")
            if isinstance(self.modes, dict) or not hasattr(self.modes, "__len__"):
                raise InputError("structure.modes: give a list of tables, modes = [{frequency = '2Hz', ...}, ...]")
            modes = tuple(_read_mode(m, k) for k, m in enumerate(self.modes))
            object.__setattr__(self, "modes", modes)
            data = {key: np.array([m[key] for m in modes]) for key in _MODE_KEYS}
            data["truncation_error"] = math.nan
        else:
            data = self._from_matrices()
        object.__setattr__(self, "_modal", data)
        top = float(np.max(data["frequency"]))
        if top > _MODE_LIMIT_HZ:
            key = "modes_kept" if self.matrices else "modes"
            raise InputError(f"structure.{key}: a mode at {top:.4g} Hz; keep modes below {_MODE_LIMIT_HZ:g} Hz (the "
                             "structure's step is explicit in the stiffness: stable for omega h < 2, and Gear's steps "
                             f"reach {_GEAR_STEP_BOUND * 1e6:g} us)" + (", e.g. modes_kept = 4" if self.matrices else ""))
        _check_structure_motion(self)

    def _from_matrices(self) -> dict:
        from scipy.linalg import eigh

        mats = read_structure_matrices(self.matrices)
        n = _check_matrices(mats)
        dofs = {}
        for key in ("damper_dof", "force_dof", "response_dof"):
            v = getattr(self, key)
            if v is None:
                if key == "damper_dof":
                    raise InputError("structure.damper_dof is missing: give the index (0-based) of the dof the "
                                     f"container sits on, along the drive direction (0 to {n - 1})")
                v = dofs["damper_dof"]
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 <= v < n:
                raise InputError(f"structure.{key} = {v!r}; must be a dof index from 0 to {n - 1} (0-based; the "
                                 f"matrices have {n} dofs)")
            dofs[key] = int(v)
        kept = n if self.modes_kept is None else self.modes_kept
        if isinstance(kept, bool) or not isinstance(kept, (int, np.integer)) or not 1 <= kept <= n:
            raise InputError(f"structure.modes_kept = {self.modes_kept!r}; must be from 1 to the number of dofs, {n}")
        damping = [k for k in ("rayleigh", "damping_ratio") if getattr(self, k) is not None]
        if mats["C"] is not None:
            damping.append("C (in the matrices)")
        if len(damping) != 1:
            raise InputError("structure: give exactly one damping: rayleigh = [alpha, beta], damping_ratio = 0.005 or "
                             "a C matrix in the matrices file" + (f" (given: {', '.join(damping)})" if damping else ""))
        w2, phi = eigh(mats["K"], mats["M"], subset_by_index=[0, kept - 1])
        w = np.sqrt(w2)
        if self.rayleigh is not None:
            r = np.asarray(self.rayleigh, dtype=float)
            if r.shape != (2,) or not np.all(np.isfinite(r)) or np.any(r < 0):
                raise InputError(f"structure.rayleigh = {self.rayleigh!r}; give [alpha, beta] >= 0 "
                                 "(C = alpha M + beta K)")
            c = r[0] + r[1] * w2
        elif self.damping_ratio is not None:
            z = self.damping_ratio
            if isinstance(z, bool) or not isinstance(z, (int, float)) or not 0.0 <= z < 1.0:
                raise InputError(f"structure.damping_ratio = {z!r}; must be in [0, 1), e.g. 0.005 (0.5 %)")
            c = 2.0 * z * w
        else:
            c = np.einsum("ik,ij,jk->k", phi, mats["C"], phi)
        zeta = c / (2.0 * w)
        if np.any(zeta >= 1.0):
            k = int(np.argmax(zeta >= 1.0))
            raise InputError(f"structure: mode {k + 1} ({w[k] / (2 * math.pi):.4g} Hz) has damping ratio {zeta[k]:.3g} "
                             ">= 1 with this damping (rayleigh or C); the modal model needs underdamped modes")
        d, f, r = dofs["damper_dof"], dofs["force_dof"], dofs["response_dof"]
        pd = phi[d]
        if not np.any(np.abs(pd) > 1e-12 * np.max(np.abs(phi))):
            raise InputError(f"structure.damper_dof = {d}: every kept mode shape is zero there; the damper would act "
                             "on none of them (choose the dof the container moves with, or keep more modes)")
        full = float(np.linalg.solve(mats["K"], np.eye(n)[:, d])[d])
        kept_c = float(np.sum(pd**2 / w2))
        return {"frequency": w / (2.0 * math.pi), "damping_ratio": zeta, "modal_mass": np.ones(kept),
                "damper": pd.copy(), "force": phi[f].copy(), "response": phi[r].copy(),
                "truncation_error": (full - kept_c) / full, "dofs": n}

    # -- the modal data ------------------------------------------------------------------
    @property
    def n_modes(self) -> int:
        """Number of modes carried."""
        return int(self._modal["frequency"].size)

    @property
    def mode_frequencies(self) -> np.ndarray:
        """f_k [Hz]."""
        return self._modal["frequency"].copy()

    @property
    def truncation_error(self) -> float:
        """Relative error of the static compliance at the damper dof from the kept modes against the
        full ``(K^-1)_dd`` (matrices only; NaN for modes given as data)."""
        return float(self._modal["truncation_error"])

    def _modal_arrays(self):
        m = self._modal
        mass = m["modal_mass"]
        w = 2.0 * math.pi * m["frequency"]
        k = mass * w * w
        c = 2.0 * m["damping_ratio"] * np.sqrt(k * mass)
        return mass, k, c, m["damper"], m["force"], m["response"]

    def modal_arrays(self):
        """(modal masses m_k [kg], stiffnesses k_k [N/m], dampings c_k [N s/m], mode shapes at the
        damper, at the force, at the response point), arrays over the modes."""
        return tuple(np.array(a, dtype=float) for a in self._modal_arrays())

    @property
    def mass(self) -> float:
        """The first mode's mass seen at the damper, m_1 / phi_1(damper)^2 [kg] (the equivalent
        single-mode structure at the damper)."""
        return float(self._modal["modal_mass"][0] / self._modal["damper"][0] ** 2)

    @property
    def natural_frequency(self) -> float:
        """f_1 [Hz], the lowest mode (without the bed)."""
        return float(self._modal["frequency"][0])

    @property
    def stiffness(self) -> float:
        """The first mode's stiffness at the damper, mass (2 pi f_1)^2 [N/m]."""
        return self.mass * (2.0 * math.pi * self.natural_frequency) ** 2

    @property
    def modal_damping_ratio(self) -> float:
        """zeta_1 [-] of the first mode."""
        return float(self._modal["damping_ratio"][0])

    @property
    def damping(self) -> float:
        """c = 2 zeta_1 sqrt(K M) [N s/m] of the first mode at the damper."""
        return 2.0 * self.modal_damping_ratio * math.sqrt(self.stiffness * self.mass)

    @property
    def highest_frequency(self) -> float:
        """The highest frequency of the structure's motion without the bed [Hz] (for time steps)."""
        return float(max(np.max(self._modal["frequency"]), self.force_frequency or 0.0))

    @property
    def frequency(self) -> float:
        """The frequency [Hz] that counts the run's cycles: f_F when forced, else f_1."""
        return self.force_frequency if self.force_amplitude > 0 else self.natural_frequency

    def initial_modes(self):
        """(q_k(0), q_k'(0)): the damper point at ``displacement`` and ``velocity`` in the static
        shape of a load at the damper, ``q_k proportional to phi_k(damper) / k_k``."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        shape = pd / k
        unit = float(np.sum(pd * shape))
        return shape * (self.displacement / unit), shape * (self.velocity / unit)

    @property
    def velocity_bound(self) -> float:
        """An upper estimate [m/s] of the damper point's speed without the bed (for the time step)."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        w = np.sqrt(k / mass)
        free = float(np.sum(np.abs(pd) * (np.abs(v0) + w * np.abs(q0))))
        forced = 0.0
        if self.force_amplitude > 0:
            wf = 2.0 * math.pi * self.force_frequency
            zeta = np.maximum(self._modal["damping_ratio"], 0.01)
            res = np.abs(pd * pf) * self.force_amplitude / k / (2.0 * zeta)
            forced = float(np.sum(np.maximum(wf, w) * res))
        return free + 2.0 * forced

    def speed_bound(self) -> float:
        """An upper estimate [m/s] of the container's speed (:attr:`velocity_bound`)."""
        return self.velocity_bound

    def duration(self, cycles: float) -> float:
        """Time [s] of ``cycles`` periods of :attr:`frequency`."""
        return cycles / self.frequency

    def modal_motion(self, t):
        """(q, q', q'') [each (N, len(t))] of the modes *without* the bed (closed form per mode)."""
        from .theory.oscillator import oscillator_response

        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        out = [oscillator_response(t, mass=mass[j], stiffness=k[j], damping_ratio=self._modal["damping_ratio"][j],
                                   force_amplitude=pf[j] * self.force_amplitude,
                                   force_frequency=self.force_frequency or 0.0, displacement=q0[j], velocity=v0[j])
               for j in range(self.n_modes)]
        return tuple(np.array([np.asarray(o[i], dtype=float) for o in out]) for i in range(3))

    def motion(self, t):
        """(x, v, a) of the damper point at times t [s] *without* the bed (modal superposition of
        the closed forms); the coupled motion is recorded by the run."""
        pd = self._modal["damper"]
        return tuple(np.tensordot(pd, z, axes=1) for z in self.modal_motion(t))

    def response_motion(self, t):
        """Displacement [m] of the response point at times t [s] without the bed (closed form)."""
        return np.tensordot(self._modal["response"], self.modal_motion(t)[0], axes=1)

    def steady_amplitude(self, frequencies, force_amplitude: float, added_mass: float = 0.0, point: str = "damper"):
        """Steady amplitude [m] at the damper (or ``point = "response"``) under ``force_amplitude``
        sin(2 pi f t) at each of ``frequencies`` [Hz], without the bed; ``added_mass`` [kg] rigidly
        at the damper (the bed as a solid mass): the modal equations coupled by it,
        ``(-W^2 (diag m + m_a phi_d phi_d^T) + i W diag c + diag k) q = phi_f F0``."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        out = []
        for f in np.atleast_1d(np.asarray(frequencies, dtype=float)):
            w = 2.0 * math.pi * f
            A = np.diag(k - w * w * mass + 1j * w * c) - w * w * added_mass * np.outer(pd, pd)
            q = np.linalg.solve(A, pf * force_amplitude)
            out.append(abs(complex(np.dot(pr if point == "response" else pd, q))))
        return np.array(out)

    def check_scale(self, length: float) -> None:
        """As a single mode's, with the first mode's frequency, stiffness and damping."""
        _check_structure_scale(self, length, self.modal_damping_ratio)

    def kernel_drive(self):
        """(kind, par, table, state) for the kernels (:func:`pdamper.kernels.structure.modal_step`);
        the state starts at rest at the initial shape (held during settling)."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        om = 2.0 * math.pi * (self.force_frequency or 0.0)
        par = np.array([self.force_amplitude, om])
        tab = np.ascontiguousarray(np.column_stack([mass, k, c, pd, pf, pr]))
        st = np.zeros((2 + self.n_modes, 5))
        q0, _ = self.initial_modes()
        st[2:, 0] = q0
        st[0, 0] = float(np.dot(pd, q0))
        st[1, 2] = float(np.dot(pr, q0))
        return 4, par, tab, st

    def container_motion(self, t: float, state):
        """The damper point's ``(x, v, a)`` now, from the kernels' state."""
        return state[0, 0], state[0, 1], state[0, 2]

    def start_state(self, st, wall_force: float = 0.0) -> float:
        """Release at t = 0: the modes at (q0, q0'), accelerations from the modal equations with
        ``wall_force`` [N] at the damper; returns the damper point's a0."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        a = (-c * v0 - k * q0 - pd * wall_force) / mass
        st[:, :] = 0.0
        st[2:, 0], st[2:, 1], st[2:, 2] = q0, v0, a
        st[0, 0:5] = (float(np.dot(pd, q0)), float(np.dot(pd, v0)), float(np.dot(pd, a)), 0.0, float(np.dot(pf, v0)))
        st[1, 2] = float(np.dot(pr, q0))
        return float(st[0, 2])

    @property
    def initial_energy(self) -> float:
        """Mechanical energy of the structure at t = 0 [J]."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        return float(np.sum(0.5 * mass * v0**2 + 0.5 * k * q0**2))

    def record_info(self) -> dict:
        """What :class:`pdamper.recorders.structure.StructureRecord` keeps of the structure."""
        return {"mass_kg": self.mass, "stiffness_N_m": self.stiffness, "x0_m": self.displacement,
                "v0_m_s": self.velocity, "initial_energy_J": self.initial_energy}

    def structure_summary(self) -> dict:
        """Plain numbers about the structure for a run's summary: the modes, and with matrices the
        truncation error (:attr:`truncation_error`) and the number of dofs."""
        out = {"modes_kept": self.n_modes, "mode_frequencies_hz": self.mode_frequencies.tolist()}
        if self.matrices:
            out.update(truncation_error=self.truncation_error, dofs=int(self._modal["dofs"]))
        return out

    def config_extra(self) -> dict:
        """The keys a config file needs beyond the plain fields: ``modes`` or ``matrices``."""
        if self.modes:
            return {"modes": [dict(m) for m in self.modes]}
        m = self.matrices
        return {"matrices": {k: str(v) for k, v in m.items()} if isinstance(m, dict) else str(m)}

    def describe(self) -> str:
        forced = (f"F0 = {self.force_amplitude:g} N at {self.force_frequency:g} Hz" if self.force_amplitude > 0
                  else f"free decay from {self.displacement * 1e3:g} mm")
        fs = ", ".join(f"{f:.4g}" for f in self.mode_frequencies[:4]) + (", ..." if self.n_modes > 4 else "")
        return f"modal structure, {self.n_modes} mode{'s' if self.n_modes > 1 else ''} ({fs} Hz), {forced}"
