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
                     table_of, vote, fresh, get, put, getf, putf)
from .warp import clock, opaque, sync

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


#: The Verlet kernel's state slots (:func:`~.forces.get`): its step, list and time buffers, whether the
#: list is to be rebuilt, the drive has started and the run is primed, the status and culprit of a
#: failure, the steps of this launch, whether its time is up, the launch's clock at its start; the
#: container's position and velocity at the step's end, the lane's largest squared displacement, the
#: container's acceleration at the step's end (kept there while the lane's spheres' forces are summed).
(U_G, U_LB, U_TK, U_MOVED, U_STARTED, U_PRIMED, U_STATUS, U_CULPRIT, U_DONE, U_STOP, U_START, U_XC, U_VC,
 U_DISP, U_AC) = range(15)


def batch_verlet(bt, tb, law, tlaw, max_steps, max_cycles):
    """Advance every case of the batch ``bt`` (:class:`~.batch.Batch`; block ``c`` is case ``c``) by
    at most ``max_steps`` steps, and with ``max_cycles`` > 0 no further than the step on which its
    block's clock passes that many cycles; ``tb``: the contact table's arrays and constants of every
    case, ``law`` and ``tlaw`` the damping and tangential laws' markers. The loop's state lives in
    each thread's state slots in the case's rows (``U_*``), read where it is used."""
    c = cuda.blockIdx.x
    hot = cuda.shared.array(0, float64)  # the spheres' hot state (SHARED_FIELDS a sphere)
    red = cuda.shared.array(MAX_WARPS, float64)  # a word a warp for the block's reductions
    acc = cuda.shared.array((MAX_SPHERES, 6), float64)  # each sphere's force and torque
    b = block(bt, c, hot, red)
    if b.ci[I_STATUS] != STATUS_OK:
        return
    table = table_of(tb, law, tlaw)
    spring = keeps_history(tlaw)
    for k, slot in ((U_G, I_STEP), (U_LB, I_LIST), (U_TK, I_TIME), (U_MOVED, I_MOVED), (U_STARTED, I_STARTED),
                    (U_PRIMED, I_PRIMED)):
        put(b, k, b.ci[slot])
    put(b, U_STATUS, STATUS_OK)
    put(b, U_CULPRIT, -1)
    put(b, U_DONE, 0)
    put(b, U_STOP, 0)
    load_spheres(b)
    put(b, U_START, clock())
    while get(b, U_G) < b.ci[I_TOTAL_STEPS] and get(b, U_DONE) < max_steps and get(b, U_STOP) == 0:
        b = fresh(block(bt, opaque(c), hot, red))
        ci = b.ci
        cf = b.cf
        # ---- the drive starts: velocities relative to the container jump, the sums restart
        if get(b, U_G) == ci[I_SETTLE_STEPS] and get(b, U_STARTED) == 0:
            start_drive(b)
            put(b, U_STARTED, 1)
        # ---- the initial accelerations (run_verlet's priming): list and forces at the start
        if get(b, U_PRIMED) == 0:
            if _prime(b, table, acc) != STATUS_OK:
                break
        b = fresh(b)
        now = ledger(b, THIS_STEP)
        for k in range(4):
            b.cf[now + k] = 0.0
        # ---- rebuild the list when a sphere moved too far in the previous step
        if get(b, U_MOVED) != 0:
            status = rebuild(b, table, get(b, U_LB), get(b, U_TK))
            put(b, U_STATUS, status)
            if status == STATUS_OK:
                put(b, U_LB, 1 - get(b, U_LB))
        # ---- drift with the half-step velocity; velocities predicted to the full step
        _drift(fresh(b), spring)
        # ---- the pairs' contact law
        b = fresh(b)
        st_, cu = pair_laws(b, table, get(b, U_LB), get(b, U_TK), b.cf[F_DT], b.cf[F_DT])
        if st_ != STATUS_OK:
            put(b, U_STATUS, st_)
            put(b, U_CULPRIT, cu)
        # ---- each sphere's force and torque, the half kick with the new accelerations
        _kick(fresh(b), table, acc)
        b = fresh(b)
        put(b, U_TK, 1 - get(b, U_TK))
        # ---- this thread's ledger: the step's powers and impulse
        _ledger(b, spring)
        put(b, U_G, get(b, U_G) + 1)
        put(b, U_DONE, get(b, U_DONE) + 1)
        # ---- the block's vote: a rebuild next step, the launch's time, a failure
        skin = b.cf[F_SKIN]
        bits, status, culprit = vote(b, MOVED_FAR if 3.0 * getf(b, U_DISP) > 0.25 * skin * skin else 0,
                                     get(b, U_STATUS), get(b, U_CULPRIT), get(b, U_START), max_cycles)
        put(b, U_STATUS, status)
        put(b, U_CULPRIT, culprit)
        put(b, U_MOVED, bits & MOVED_FAR)
        put(b, U_STOP, bits & TIME_UP)
        if bits & FAILED:
            break
        # ---- a sample ends: the block's sums, the energies, a frame
        b = fresh(b)
        g = get(b, U_G)
        sub = b.ci[I_SUB]
        if g > b.ci[I_SETTLE_STEPS] and g % sub == 0:
            record_sample(b, bt.out[c], g // sub - 1 - b.ci[I_SETTLE_SAMPLES], (getf(b, U_XC), getf(b, U_VC)),
                          get(b, U_LB), get(b, U_TK), spring)
    # ---- leave the state and the clock for the next launch
    b = fresh(b)
    sync(b.bd)
    store_spheres(b)
    if b.tid == 0:
        b.ci[I_STEP] = get(b, U_G)
        b.ci[I_MOVED] = get(b, U_MOVED)
        keep_state(b, get(b, U_LB), get(b, U_TK), get(b, U_STARTED), get(b, U_PRIMED), get(b, U_STATUS),
                   get(b, U_CULPRIT), get(b, U_G))


@cuda.jit(device=True)
def _time(b, g):
    """The case's time [s] at the end of step ``g`` (:func:`case_time` of its clock)."""
    ci = b.ci
    return case_time(g, b.cf[F_DT], ci[I_SETTLE_STEPS], ci[I_SEG_STEPS], ci[I_SEG_SAMPLES], b.cf[F_INTERVAL])


@cuda.jit(device=True)
def _prime(b, table, acc):
    """The initial accelerations (run_verlet's priming): the list and the forces at the start, the
    history's time buffer flipped. Returns the status (also in the thread's slot)."""
    dt = b.cf[F_DT]
    status, lb = prime(b, table, get(b, U_LB), get(b, U_TK), dt)
    put(b, U_LB, lb)
    put(b, U_STATUS, status)
    b = fresh(b)
    xc, vc, ac = motion_at(b, _time(b, get(b, U_G)))
    putf(b, U_AC, ac)
    i = b.tid
    while i < b.n:
        sphere_force(b, table, acc, i, get(b, U_LB), get(b, U_TK), b.cf[F_DT], 0.0)
        # (what the sum of the forces needs, read after it: not held through it)
        b = fresh(b)
        N = b.N
        st = b.st
        cf = b.cf
        ac = getf(b, U_AC)
        im = st[IMASS * N + i]
        ii = st[IINERT * N + i]
        for k in range(3):
            a0 = acc[i, k] * im + cf[F_GRAVITY + k] - ac * cf[F_DIRECTION + k]
            st[(A + k) * N + i] = a0
            st[(AP + k) * N + i] = a0
            w0 = acc[i, 3 + k] * ii
            st[(AL + k) * N + i] = w0
            st[(ALP + k) * N + i] = w0
        i += b.bd
    b = fresh(b)
    put(b, U_TK, 1 - get(b, U_TK))
    put(b, U_PRIMED, 1)
    put(b, U_MOVED, 0)
    return status


@cuda.jit(device=True)
def _drift(b, spring):
    """Each lane's spheres drift with the half-step velocity, their velocities predicted to the full
    step (the springs' displacements noted); the lane's largest squared displacement since the list
    was built into its slot. A barrier after."""
    dt = b.cf[F_DT]
    half = 0.5 * dt
    N = b.N
    st = b.st
    sh = b.sh
    disp = 0.0
    i = b.tid
    while i < b.n:
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
        i += b.bd
    putf(b, U_DISP, disp)
    sync(b.bd)


@cuda.jit(device=True)
def _kick(b, table, acc):
    """Each lane's spheres' force and torque (:func:`~.forces.sphere_force`) and the half kick with
    the new accelerations; the container's motion at the step's end into the thread's slots."""
    xc, vc, ac = motion_at(b, _time(b, get(b, U_G) + 1))
    putf(b, U_XC, xc)
    putf(b, U_VC, vc)
    putf(b, U_AC, ac)
    i = fresh(b).tid
    while i < fresh(b).n:
        dt = fresh(b).cf[F_DT]
        st_ = sphere_force(b, table, acc, i, get(b, U_LB), get(b, U_TK), dt, dt)
        if st_ != STATUS_OK:
            put(b, U_STATUS, st_)
            put(b, U_CULPRIT, i)
        # (what the kick needs, read after the sum of the forces: not held through it)
        b = fresh(b)
        N = b.N
        st = b.st
        sh = b.sh
        cf = b.cf
        half = 0.5 * cf[F_DT]
        ac = getf(b, U_AC)
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
        if bad and get(b, U_CULPRIT) < 0:
            put(b, U_STATUS, STATUS_NAN)
            put(b, U_CULPRIT, i)
        i += b.bd


@cuda.jit(device=True)
def _ledger(b, spring):
    """This thread's running sums take the step's powers and impulse (:func:`~.forces.ledger`)."""
    cf = b.cf
    dt = cf[F_DT]
    run = ledger(b, RUNNING)
    now = ledger(b, THIS_STEP)
    fd = cf[now + 3]
    cf[run] += getf(b, U_VC) * fd * dt
    cf[run + 1] += cf[now] * dt
    cf[run + 2] += cf[now + 1] * dt
    if spring:
        cf[run + 2] += cf[now + 2]
    cf[run + 3] += fd * dt
