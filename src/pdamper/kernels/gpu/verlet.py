"""Velocity Verlet for a batch of cases on the GPU: one block a case (one warp for a bed of up to 64
spheres), the lanes over its spheres and, for the contact law, over its pairs.

The step is :func:`pdamper.kernels.verlet.run_verlet`'s, with the same expressions in the same
order per sphere: half kick and drift (``x += dt (v + dt/2 a)``, velocities predicted to the full
step), the contact forces at the new positions (:mod:`.forces`), the container's acceleration as a
pseudo-force, the half kick with the new accelerations. A step is three passes and two warp
barriers: the drift (each lane its spheres), the pairs' law (each lane its pairs), each sphere's sum
and kick; then one vote of the block says whether a sphere moved far enough for a rebuild next
step, whether the launch's time is up and whether a step failed. The energy ledger and the wall
force's impulse are summed by each thread and over the block at the end of each sample (a sum of
sums: equal to the CPU's running sums to rounding). A failed step (an overlap beyond the limit, a
non-finite velocity, a full pair list) stops its case; the others go on.

A launch advances every case by at most ``max_steps`` steps, and with ``max_cycles`` no further than
the step on which its block has run that many cycles; the state stays in the batch's rows, so the
next launch goes on where it stopped.
"""

from __future__ import annotations

import math

from numba import cuda, float64

from ..contact import keeps_history
from ..forces import STATUS_NAN, STATUS_OK
from .batch import (A, AL, ALP, AP, F_DIRECTION, F_DT, F_GRAVITY, F_INTERVAL, F_SKIN, IINERT, IMASS, I_LIST, I_MOVED,
                    I_PRIMED, I_SEG_SAMPLES, I_SEG_STEPS, I_SETTLE_SAMPLES, I_SETTLE_STEPS, I_STARTED, I_STATUS,
                    I_STEP, I_SUB, I_TIME, I_TOTAL_STEPS, MAX_SPHERES, MAX_WARPS, REF, S_MOVED, S_SPIN,
                    S_V, S_X)
from .forces import (FAILED, MOVED_FAR, RUNNING, THIS_STEP, TIME_UP, block, keep_state, ledger, load_spheres,
                     motion_at, pair_laws, prime, rebuild, record_sample, sphere_force, start_drive, store_spheres,
                     table_of, vote)
from .warp import clock, sync

__all__ = ["batch_verlet", "verlet_kernel", "case_time"]

_KERNEL = []


def verlet_kernel():
    """The batch Verlet kernel (compiled when first launched, once per damping and tangential law:
    their markers are arguments, and their types pick the laws; cached on disk by numba-cuda)."""
    if not _KERNEL:
        _KERNEL.append(cuda.jit(cache=True)(batch_verlet))
    return _KERNEL[0]


@cuda.jit(device=True)
def case_time(g, dt, settle, seg_steps, seg_samples, interval):
    """The time [s] at the end of step ``g`` (counted from 1 at the start of the settling; 0: the
    start), as the CPU engine's clock gives it: the settling from ``-settle dt``, the drive in
    segments of ``seg_samples`` samples whose clock restarts at their first sample
    (:meth:`pdamper.simulation.Simulation.advance`)."""
    if g <= settle:
        return float(-settle) * dt + float(g) * dt
    q = g - settle
    j = (q - 1) // seg_steps
    return float(j * seg_samples) * interval + float(q - j * seg_steps) * dt


def batch_verlet(bt, tb, law, tlaw, max_steps, max_cycles):
    """Advance every case of the batch ``bt`` (:class:`~.batch.Batch`; block ``c`` is case ``c``) by
    at most ``max_steps`` steps, and with ``max_cycles`` > 0 no further than the step on which its
    block's clock passes that many cycles; ``tb``: the contact table's arrays and constants of every
    case, ``law`` and ``tlaw`` the damping and tangential laws' markers."""
    c = cuda.blockIdx.x
    hot = cuda.shared.array(0, float64)  # the spheres' hot state (SHARED_FIELDS a sphere)
    red = cuda.shared.array(MAX_WARPS, float64)  # a word a warp for the block's reductions
    b = block(bt, c, hot, red)
    acc = cuda.shared.array((MAX_SPHERES, 6), float64)  # each sphere's force and torque
    ci = b.ci
    cf = b.cf
    st = b.st
    sh = b.sh
    if ci[I_STATUS] != STATUS_OK:
        return
    table = table_of(tb, law, tlaw)
    spring = keeps_history(tlaw)
    tid = b.tid
    bd = b.bd
    n = b.n
    N = b.N
    g = ci[I_STEP]
    lb = ci[I_LIST]
    tk = ci[I_TIME]
    moved = ci[I_MOVED]
    started = ci[I_STARTED]
    primed = ci[I_PRIMED]
    run = ledger(b, RUNNING)
    now = ledger(b, THIS_STEP)
    load_spheres(b)
    status = STATUS_OK
    culprit = -1
    done = 0
    stop = 0
    start = clock()
    while g < ci[I_TOTAL_STEPS] and done < max_steps and stop == 0:
        dt = cf[F_DT]
        half = 0.5 * dt
        settle = ci[I_SETTLE_STEPS]
        # ---- the drive starts: velocities relative to the container jump, the sums restart
        if g == settle and started == 0:
            start_drive(b)
            started = 1
        # ---- the initial accelerations (run_verlet's priming): list and forces at the start
        if primed == 0:
            status, lb = prime(b, table, lb, tk, dt)
            xc, vc, ac = motion_at(b, case_time(g, dt, settle, ci[I_SEG_STEPS], ci[I_SEG_SAMPLES], cf[F_INTERVAL]))
            i = tid
            while i < n:
                sphere_force(b, table, acc, i, lb, tk, dt, 0.0)
                im = st[IMASS * N + i]
                ii = st[IINERT * N + i]
                for k in range(3):
                    a0 = acc[i, k] * im + cf[F_GRAVITY + k] - ac * cf[F_DIRECTION + k]
                    st[(A + k) * N + i] = a0
                    st[(AP + k) * N + i] = a0
                    w0 = acc[i, 3 + k] * ii
                    st[(AL + k) * N + i] = w0
                    st[(ALP + k) * N + i] = w0
                i += bd
            tk = 1 - tk
            primed = 1
            moved = 0
            if status != STATUS_OK:
                break
        for k in range(4):
            cf[now + k] = 0.0
        t = case_time(g + 1, dt, settle, ci[I_SEG_STEPS], ci[I_SEG_SAMPLES], cf[F_INTERVAL])
        # ---- rebuild the list when a sphere moved too far in the previous step
        if moved != 0:
            status = rebuild(b, table, lb, tk)
            if status == STATUS_OK:
                lb = 1 - lb
        # ---- drift with the half-step velocity; velocities predicted to the full step
        disp = 0.0
        i = tid
        while i < n:
            for k in range(3):
                a = st[(A + k) * N + i]
                v = sh[(S_V + k) * N + i]
                if spring:
                    # what the drift moves and turns the sphere by: the springs advance by it
                    sh[(S_MOVED + k) * N + i] = dt * (v + half * a)
                    sh[(S_MOVED + 3 + k) * N + i] = dt * (sh[(S_SPIN + k) * N + i] + half * st[(AL + k) * N + i])
                x = sh[(S_X + k) * N + i] + dt * (v + half * a)
                sh[(S_X + k) * N + i] = x
                sh[(S_V + k) * N + i] = v + half * (3.0 * a - st[(AP + k) * N + i])
                sh[(S_SPIN + k) * N + i] = sh[(S_SPIN + k) * N + i] + half * (3.0 * st[(AL + k) * N + i]
                                                                            - st[(ALP + k) * N + i])
                dd = x - st[(REF + k) * N + i]
                disp = max(disp, dd * dd)
            i += bd
        sync(bd)
        # ---- the pairs' contact law
        st_, cu = pair_laws(b, table, lb, tk, dt, dt)
        if st_ != STATUS_OK:
            status = st_
            culprit = cu
        # ---- each sphere's force and torque, the half kick with the new accelerations
        xc, vc, ac = motion_at(b, t)
        i = tid
        while i < n:
            st_ = sphere_force(b, table, acc, i, lb, tk, dt, dt)
            if st_ != STATUS_OK:
                status = st_
                culprit = i
            im = st[IMASS * N + i]
            ii = st[IINERT * N + i]
            bad = False
            for k in range(3):
                an = acc[i, k] * im + (cf[F_GRAVITY + k] - ac * cf[F_DIRECTION + k])
                a = st[(A + k) * N + i]
                vn = sh[(S_V + k) * N + i] + half * (an - 2.0 * a + st[(AP + k) * N + i])
                sh[(S_V + k) * N + i] = vn
                st[(AP + k) * N + i] = a
                st[(A + k) * N + i] = an
                wn = acc[i, 3 + k] * ii
                al = st[(AL + k) * N + i]
                sh[(S_SPIN + k) * N + i] = sh[(S_SPIN + k) * N + i] + half * (wn - 2.0 * al + st[(ALP + k) * N + i])
                st[(ALP + k) * N + i] = al
                st[(AL + k) * N + i] = wn
                if not (math.fabs(vn) < 1e6):
                    bad = True
            if bad and culprit < 0:
                status = STATUS_NAN
                culprit = i
            i += bd
        tk = 1 - tk
        # ---- this thread's ledger: the step's powers and impulse
        fd = cf[now + 3]
        cf[run] += vc * fd * dt
        cf[run + 1] += cf[now] * dt
        cf[run + 2] += cf[now + 1] * dt
        if spring:
            cf[run + 2] += cf[now + 2]
        cf[run + 3] += fd * dt
        g += 1
        done += 1
        # ---- the block's vote: a rebuild next step, the launch's time, a failure
        bits, status, culprit = vote(b, MOVED_FAR if 3.0 * disp > 0.25 * cf[F_SKIN] * cf[F_SKIN] else 0, status,
                                     culprit, start, max_cycles)
        moved = bits & MOVED_FAR
        stop = bits & TIME_UP
        if bits & FAILED:
            break
        # ---- a sample ends: the block's sums, the energies, a frame
        if g > settle and g % ci[I_SUB] == 0:
            record_sample(b, bt.out[c], g // ci[I_SUB] - 1 - ci[I_SETTLE_SAMPLES], (xc, vc), lb, tk, spring)
    # ---- leave the state and the clock for the next launch
    sync(bd)
    store_spheres(b)
    if tid == 0:
        ci[I_STEP] = g
        ci[I_MOVED] = moved
        keep_state(b, lb, tk, started, primed, status, culprit, g)
