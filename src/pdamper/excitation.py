"""Prescribed container motion: harmonic ``x_c = X sin(Omega t)``, a motion given as samples, or
the motion of a structure the container rides on (:class:`CoupledStructure`, two-way coupled).

The drive acts along a direction in the lab's horizontal plane, given as an angle [rad] from
the lab x axis (the container's length when untilted) towards the lab z axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import InputError
from .schema import convert_fields, param

__all__ = ["HarmonicDrive", "SampledDrive", "Still", "CoupledStructure"]


@dataclass(frozen=True, kw_only=True)
class HarmonicDrive:
    """``x_c = X sin(Omega t)``, Omega = 2 pi f (paper Sect. 2).

    Parameters
    ----------
    stroke : float
        X [m], > 0 (amplitude of the container motion).
    frequency : float
        f [Hz], > 0.
    angle : float
        Direction of the drive in the horizontal plane [rad] (0: along the container's length).
    """

    stroke: float = param(dimension="length", paper="3-50 mm")
    frequency: float = param(2.0, dimension="frequency", paper="2 Hz")
    angle: float = param(0.0, dimension="angle")
    kind: str = param("harmonic", kind="tag")

    def __post_init__(self):
        convert_fields(self, "drive")
        if not (self.stroke > 0 and math.isfinite(self.stroke)):
            raise InputError(f"drive.stroke = {self.stroke!r} m; must be > 0 (e.g. '12mm')")
        if not (self.frequency > 0 and math.isfinite(self.frequency)):
            raise InputError(f"drive.frequency = {self.frequency!r} Hz; must be > 0 (e.g. '2Hz')")
        if not math.isfinite(self.angle):
            raise InputError(f"drive.angle = {self.angle!r}; must be a finite angle")

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


@dataclass(frozen=True, kw_only=True)
class SampledDrive:
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
    kind: str = param("samples", kind="tag")

    def __post_init__(self):
        convert_fields(self, "drive")
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


@dataclass(frozen=True, kw_only=True)
class Still:
    """A container at rest for ``duration`` [s] (settling, tests, free motion of the bed)."""

    duration_s: float = param(1.0, dimension="time", key="duration")
    angle: float = param(0.0, dimension="angle")
    kind: str = param("still", kind="tag")

    def __post_init__(self):
        convert_fields(self, "drive")
        if not (self.duration_s > 0 and math.isfinite(self.duration_s)):
            raise InputError(f"drive.duration = {self.duration_s!r} s; must be > 0")

    def duration(self, cycles: float | None = None) -> float:
        """Length of the run [s] (``cycles`` is ignored)."""
        return self.duration_s

    def motion(self, t):
        """(0, 0, 0) at every time."""
        z = np.zeros(np.shape(t))
        return z, z.copy(), z.copy()

    def kernel_args(self):
        """(kind, par, tab) for :func:`pdamper.kernels.drive.drive_motion`."""
        return 0, np.zeros(3), np.zeros((1, 5))


@dataclass(frozen=True, kw_only=True)
class CoupledStructure:
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
    kind: str = param("structure", kind="tag")
    #: A case's drive field is the config section [drive]; a structure is [structure] (schema.replace).
    config_section = "structure"

    def __post_init__(self):
        convert_fields(self, "structure")
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
        for name in ("displacement", "velocity", "angle"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise InputError(f"structure.{name} = {v!r}; must be a finite number")
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

    def kernel_args(self):
        """(kind, par, state) for the kernels (:mod:`pdamper.kernels.structure`); the state
        starts at rest at the initial displacement (held during settling)."""
        om = 2.0 * math.pi * (self.force_frequency or 0.0)
        par = np.array([self.mass, self.stiffness, self.damping, self.force_amplitude, om])
        st = np.zeros((2, 5))
        st[0, 0] = self.displacement
        return 3, par, st

    def start_state(self, st, wall_force: float = 0.0) -> float:
        """Release the structure at t = 0: set (x0, v0, a0) in the kernel state ``st``, with
        ``wall_force`` [N] the bed's wall force along the drive at that moment; returns a0."""
        a0 = (-self.damping * self.velocity - self.stiffness * self.displacement - wall_force) / self.mass
        st[0, 0:4] = (self.displacement, self.velocity, a0, 0.0)
        st[1, :] = 0.0
        return a0
