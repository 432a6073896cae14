"""A case in motion: :class:`Simulation` owns the kernels' state, advances it, and feeds its
recorders. It analyses nothing: :func:`pdamper.run.run_case` composes a simulation, its
recorders, the complex-power analysis and the motion mode.

A run settles the spheres in the still container (``initial.settle_time``, whole samples), then
drives it for ``case.duration`` in segments of about a quarter second of simulated time (for
progress and clean interrupts), stopping also wherever a Python recorder is due.

>>> from pdamper.params import Case, ParticleSet
>>> sim = Simulation(Case(particles=(ParticleSet(count=4),), cycles=1, drop_cycles=0))
>>> sim.n, sim.n_samples
(4, 500)
"""

from __future__ import annotations

from ._deprecated import renamed
from ._repr import short_repr

import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from .engine import warmup
from .engine.build import CELLS_THRESHOLD, auto_time_step, build
from .engine.steppers import GEAR_MIN_STEP, stepper_for
from .errors import InputError, shown
from .kernels.bundles import (CONTACT_TYPES, ENERGY_COLUMNS, FRAME_COLUMNS, NO_SPLIT, STRUCTURE_COLUMNS, ContactSplit,
                              Samples)
from .params import Case
from .recorders.base import Recorded, RunInfo, State, check_recorders
from .recorders.energy import EnergyRecorder
from .recorders.signals import SignalsRecorder
from .recorders.structure import StructureRecord, StructureRecorder
from .recorders.trajectory import TrajectoryRecorder

__all__ = ["Simulation", "RunRecord", "default_recorders", "auto_time_step", "run_bare_structure", "run_on_gpu",
           "CELLS_THRESHOLD", "GEAR_MIN_STEP"]

#: Simulated time [s] the compiled loop runs between returns to Python (progress, interrupts).
SEGMENT = 0.25


def default_recorders(case: Case) -> list:
    """What a run records unless told otherwise: the signals and the energy ledger, the coupled
    structure's motion when there is one, and the trajectory at ``recording.trajectory_fps``."""
    out = [SignalsRecorder(), EnergyRecorder()]
    if case.drive.coupled:
        out.append(StructureRecorder())
    if case.recording.trajectory_fps > 0:
        out.append(TrajectoryRecorder(case.recording.trajectory_fps))
    return out


@dataclass(frozen=True, kw_only=True)
class RunRecord:
    """What a simulation recorded: each recorder's result by name, and how the run went.

    ``signals``, ``energy``, ``trajectory`` and ``structure`` are the built-in recorders' results
    (None when not recorded). ``steps`` time steps were taken, ``time_step_s`` [s] is Verlet's step
    or Gear's mean accepted step (settling included), ``rejected_steps`` Gear's rejections.
    """

    case: Case
    outputs: dict = field(default_factory=dict)
    steps: int = 0
    time_step_s: float = 0.0
    wall_time_s: float = 0.0
    neighbour_search: str = ""
    rejected_steps: int | None = None

    time_step = renamed("time_step_s")

    @property
    def signals(self):
        return self.outputs.get("signals")

    @property
    def energy(self):
        return self.outputs.get("energy")

    @property
    def trajectory(self):
        return self.outputs.get("trajectory")

    @property
    def structure(self):
        return self.outputs.get("structure")

    def __getattr__(self, name):
        if name in ("eta_star", "analysis", "mode", "energy_per_cycle"):
            raise AttributeError(f"RunRecord has no {name!r}: a Simulation records, it does not analyse; use "
                                 "pdamper.run_case(case) for eta*, the energy per cycle and the motion mode")
        raise AttributeError(name)


class Simulation:
    """A case turned into the kernels' state, advanced in time, feeding its recorders.

    Parameters
    ----------
    case : the :class:`~pdamper.params.Case` to simulate.
    recorders : the recorders (:mod:`pdamper.recorders.base`); default :func:`default_recorders`.
    analyze : the run is analysed by the complex power method, so the case needs whole cycles after
        the dropped ones (:func:`pdamper.plausible.check_case`, which checks the case here).
    checked : the case was checked already (:func:`pdamper.run.run_case`'s ``checked``).

    Notes
    -----
    The state lives in the kernels' bundles (:mod:`pdamper.kernels.bundles`): ``sim.bodies``
    (positions, velocities, spins of the spheres, container frame), ``sim.pairs``, ``sim.walls``.
    :meth:`run` does everything; :meth:`settle` and :meth:`advance` do it in parts.
    """

    def __init__(self, case: Case, recorders=None, *, analyze: bool = False, checked: bool = False):
        from .plausible import check_case, check_memory

        self.case = case
        #: the drive as it runs (a structure with the empty container's mass on it)
        self.drive = case.running_drive
        if not checked:
            check_case(case, analyze=analyze)  # once a run, before anything is simulated
        # a list once: a generator of recorders is read here and nowhere else
        recs = list(default_recorders(case) if recorders is None else recorders)
        check_memory(case, max((getattr(r, "fps", 0.0) or 0.0 for r in recs if "frames" in getattr(r, "channels", ())),
                               default=0.0))
        self.engine = build(case)
        fs = case.recording.sample_rate
        self.interval = 1.0 / fs
        #: samples of the driven phase, and of the settling before it
        self.n_samples = int(math.floor(case.duration * fs + 1e-9))
        self.settle_samples = int(math.ceil(case.initial.settle_time / self.interval))
        self.stepper = stepper_for(self.engine, self.interval, self.settle_samples)
        self.recorders = check_recorders(recs)
        self.sample = 0  # driven samples done
        self._settled = False
        self._wall = 0.0
        #: driven samples the GPU engine simulated past the record it kept (a run stopped early there)
        self._reached = None
        fps = {r.fps for r in self.recorders if "frames" in r.channels}
        if len(fps) > 1:
            raise ValueError(f"recorders ask for frames at {sorted(fps)} frames/s; one frame rate per run")
        frame_every = max(1, int(round(fs / fps.pop()))) if fps else 0
        self.info = RunInfo(case=case, interval=self.interval, n_samples=self.n_samples,
                            radius=self.bodies.radius, mass=self.bodies.mass, direction=self.engine.drive.direction,
                            gravity=self.engine.drive.gravity, frame_every=frame_every)
        self._channels = set().union(*(r.channels for r in self.recorders)) if self.recorders else set()
        if case.drive.coupled:
            self._channels.add("structure")
        self.samples = self._allocate(self._channels, frame_every)

    # ------------------------------------------------------------------ the state
    @property
    def n(self) -> int:
        """Number of spheres."""
        return self.engine.n

    @property
    def bodies(self):
        """The spheres (:class:`~pdamper.kernels.bundles.Bodies`)."""
        return self.engine.bodies

    @property
    def pairs(self):
        """The Verlet list with its contact history (:class:`~pdamper.kernels.bundles.PairList`)."""
        return self.engine.pairs

    @property
    def walls(self):
        """The walls and sphere-wall contacts (:class:`~pdamper.kernels.bundles.WallList`)."""
        return self.engine.walls

    @property
    def time(self) -> float:
        """Simulated time [s] since the drive started (negative during settling: not started)."""
        return self.sample * self.interval if self._settled else -self.settle_samples * self.interval

    def _allocate(self, channels, frame_every) -> Samples:
        n = self.n_samples if self.n_samples >= 2 else 0
        rows = {c: (n if c in channels else 0) for c in ("wall_force", "energy", "structure")}
        frames = n // frame_every if "frames" in channels and frame_every else 0
        interval = self.stepper.sample_interval
        # a structure's record: its columns, then its modal coordinates (every dof's motion follows)
        modes = self.drive.n_modes if self.case.drive.coupled else 0
        split = NO_SPLIT  # the ledger by contact type: compiled in only when a recorder asks for it
        if "energy_by_contact" in channels:
            k = len(CONTACT_TYPES)
            split = ContactSplit(self.engine.wall_types, np.zeros((k, 3)), np.zeros((k, 2)), np.zeros((k, 2)),
                                 np.zeros((n, k, 2)))
        return Samples(interval=float(interval), wall_force=np.zeros(rows["wall_force"]),
                       energy=np.zeros((rows["energy"], len(ENERGY_COLUMNS))),
                       frames=np.zeros((frames, self.n, FRAME_COLUMNS)), frame_every=int(frame_every),
                       structure=np.zeros((rows["structure"], len(STRUCTURE_COLUMNS) + modes)), sums=np.zeros(4),
                       split=split)

    # ------------------------------------------------------------------ running
    def settle(self) -> None:
        """Let the spheres settle in the still container for ``initial.settle_time`` (whole
        samples, so the drive starts on a sample boundary); then the drive starts."""
        if self._settled:
            return
        if self.n_samples < 2:
            raise InputError(f"run: {self.case.duration:g} s at {self.case.recording.sample_rate:g} Hz gives fewer "
                             "than 2 samples; run longer")
        t0 = _time.perf_counter()
        warmup.start(self.case, self.stepper)  # a cold kernel cache: compile on a second core too
        for r in self.recorders:
            r.start(self.info)
        s = self.settle_samples
        if s:
            self.stepper.advance(self.samples, -s * self.interval, 0.0, False)
        self._start_drive()
        self._settled = True
        self._wall += _time.perf_counter() - t0

    def _start_drive(self) -> None:
        """The drive starts: the spheres keep their lab velocity, so their velocity relative to the
        container jumps by ``-v_c(0+)``; a coupled structure is released; the running sums restart."""
        e = self.engine
        _, v0, _ = self.drive.motion(np.array([0.0]))
        jump = float(v0[0]) * e.drive.direction
        e.bodies.velocity[:] -= jump
        a0 = self.drive.start_state(e.drive.state)
        self.stepper.start_drive(jump, a0)
        self.samples.sums[:] = 0.0
        if "energy_by_contact" in self._channels:
            self.samples.split.sums[:] = 0.0

    def advance(self, n_samples: int | None = None, *, progress=None) -> None:
        """Drive ``n_samples`` more samples (default: to the end of the case's duration), calling
        the Python recorders when due; ``progress(done_fraction)`` after every segment."""
        self.settle()
        t0 = _time.perf_counter()
        end = self.n_samples if n_samples is None else min(self.n_samples, self.sample + int(n_samples))
        seg = max(1, int(SEGMENT * self.case.recording.sample_rate))
        python = [r for r in self.recorders if r.every > 0]
        st = self.stepper
        while self.sample < end:
            stop = min(end, self.sample + seg)
            for r in python:
                stop = min(stop, (self.sample // r.every + 1) * r.every)
            st.advance(self.samples, self.sample * self.interval, stop * self.interval, True)
            self.sample = stop
            due = [r for r in python if stop % r.every == 0]
            if due:
                state = self.state(contacts=any("contacts" in r.channels for r in due))
                for r in due:
                    r.record(state)
            if progress is not None:
                progress(self.sample / self.n_samples)
        self._wall += _time.perf_counter() - t0

    def advance_moved(self, n_samples: int, piece) -> float:
        """One step of the coupling loop (:mod:`pdamper.cosim`), on a case whose drive is the seat of
        the loop (:class:`~pdamper.structure.backend.BedSeat`): the container put where the structure is,
        ``piece[:3]`` = (x [m], v [m/s], a [m/s^2]) now (where its velocity and acceleration differ from
        the kernels' the spheres keep their lab velocity, as at the drive's start), then moved as
        ``piece`` says (:meth:`~pdamper.structure.backend.BedSeat.write_piece`) for ``n_samples``
        samples. Returns the mean force of the walls on the spheres along the drive over them [N]."""
        self.settle()
        e = self.engine
        _, v, a = self.drive.container_motion(self.time, e.drive.state)
        dv, da = float(piece[1]) - float(v), float(piece[2]) - float(a)
        if dv or da:
            d = e.drive.direction
            e.bodies.velocity[:] -= dv * d
            self.stepper.start_drive(dv * d, da)
        k0 = self.sample
        self.drive.write_piece(e.drive, self.time, piece)
        self.advance(n_samples)
        return float(np.mean(self.samples.wall_force[k0:self.sample]))

    def state(self, contacts: bool = False) -> State:
        """The state now, as the Python recorders see it (:class:`~pdamper.recorders.base.State`); with
        ``contacts``, the contacts touching now and their normal forces too (:meth:`contacts`)."""
        e = self.engine
        t = self.time
        xc, vc, ac = self.drive.container_motion(t, e.drive.state)
        b = e.bodies
        sums = self.samples.sums
        views = [a.view() for a in (b.position, b.velocity, b.spin)]
        for v in views:
            v.flags.writeable = False
        return State(sample=self.sample - 1, time=t, position=views[0], velocity=views[1], spin=views[2],
                     container_position=float(np.ravel(xc)[0]), container_velocity=float(np.ravel(vc)[0]),
                     container_acceleration=float(np.ravel(ac)[0]), direction=e.drive.direction,
                     work=float(sums[0]), damping=float(sums[1]), friction=float(sums[2]),
                     contacts=self.contacts() if contacts else None)

    def contacts(self):
        """The contacts touching now, each with its normal force (a
        :class:`~pdamper.recorders.contacts.Contacts`; :func:`pdamper.kernels.forces.touching_contacts`)."""
        from .kernels.forces import touching_contacts
        from .recorders.contacts import Contacts

        e = self.engine
        cap = e.pairs.row[-1] + e.n + e.walls.n_candidates[0]
        ends = np.zeros((cap, 2), dtype=np.int64)
        force = np.zeros(cap)
        kind = np.zeros(cap, dtype=np.int64)
        m = touching_contacts(e.bodies, e.pairs, e.walls, e.table, e.wall_types, ends, force, kind)
        return Contacts(time=self.time, ends=ends[:m], normal_force=force[:m], kind=kind[:m],
                        wall_names=e.wall_names, n_spheres=e.n)

    def finalize(self) -> RunRecord:
        """The recorders' results and how the run went."""
        s = self.samples
        k = self.sample
        channels = {}
        if "wall_force" in self._channels:
            channels["wall_force"] = s.wall_force[:k]
        if "energy" in self._channels:
            channels["energy"] = s.energy[:k]
        if "frames" in self._channels and s.frame_every:
            channels["frames"] = s.frames[: k // s.frame_every]
        if "structure" in self._channels:
            channels["structure"] = s.structure[:k]
        if "energy_by_contact" in self._channels:
            channels["energy_by_contact"] = s.split.record[:k]
        data = Recorded(info=self.info, time_end=(np.arange(k) + 1) * self.interval, channels=channels)
        outputs = {r.name: r.finalize(data) for r in self.recorders}
        st = self.stepper
        # the steps taken over the time they took (a GPU run stopped early went on past its record)
        simulated = k if self._reached is None else self._reached
        return RunRecord(case=self.case, outputs=outputs, steps=st.steps,
                         time_step_s=st.mean_step((self.settle_samples + simulated) * self.interval),
                         wall_time_s=self._wall,
                         neighbour_search=self.engine.search_name, rejected_steps=st.rejected)

    def run(self, *, progress=None) -> RunRecord:
        """Settle, drive for the case's duration, and return what the recorders recorded."""
        self.settle()
        self.advance(progress=progress)
        return self.finalize()

    # ------------------------------------------------------------------ on the GPU
    def _gpu_job(self):
        """This simulation as a job of the GPU engine (:class:`pdamper.engine.cuda.GpuJob`): the
        whole run, settling and drive, with the recorders started; None and a reason when the GPU
        engine does not run it."""
        from .engine.cuda import GpuJob, refusal

        if self._settled or self.sample:
            raise InputError("a simulation that has started on the CPU cannot go on on the GPU")
        why = refusal(self.engine, any(r.every > 0 for r in self.recorders))
        if why is not None:
            return None, why
        if self.n_samples < 2:
            raise InputError(f"run: {self.case.duration:g} s at {self.case.recording.sample_rate:g} Hz gives fewer "
                             "than 2 samples; run longer")
        for r in self.recorders:
            r.start(self.info)
        e = self.engine
        _, v0, _ = self.case.drive.motion(np.array([0.0]))
        st = self.stepper
        num = self.case.numerics
        clock = dict(samples=self.samples, settle_samples=self.settle_samples, n_samples=self.n_samples,
                     interval=self.interval, segment_samples=max(1, int(SEGMENT * self.case.recording.sample_rate)),
                     jump=float(v0[0]) * e.drive.direction)
        if st.rejected is not None:  # Gear
            return GpuJob(engine=e, dt=st.h_next, sub=1, integrator="gear", h0=st.h_next,
                          tolerance=float(num.gear_tolerance), h_min=GEAR_MIN_STEP, h_max=float(num.gear_max_step),
                          **clock), None
        return GpuJob(engine=e, dt=st.dt, sub=st.sub, **clock), None

    def _gpu_done(self, outcome):
        """Take a finished GPU job's outcome: the run is done (or raise its failure)."""
        from .engine.cuda import STATUS_STOPPED
        from .engine.steppers import failure_message
        from .errors import SimulationError
        from .kernels.forces import STATUS_LIST_OVERFLOW, STATUS_OK

        self._settled = True
        self.stepper.primed = True
        self.stepper.steps = outcome.steps
        if self.stepper.rejected is not None:
            self.stepper.rejected = outcome.rejected
            self.stepper.h_next = outcome.h_next
        self._wall = outcome.wall_time_s / max(outcome.batch, 1)
        if outcome.status == STATUS_STOPPED:
            raise SimulationError(f"the GPU batch was stopped at t = {outcome.t_fail:.6f} s, before this case's end")
        if outcome.status == STATUS_LIST_OVERFLOW:
            raise SimulationError(f"sphere {outcome.culprit} has more neighbours than the GPU engine's rows hold "
                                  f"(at t = {outcome.t_fail:.6f} s); run this case on the CPU (device = \"cpu\")")
        if outcome.status != STATUS_OK:
            step = self.stepper.dt if self.stepper.rejected is None else self.stepper.h_next
            raise SimulationError(failure_message(self.case, outcome.status, outcome.culprit, outcome.t_fail, step))
        self.sample = self.n_samples
        if outcome.kept >= 0:  # stopped early (run_jobs' ``steady``): the record ends where it was judged steady
            self.sample = outcome.kept
            self._reached = outcome.reached


def run_on_gpu(sims, *, progress=None, compile_only: bool = False, threads: int | None = None, steady=None) -> list:
    """Run every simulation of ``sims`` to its end together on one GPU (the GPU engine,
    :mod:`pdamper.engine.cuda`): for each, its :class:`RunRecord`, or the
    :class:`~pdamper.errors.SimulationError` of its failed step (the others go on).

    Raises :class:`~pdamper.errors.InputError` when no GPU can run (one line saying why) or when a
    simulation is one the GPU engine does not run (a coupled structure, a sampled drive, a Python
    recorder): before anything runs. ``progress(done, total)`` gets the steps done between
    launches (returning False stops the batch; the unfinished cases end with a SimulationError). ``compile_only``: compile the kernel (a launch with no steps) and return ``[]``.
    ``threads``: threads per block (default: the smallest multiple of 32 that gives each sphere its
    own thread, at most the kernels' largest block). ``steady``: per simulation, None or a judge
    that may stop it early (:class:`pdamper.run.SteadyJudge`; :func:`pdamper.engine.cuda.run_jobs`):
    its record then ends where the judge said.
    """
    from .engine.cuda import require, run_jobs
    from .errors import SimulationError

    require()
    if threads is not None:
        from .kernels.gpu.batch import MAX_WARPS, WARP

        most = MAX_WARPS * WARP
        if not (isinstance(threads, int) and 1 <= threads <= most):
            raise InputError(f"threads = {shown(threads)}: a block of the GPU engine has 1 to {most} threads "
                             "(whole warps, multiples of 32, use the GPU best); leave it out for one warp a 64 spheres")
    jobs = []
    for k, sim in enumerate(sims):
        job, why = sim._gpu_job()
        if why is not None:
            raise InputError(f"case {k} ({shown(sim.case)}): {why}")
        jobs.append(job)
    if not jobs:
        return []
    outcomes = run_jobs(jobs, progress=progress, compile_only=compile_only, threads=threads, steady=steady)
    if compile_only:
        return []
    out = []
    for sim, o in zip(sims, outcomes):
        try:
            sim._gpu_done(o)
            out.append(sim.finalize())
        except SimulationError as exc:
            out.append(exc)
    return out


def run_bare_structure(structure, duration: float, *, sample_rate: float = 1000.0,
                       time_step: float | None = None) -> StructureRecord:
    """The structure of ``structure`` (a :class:`~pdamper.structure.CoupledStructure` or
    :class:`~pdamper.structure.ModalStructure`) without a bed, for ``duration`` [s]: the same
    compiled step as the coupled runs (:func:`pdamper.kernels.structure.structure_step`) with no
    wall force.

    ``time_step`` [s] defaults to a tenth of the sample interval (and at most 1/2000 of the
    shortest period). Returns a :class:`~pdamper.recorders.structure.StructureRecord`.
    """
    from .engine.build import drive_bundle
    from .kernels.structure import run_structure_alone

    if not (duration > 0 and math.isfinite(duration)):
        raise InputError(f"duration = {shown(duration)} s; must be > 0")
    ts = 1.0 / sample_rate
    fmax = structure.highest_frequency
    dt = time_step if time_step is not None else min(ts / 10, 1.0 / (2000.0 * fmax))
    sub = max(1, int(math.ceil(ts / dt - 1e-9)))
    dt = ts / sub
    n = int(math.floor(duration * sample_rate + 1e-9))
    drive = drive_bundle(structure)
    structure.start_state(drive.state)
    out = np.zeros((n, len(STRUCTURE_COLUMNS) + structure.n_modes))
    run_structure_alone(n * sub, dt, 0.0, sub, drive, out)
    return StructureRecord.from_array(structure, (np.arange(n) + 1) * ts, out)


# short reprs: names, shapes and key numbers (a notebook shows a line, not a dump)
RunRecord.__repr__ = short_repr
