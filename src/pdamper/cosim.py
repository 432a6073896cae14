"""The coupling loop: one structure, several beds, advanced a coupling step at a time.

A structure backend (:mod:`pdamper.structure.backend`: pdamper's own linear modes, exact between
the steps, or OpenSees advancing a model with its own integrator and materials,
:class:`~pdamper.structure.opensees.OpenSeesBackend`) and one DEM bed per damper (each a
:class:`~pdamper.simulation.Simulation` of the damper's container and filling, its container on a
:class:`~pdamper.structure.backend.BedSeat`) take turns at every coupling step h (default: the
case's sample interval, 1 ms):

1. **the beds first**, each over [t_n, t_n + h], its container on the damper point's apparent mass
   M_a (the mass an impulse there meets, ``1/M_a = sum_k phi_k^2 / m_k``) under the structure's
   acceleration there *without this bed*, a_free, predicted: ``a_c = a_free(t) - F_w / M_a``, a_free
   linear over the step with the last step's slope (the ground's acceleration, known, in it). So a
   bed meets the structure's recoil at each of its impacts within the step, and what is slow (the
   structure's stiffness, damping and load, the other beds) comes in through a_free; each bed
   returns its mean wall force over the step, F_j (the kernels' impulse over it);
2. **the structure**, over the same step, with -F_j held at each damper point (Newton 3; the mean
   the beds produced over this very step, no lag);
3. **the correction**: the next step starts each bed's container where the structure is (its
   displacement, velocity, acceleration at t_n + h); where the seat's differ, the spheres keep
   their lab velocity, as at a drive's start.

**Its order and error.** a_free is smooth (the bed's own impulsive force is the seat's, not the
prediction's): predicted to O(h^2) per step. The seat is exact for the instantaneous response to an
impulse and misses the structure's restoring force on the recoil within the step (relative
O((omega h)^2)); another bed's force reaches a bed at the next step. The force enters the
structure as its mean over the step: exact for pdamper's linear backend (a force held over the
step, integrated exactly); OpenSees' Newmark average-acceleration step applies the load at the
step's two ends, (F_(n-1) + F_n) / 2 over the step: half a step late there (first order, a phase
lag of Omega h / 2, 6e-3 rad at 2 Hz and 1 ms). What it costs, measured, is in docs/structure.md
("The coupling loop"). The energy the coupling makes or loses is the interface mismatch: the work
the walls did on the beds (the DEM's own ledger) against the work the beds' forces took from the
structure (sum of F_j dx_j over the steps, the same frame), reported with every run.

**Kill and resume.** A coupled run is one unit of work: the beds' and the structure's states live
in memory (and in the OpenSees child), so a run killed part-way is run again from its start; what
it writes (a JSON, a figure) is written only when it has finished, by a temporary file and a rename.
The OpenSees child ends by itself when its parent is gone.
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from .errors import InputError, shown
from .params import Case
from .recorders.energy import EnergyRecorder
from .simulation import Simulation
from .structure.backend import BedSeat, apparent_masses, ground_motion

__all__ = ["CoupledRun", "run_coupled", "run_bare", "coupling_step", "bed_case", "SCHEME"]

#: The scheme in words (a run's summary carries it).
SCHEME = ("beds first, each container on the damper point's apparent mass under the structure's acceleration there "
          "without the bed (predicted, linear over the step); then the structure with the beds' mean forces of the same "
          "step; each step starts the containers where the structure is")


class _WallForce:
    """The recorder a bed of the loop runs with: the kernels' wall force channel (read step by step
    from the simulation's samples)."""

    name = "wall_force"
    channels = frozenset({"wall_force"})
    every = 0

    def start(self, run) -> None:
        pass

    def record(self, state) -> None:
        pass

    def finalize(self, data):
        return data.channels["wall_force"].copy()


def _steps(duration: float, h: float) -> int:
    """The coupling steps of a run: whole steps of ``h`` within ``duration`` (as its beds' samples)."""
    return int(math.floor(duration / h + 1e-9))


def coupling_step(case: Case) -> float:
    """The coupling loop's step [s]: ``[structure] coupling_step``, else the case's sample interval;
    at most a twentieth of the period of the structure's highest mode."""
    s = case.drive
    h = s.coupling_step if s.coupling_step is not None else 1.0 / case.recording.sample_rate
    top = float(np.max(s.mode_frequencies))
    if not (h > 0 and math.isfinite(h)):
        raise InputError(f"structure.coupling_step = {shown(h)} s; must be > 0, e.g. '1ms'")
    if h > 1.0 / (20.0 * top) * (1 + 1e-9):
        raise InputError(f"structure.coupling_step = {h * 1e3:.4g} ms is more than a twentieth of the period of the "
                         f"structure's highest mode ({top:.4g} Hz); give at most {1e3 / (20 * top):.3g} ms (or keep "
                         "fewer modes: modes_kept)")
    return float(h)


def _direction(d, structure) -> dict:
    """The drive direction of a bed: its damper's, else the structure's."""
    if d.direction is not None:
        return {"direction": d.direction}
    if d.angle is not None:
        return {"angle": d.angle}
    if structure.direction is not None:
        return {"direction": structure.direction}
    return {"angle": structure.angle}


def bed_case(case: Case, k: int, step: float, speed: float, seat: dict) -> Case:
    """The case of damper ``k``'s bed in the loop: its container and filling, the case's contact,
    numerics and start, its container on the loop's seat (:class:`~pdamper.structure.backend.BedSeat`,
    ``seat``: its apparent mass, start) for the case's duration (``speed`` [m/s] its speed bound),
    sampled once a coupling ``step``."""
    d = case.damper_beds()[k]
    motion = BedSeat(duration_s=case.duration, speed=float(speed), **seat, **_direction(d, case.drive))
    recording = dataclasses.replace(case.recording, sample_rate=1.0 / step, trajectory_fps=0.0)
    return dataclasses.replace(case, container=d.container, particles=d.particles, drive=motion, dampers=(),
                               rig=None, recording=recording)


def _speeds(structure, points, step: float, duration: float) -> list[float]:
    """Each damper point's largest speed [m/s] without the beds (the ground's added), on the steps of
    the first 20 s at most: the beds' automatic time step."""
    from .structure.backend import bare_modal_states, ground_motion

    n = int(min(round(duration / step), round(20.0 / step))) + 1
    t = np.arange(n) * step
    _, qd, _ = bare_modal_states(structure, t)
    P = structure.damper_shapes()
    vg = np.max(np.abs(ground_motion(structure.load, t)[1])) if structure.load is not None and structure.load.ground \
        else 0.0
    return [float(np.max(np.abs(qd @ P[p]))) + float(vg) + 1e-3 for p in points]


@dataclass(frozen=True, kw_only=True)
class CoupledRun:
    """What the coupling loop recorded, at the steps' ends ``time`` [s]: the structure's ``dofs``
    (labels) displacements [m] ``displacements`` (steps, dofs; relative to the ground under a ground
    acceleration), each damper point's ``damper_displacement`` (steps, dampers) and the beds' mean
    wall forces ``forces`` [N] (on the spheres, along each drive) over each step; the beds' energy
    ledgers ``ledgers`` (:class:`~pdamper.recorders.energy.EnergyLedger`, one per damper); the
    structure's (:class:`~pdamper.structure.backend.LinearLedger`, None for OpenSees); ``summary``."""

    case: Case
    time: np.ndarray
    dofs: list
    displacements: np.ndarray
    damper_displacement: np.ndarray
    forces: np.ndarray
    ledgers: list
    structure_ledger: object = None
    steps: int = 0
    wall_time_s: float = 0.0
    summary: dict = field(default_factory=dict)
    #: the structure's response point's displacement [m] over the steps (NaN where not known)
    response_displacement: np.ndarray | None = None
    #: each container's absolute displacement [m] and velocity [m/s] at the steps' edges (t = 0 first)
    container_displacement: np.ndarray | None = None
    container_velocity: np.ndarray | None = None

    @property
    def displacement(self) -> np.ndarray:
        """The first damper point's displacement [m] over the steps."""
        return self.damper_displacement[:, 0]


def _sum_energy(ledgers):
    """(mechanical, dissipated, work) of the beds together [J] at each step."""
    mech = sum(L.mechanical for L in ledgers)
    diss = sum(L.damping + L.friction for L in ledgers)
    work = sum(L.work for L in ledgers)
    return mech, diss, work


def run_coupled(case: Case, *, progress=None) -> CoupledRun:
    """Run ``case`` in the coupling loop (module docstring): its structure by its backend
    (:meth:`~pdamper.structure.StructureBase.backend`), a bed per damper
    (:meth:`~pdamper.params.Case.damper_beds`); ``progress(fraction)`` after each step's batch."""
    if not case.drive.coupled:
        raise InputError("the coupling loop needs a [structure] (the containers riding on it)")
    t_start = _time.perf_counter()
    s = case.drive
    h = coupling_step(case)
    n = _steps(case.duration, h)
    if n < 2:
        raise InputError(f"run: {case.duration:g} s is less than two coupling steps of {h * 1e3:g} ms; run longer")
    nd = case.damper_count
    points = [case.damper_point(k) for k in range(nd)]
    beds_of = case.damper_beds()
    running = case.running_drive
    speeds = _speeds(running, points, h, case.duration)
    masses = apparent_masses(running, points)
    backend = s.backend(h, case.duration, points, [b.container.mass for b in beds_of])
    grid = np.arange(n + 2) * h
    ag = ground_motion(s.load, grid)[2] if s.load is not None and s.load.ground else np.zeros(n + 2)
    try:
        m = backend.start()
        sims = [Simulation(bed_case(case, k, h, speeds[k], {"apparent_mass": float(masses[k]),
                                                              "x0": float(m.x[k] + m.ground[0]),
                                                              "a0": float(m.a[k]) + ag[0]}),
                           recorders=[EnergyRecorder(), _WallForce()]) for k in range(nd)]
        for sim in sims:
            sim.settle()
        labels = list(backend.labels)
        X = np.zeros((n, len(labels)))
        XD = np.zeros((n, nd))
        XR = np.zeros(n)
        F = np.zeros((n, nd))
        xabs = np.zeros((n + 1, nd))
        vabs = np.zeros((n + 1, nd))
        xabs[0], vabs[0] = m.x + m.ground[0], m.v + m.ground[1]
        forces = np.zeros(nd)
        free_prev = None
        every = max(1, n // 200)
        for k in range(n):
            # each damper point's acceleration without its bed (the bed's force of the last step taken
            # out: within the step the bed feels it through the apparent mass), the ground's added,
            # linear over the step with the last step's slope
            free = m.a + forces / masses + ag[k]
            slope = np.zeros(nd) if free_prev is None else (free - free_prev) / h
            pieces = [(float(m.x[j] + m.ground[0]), float(m.v[j] + m.ground[1]), float(m.a[j]) + ag[k],
                       float(free[j]), float(slope[j])) for j in range(nd)]
            forces = np.array([sim.advance_moved(1, pieces[j]) for j, sim in enumerate(sims)])
            free_prev = free
            m = backend.advance(forces)
            X[k] = m.dofs
            XD[k] = m.x
            XR[k] = m.response
            F[k] = forces
            xabs[k + 1], vabs[k + 1] = m.x + m.ground[0], m.v + m.ground[1]
            if progress is not None and (k % every == 0 or k == n - 1):
                progress((k + 1) / n)
    finally:
        backend.close()
    records = [sim.finalize() for sim in sims]
    ledgers = [r.energy for r in records]
    t = (np.arange(n) + 1) * h
    summary = _summary(case, backend, h, F, xabs, ledgers)
    summary.update(steps=int(sum(r.steps for r in records)), wall_time_s=_time.perf_counter() - t_start)
    return CoupledRun(case=case, time=t, dofs=labels, displacements=X, damper_displacement=XD, forces=F,
                      ledgers=ledgers, structure_ledger=getattr(backend, "ledger", None),
                      steps=summary["steps"], wall_time_s=summary["wall_time_s"], summary=summary,
                      response_displacement=XR, container_displacement=xabs, container_velocity=vabs)


def _summary(case: Case, backend, h: float, F, xabs, ledgers) -> dict:
    """The coupling's numbers: the scheme, the step, each bed's ledger, the interface mismatch and,
    on pdamper's linear backend under a force or a start, the coupled ledger."""
    # the work the beds' forces took from the structure, step by step, against the walls' work on the beds
    work_struct = np.cumsum(F * np.diff(xabs, axis=0), axis=0)
    work_beds = np.column_stack([np.asarray(L.work) for L in ledgers])
    mech, diss, work = _sum_energy(ledgers)
    mismatch = np.sum(work_beds - work_struct, axis=1)
    scale = max(float(np.max(np.sum(np.abs(work_beds), axis=1))), float(diss[-1]), 1e-300)
    out = {"coupling": "opensees" if case.drive.cosimulated else "loop", "coupling_scheme": SCHEME,
           "coupling_step_s": h, "dampers": case.damper_count,
           "bed_energy_balance_errors": [float(L.balance_error()) for L in ledgers],
           "interface_work_beds_J": work_beds[-1].tolist(), "interface_work_structure_J": work_struct[-1].tolist(),
           "interface_energy_error": float(np.max(np.abs(mismatch)) / scale),
           "beds_dissipated_J": float(diss[-1])}
    L = getattr(backend, "ledger", None)
    ground = bool(case.drive.load is not None and case.drive.load.ground)
    out["coupled_energy_balance_error"] = None
    if L is not None and not ground:
        # structure: E_s + D_s - W_ext = W_bs (the beds' forces' work on it); beds: E_b + D_b = W_b (the walls'
        # work on them); W_bs + W_b is the interface mismatch, so E_s + D_s - W_ext + E_b + D_b is constant
        # up to it (both from the first step's end, where the beds' ledgers start)
        Es, Ds, We = (np.asarray(v[1:]) for v in (L.energy, L.damping_loss, L.external_work))
        r = Es + Ds - We + mech + diss
        scale = max(float(L.energy[0]) + float(np.max(np.abs(We))), 1e-300)
        out["coupled_energy_balance_error"] = float(np.max(np.abs(r - r[0])) / scale)
    return out


def run_bare(case: Case, *, progress=None) -> CoupledRun:
    """The structure of ``case`` without the beds by its own backend, the empty containers' masses at
    the damper points (OpenSees' run of a co-simulated model; pdamper's exact modes else), on the
    loop's steps: the "without the dampers" of a co-simulated study."""
    s = case.drive
    h = coupling_step(case)
    n = _steps(case.duration, h)
    nd = case.damper_count
    points = [case.damper_point(k) for k in range(nd)]
    backend = s.backend(h, case.duration, points, [b.container.mass for b in case.damper_beds()])
    try:
        m = backend.start()
        X = np.zeros((n, len(backend.labels)))
        XD = np.zeros((n, nd))
        XR = np.zeros(n)
        zero = [0.0] * nd
        for k in range(n):
            m = backend.advance(zero)
            X[k], XD[k], XR[k] = m.dofs, m.x, m.response
            if progress is not None and k % max(1, n // 100) == 0:
                progress((k + 1) / n)
    finally:
        backend.close()
    t = (np.arange(n) + 1) * h
    return CoupledRun(case=case, time=t, dofs=list(backend.labels), displacements=X, damper_displacement=XD,
                      forces=np.zeros((n, nd)), ledgers=[], structure_ledger=getattr(backend, "ledger", None),
                      summary={"coupling_step_s": h}, response_displacement=XR)
