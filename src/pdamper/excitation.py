"""Prescribed container motion: harmonic ``x_c = X sin(Omega t)`` or a motion given as samples.

The drive acts along a direction in the lab's horizontal plane, given as an angle [rad] from
the lab x axis (the container's length when untilted) towards the lab z axis.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError

__all__ = ["HarmonicDrive", "SampledDrive", "Still"]


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

    stroke: float
    frequency: float = 2.0
    angle: float = 0.0
    kind: str = "harmonic"

    def __post_init__(self):
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

    time: tuple = field(default=())
    position: tuple = field(default=())
    velocity: tuple | None = None
    acceleration: tuple | None = None
    angle: float = 0.0
    frequency: float | None = None
    kind: str = "samples"

    def __post_init__(self):
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

    duration_s: float = 1.0
    angle: float = 0.0
    kind: str = "still"

    def __post_init__(self):
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
