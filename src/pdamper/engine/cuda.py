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
from ..kernels.bundles import SAVED_HISTORY_ROWS, TANGENTIAL_COLUMNS
from ..kernels.contact import keeps_history
from ..kernels.drive import is_parametric

__all__ = ["GpuJob", "GpuOutcome", "run_jobs", "STATUS_STOPPED", "unavailable", "require", "refusal", "row_capacity",
           "threads_for", "kernel_arguments", "GPU_HINT"]

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
    #: under ``run_jobs(probe=True)``: the probed Gear kernel's cycles in each phase of a step, then
    #: its counts (:mod:`pdamper.kernels.gpu.probe`); empty otherwise
    cycles: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
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


def refusal(engine, python_recorders: bool = False, gear: bool = False) -> str | None:
    """Why the GPU engine does not run this case (None: it does), and how to run it on the CPU.
    ``gear``: the case runs Gear's integrator."""
    from ..kernels.gpu.targets import SIMULATOR

    how = "; run it on the CPU (device = \"cpu\", the default)"
    if not is_parametric(engine.drive.kind):  # the kernels move the container by (kind, parameters, t) alone
        return ("the GPU engine runs harmonic drives (and a container at rest); a coupled structure or a motion "
                "given as samples is not on the GPU yet" + how)
    if python_recorders:
        return "the GPU engine records the kernel channels only; a Python recorder (every > 0) is not on the GPU" + how
    if gear and keeps_history(engine.table.tangential) and not SIMULATOR:
        # the same kernel runs right in numba-cuda's simulator (tests/kernels/gpu); on a GPU it writes out of
        # bounds in its first launch (compute-sanitizer on an H200, 2026-11-26: docs/performance.md)
        return ("Gear's GPU kernel with the tangential spring (contact.tangential = \"spring\") is refused: on a GPU "
                "it faults (an out-of-bounds write, not yet found); run it on the GPU with numerics.integrator = "
                "\"verlet\", or on the CPU (device = \"cpu\", the default)")
    return None


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
    """Threads of a block for ``n`` spheres: one a sphere, whole warps, at most
    :data:`~pdamper.kernels.gpu.verlet.MAX_THREADS` (each thread then takes several). In numba-cuda's
    simulator, where every thread is a Python thread, at most 4."""
    from ..kernels.gpu.targets import SIMULATOR
    from ..kernels.gpu.verlet import MAX_THREADS

    if SIMULATOR:
        return int(max(1, min(n, 4)))
    return int(min(MAX_THREADS, max(32, 32 * math.ceil(n / 32))))


def _group_key(job):
    t = job.engine.table
    return (job.integrator, type(t.law), type(t.tangential), t.coefficient.shape[1], float(t.log_speed0),
            float(t.dlog_speed), float(t.tau), float(t.v_floor), float(t.overlap_limit))


def launch_cycles(seconds: float) -> int:
    """``seconds`` of a launch as its blocks' clocks count them: cycles of the GPU's rated clock
    (the multiprocessors' counter runs at the clock of the moment, which boost and throttling move by
    some percent: a launch's length, not a measurement; 2 GHz if the driver does not say), the
    host's nanoseconds in numba-cuda's simulator (:func:`pdamper.kernels.gpu.probe.clock`)."""
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
             progress=None, compile_only: bool = False, probe: bool = False, steady=None) -> list[GpuOutcome]:
    """Run every job to its end on the GPU (or numba-cuda's simulator); fill its samples and leave
    its final state in its engine's bodies.

    The jobs are grouped by what one launch can take together (the damping law and the contact
    table's constants, and the block size: a 36-sphere bed does not wait in a block sized for 176
    spheres); each group is one batch on its own CUDA stream, and the groups' launches run side by
    side. ``threads`` per block (default :func:`threads_for` each group's largest bed);
    ``launch_seconds``: a launch's length after the first (which takes 200 steps of every case): each
    block stops at the step on which its clock has run that long (:func:`launch_cycles`), so every
    case takes as many steps as its own step's cost allows instead of all waiting for the slowest;
    after each round ``progress(done, total)`` is called with the steps done, and returning False
    stops: the unfinished cases end with :data:`STATUS_STOPPED`. ``max_launch_steps`` caps the steps
    of a launch. ``compile_only``: launch once with no steps (compiles the kernel) and return.
    ``probe``: Gear's jobs run the probed kernel, which times each phase of a step
    (:mod:`pdamper.kernels.gpu.probe`; each outcome's ``cycles``): a profile, not a production run.

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
    batches = [_Batch([jobs[k] for k in idx], threads or key[-1], probe,
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
        if all(b.finished for b in batches):
            break
        if progress is not None:
            done = sum(int(np.minimum(b.done, b.total).sum()) for b in batches)
            if progress(done, sum(int(b.total.sum()) for b in batches)) is False:
                break  # the caller stops the batch: the unfinished cases say so
        chunk, cycles = max_launch_steps, timed
    wall = time.perf_counter() - t_start
    out = [None] * len(jobs)
    for b, idx in zip(batches, groups.values()):
        for k, r in zip(idx, b.unpack(wall, len(jobs))):
            out[k] = r
    return out


class _Batch:
    """One group of jobs packed for one kernel: its bundles on the GPU, its stream, its progress."""

    def __init__(self, jobs, threads, probe=False, judges=None):
        from ..kernels.gpu.targets import SIMULATOR
        from ..kernels.gpu.verlet import verlet_kernel

        self.jobs = jobs
        self.judges = judges
        args, bd = kernel_arguments(jobs, threads)
        sp, li, wl, tb, law, tlaw, mo, ct, rec, nmat, row0, *gear = args
        self.types = (type(sp), type(ct), type(rec))
        self.bd = bd
        self.total = ct.total_steps.copy()
        self.done = np.zeros_like(self.total)
        self.status = np.zeros_like(self.total)
        #: per case, the driven samples its judge kept (-1: none) and those it had reached then
        self.kept = np.full(len(jobs), -1, dtype=np.int64)
        self.reached = np.full(len(jobs), -1, dtype=np.int64)
        self.finished = False
        self.stream = None if SIMULATOR else _stream()
        #: the bundles on the GPU, by name (the kernel's arguments, in order, are :attr:`args`)
        self.sp, self.ct, self.rec = _device(sp), _device(ct), _device_record(rec)
        self.args = [self.sp, _device(li), _device(wl), _device_tuple(tb), law, tlaw, _device(mo), self.ct, self.rec,
                     _device_array(nmat), _device_array(row0)]
        self.gear = jobs[0].integrator == "gear"
        self.gs = self.gc = None
        if self.gear:
            from ..kernels.gpu.gear import gear_kernel

            gs, gc = gear
            self.gear_types = (type(gc),)
            self.gs, self.gc = _device(gs), _device(gc)
            self.args += [self.gs, self.gc]
            self.total = gc.spans.copy()
            self.kernel = gear_kernel(probed=probe)
        else:
            self.kernel = verlet_kernel()

    def launch(self, steps, cycles=0):
        """Every case at most ``steps`` further, and with ``cycles`` > 0 no further than the step on
        which its block's clock has run that many cycles (:func:`launch_cycles`)."""
        C = len(self.jobs)
        if self.stream is None:  # numba-cuda's simulator: its threads switch at every barrier (SIMULATOR_SWITCH_S)
            old = sys.getswitchinterval()
            sys.setswitchinterval(min(old, SIMULATOR_SWITCH_S))
            try:
                self.kernel[C, self.bd](*self.args, int(steps), int(cycles))
            finally:
                sys.setswitchinterval(old)
        else:
            self.kernel[C, self.bd, self.stream](*self.args, int(steps), int(cycles))

    def poll(self):
        """Each case's progress and status after a launch; the cases' judges asked (:meth:`judge`)."""
        ct = self.ct
        self.done = _host(self.gc.span) if self.gear else _host(ct.step)
        self.status = _host(ct.status)
        self.judge()
        self.done = np.where(self.kept >= 0, self.total, self.done)
        self.finished = bool(np.all((self.done >= self.total) | (self.status != 0)))

    def recorded(self):
        """Per case, the driven samples whose record is complete now: up to its clock (Gear: a step
        that reaches a sample's end records it, but a failed step that reaches one does not: one
        less) or its steps (Verlet: up to its last whole sample before a failed step)."""
        n = np.array([j.n_samples for j in self.jobs], dtype=np.int64)
        if self.gear:
            ts = np.array([j.interval for j in self.jobs])
            rows = np.floor(_host(self.gc.t) / ts + 1e-6).astype(np.int64) - (self.status > 0)
        else:
            sub = np.array([j.sub for j in self.jobs], dtype=np.int64)
            settle = np.array([j.settle_samples * j.sub for j in self.jobs], dtype=np.int64)
            steps = np.where(self.status > 0, _host(self.ct.fail_step) - 1, _host(self.ct.step))
            rows = (steps - settle) // sub
        return np.clip(rows, 0, n)

    def judge(self):
        """Ask each case's judge (``run_jobs(steady=)``) about its record so far, and stop the cases
        it says are steady: a running one by a status the kernels skip (:data:`STATUS_JUDGED`), a
        finished or failed one by keeping the record up to there."""
        if self.judges is None:
            return
        rows = self.recorded()
        stop = []
        for c, judge in enumerate(self.judges):
            if judge is None or self.kept[c] >= 0:
                continue
            need = judge.next_samples()
            if need >= judge.n_samples or rows[c] < need:
                continue
            kept = judge(_host(self.rec.wall_force[c, : rows[c]]))
            if kept is not None:
                self.kept[c], self.reached[c] = kept, rows[c]
                if self.status[c] == 0 and self.done[c] < self.total[c]:
                    stop.append(c)
        if stop:
            self.status[stop] = STATUS_JUDGED
            _to_device(self.ct.status, self.status)

    def unpack(self, wall, batch):
        """Each job's channels, final state and outcome."""
        sp_t, ct_t, rec_t = self.types
        rec_h = rec_t(*[_host(a) for a in self.rec])
        sp_h = sp_t(*[_host(a) for a in self.sp])
        ct_h = ct_t(*[_host(a) for a in self.ct])
        gc_h = self.gear_types[0](*[_host(a) for a in self.gc]) if self.gear else None
        out = []
        for c, job in enumerate(self.jobs):
            e = job.engine
            n = e.n
            s = job.samples
            s.wall_force[:] = rec_h.wall_force[c, : s.wall_force.shape[0]]
            s.energy[:] = rec_h.energy[c, : s.energy.shape[0]]
            if s.frames.shape[0]:
                s.frames[:] = rec_h.frames[c, : s.frames.shape[0], :n]
            for name in ("position", "velocity", "spin"):
                getattr(e.bodies, name)[:] = getattr(sp_h, name)[c, :n]
            sums = ct_h.partials[c].sum(axis=0)
            s.sums[:3] = sums[:3]
            status = int(ct_h.status[c])
            kept = dict(kept=int(self.kept[c]), reached=int(self.reached[c]))
            judged = self.kept[c] >= 0
            if judged:  # stopped early by its judge, before any failure after that point
                status = 0
            if self.gear:
                if status == 0 and not judged and gc_h.span[c] < self.total[c]:
                    status = STATUS_STOPPED
                out.append(GpuOutcome(steps=int(ct_h.step[c]), status=status, culprit=int(ct_h.culprit[c]),
                                      t_fail=float(gc_h.t[c]), wall_time_s=wall, batch=batch, sums=sums[:3],
                                      rejected=int(gc_h.rejected[c]), h_next=float(gc_h.h[c]),
                                      cycles=gc_h.cycles[c].copy(), **kept))
                continue
            fail = int(ct_h.fail_step[c])
            if status == 0 and not judged and ct_h.step[c] < self.total[c]:
                status, fail = STATUS_STOPPED, int(ct_h.step[c])
            out.append(GpuOutcome(steps=int(ct_h.step[c]), status=status, culprit=int(ct_h.culprit[c]),
                                  t_fail=_time_of(job, fail), wall_time_s=wall, batch=batch, sums=sums[:3], **kept))
        return out


def kernel_arguments(jobs, threads: int | None = None):
    """The arguments of one batch's kernel (:func:`pdamper.kernels.gpu.verlet.batch_verlet`, or
    :func:`pdamper.kernels.gpu.gear.batch_gear` for Gear's jobs) on the host, less the steps of the
    launch, and the block size: the bundles, the contact table's arrays, the damping and tangential
    laws' markers (one group's: :func:`run_jobs` groups by them), the materials and table rows, Gear's
    state and clock."""
    sp, li, wl, tb, mo, ct, rec, nmat, row0, bd = _pack(jobs, threads)
    table = jobs[0].engine.table
    args = [sp, li, wl, tb, table.law, table.tangential, mo, ct, rec, nmat, row0]
    if jobs[0].integrator == "gear":
        args += list(_pack_gear(jobs, sp, li, wl, bd, keeps_history(table.tangential)))
    return args, bd


def _pack_gear(jobs, sp, li, wl, bd, history):
    """Gear's state and clock of every job: the Nordsieck vectors (filled by the kernel's priming),
    the saved history (with the tangential history's rows under a law that keeps one), the clock at
    the start of the first span."""
    from ..kernels.gpu.batch import PAIR_ROW, GearClock, GearState, pair_row_capacity
    from ..kernels.gpu.probe import PROBES

    C, N = sp.position.shape[:2]
    K = li.partner.shape[3]
    W = wl.kind.shape[1]
    rows = SAVED_HISTORY_ROWS if history else 2
    # the implicit friction pass's compact rows (none under a law with history: that pass is skipped)
    P = 1 if history else pair_row_capacity(N, K)
    gs = GearState(nordsieck=np.zeros((C, 6, N, 6)), increments=np.zeros((C, N, 6)),
                   saved_pair=np.zeros((C, rows, N, K)), saved_wall=np.zeros((C, rows, N, W)),
                   anchor=np.zeros((C, N, 6)), integrands=np.zeros((C, bd, 4)), pair_rows=np.zeros((C, P, PAIR_ROW)),
                   pair_ends=np.zeros((C, P, 3), dtype=np.int64))
    settle = np.array([j.settle_samples for j in jobs], dtype=np.int64)
    n = np.array([j.n_samples for j in jobs], dtype=np.int64)
    seg = np.array([j.segment_samples for j in jobs], dtype=np.int64)
    interval = np.array([j.interval for j in jobs])
    spans = (settle > 0).astype(np.int64) + -(-n // seg)
    # the first span's start: the settling's, (-S) x interval, or the drive's, 0
    t0 = np.array([float(-j.settle_samples) * j.interval if j.settle_samples > 0 else 0.0 for j in jobs])
    h0 = np.array([j.h0 for j in jobs])
    gc = GearClock(interval=interval, tolerance=np.array([j.tolerance for j in jobs]),
                   h_min=np.array([j.h_min for j in jobs]), h_max=np.array([j.h_max for j in jobs]),
                   settle_samples=settle, n_samples=n, segment_samples=seg, spans=spans,
                   span=np.zeros(C, dtype=np.int64), t=t0, h=h0.copy(), hs=h0.copy(),
                   rejected=np.zeros(C, dtype=np.int64), cycles=np.zeros((C, PROBES), dtype=np.int64))
    return gs, gc


def _stream():
    from numba import cuda

    return cuda.stream()


def _device_record(rec):
    """The record bundle on the GPU: its large output arrays allocated there, not copied (every row a
    case records is written before it is read; the rows beyond are never read)."""
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return rec
    from numba import cuda

    big = ("wall_force", "energy", "frames")
    return type(rec)(*[cuda.device_array(a.shape, dtype=a.dtype) if name in big else cuda.to_device(a)
                       for name, a in zip(rec._fields, rec)])


def _device(bundle):
    """The bundle with its arrays on the GPU (in the simulator: as they are; the simulator passes a
    bundle's arrays to the kernel untouched, so the CPU-compiled functions the kernel calls get
    plain arrays)."""
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return bundle
    from numba import cuda

    return type(bundle)(*[cuda.to_device(np.ascontiguousarray(a)) if isinstance(a, np.ndarray) else a
                          for a in bundle])


def _host(a):
    return a if isinstance(a, np.ndarray) else a.copy_to_host()


def _to_device(dev, host):
    """Write the host array ``host`` into ``dev`` (a bundle's array on the GPU; in the simulator the
    same array)."""
    if isinstance(dev, np.ndarray):
        if dev is not host:
            dev[:] = host
    else:
        dev.copy_to_device(np.ascontiguousarray(host, dtype=dev.dtype))


def _pack(jobs, threads):
    from ..kernels.gpu.batch import (CONTROL_FLAGS, PAIR_RESULT, PARTIALS, WALL_ROW, Control, Lists, Motion, Record,
                                     Spheres, Walls)

    C = len(jobs)
    engines = [j.engine for j in jobs]
    N = max(e.n for e in engines)
    W = max(e.walls.kind.shape[0] for e in engines)
    K = max(row_capacity(e.bodies.radius, e.search.skin) for e in engines)
    bd = threads or threads_for(N)
    # the tangential history: one entry a row under a law without one (never read)
    history = keeps_history(engines[0].table.tangential)
    nt = len(TANGENTIAL_COLUMNS)
    zeros3 = np.zeros((C, N, 3))
    sp = Spheres(position=zeros3.copy(), velocity=zeros3.copy(), spin=zeros3.copy(), acceleration=zeros3.copy(),
                 angular_acceleration=zeros3.copy(), previous_acceleration=zeros3.copy(),
                 previous_angular_acceleration=zeros3.copy(), reference=np.full((C, N, 3), np.inf),
                 moved=np.zeros((C, N, 6)),
                 radius=np.ones((C, N)), mass=np.ones((C, N)), inv_mass=np.ones((C, N)), inv_inertia=np.ones((C, N)),
                 material=np.zeros((C, N), dtype=np.int64), count=np.array([e.n for e in engines], dtype=np.int64))
    wl = Walls(kind=np.zeros((C, W), dtype=np.int64), data=np.zeros((C, W, 7)),
               count=np.array([e.walls.kind.shape[0] for e in engines], dtype=np.int64),
               floor=np.array([e.walls.floor for e in engines], dtype=np.int64), stiffness=np.zeros((C, N, W)),
               material_pair=np.zeros((C, N, W), dtype=np.int64), effective_radius=np.ones((C, N, W)),
               approach_speed=np.zeros((C, N, W)), damping=np.zeros((C, N, W)),
               tangential=np.zeros((C, N, W if history else 1, nt)), row=np.zeros((C, N, W, WALL_ROW)))
    li = Lists(partner=np.zeros((C, 2, N, K), dtype=np.int64), length=np.zeros((C, 2, N), dtype=np.int64),
               slot=np.zeros((C, N, K), dtype=np.int64), approach_speed=np.zeros((C, 2, N, K)),
               damping=np.zeros((C, 2, N, K)), tangential=np.zeros((C, 2, N, K if history else 1, nt)),
               stiffness=np.zeros((C, N, K)),
               material_pair=np.zeros((C, N, K), dtype=np.int64), friction_cap=np.zeros((C, N, K)),
               result=np.zeros((C, N, K, PAIR_RESULT)), buffer=np.zeros(C, dtype=np.int64),
               skin=np.array([e.search.skin for e in engines]))
    rows0, nmat = [], []
    row = 0
    for c, (job, e) in enumerate(zip(jobs, engines)):
        b = e.bodies
        n = e.n
        for name in ("position", "velocity", "spin"):
            getattr(sp, name)[c, :n] = getattr(b, name)
        for name in ("radius", "mass", "inv_mass", "inv_inertia", "material"):
            getattr(sp, name)[c, :n] = getattr(b, name)
        w = e.walls
        nw = w.kind.shape[0]
        wl.kind[c, :nw] = w.kind
        wl.data[c, :nw] = w.data
        wl.stiffness[c, :n, :nw] = w.stiffness
        wl.material_pair[c, :n, :nw] = w.material_pair + row
        wl.effective_radius[c, :n, :nw] = w.effective_radius
        rows0.append(row)
        nmat.append(e.table.n_materials)
        row += e.table.modulus.shape[0]
    tables = [e.table for e in engines]
    t0 = tables[0]
    tb = (np.concatenate([t.modulus for t in tables]), np.concatenate([t.shear_modulus for t in tables]),
          np.concatenate([t.friction for t in tables]), np.ascontiguousarray(np.concatenate([t.coefficient for t in tables])),
          np.ascontiguousarray(np.concatenate([t.tangential_damping for t in tables])),
          np.concatenate([t.yield_pressure for t in tables]), float(t0.log_speed0), float(t0.dlog_speed),
          float(t0.tau), float(t0.v_floor), float(t0.overlap_limit))
    mo = Motion(kind=np.array([e.drive.kind for e in engines], dtype=np.int64),
                par=np.array([np.resize(np.asarray(e.drive.par, dtype=float), 3) for e in engines]),
                gravity=np.array([e.drive.gravity for e in engines]),
                direction=np.array([e.drive.direction for e in engines]), jump=np.array([j.jump for j in jobs]))
    settle = np.array([j.settle_samples * j.sub for j in jobs], dtype=np.int64)
    ct = Control(dt=np.array([j.dt for j in jobs]), sub=np.array([j.sub for j in jobs], dtype=np.int64),
                 settle_steps=settle, total_steps=settle + np.array([j.n_samples * j.sub for j in jobs], dtype=np.int64),
                 segment_steps=np.array([j.segment_samples * j.sub for j in jobs], dtype=np.int64),
                 segment_samples=np.array([j.segment_samples for j in jobs], dtype=np.int64),
                 interval=np.array([j.interval for j in jobs]), sample_interval=np.array([j.samples.interval for j in jobs]),
                 step=np.zeros(C, dtype=np.int64), status=np.zeros(C, dtype=np.int64),
                 culprit=np.full(C, -1, dtype=np.int64), fail_step=np.zeros(C, dtype=np.int64),
                 flags=np.zeros((C, CONTROL_FLAGS), dtype=np.int64), partials=np.zeros((C, bd, PARTIALS)))
    S = max(1, max(max(j.samples.wall_force.shape[0], j.samples.energy.shape[0]) for j in jobs))
    F = max(1, max(j.samples.frames.shape[0] for j in jobs))
    from ..kernels.gpu.targets import SIMULATOR

    # on the GPU the output arrays are allocated there (_device_record): here only their shapes
    alloc = np.zeros if SIMULATOR else (lambda shape: np.lib.stride_tricks.as_strided(np.zeros(1), shape, [0] * len(shape)))
    rec = Record(wall_force=alloc((C, S)), energy=alloc((C, S, 7)), frames=alloc((C, F, N, 9)),
                 wall_force_rows=np.array([j.samples.wall_force.shape[0] for j in jobs], dtype=np.int64),
                 energy_rows=np.array([j.samples.energy.shape[0] for j in jobs], dtype=np.int64),
                 frame_rows=np.array([j.samples.frames.shape[0] for j in jobs], dtype=np.int64),
                 frame_every=np.array([j.samples.frame_every for j in jobs], dtype=np.int64),
                 settle_samples=np.array([j.settle_samples for j in jobs], dtype=np.int64),
                 bed_mass=np.array([float(np.sum(e.bodies.mass)) for e in engines]))
    return sp, li, wl, tb, mo, ct, rec, np.array(nmat, dtype=np.int64), np.array(rows0, dtype=np.int64), bd


def _time_of(job, g):
    """The time [s] at the end of step ``g`` (the kernel's clock, :func:`pdamper.kernels.gpu.verlet._case_time`)."""
    settle = job.settle_samples * job.sub
    if g <= settle:
        return float(-settle) * job.dt + float(g) * job.dt
    q = g - settle
    seg = job.segment_samples * job.sub
    j = (q - 1) // seg
    return float(j * job.segment_samples) * job.interval + float(q - j * seg) * job.dt


def _device_tuple(tb):
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return tb
    from numba import cuda

    return tuple(cuda.to_device(a) if isinstance(a, np.ndarray) else a for a in tb)


def _device_array(a):
    from ..kernels.gpu.targets import SIMULATOR

    if SIMULATOR:
        return a
    from numba import cuda

    return cuda.to_device(a)


def _sync():
    from ..kernels.gpu.targets import SIMULATOR

    if not SIMULATOR:
        from numba import cuda

        cuda.synchronize()
