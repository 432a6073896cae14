"""Driving force and container motion, sampled as means over each sample interval.

Impacts last ~30-60 us; a point sample of the wall force at 1 kHz would alias them. The kernels
integrate the impulse of the wall forces over each interval and pdamper reports
``impulse / interval``; the container velocity is likewise the interval mean
``(x_c(t_k+1) - x_c(t_k)) / interval``. Both signals are the same box-filtered view of the
truth, so the complex power (eq. 3) sees no aliasing and no relative phase error.
"""

from __future__ import annotations

from .._repr import short_repr

from dataclasses import dataclass

import numpy as np

__all__ = ["Signals", "SignalsRecorder"]


@dataclass(frozen=True, kw_only=True)
class Signals:
    """Recorded signals; sample k covers ``[k dt, (k+1) dt)`` and is stamped at its centre.

    Attributes
    ----------
    time : [s] interval centres.  time_end : [s] interval ends.
    force : driving force on the container along the drive, interval mean [N]
        (``m_c x_c'' + sum of wall forces on the particles``).
    velocity : container velocity along the drive, interval mean [m/s].
    position : container position along the drive at the interval centre [m].
    """

    time: np.ndarray
    time_end: np.ndarray
    force: np.ndarray
    velocity: np.ndarray
    position: np.ndarray

    @classmethod
    def from_run(cls, case, interval: float, wall_force: np.ndarray, motion=None) -> "Signals":
        """``motion``: recorded (x, v) of the container at the n + 1 interval edges [m, m/s]
        (a coupled structure); else the drive's prescribed motion."""
        n = wall_force.size
        edges = np.arange(n + 1) * interval
        if motion is None:
            x, v, _ = case.drive.motion(edges)
            xm, _, _ = case.drive.motion((np.arange(n) + 0.5) * interval)
        else:
            x, v = motion
            xm = 0.5 * (x[:-1] + x[1:])
        vel = np.diff(x) / interval
        acc = np.diff(v) / interval
        acc[0] = (v[1] - v[0]) / interval  # v(0+) is the start of the drive (no jump counted)
        force = wall_force + case.container.mass * acc
        return cls(time=edges[:-1] + 0.5 * interval, time_end=edges[1:], force=force, velocity=vel, position=xm)

    def as_dict(self) -> dict:
        """Columns with units in their names, for CSV/netCDF writers."""
        return {"time [s]": self.time, "force [N]": self.force, "velocity [m/s]": self.velocity,
                "position [m]": self.position}


class SignalsRecorder:
    """The driving force and the container motion (kernel channel ``"wall_force"``; on a coupled
    structure its recorded motion) as :class:`Signals`."""

    name = "signals"
    channels = frozenset({"wall_force"})
    every = 0

    def start(self, run) -> None:
        self.case = run.case

    def record(self, state) -> None:  # kernel channels only
        pass

    def finalize(self, data) -> Signals:
        motion = None
        if "structure" in data.channels:
            from .structure import StructureRecord

            motion = StructureRecord.from_channel(self.case, data).edges()
        return Signals.from_run(self.case, data.info.interval, data.channels["wall_force"], motion=motion)


# short reprs: names, shapes and key numbers (a notebook shows a line, not a dump)
Signals.__repr__ = short_repr
