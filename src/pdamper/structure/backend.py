"""A structure advanced a coupling step at a time: the protocol the co-simulation loop drives
(:mod:`pdamper.cosim`), and pdamper's own linear modes behind it.

As a preCICE adapter or LAMMPS' ``fix external`` do, the other side of the coupling is one small
object that keeps its own integrator and answers two things::

    class StructureBackend(Protocol):
        step: float                     # the coupling step [s]
        labels: list                    # the dofs it reports (Motion.dofs)
        def start(self) -> Motion: ...  # the state at t = 0
        def advance(self, forces) -> Motion: ...   # one step with the beds' wall forces [N]
        def close(self) -> None: ...
        ledger                          # the structure's energy ledger (LinearLedger) or None

``forces`` are the mean wall forces on each damper's spheres along its drive over the step (what
the DEM measures); the structure feels minus them at the damper points, held over the step.
:class:`Motion` is the state at a step's end: every damper point's displacement, velocity and
acceleration (relative to the ground under a ground acceleration), the ground's motion, the
reported dofs.

:class:`LinearBackend` is pdamper's structure of N modes (``[structure]`` mass or matrices, or an
OpenSees model used linearly). It is exact between the steps: the response to the load without the
beds is the closed form (:mod:`pdamper.structure.linear`, ``theory.oscillator``), and each mode's
response to the beds' forces, constant over a step, is the free vibration about the static
deflection of the step's force (no time step in it); the two add (linear superposition). So the
only error of a coupled run on it is the coupling's own (:mod:`pdamper.cosim`).
:class:`pdamper.structure.opensees.OpenSeesBackend` is the other implementation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, shown
from ..excitation import DriveBase
from ..schema import param
from .loads.base import FORM_LINEAR

__all__ = ["Motion", "LinearBackend", "LinearLedger", "BedSeat", "ground_motion", "bare_modal_states",
           "apparent_masses"]


@dataclass(frozen=True, kw_only=True)
class Motion:
    """The structure at time ``t`` [s]: the damper points' ``x`` [m], ``v`` [m/s], ``a`` [m/s^2]
    (one per damper, relative to the ground under a ground acceleration), the ``ground``'s (x, v, a)
    (zeros without one), the reported ``dofs``' displacements [m] and ``dofs_velocity`` [m/s]."""

    t: float
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    ground: tuple = (0.0, 0.0, 0.0)
    dofs: np.ndarray = field(default_factory=lambda: np.zeros(0))
    dofs_velocity: np.ndarray = field(default_factory=lambda: np.zeros(0))
    #: the structure's response point's displacement [m] (NaN where the backend does not know it)
    response: float = math.nan


def ground_motion(load, t) -> tuple:
    """(x_g, v_g, a_g) [m, m/s, m/s^2] of the ground at the times ``t`` (increasing from 0), from
    rest: the acceleration linear between the times, integrated exactly."""
    t = np.asarray(t, dtype=float)
    a = np.asarray(load.values(t), dtype=float)
    h = np.diff(t)
    v = np.concatenate([[0.0], np.cumsum(0.5 * h * (a[1:] + a[:-1]))])
    x = np.concatenate([[0.0], np.cumsum(v[:-1] * h + h * h * (a[:-1] / 3.0 + a[1:] / 6.0))])
    return x, v, a


def bare_modal_states(structure, t):
    """(q, q', q'') [times, modes] of ``structure`` (as it runs) without the bed at the times ``t``
    [s] >= 0: under its load in time the exact linear response, else the closed form of its
    harmonic force and start."""
    t = np.asarray(t, dtype=float)
    mass, k, c, pd, pf, pr = (np.asarray(a, dtype=float) for a in structure.modal_arrays())
    if structure.load is not None:
        from .linear import modal_response

        q, qd = modal_response(structure, t)
        b = np.asarray(structure.load.modal_coefficients(structure), dtype=float)
        f = np.asarray(structure.load.values(t), dtype=float)[:, None]
        return q, qd, (b * f - c * qd - k * q) / mass
    return tuple(np.asarray(z, dtype=float).T for z in structure.modal_motion(t))


@dataclass
class LinearLedger:
    """The structure's energies at the steps' ends [J]: its mechanical energy, the work of the load on
    it and its damping loss (Simpson's rule on each step's ends and middle), the work the beds'
    forces did on it (exact for a force held over a step: -F dx)."""

    energy: list = field(default_factory=list)
    external_work: list = field(default_factory=list)
    damping_loss: list = field(default_factory=list)
    bed_work: list = field(default_factory=list)


def _free(zeta, w, wd, tau):
    """``tau`` of free vibration of each mode: (q, q') -> A (q, q') (A: 2 x 2 x modes)."""
    e = np.exp(-zeta * w * tau)
    co, si = np.cos(wd * tau), np.sin(wd * tau)
    return np.array([[e * (co + zeta * w / wd * si), e * si / wd],
                     [-e * w * w / wd * si, e * (co - zeta * w / wd * si)]])


class LinearBackend:
    """pdamper's linear structure (:class:`~pdamper.structure.StructureBase`) advanced a coupling
    ``step`` [s] at a time for ``duration`` [s] (module docstring): the dampers at its damper points
    ``points`` (indices of :meth:`~pdamper.structure.StructureBase.damper_shapes`, one per damper)
    carrying the empty containers' ``masses`` [kg]."""

    def __init__(self, structure, *, step: float, duration: float, points, masses):
        self.points = [int(p) for p in points]
        per_point = np.zeros(structure.damper_count)
        for p, m in zip(self.points, masses):
            per_point[p] += float(m)
        s = structure.carrying(per_point if structure.damper_count > 1 else float(per_point[0]))
        self.s = s
        self.step = h = float(step)
        self.n_steps = int(math.floor(duration / step + 1e-9))
        mass, k, c, _, pf, pr = (np.asarray(a, dtype=float) for a in s.modal_arrays())
        self.m, self.k, self.c, self.pr = mass, k, c, pr
        w = np.sqrt(k / mass)
        zeta = c / (2.0 * mass * w)
        if np.any(zeta >= 1.0):
            raise InputError("the coupled structure needs underdamped modes (zeta < 1)")
        wd = w * np.sqrt(1.0 - zeta * zeta)
        self._A, self._A_half = _free(zeta, w, wd, h), _free(zeta, w, wd, 0.5 * h)
        self.P = np.asarray(s.damper_shapes(), dtype=float)[self.points]
        labels, shapes = s.dof_shapes()
        self.labels = list(labels)
        self.shapes = np.asarray(shapes, dtype=float)
        t = np.arange(2 * self.n_steps + 3) * (0.5 * h)   # the steps' ends and middles
        self._bare = bare_modal_states(s, t)
        load = s.load
        self.ground = bool(load is not None and load.ground)
        self._g = tuple(z[::2] for z in ground_motion(load, t)) if self.ground else None
        # the load's generalised force on each mode, per unit of f(t), and f at the half steps
        if load is not None:
            self._b = np.asarray(load.modal_coefficients(s), dtype=float)
            self._f = np.asarray(load.values(t), dtype=float)
        else:
            self._b = pf
            self._f = s.force_amplitude * np.sin(2.0 * math.pi * (s.force_frequency or 0.0) * t)
        n = mass.size
        self._y = np.zeros(n)   # the modes' response to the beds' forces (q, q')
        self._yd = np.zeros(n)
        self._u = np.zeros(len(self.points))
        self.k_step = 0
        self.ledger = LinearLedger()
        self._note(0)

    def _modes(self, i, y=None, yd=None):
        """(q, q', q'') of the modes at half step ``i``: the bare response there plus the beds' share
        (``y``, ``yd``; default the step's end) under the held forces."""
        q, qd, qdd = (z[i] for z in self._bare)
        y = self._y if y is None else y
        yd = self._yd if yd is None else yd
        g = -self.P.T @ self._u
        ydd = (g - self.c * yd - self.k * y) / self.m
        return q + y, qd + yd, qdd + ydd

    def _note(self, j, mid=None):
        """The ledger at the end of step ``j`` (``mid``: the beds' share at its middle): the work and
        the damping loss over the step by Simpson's rule on its ends and middle."""
        q, qd, _ = self._modes(2 * j)
        L = self.ledger
        L.energy.append(float(np.sum(0.5 * self.m * qd * qd + 0.5 * self.k * q * q)))
        if j == 0:
            L.external_work.append(0.0)
            L.damping_loss.append(0.0)
            L.bed_work.append(0.0)
            self._last = (qd, q)
            return
        qd0, q0 = self._last
        _, qdm, _ = self._modes(2 * j - 1, *mid)
        h, f, b = self.step, self._f, self._b

        def simpson(a, m, e):
            return h / 6.0 * (a + 4.0 * m + e)

        L.external_work.append(L.external_work[-1] + simpson(f[2 * j - 2] * (b @ qd0), f[2 * j - 1] * (b @ qdm),
                                                             f[2 * j] * (b @ qd)))
        L.damping_loss.append(L.damping_loss[-1] + simpson(*(float(np.sum(self.c * z * z)) for z in (qd0, qdm, qd))))
        L.bed_work.append(L.bed_work[-1] - float(self._u @ (self.P @ (q - q0))))
        self._last = (qd, q)

    def _motion(self, j) -> Motion:
        q, qd, qdd = self._modes(2 * j)
        g = (self._g[0][j], self._g[1][j], self._g[2][j]) if self._g is not None else (0.0, 0.0, 0.0)
        return Motion(t=j * self.step, x=self.P @ q, v=self.P @ qd, a=self.P @ qdd, ground=g,
                      dofs=self.shapes @ q, dofs_velocity=self.shapes @ qd, response=float(self.pr @ q))

    def start(self) -> Motion:
        """The state at t = 0."""
        return self._motion(0)

    def advance(self, forces) -> Motion:
        """One step with the beds' wall forces ``forces`` [N] (on the spheres; the structure feels
        minus them at the damper points, held over the step); the state at its end."""
        if self.k_step >= self.n_steps + 1:
            raise InputError("the coupled structure was advanced beyond its duration")
        u = np.asarray(forces, dtype=float)
        # about the static deflection of the held force, exactly
        self._u = u
        qs = (-self.P.T @ u) / self.k
        a0, v0 = self._y - qs, self._yd
        A, Ah = self._A, self._A_half
        mid = (qs + Ah[0, 0] * a0 + Ah[0, 1] * v0, Ah[1, 0] * a0 + Ah[1, 1] * v0)
        self._y = qs + A[0, 0] * a0 + A[0, 1] * v0
        self._yd = A[1, 0] * a0 + A[1, 1] * v0
        self.k_step += 1
        self._note(self.k_step, mid)
        return self._motion(self.k_step)

    def close(self) -> None:
        pass


def apparent_masses(structure, points) -> np.ndarray:
    """Each damper point's apparent mass [kg] for a force over a short time: the mass an impulse J
    there meets, ``1 / M_a = sum_k phi_k(d)^2 / m_k`` over the structure's modes (as it runs; a lumped
    floor mass when every mode is kept). What a bed feels of the structure within a coupling step."""
    m = np.asarray(structure.modal_arrays()[0], dtype=float)
    P = np.asarray(structure.damper_shapes(), dtype=float)[list(points)]
    return 1.0 / np.sum(P * P / m, axis=1)


@dataclass(frozen=True, kw_only=True)
class BedSeat(DriveBase):
    """The container on the structure as its bed feels it within a coupling step of the loop
    (:mod:`pdamper.cosim`): the damper point as a free mass, its ``apparent_mass`` [kg]
    (:func:`apparent_masses`), under the structure's own acceleration there without this bed (given
    a step at a time, linear in the step: :meth:`write_piece`),

        a_c = a_free(t) - F_w / M_a,

    so the bed meets the structure's recoil at every contact within the step (an impact on a light
    floor moves it at once), and the structure's stiffness, damping, load and the other beds come in
    through ``a_free``. The kernels' modal step of one mode under a load in time advances it
    (:mod:`pdamper.kernels.structure`, kind ``"modal_load"``: m = M_a, k = c = 0, the load M_a a_free).
    Not a config kind: the loop makes one for each bed.

    Parameters
    ----------
    apparent_mass : M_a [kg].
    duration_s : the driven time [s].
    speed : an upper estimate of the container's speed [m/s] (the automatic time step).
    x0, a0 : the damper point's displacement [m] and acceleration [m/s^2] at t = 0 (held before).
    angle, direction : the direction of the motion (as a drive's).
    """

    apparent_mass: float = param(1.0, dimension="mass")
    duration_s: float = param(1.0, dimension="time", key="duration")
    speed: float = param(0.0, dimension="velocity")
    x0: float = param(0.0, dimension="length")
    a0: float = param(0.0, dimension="acceleration")
    angle: float = param(0.0, dimension="angle")
    direction: tuple | None = param(None, kind="list")
    kind: str = param("seat", kind="tag")
    coupled = True
    n_modes = 1
    config_label = "a container seat of the coupling loop"

    def __post_init__(self):
        self._prepare()
        self._check_direction()
        for key in ("apparent_mass", "duration_s"):
            v = getattr(self, key)
            if not (v > 0 and math.isfinite(v)):
                raise InputError(f"the bed's seat: {key} = {shown(v)}; must be > 0")

    def duration(self, cycles: float | None = None) -> float:
        return self.duration_s

    def speed_bound(self) -> float:
        return self.speed

    def motion(self, t):
        """At rest at x0 (the motion is the loop's, a step at a time)."""
        z = np.zeros(np.shape(t))
        return z + self.x0, z.copy(), z.copy()

    def carrying(self, mass: float):
        """Itself: the empty container's mass is the structure's (in its apparent mass)."""
        return self

    def kernel_drive(self):
        """("modal_load", par, table, state): one mode of mass M_a, no stiffness or damping, shapes 1,
        under a load of the linear form; held at x0 before t = 0."""
        par = np.array([float(FORM_LINEAR), 0.0])
        tab = np.array([[self.apparent_mass, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]])
        st = np.zeros((3, 5))
        st[2, 0] = st[0, 0] = self.x0
        return "modal_load", par, tab, st

    def kernel_load(self):
        tab = np.zeros((2, 4))
        tab[1, 0] = 1e9
        return tab

    def start_state(self, st, wall_force: float = 0.0) -> float:
        """Released at t = 0 at (x0, 0, a0); returns a0."""
        st[:, :] = 0.0
        st[2, 0], st[2, 2] = self.x0, self.a0
        st[0, 0], st[0, 2] = self.x0, self.a0
        return float(self.a0)

    def container_motion(self, t: float, state):
        return state[0, 0], state[0, 1], state[0, 2]

    def write_piece(self, drive, t0: float, piece) -> None:
        """The step from ``t0`` [s]: ``piece`` = (x, v, a, f, s): the damper point's displacement [m],
        velocity [m/s] and acceleration [m/s^2] now (the structure's, absolute), its acceleration
        without this bed ``a_free = f + s (t - t0)`` [m/s^2, m/s^3] over the step; written into the
        kernels' ``drive`` bundle in place (its state and load table)."""
        x, v, a, f, slope = (float(z) for z in piece)
        st, load, m = drive.state, drive.load, self.apparent_mass
        st[2, 0], st[2, 1], st[2, 2] = x, v, a
        st[0, 0], st[0, 1], st[0, 2] = x, v, a
        st[0, 3], st[0, 4] = m * f, v
        load[0, :] = (t0, m * f, m * slope, 0.0)
        load[1, :] = (t0 + 1e9, 0.0, 0.0, 0.0)

    def describe(self) -> str:
        return f"a container on a {self.apparent_mass:.4g} kg seat of the coupling loop, {self.duration_s:g} s"
