"""The GPU engine from Python: cases packed into one batch, advanced together on one NVIDIA GPU
(:mod:`pdamper.kernels.gpu`), their recorded channels handed back.

A :class:`GpuJob` is one case as the CPU engine has built it (:func:`pdamper.engine.build.build`:
the same initial positions, contact table and walls), with its output arrays
(:class:`~pdamper.kernels.bundles.Samples`) and its clock. :func:`run_jobs` groups the jobs that one
launch can take together (the same integrator, damping law, contact-table constants and block size),
packs each group into the batch bundles (:mod:`pdamper.kernels.gpu.batch`), launches the groups'
kernels side by side (:mod:`pdamper.kernels.gpu.gear`, :mod:`pdamper.kernels.gpu.verlet`) until
every case is done, and copies each case's channels and final state back into its own arrays.

numba-cuda is imported here only when a batch runs: ``import pdamper`` never needs it.
:func:`unavailable` says why no GPU can run (no numba-cuda, no driver, no device).
"""

from __future__ import annotations

import math
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError
from ..kernels.contact import keeps_history
from ..kernels.drive import is_parametric
from ..kernels.gpu.batch import (F_H, F_INTERVAL, F_T, I_CULPRIT, I_FAIL_STEP, I_FLOOR, I_N, I_NW, I_REJECTED,
                                 I_SAMPLES, I_SEG_SAMPLES, I_SEG_STEPS, I_SETTLE_SAMPLES, I_SETTLE_STEPS, I_SPAN,
                                 I_SPANS, I_STATUS, I_STEP, I_SUB, I_TIME, I_TOTAL_STEPS)

__all__ = ["GpuJob", "GpuOutcome", "run_jobs", "STATUS_STOPPED", "unavailable", "require", "refusal", "takes",
           "row_capacity", "pair_capacity", "threads_for", "kernel_arguments", "kernel_for", "GPU_HINT"]

#: How to get the GPU engine, for messages.
GPU_HINT = 'pip install -e ".[gpu]"'
#: :attr:`GpuOutcome.status` of a case whose batch was stopped (``progress`` returned False) before its end.
STATUS_STOPPED = -1
#: The status :func:`run_jobs` gives a case on the GPU that its judge stopped early (``steady``): the
#: kernels skip a case whose status is not 0. Its outcome says 0, with the samples it keeps.
STATUS_JUDGED = -2


@dataclass
class GpuJob:
    """One case for the GPU: its CPU-built engine (:class:`~pdamper.engine.build.Engine`), its
    output arrays and its clock (Verlet's ``dt`` and ``sub`` steps per sample, the settling and
    driven samples, the sample interval, the samples of one of the CPU engine's segments) and the
    velocity jump at the drive's start."""

    engine: object
    samples: object
    dt: float
    sub: int
    settle_samples: int
    n_samples: int
    interval: float
    segment_samples: int
    jump: np.ndarray
    #: "verlet" or "gear"; Gear's first step, tolerance, shortest and longest step [s, m, s, s]
    integrator: str = "verlet"
    h0: float = 0.0
    tolerance: float = 0.0
    h_min: float = 0.0
    h_max: float = 0.0


@dataclass
class GpuOutcome:
    """How a job went: steps taken, the kernels' status (0: ok), the sphere concerned, the time of a
    failed step [s], the batch's wall time [s] and the batch's size."""

    steps: int
    status: int
    culprit: int
    t_fail: float
    wall_time_s: float
    batch: int
    sums: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rejected: int = 0
    h_next: float = math.nan
    #: a case stopped early by its judge (``run_jobs(steady=)``): the driven samples its record keeps,
    #: and the driven samples it had simulated when the judge was asked (-1: not stopped early)
    kept: int = -1
    reached: int = -1


def numpy_aliases_for_numba_cuda() -> None:
    """Give numpy >= 2.5 back ``np.row_stack`` (an alias of ``np.vstack`` until numpy 2.4) when
    numba-cuda is about to load.

    numba-cuda 0.30.4 registers a CUDA overload of ``np.row_stack`` for every numpy >= 2.0 when it
    first compiles a kernel (``numba/cuda/np/arrayobj.py``); numpy 2.5 removed the name, so every
    compile failed with ``AttributeError: module 'numpy' has no attribute 'row_stack'`` (measured on
    the GPU machine: numpy 2.5.2, numba 0.68.0, numba-cuda 0.30.4). numba itself guards the same line
    by numpy's version. The alias is the function numpy <= 2.4 had under that name; nothing else is
    changed, and nothing when numpy has the name."""
    if not hasattr(np, "row_stack"):
        np.row_stack = np.vstack


def unavailable() -> str | None:
    """Why the GPU engine cannot run here (None: it can): numba-cuda missing, or no GPU. numba-cuda's
    simulator (``NUMBA_ENABLE_CUDASIM=1``) counts as a GPU."""
    import importlib.util

    if importlib.util.find_spec("numba_cuda") is None:
        return "numba-cuda is not installed"
    numpy_aliases_for_numba_cuda()
    try:
        from numba import cuda

        if cuda.jit.__module__.startswith("numba.cuda.simulator"):
            return None
        if not cuda.is_available():
            return "no CUDA driver or GPU (numba.cuda.is_available() is False)"
    except Exception as exc:  # a broken driver or toolkit: say what numba-cuda said
        return f"{type(exc).__name__}: {' '.join(str(exc).split())[:200]}"
    return None


def require() -> None:
    """Raise :class:`~pdamper.errors.InputError` (one line) when the GPU engine cannot run here."""
    why = unavailable()
    if why is not None:
        raise InputError(f"--device cuda needs an NVIDIA GPU and numba-cuda ({GPU_HINT}); none found: {why}")


def refusal(engine, python_recorders: bool = False) -> str | None:
    """Why the GPU engine does not run this case (None: it does), and how to run it on the CPU."""
    how = "; run it on the CPU (device = \"cpu\", the default)"
    if not is_parametric(engine.drive.kind):  # the kernels move the container by (kind, parameters, t) alone
        return ("the GPU engine runs harmonic drives (and a container at rest); a coupled structure or a motion "
                "given as samples is not on the GPU yet" + how)
    if python_recorders:
        return "the GPU engine records the kernel channels only; a Python recorder (every > 0) is not on the GPU" + how
    return None


def takes(case) -> bool:
    """Whether the GPU engine takes ``case``'s bed: one block holds at most
    :data:`~pdamper.kernels.gpu.batch.MAX_SPHERES` spheres (their hot state in its 48 KB of shared
    memory). A larger bed runs on the CPU engine (:func:`pdamper.run.run_cases` says so): the one
    large bed measured on a GPU, 5,000 spheres in one block of the kernel before this one, took
    2,068 ns per particle-step against the CPU engine's 48.8 (docs/performance.md)."""
    from ..kernels.gpu.batch import MAX_SPHERES

    return case.n_particles <= MAX_SPHERES


def row_capacity(radius: np.ndarray, skin: float) -> int:
    """Entries per sphere of the GPU's neighbour rows: the spheres of the smallest radius that fit,
    packed at 74 %, in the shell a pair is listed within around the largest one (and at most the
    other spheres), plus two."""
    r1 = float(np.max(radius))
    r0 = float(np.min(radius))
    shell = (r1 + 2.0 * r0 + skin) ** 3 - r1 ** 3
    k = int(math.ceil(0.74 * shell / r0 ** 3)) + 2
    return max(1, min(int(radius.size) - 1, k))


#: The interpreter's thread switch interval [s] during a launch in numba-cuda's simulator. The simulator
#: runs each GPU thread as a Python thread, and its scheduler thread polls them, holding the
#: interpreter until its switch interval ends, whenever they wait at a barrier; at Python's default
#: (5 ms) every barrier costs milliseconds (the agree part's Gear run of 37 steps: 21.5 s in all, 4.4 s
#: at this interval). Restored after the launch.
SIMULATOR_SWITCH_S = 1e-4


def threads_for(n: int) -> int:
    """Threads of a block for ``n`` spheres: one warp for up to 64 spheres, a warp more for every 64
    beyond (each lane takes two spheres in a step's sphere passes, and the pairs in its pair pass), at
    most :data:`~pdamper.kernels.gpu.batch.MAX_WARPS` warps. In numba-cuda's simulator, where every
    thread is a Python thread, at most 4."""
    from ..kernels.gpu.batch import MAX_WARPS, SPHERES_PER_LANE, WARP
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return int(max(1, min(n, 4)))
    return int(WARP * min(MAX_WARPS, max(1, math.ceil(n / (WARP * SPHERES_PER_LANE)))))


def _group_key(job):
    t = job.engine.table
    return (job.integrator, type(t.law), type(t.tangential), t.coefficient.shape[1], float(t.log_speed0),
            float(t.dlog_speed), float(t.tau), float(t.v_floor), float(t.overlap_limit))


def launch_cycles(seconds: float) -> int:
    """``seconds`` of a launch as its blocks' clocks count them: cycles of the GPU's rated clock
    (the multiprocessors' counter runs at the clock of the moment, which boost and throttling move by
    some percent: a launch's length, not a measurement; 2 GHz if the driver does not say), the
    host's nanoseconds in numba-cuda's simulator (:func:`pdamper.kernels.gpu.warp.clock`)."""
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return max(1, int(seconds * 1e9))
    try:
        from numba import cuda

        khz = float(cuda.get_current_device().CLOCK_RATE)
    except Exception:  # noqa: BLE001  (an attribute newer drivers may drop: a length, not a figure)
        khz = 2e6
    return max(1, int(seconds * 1e3 * khz))


def run_jobs(jobs, *, threads: int | None = None, launch_seconds: float = 2.0, max_launch_steps: int = 10**9,
             progress=None, compile_only: bool = False, steady=None) -> list[GpuOutcome]:
    """Run every job to its end on the GPU (or numba-cuda's simulator); fill its samples and leave
    its final state in its engine's bodies.

    The jobs are grouped by what one launch can take together (the integrator, the laws and the
    contact table's constants, and the block size: a 36-sphere bed does not wait in a block sized
    for 176 spheres); each group is one batch on its own CUDA stream, its cases in the order given
    (the studies give the longest first, so they start first), and the groups' launches run side by
    side. ``threads`` per block (default :func:`threads_for` each group's largest bed);
    ``launch_seconds``: a launch's length after the first (which takes 200 steps of every case): each
    block stops at the step on which its clock has run that long (:func:`launch_cycles`), so every
    case takes as many steps as its own step's cost allows instead of all waiting for the slowest;
    after each round ``progress(done, total)`` is called with the steps done (a finished or failed
    case counts whole, so the last call says ``done == total``), and returning False stops: the
    unfinished cases end with :data:`STATUS_STOPPED`. ``max_launch_steps`` caps the steps of a
    launch. ``compile_only``: launch once with no steps (compiles the kernel) and return.

    ``steady``: per job, None or a judge that may stop it early (:class:`pdamper.run.SteadyJudge`:
    ``judge.next_samples()``, the driven samples it needs next; ``judge(wall_force)``, the samples
    to keep or None). After each round every case that has recorded what its judge needs (and has
    not failed) is judged on its record so far; one it stops is skipped by the next launches, and
    its outcome keeps that many samples (``kept``; ``reached``: how far it had gone). The judge sees
    the record the CPU engine's run would have had at each of its points, so the case stops where
    the CPU engine's would, only its last launch's steps past that point are spent for nothing.
    """
    groups = {}
    for k, job in enumerate(jobs):
        key = _group_key(job) + (threads or threads_for(job.engine.n),)
        groups.setdefault(key, []).append(k)
    batches = [_Batch([jobs[k] for k in idx], threads or key[-1],
                      None if steady is None else [steady[k] for k in idx]) for key, idx in groups.items()]
    t_start = time.perf_counter()
    if compile_only:
        for b in batches:
            b.launch(0)
        _sync()
        return [GpuOutcome(steps=0, status=0, culprit=-1, t_fail=math.nan, wall_time_s=time.perf_counter() - t_start,
                           batch=len(jobs)) for _ in jobs]
    timed = launch_cycles(launch_seconds)  # (a launch after the first: bounded by time and max_launch_steps)
    chunk, cycles = min(200, max_launch_steps), 0
    while True:
        live = [b for b in batches if not b.finished]
        for b in live:
            b.launch(chunk, cycles)
        _sync()
        for b in live:
            b.poll()
        finished = all(b.finished for b in batches)
        if progress is not None:
            done = sum(b.progress() for b in batches)
            if progress(done, sum(int(b.total.sum()) for b in batches)) is False and not finished:
                break  # the caller stops the batch: the unfinished cases say so
        if finished:
            break
        chunk, cycles = max_launch_steps, timed
    wall = time.perf_counter() - t_start
    out = [None] * len(jobs)
    for b, idx in zip(batches, groups.values()):
        for k, r in zip(idx, b.unpack(wall, len(jobs))):
            out[k] = r
    return out


def kernel_for(integrator: str):
    """The batch kernel of ``integrator`` ("gear" or "verlet"; chosen once, as the CPU engine's
    :func:`pdamper.engine.steppers.stepper_for` chooses its stepper)."""
    from ..kernels.gpu.gear import gear_kernel
    from ..kernels.gpu.verlet import verlet_kernel

    return {"gear": gear_kernel, "verlet": verlet_kernel}[integrator]()


class _Batch:
    """One group of jobs packed for one kernel: its buffers on the GPU, its stream, its progress."""

    def __init__(self, jobs, threads, judges=None):
        from ..kernels.gpu.targets import SIMULATOR

        self.jobs = jobs
        self.judges = judges
        bt, tb, self.bd, self.shared = _pack(jobs, threads)
        self.gear = jobs[0].integrator == "gear"
        self.ci = bt.ci.copy()
        self.total = self.ci[:, I_SPANS].copy() if self.gear else self.ci[:, I_TOTAL_STEPS].copy()
        self.done = np.zeros_like(self.total)
        self.status = np.zeros_like(self.total)
        #: per case, the driven samples its judge kept (-1: none) and those it had reached then
        self.kept = np.full(len(jobs), -1, dtype=np.int64)
        self.reached = np.full(len(jobs), -1, dtype=np.int64)
        self.finished = False
        self.stream = None if SIMULATOR else _stream()
        #: the batch's buffers on the GPU (:class:`pdamper.kernels.gpu.batch.Batch`)
        self.bt = _device_batch(bt)
        table = jobs[0].engine.table
        self.args = (self.bt, _device_tuple(tb), table.law, table.tangential)
        self.kernel = kernel_for(jobs[0].integrator)

    def launch(self, steps, cycles=0):
        """Every case at most ``steps`` further, and with ``cycles`` > 0 no further than the step on
        which its block's clock has run that many cycles (:func:`launch_cycles`)."""
        C = len(self.jobs)
        if self.stream is None:  # numba-cuda's simulator: its threads switch at every barrier (SIMULATOR_SWITCH_S)
            old = sys.getswitchinterval()
            sys.setswitchinterval(min(old, SIMULATOR_SWITCH_S))
            try:
                self.kernel[C, self.bd, 0, self.shared](*self.args, int(steps), int(cycles))
            finally:
                sys.setswitchinterval(old)
        else:
            self.kernel[C, self.bd, self.stream, self.shared](*self.args, int(steps), int(cycles))

    def poll(self):
        """Each case's progress and status after a launch; the cases' judges asked (:meth:`judge`)."""
        self.ci = _host(self.bt.ci).copy()
        self.done = self.ci[:, I_SPAN if self.gear else I_STEP].copy()
        self.status = self.ci[:, I_STATUS].copy()
        self.judge()
        self.done = np.where(self.kept >= 0, self.total, self.done)
        self.finished = bool(np.all((self.done >= self.total) | (self.status != 0)))

    def progress(self) -> int:
        """The batch's steps (Gear: spans) done, a finished or failed case counted whole."""
        return int(np.where(self.status != 0, self.total, np.minimum(self.done, self.total)).sum())

    def recorded(self):
        """Per case, the driven samples whose record is complete now: up to its clock (Gear: a step
        that reaches a sample's end records it, but a failed step that reaches one does not: one
        less) or its steps (Verlet: up to its last whole sample before a failed step)."""
        n = np.array([j.n_samples for j in self.jobs], dtype=np.int64)
        if self.gear:
            ts = np.array([j.interval for j in self.jobs])
            rows = np.floor(_host(self.bt.cf)[:, F_T] / ts + 1e-6).astype(np.int64) - (self.status > 0)
        else:
            ci = self.ci
            steps = np.where(self.status > 0, ci[:, I_FAIL_STEP] - 1, ci[:, I_STEP])
            rows = (steps - ci[:, I_SETTLE_STEPS]) // ci[:, I_SUB]
        return np.clip(rows, 0, n)

    def judge(self):
        """Ask each case's judge (``run_jobs(steady=)``) about its record so far, and stop the cases
        it says are steady: a running one by a status the kernels skip (:data:`STATUS_JUDGED`), a
        finished or failed one by keeping the record up to there."""
        if self.judges is None:
            return
        rows = self.recorded()
        out = None
        stop = []
        for c, judge in enumerate(self.judges):
            if judge is None or self.kept[c] >= 0:
                continue
            need = judge.next_samples()
            if need >= judge.n_samples or rows[c] < need:
                continue
            if out is None:
                out = _host(self.bt.out)
            kept = judge(np.array(out[c, : rows[c]]))
            if kept is not None:
                self.kept[c], self.reached[c] = kept, rows[c]
                if self.status[c] == 0 and self.done[c] < self.total[c]:
                    stop.append(c)
        if stop:
            self.status[stop] = STATUS_JUDGED
            self.ci[stop, I_STATUS] = STATUS_JUDGED
            _to_device(self.bt.ci, self.ci)

    def snapshot(self, c):
        """Case ``c`` as the CPU engine's arrays hold it (for the tests): positions, velocities and
        spins (n, 3), Gear's Nordsieck vector (6, n, 6), the walls' tangential springs of the current
        history (n, W, 5), the touching pairs with friction of the last step in the pair list's order
        (k, 2) with their rows (normal, slip, c, limit: (k, 8)) and their levels in Gear's walk (k,),
        the steps, the rejected steps, the clock, the step and the threads' running sums."""
        from types import SimpleNamespace

        from ..kernels.gpu import batch as lay

        st, gv, iv, cf = (_host(a)[c] for a in (self.bt.st, self.bt.gv, self.bt.iv, self.bt.cf))
        ci = _host(self.bt.ci)[c]
        n, N, W, P = (int(ci[k]) for k in (I_N, lay.O_N, lay.O_W, lay.O_P))
        lb, tk = int(ci[lay.I_LIST]), int(ci[I_TIME])

        def field(f, k):
            return st[f * N:(f + k) * N].reshape(k, N)[:, :n].T.copy()

        nord = st[lay.NORD * N:(lay.NORD + 36) * N].reshape(6, 6, N)[:, :, :n].transpose(0, 2, 1).copy()
        tw = int(ci[lay.O_TW])
        at = int(ci[lay.O_TWALL]) + tk * tw
        th = _host(self.bt.th)[c]
        springs = th[at:at + tw].reshape(N, W, 5)[:n].copy() if tw > 1 else np.zeros((n, W, 5))
        npairs = int(iv[int(ci[lay.O_ROW]) + lb * (N + 1) + n])
        v = gv[int(ci[lay.O_PV]) + (lb * 2 + tk) * P:][:npairs]
        res = gv[int(ci[lay.O_RES]):int(ci[lay.O_RES]) + lay.RESULT * P].reshape(lay.RESULT, P)[:, :npairs]
        touching = np.flatnonzero((v != 0.0) & (res[lay.R_C] > 0.0))
        ends = np.stack([iv[int(ci[lay.O_FIRST]) + lb * P + touching], iv[int(ci[lay.O_SEC]) + lb * P + touching]], 1)
        rows = np.concatenate([res[lay.R_N:lay.R_N + 3], res[lay.R_S:lay.R_LIM + 1]])[:, touching].T.copy()
        levels = iv[int(ci[lay.O_LEVEL]):int(ci[lay.O_LEVEL]) + touching.size].copy()
        sums = cf[lay.F_PARTIALS:lay.F_PARTIALS + 2 * lay.PARTIALS * self.bd].copy()
        return SimpleNamespace(position=field(lay.X, 3), velocity=field(lay.V, 3), spin=field(lay.SPIN, 3),
                               nordsieck=nord, wall_springs=springs, pairs=ends, pair_rows=rows, levels=levels,
                               steps=int(ci[I_STEP]), rejected=int(ci[I_REJECTED]), partials=sums,
                               time=float(cf[F_T]), step=float(cf[lay.F_HS]))

    def unpack(self, wall, batch):
        """Each job's channels, final state and outcome."""
        from ..kernels.gpu import batch as lay

        st, ci, cf, out = (_host(a) for a in (self.bt.st, self.bt.ci, self.bt.cf, self.bt.out))
        result = []
        for c, job in enumerate(self.jobs):
            e = job.engine
            n, N = e.n, int(ci[c, lay.O_N])
            s = job.samples
            s.wall_force[:] = out[c, : s.wall_force.shape[0]]
            at = int(ci[c, lay.O_ENERGY])
            s.energy[:] = out[c, at:at + 7 * s.energy.shape[0]].reshape(-1, 7)
            if s.frames.shape[0]:
                at = int(ci[c, lay.O_FRAMES])
                s.frames[:] = out[c, at:at + s.frames.shape[0] * N * 9].reshape(-1, N, 9)[:, :n]
            for name, f in (("position", lay.X), ("velocity", lay.V), ("spin", lay.SPIN)):
                getattr(e.bodies, name)[:] = st[c, f * N:(f + 3) * N].reshape(3, N)[:, :n].T
            sums = cf[c, lay.F_PARTIALS:lay.F_PARTIALS + lay.PARTIALS * self.bd].reshape(-1, lay.PARTIALS).sum(axis=0)
            s.sums[:3] = sums[:3]
            status = int(ci[c, I_STATUS])
            kept = dict(kept=int(self.kept[c]), reached=int(self.reached[c]))
            judged = self.kept[c] >= 0
            if judged:  # stopped early by its judge, before any failure after that point
                status = 0
            done = ci[c, I_SPAN] if self.gear else ci[c, I_STEP]
            if status == 0 and not judged and done < self.total[c]:
                status = STATUS_STOPPED
            if self.gear:
                result.append(GpuOutcome(steps=int(ci[c, I_STEP]), status=status, culprit=int(ci[c, I_CULPRIT]),
                                         t_fail=float(cf[c, F_T]), wall_time_s=wall, batch=batch, sums=sums[:3],
                                         rejected=int(ci[c, I_REJECTED]), h_next=float(cf[c, F_H]), **kept))
                continue
            fail = int(ci[c, I_FAIL_STEP]) if status != STATUS_STOPPED else int(ci[c, I_STEP])
            result.append(GpuOutcome(steps=int(ci[c, I_STEP]), status=status, culprit=int(ci[c, I_CULPRIT]),
                                     t_fail=_time_of(job, fail), wall_time_s=wall, batch=batch, sums=sums[:3],
                                     **kept))
        return result


def kernel_arguments(jobs, threads: int | None = None):
    """The arguments of one batch's kernel (:func:`pdamper.kernels.gpu.verlet.batch_verlet`, or
    :func:`pdamper.kernels.gpu.gear.batch_gear` for Gear's jobs) on the host, less the steps of the
    launch: the batch's buffers, the contact table's arrays and constants, the damping and
    tangential laws' markers (one group's: :func:`run_jobs` groups by them); and the block size and
    its dynamic shared memory [B]."""
    bt, tb, bd, shared = _pack(jobs, threads)
    table = jobs[0].engine.table
    return [bt, tb, table.law, table.tangential], bd, shared


def pair_capacity(n: int, k: int) -> int:
    """Pairs a case's list holds: every sphere with ``k`` partners at most (:func:`row_capacity`),
    each pair counted once, and no more than all pairs of ``n`` spheres."""
    return max(1, min(n * (n - 1) // 2, -(-n * k // 2)))


def _pack(jobs, threads):
    """The batch's buffers on the host (:mod:`pdamper.kernels.gpu.batch`), the contact table's
    arrays and constants, the block size and its dynamic shared memory [B]."""
    from ..kernels.gpu import batch as lay
    from ..kernels.gpu.targets import SIMULATOR

    C = len(jobs)
    engines = [j.engine for j in jobs]
    N = max(e.n for e in engines)
    W = max(e.walls.kind.shape[0] for e in engines)
    P = max(pair_capacity(e.n, row_capacity(e.bodies.radius, e.search.skin)) for e in engines)
    bd = threads or threads_for(N)
    spring = keeps_history(engines[0].table.tangential)
    S = max(1, max(max(j.samples.wall_force.shape[0], j.samples.energy.shape[0]) for j in jobs))
    F = max(1, max(j.samples.frames.shape[0] for j in jobs))
    o = lay.layout(N, P, W, spring, S, F)
    widths = lay.row_widths(N, bd)
    st = np.zeros((C, widths["st"]))
    gv = np.zeros((C, o["gv"]))
    th = np.zeros((C, o["th"], 5))
    iv = np.zeros((C, o["iv"]), dtype=np.int32)
    ci = np.zeros((C, widths["ci"]), dtype=np.int64)
    cf = np.zeros((C, widths["cf"]))
    walls = np.zeros((C * W, 7))
    st[:, lay.RAD * N:(lay.IINERT + 1) * N] = 1.0  # (padding spheres: never read)
    st[:, lay.REF * N:(lay.REF + 3) * N] = np.inf
    gv[:, o[lay.O_WRS]:o[lay.O_WRS] + W * N] = 1.0
    row = 0
    for c, (job, e) in enumerate(zip(jobs, engines)):
        b, n, w = e.bodies, e.n, e.walls
        nw = w.kind.shape[0]
        for f, a in ((lay.X, b.position), (lay.V, b.velocity), (lay.SPIN, b.spin)):
            st[c, f * N:(f + 3) * N].reshape(3, N)[:, :n] = a.T
        for f, a in ((lay.RAD, b.radius), (lay.MASS, b.mass), (lay.IMASS, b.inv_mass), (lay.IINERT, b.inv_inertia)):
            st[c, f * N:f * N + n] = a
        iv[c, o[lay.O_MAT]:o[lay.O_MAT] + n] = b.material
        iv[c, o[lay.O_WKIND]:o[lay.O_WKIND] + nw] = w.kind
        walls[c * W:c * W + nw] = w.data
        for slot, a in ((lay.O_WK, w.stiffness), (lay.O_WRS, w.effective_radius)):
            gv[c, o[slot]:o[slot] + W * N].reshape(W, N)[:nw, :n] = a.T
        iv[c, o[lay.O_WMP]:o[lay.O_WMP] + W * N].reshape(W, N)[:nw, :n] = (w.material_pair + row).T
        settle = job.settle_samples * job.sub
        ci[c, [I_N, I_NW, I_FLOOR, I_CULPRIT, I_SUB, I_SETTLE_STEPS, I_TOTAL_STEPS, I_SEG_STEPS, I_SEG_SAMPLES,
               lay.I_WF_ROWS, lay.I_EN_ROWS, lay.I_FR_ROWS, lay.I_FRAME_EVERY, I_SETTLE_SAMPLES, lay.I_NMAT, lay.I_ROW0,
               lay.I_DRIVE, I_SPANS, I_SAMPLES]] = (
            n, nw, w.floor, -1, job.sub, settle, settle + job.n_samples * job.sub, job.segment_samples * job.sub,
            job.segment_samples, job.samples.wall_force.shape[0], job.samples.energy.shape[0],
            job.samples.frames.shape[0], job.samples.frame_every, job.settle_samples, e.table.n_materials, row,
            e.drive.kind, int(job.settle_samples > 0) - (-job.n_samples // job.segment_samples), job.n_samples)
        for slot in [k for k in o if isinstance(k, int)]:
            ci[c, slot] = o[slot]
        cf[c, [lay.F_DT, F_INTERVAL, lay.F_SAMPLE_INTERVAL, lay.F_SKIN, lay.F_BED_MASS, F_T, F_H, lay.F_HS, lay.F_TOL,
               lay.F_H_MIN, lay.F_H_MAX]] = (
            job.dt, job.interval, job.samples.interval, e.search.skin, float(np.sum(b.mass)),
            float(-job.settle_samples) * job.interval if job.settle_samples > 0 else 0.0, job.h0, job.h0,
            job.tolerance, job.h_min, job.h_max)
        cf[c, lay.F_GRAVITY:lay.F_GRAVITY + 3] = e.drive.gravity
        cf[c, lay.F_DIRECTION:lay.F_DIRECTION + 3] = e.drive.direction
        cf[c, lay.F_JUMP:lay.F_JUMP + 3] = job.jump
        cf[c, lay.F_PAR:lay.F_PAR + 3] = np.resize(np.asarray(e.drive.par, dtype=float), 3)
        row += e.table.modulus.shape[0]
    tables = [e.table for e in engines]
    t0 = tables[0]
    tb = (np.concatenate([t.modulus for t in tables]), np.concatenate([t.shear_modulus for t in tables]),
          np.concatenate([t.friction for t in tables]), np.ascontiguousarray(np.concatenate([t.coefficient for t in tables])),
          np.ascontiguousarray(np.concatenate([t.tangential_damping for t in tables])),
          np.concatenate([t.yield_pressure for t in tables]), float(t0.log_speed0), float(t0.dlog_speed),
          float(t0.tau), float(t0.v_floor), float(t0.overlap_limit))
    # the recorded channels: allocated on the GPU, not copied (every row a case records is written
    # before it is read): here only their shape
    out = np.zeros((C, o["out"])) if SIMULATOR else np.lib.stride_tricks.as_strided(np.zeros(1), (C, o["out"]), (0, 0))
    shared = 8 * lay.SHARED_FIELDS * N
    return lay.Batch(st=st, gv=gv, th=th, iv=iv, ci=ci, cf=cf, walls=walls, out=out), tb, bd, shared


def _time_of(job, g):
    """The time [s] at the end of step ``g`` (the kernel's clock, :func:`pdamper.kernels.gpu.verlet.case_time`)."""
    settle = job.settle_samples * job.sub
    if g <= settle:
        return float(-settle) * job.dt + float(g) * job.dt
    q = g - settle
    seg = job.segment_samples * job.sub
    j = (q - 1) // seg
    return float(j * job.segment_samples) * job.interval + float(q - j * seg) * job.dt


def _stream():
    from numba import cuda

    return cuda.stream()


def _device_batch(bt):
    """The batch's buffers on the GPU (in the simulator: as they are; the simulator passes a bundle's
    arrays to the kernel untouched, so the CPU-compiled functions the kernel calls get plain
    arrays); the recorded channels allocated there, not copied."""
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return bt
    from numba import cuda

    return type(bt)(*[cuda.device_array(a.shape, dtype=a.dtype) if name == "out" else cuda.to_device(a)
                      for name, a in zip(bt._fields, bt)])


def _host(a):
    return a if isinstance(a, np.ndarray) else a.copy_to_host()


def _to_device(dev, host):
    """Write the host array ``host`` into ``dev`` (a buffer on the GPU; in the simulator the same
    array)."""
    if isinstance(dev, np.ndarray):
        if dev is not host:
            dev[:] = host
    else:
        dev.copy_to_device(np.ascontiguousarray(host, dtype=dev.dtype))


def _device_tuple(tb):
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return tb
    from numba import cuda

    return tuple(cuda.to_device(a) if isinstance(a, np.ndarray) else a for a in tb)


def _sync():
    from ..kernels.gpu.targets import SIMULATOR

    if not SIMULATOR:
        from numba import cuda

        cuda.synchronize()
