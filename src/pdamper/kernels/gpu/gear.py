"""Gear's variable-step predictor-corrector for a batch of cases on the GPU: one block a case (one
warp for a bed of up to 64 spheres), each case with its own adaptive step (its error norm reduced
over the block, its rejections its own).

The step is :func:`pdamper.kernels.gear.run_gear`'s: the Nordsieck vector rescaled and predicted
(each lane its spheres' degrees of freedom, into the block's shared memory), the pair list rebuilt
when a sphere moved more than half the skin, the contact forces at the predicted state
(:mod:`.forces`, with no friction cap), the corrector's increments (in shared memory), the friction
of every touching contact evaluated again at the corrected slip (the CPU's Gauss-Seidel sweep in its
order: the touching pairs' rows listed by a scan of the block in the pair list's order, each row
given a level one above the last of either of its spheres, the rows of a level, which share no
sphere, taken by the lanes together, so that every sphere sees its rows in the CPU's order; then the
floor and the other walls, each sphere's by its lane, which gives the same increments since a wall
row changes its own sphere alone; the CPU's ``corrected_friction``, kinematics and ``scatter``), the
block's largest increment as the error, a rejected step retried shorter, an accepted one corrected,
its ledger summed by the trapezoid, a sample written where it ends on a sample boundary. The clock
follows the CPU stepper's spans (the settling, then segments of the drive, each starting at its
exact time).

The contact history is double-buffered (:mod:`.forces`): a step writes the other buffer and only an
accepted step makes it the current one, so a rejected step has nothing to restore. The prediction
is not stored but recomputed from the Nordsieck vector where the step needs it (the same operations
on the same values: the same bits).
"""

from __future__ import annotations

import math

from numba import cuda, float64, int32

from ..contact import corrected_friction, keeps_history, pair_point_velocity, scatter
from ..forces import STATUS_NAN, STATUS_OK
from ..gear import (GEAR_C, floor_friction_step, next_step, predict_dof, shorter_step, step_to_boundary,
                    wall_friction_step)
from .batch import (ANCHOR, F_DIRECTION, F_GRAVITY, F_H, F_HS, F_H_MAX, F_H_MIN, F_INTERVAL, F_JUMP, F_SKIN, F_T,
                    F_TOL, IINERT, IMASS, I_FLOOR, I_LIST, I_NW, I_PRIMED, I_REJECTED, I_SAMPLES, I_SEG_SAMPLES,
                    I_SETTLE_SAMPLES, I_SPAN, I_SPANS, I_STARTED, I_STATUS, I_STEP, I_TIME, MAX_SPHERES, MAX_WARPS,
                    NORD, O_DP, O_FIRST, O_LEVEL, O_P, O_PV, O_RES, O_ROW, O_SEC, O_W, O_WALK, O_WROW, O_WV, REF, R_C,
                    R_LIM, R_N, R_S, S_MOVED, S_RAD, S_SPIN, S_V, S_X)
from .forces import (FAILED, INTEGRANDS, RUNNING, THIS_STEP, TIME_UP, block, keep_state, ledger, load_spheres,
                     motion_at, pair_laws, prime, rebuild, record_sample, sphere_force, start_drive, store_spheres,
                     table_of, vote, fresh, get, put, getf, putf)
from .warp import block_max, block_scan, clock, opaque, sync

__all__ = ["batch_gear", "gear_kernel", "NO_CAP"]

#: The force loops' step argument that switches the explicit friction cap off (as the CPU's Gear).
NO_CAP = 1e-300
_C0, _C1, _C2, _C3, _C4, _C5 = GEAR_C

_KERNEL = []


def gear_kernel():
    """The batch Gear kernel (compiled when first launched, once per damping and tangential law;
    disk-cached)."""
    if not _KERNEL:
        _KERNEL.append(cuda.jit(cache=True)(batch_gear))
    return _KERNEL[0]


@cuda.jit(device=True)
def _span(k, settle, n_samples, seg, interval):
    """Span ``k`` of the CPU stepper's clock: ``(t0, t_end, records)``: the settling first (when
    there is one), then the drive's segments."""
    if settle > 0:
        if k == 0:
            return float(-settle) * interval, 0.0, False
        k -= 1
    a = k * seg
    e = min(n_samples, a + seg)
    return float(a) * interval, float(e) * interval, True


@cuda.jit(device=True)
def _nv(b, k, d, i):
    """Where row ``k`` of degree of freedom ``d`` of sphere ``i``'s Nordsieck vector is in ``st``."""
    return (NORD + 6 * k + d) * b.N + i


@cuda.jit(device=True)
def _predicted(b, i, d):
    """Degree of freedom ``d`` of sphere ``i``'s Nordsieck vector predicted a step on (the CPU's
    ``predict_dof``)."""
    st = b.st
    return predict_dof(st[_nv(b, 0, d, i)], st[_nv(b, 1, d, i)], st[_nv(b, 2, d, i)], st[_nv(b, 3, d, i)],
                       st[_nv(b, 4, d, i)], st[_nv(b, 5, d, i)])


@cuda.jit(device=True)
def _rescale(b, i, d, ratio):
    """Degree of freedom ``d`` of sphere ``i``'s Nordsieck vector rescaled to a step ``ratio`` times
    the last (row q by ``ratio**q``, the CPU's ``_rescale``)."""
    f = 1.0
    for k in range(1, 6):
        f *= ratio
        b.st[_nv(b, k, d, i)] *= f


@cuda.jit(device=True)
def _gather(b, lb, tk):
    """The touching pairs with friction (``c > 0``), in the pair list's order (the CPU friction
    record's), into the case's list of rows (``iv[O_WALK]``): the lanes take the pairs a block's
    width at a time, a scan places them. Returns the rows."""
    b = fresh(b)
    ci = b.ci
    P = ci[O_P]
    v_new = ci[O_PV] + (lb * 2 + 1 - tk) * P
    c_at = ci[O_RES] + R_C * P
    npairs = b.iv[ci[O_ROW] + lb * (b.N + 1) + b.n]
    rows = 0
    start = 0
    while start < npairs:
        p = start + b.tid
        m = 0
        if p < npairs and b.gv[v_new + p] != 0.0 and b.gv[c_at + p] > 0.0:
            m = 1
        before, total = block_scan(m, b.tid, b.bd, b.red)
        if m:
            b.iv[ci[O_WALK] + rows + before] = p
        rows += total
        start += b.bd
    return rows


@cuda.jit(device=True)
def _levels(b, rows, lb, last, top):
    """Each row's level, one above the last level of either of its spheres, in the CPU's order (the
    rows of one level share no sphere), by thread 0; the highest level into ``top[0]`` (``last``: a
    sphere's latest level, shared)."""
    b = fresh(b)
    N = b.N
    i = b.tid
    while i < b.n:
        last[i] = 0
        i += b.bd
    sync(b.bd)
    if b.tid == 0:
        ci = b.ci
        P = ci[O_P]
        high = 0
        for k in range(rows):
            p = b.iv[ci[O_WALK] + k]
            i = b.iv[ci[O_FIRST] + lb * P + p]
            j = b.iv[ci[O_SEC] + lb * P + p]
            lev = max(last[i], last[j]) + 1
            last[i] = lev
            last[j] = lev
            b.iv[ci[O_LEVEL] + k] = lev
            high = max(high, lev)
        top[0] = high
    _ = N
    sync(b.bd)


@cuda.jit(device=True)
def _pair_row(b, dl, k, lb, g, a, hh):
    """Row ``k`` at its corrected slip: what depends on the increments ``dl`` (the slip increment,
    the corrected force, its scatter into the increments of the row's two spheres), ``g = c1 / h``,
    ``a = c1 h / 2``, ``hh = h^2 / 2``. Returns its change of the friction power [W]."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    gv = b.gv
    st = b.st
    P = ci[O_P]
    p = b.iv[ci[O_WALK] + k]
    i = b.iv[ci[O_FIRST] + lb * P + p]
    j = b.iv[ci[O_SEC] + lb * P + p]
    ri = b.sh[S_RAD * N + i]
    rj = b.sh[S_RAD * N + j]
    res = ci[O_RES]
    nx = gv[res + R_N * P + p]
    ny = gv[res + (R_N + 1) * P + p]
    nz = gv[res + (R_N + 2) * P + p]
    tx = gv[res + R_S * P + p]
    ty = gv[res + (R_S + 1) * P + p]
    tz = gv[res + (R_S + 2) * P + p]
    cf = gv[res + R_C * P + p]
    im_i = st[IMASS * N + i]
    im_j = st[IMASS * N + j]
    ii_i = st[IINERT * N + i]
    ii_j = st[IINERT * N + j]
    kk = im_i + im_j + ri * ri * ii_i + rj * rj * ii_j
    vt = math.sqrt(tx * tx + ty * ty + tz * tz)
    dv = dl[:, 0:3]
    dw = dl[:, 3:6]
    dcx, dcy, dcz, dcn = pair_point_velocity(
        g * (dv[i, 0] - dv[j, 0]), g * (dv[i, 1] - dv[j, 1]), g * (dv[i, 2] - dv[j, 2]),
        g * (ri * dw[i, 0] + rj * dw[j, 0]), g * (ri * dw[i, 1] + rj * dw[j, 1]),
        g * (ri * dw[i, 2] + rj * dw[j, 2]), nx, ny, nz)
    gx, gy, gz, fx, fy, fz = corrected_friction(cf, gv[res + R_LIM * P + p], kk, a, tx, ty, tz,
                                                dcx - dcn * nx, dcy - dcn * ny, dcz - dcn * nz)
    dp = -(fx * (tx + dcx - dcn * nx + a * kk * gx) + fy * (ty + dcy - dcn * ny + a * kk * gy)
           + fz * (tz + dcz - dcn * nz + a * kk * gz)) - cf * vt * vt
    scatter(dv, dw, i, j, (gx, gy, gz), (nx, ny, nz), (gx, gy, gz), hh * im_i, hh * im_j, hh * ii_i * ri, hh * ii_j * rj)
    return dp


@cuda.jit(device=True)
def _implicit_pairs(b, dl, lb, tk, hs, last, top):
    """The friction of every touching pair at its corrected slip, level by level (:func:`_levels`):
    the first part of the CPU's :func:`pdamper.kernels.gear._implicit_friction`, every sphere's rows
    in its order. Each row's change of the friction power is kept at it and summed by thread 0 in
    the CPU's order. Returns the power [W] (thread 0; the others 0)."""
    b = fresh(b)
    rows = _gather(b, lb, tk)
    dpf = 0.0
    if rows == 0:
        return dpf
    _levels(b, rows, lb, last, top)
    g = _C1 / hs
    a = 0.5 * _C1 * hs
    hh = 0.5 * hs * hs
    ci = b.ci
    for lev in range(1, top[0] + 1):
        k = b.tid
        while k < rows:
            if b.iv[ci[O_LEVEL] + k] == lev:
                b.gv[ci[O_DP] + k] = _pair_row(b, dl, k, lb, g, a, hh)
            k += b.bd
        sync(b.bd)
    if b.tid == 0:
        for k in range(rows):
            dpf += b.gv[ci[O_DP] + k]
    sync(b.bd)  # (top[0] is read by every thread before thread 0 writes it again)
    return dpf


@cuda.jit(device=True)
def _implicit_walls(b, dl, i, tk, hs):
    """The friction of sphere ``i``'s floor and other walls at their corrected slip: the rest of the
    CPU's :func:`pdamper.kernels.gear._implicit_friction` (a wall row changes its own sphere alone, so
    each lane takes its spheres after all pair rows, the floor then the walls: the CPU sweep's
    increments). Returns ``(dfx, dfy, dfz, dp_f)`` of this sphere's rows."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    gv = b.gv
    nW = ci[O_W]
    dv = dl[:, 0:3]
    dw = dl[:, 3:6]
    g = _C1 / hs
    a = 0.5 * _C1 * hs
    hh = 0.5 * hs * hs
    dfx = dfy = dfz = dpf = 0.0
    ri = b.sh[S_RAD * N + i]
    im = b.st[IMASS * N + i]
    ii = b.st[IINERT * N + i]
    v_new = ci[O_WV] + (1 - tk) * nW * N
    wrow = ci[O_WROW]
    wn = nW * N
    floor = ci[I_FLOOR]
    if floor >= 0 and gv[v_new + floor * N + i] != 0.0:
        at = wrow + floor * N + i
        cf = gv[at + 6 * wn]
        if cf > 0.0:
            kk = im + ri * ri * ii
            gx, gz, dp = floor_friction_step(cf, gv[at + 7 * wn], gv[at + 3 * wn], gv[at + 5 * wn], dv[i, 0],
                                             dv[i, 2], dw[i, 0], dw[i, 2], ri, g, a, kk)
            dpf += dp
            scatter(dv, dw, i, -1, (gx, 0.0, gz), (0.0, 1.0, 0.0), (gx, 0.0, gz), hh * im, 0.0, -(hh * ii * ri), 0.0)
            dfx += gx
            dfz += gz
    for w in range(ci[I_NW]):
        if w == floor or gv[v_new + w * N + i] == 0.0:
            continue
        at = wrow + w * N + i
        cf = gv[at + 6 * wn]
        if not (cf > 0.0):
            continue
        nx = gv[at]
        ny = gv[at + wn]
        nz = gv[at + 2 * wn]
        kk = im + ri * ri * ii
        gx, gy, gz, dp = wall_friction_step(cf, gv[at + 7 * wn], (nx, ny, nz),
                                            (gv[at + 3 * wn], gv[at + 4 * wn], gv[at + 5 * wn]),
                                            (dv[i, 0], dv[i, 1], dv[i, 2]), (dw[i, 0], dw[i, 1], dw[i, 2]), ri, g, a, kk)
        dpf += dp
        scatter(dv, dw, i, -1, (gx, gy, gz), (nx, ny, nz), (gx, gy, gz), hh * im, 0.0, -(hh * ii * ri), 0.0)
        dfx += gx
        dfy += gy
        dfz += gz
    return dfx, dfy, dfz, dpf


@cuda.jit(device=True)
def _unpack(b, hs):
    """Each lane's spheres' positions, velocities and spins from the Nordsieck vector (scaled to
    step ``hs``) into shared memory."""
    b = fresh(b)
    N = b.N
    inv_h = 1.0 / hs
    i = b.tid
    while i < b.n:
        for k in range(3):
            b.sh[(S_X + k) * N + i] = b.st[_nv(b, 0, k, i)]
            b.sh[(S_V + k) * N + i] = b.st[_nv(b, 1, k, i)] * inv_h
            b.sh[(S_SPIN + k) * N + i] = b.st[_nv(b, 1, 3 + k, i)] * inv_h
        i += b.bd


#: The Gear kernel's state slots (:func:`~.forces.get`): the span of the clock, the accepted and rejected
#: steps, the list and history buffers, whether the drive has started and the run is primed, the
#: status and culprit, the attempts of this launch, whether its time is up, the launch's clock at its
#: start, the sample the step ends on; the time, the next step, the step taken, the sample's time, the
#: rescale of the Nordsieck vector, the container's position, velocity and acceleration at the step's end
#: (the acceleration kept there while the lane's spheres' forces are summed).
(U_SPAN, U_STEPS, U_REJECTED, U_LB, U_TK, U_STARTED, U_PRIMED, U_STATUS, U_CULPRIT, U_DONE, U_STOP, U_START, U_KB,
 U_T, U_H, U_HS, U_TB_END, U_RATIO, U_XC, U_VC, U_AC) = range(21)


@cuda.jit(device=True)
def _span_of(b):
    """The current span of the case's clock (:func:`_span`): ``(t0, t_end, records)``."""
    ci = b.ci
    return _span(get(b, U_SPAN), ci[I_SETTLE_SAMPLES], ci[I_SAMPLES], ci[I_SEG_SAMPLES], b.cf[F_INTERVAL])


def batch_gear(bt, tb, law, tlaw, max_steps, max_cycles):
    """Advance every case of the batch ``bt`` by at most ``max_steps`` attempted steps (block ``c``
    is case ``c``), as :func:`pdamper.kernels.gear.run_gear` does over the CPU stepper's spans; with
    ``max_cycles`` > 0, also no further than the step on which its block's clock passes that many
    cycles. The arguments as :func:`.verlet.batch_verlet`'s; the loop's state lives in each thread's
    state slots in the case's rows (``U_*``), read where it is used."""
    c = cuda.blockIdx.x
    hot = cuda.shared.array(0, float64)  # the spheres' hot state (SHARED_FIELDS a sphere)
    red = cuda.shared.array(MAX_WARPS, float64)  # a word a warp for the block's reductions
    # the corrector's increments (position, angle) of each sphere, and the walk's levels
    dl = cuda.shared.array((MAX_SPHERES, 6), float64)
    last = cuda.shared.array(MAX_SPHERES, int32)
    top = cuda.shared.array(1, int32)
    b = block(bt, c, hot, red)
    if b.ci[I_STATUS] != STATUS_OK:
        return
    table = table_of(tb, law, tlaw)
    spring = keeps_history(tlaw)
    for k, slot in ((U_SPAN, I_SPAN), (U_STEPS, I_STEP), (U_REJECTED, I_REJECTED), (U_LB, I_LIST), (U_TK, I_TIME),
                    (U_STARTED, I_STARTED), (U_PRIMED, I_PRIMED)):
        put(b, k, b.ci[slot])
    for k, slot in ((U_T, F_T), (U_H, F_H), (U_HS, F_HS)):
        putf(b, k, b.cf[slot])
    put(b, U_STATUS, STATUS_OK)
    put(b, U_CULPRIT, -1)
    put(b, U_DONE, 0)
    put(b, U_STOP, 0)
    load_spheres(b)
    put(b, U_START, clock())
    while get(b, U_SPAN) < b.ci[I_SPANS] and get(b, U_DONE) < max_steps and get(b, U_STOP) == 0:
        b = fresh(block(bt, opaque(c), hot, red))
        ts = b.cf[F_INTERVAL]
        # ---- a span ends: the next one starts at its exact time (the CPU stepper's next call)
        t0, t_end, recording = _span_of(b)
        if not (getf(b, U_T) < t_end - 1e-12 * ts):
            put(b, U_SPAN, get(b, U_SPAN) + 1)
            if get(b, U_SPAN) >= b.ci[I_SPANS]:
                break
            t0, t_end, recording = _span_of(b)
            putf(b, U_T, t0)
        # ---- the drive starts (after the settling): velocities jump, the sums restart
        if recording and get(b, U_STARTED) == 0:
            _start(b)
        # ---- the Nordsieck vector at the start (run_gear's priming), forces with the capped friction
        if get(b, U_PRIMED) == 0:
            if _prime(fresh(b), table, dl, spring) != STATUS_OK:
                break
        # ---- the step: end on the next sample boundary or the span's end
        b = fresh(b)
        t0, t_end, recording = _span_of(b)
        kb, tb_end, hh = step_to_boundary(getf(b, U_T), ts, getf(b, U_H), t_end)
        put(b, U_KB, kb)
        putf(b, U_TB_END, tb_end)
        putf(b, U_RATIO, 1.0)
        if hh != getf(b, U_HS):
            putf(b, U_RATIO, hh / getf(b, U_HS))
            putf(b, U_HS, hh)
        # ---- the pair list at the current positions (the Nordsieck vector's first row)
        if _moved_far(fresh(b)):
            if _rebuild(fresh(b), table) != STATUS_OK:
                break
        # ---- rescale, predict, unpack into shared memory
        _predict(fresh(b), spring)
        # ---- forces at the prediction (no friction cap), the corrector's increments; this attempt's
        #      own status (compute_forces' on the CPU): an overlap at a rejected step's prediction is
        #      forgotten with the step, it stops the case only when the step is accepted
        _increments(fresh(b), table, dl)
        # ---- the friction at the corrected slip, in the CPU's order: the touching pairs' rows level by
        #      level, then each sphere's floor and walls by its lane (a law with history, the spring,
        #      leaves no friction rows: nothing to correct)
        if not spring:
            _implicit(fresh(b), dl, last, top)
        # ---- the error: the block's largest increment
        err = _error(fresh(b), dl)
        b = fresh(b)
        put(b, U_DONE, get(b, U_DONE) + 1)
        if not (err < 1e300):
            put(b, U_STATUS, STATUS_NAN)
            break
        cf = b.cf
        tol = cf[F_TOL]
        hs = getf(b, U_HS)
        if err > 4.0 * tol and hs > cf[F_H_MIN] * 1.000001:
            # reject: a shorter step (the Nordsieck vector and the history's current buffer are untouched)
            putf(b, U_H, shorter_step(hs, tol, err, cf[F_H_MIN]))
            put(b, U_REJECTED, get(b, U_REJECTED) + 1)
            bits, _, _ = vote(b, 0, STATUS_OK, -1, get(b, U_START), max_cycles)
            put(b, U_STOP, bits & TIME_UP)
            continue
        # ---- accept: correct the prediction into the Nordsieck vector; the history's new buffer is current
        putf(b, U_H, next_step(hs, getf(b, U_H), tol, err, cf[F_H_MIN], cf[F_H_MAX]))
        _accept(fresh(b), dl, spring)
        b = fresh(b)
        bits, status, culprit = vote(b, 0, get(b, U_STATUS), get(b, U_CULPRIT), get(b, U_START), max_cycles)
        put(b, U_STATUS, status)
        put(b, U_CULPRIT, culprit)
        put(b, U_STOP, bits & TIME_UP)
        if bits & FAILED:
            break
        # ---- a sample ends on this step: the block's sums, the energies, a frame
        b = fresh(b)
        t0, t_end, recording = _span_of(b)
        if recording and math.fabs(getf(b, U_T) - getf(b, U_TB_END)) <= 1e-9 * b.cf[F_INTERVAL]:
            _unpack(b, getf(b, U_HS))
            sync(b.bd)
            record_sample(b, bt.out[c], get(b, U_KB) - 1, (getf(b, U_XC), getf(b, U_VC)), get(b, U_LB), get(b, U_TK),
                          spring)
    # ---- the state (once there is a Nordsieck vector); the clock and the running sums for the next launch
    b = fresh(b)
    sync(b.bd)
    if get(b, U_PRIMED) != 0:
        _unpack(b, getf(b, U_HS))
    store_spheres(b)
    if b.tid == 0:
        ci = b.ci
        cf = b.cf
        span = get(b, U_SPAN)
        n_spans = ci[I_SPANS]
        t0, t_end, recording = _span_of(b)
        if span >= n_spans or not (getf(b, U_T) < t_end - 1e-12 * cf[F_INTERVAL]) and span == n_spans - 1:
            span = n_spans
        ci[I_SPAN] = span
        cf[F_T] = getf(b, U_T)
        cf[F_H] = getf(b, U_H)
        cf[F_HS] = getf(b, U_HS)
        ci[I_REJECTED] = get(b, U_REJECTED)
        ci[I_STEP] = get(b, U_STEPS)
        keep_state(b, get(b, U_LB), get(b, U_TK), get(b, U_STARTED), get(b, U_PRIMED), get(b, U_STATUS),
                   get(b, U_CULPRIT), get(b, U_STEPS))


@cuda.jit(device=True)
def _start(b):
    """The drive starts: the velocities (the Nordsieck vector's, once primed) jump, the sums restart."""
    if get(b, U_PRIMED) != 0:
        b = fresh(b)
        N = b.N
        hs = getf(b, U_HS)
        i = b.tid
        while i < b.n:
            for k in range(3):
                b.st[_nv(b, 1, k, i)] -= hs * b.cf[F_JUMP + k]
            i += b.bd
    start_drive(b)
    put(b, U_STARTED, 1)


@cuda.jit(device=True)
def _prime(b, table, dl, spring):
    """The Nordsieck vector at the start (run_gear's priming), from the forces with the capped
    friction; the history's time buffer flipped. Returns the status (also in the thread's slot)."""
    h = getf(b, U_H)
    status, lb = prime(b, table, get(b, U_LB), get(b, U_TK), h)
    put(b, U_LB, lb)
    put(b, U_STATUS, status)
    b = fresh(b)
    xc, vc, ac = motion_at(b, getf(b, U_T))
    putf(b, U_HS, h)
    putf(b, U_AC, ac)
    i = b.tid
    while i < b.n:
        sphere_force(b, table, dl, i, get(b, U_LB), get(b, U_TK), getf(b, U_HS), 0.0)
        # (what the Nordsieck vector needs, read after the sum of the forces: not held through it)
        b = fresh(b)
        N = b.N
        st = b.st
        sh = b.sh
        cf = b.cf
        hs = getf(b, U_HS)
        ac = getf(b, U_AC)
        im = st[IMASS * N + i]
        ii = st[IINERT * N + i]
        for k in range(3):
            fk = dl[i, k]
            qk = dl[i, 3 + k]
            st[_nv(b, 0, k, i)] = sh[(S_X + k) * N + i]
            st[_nv(b, 1, k, i)] = hs * sh[(S_V + k) * N + i]
            st[_nv(b, 2, k, i)] = 0.5 * hs * hs * (fk * im + cf[F_GRAVITY + k] - ac * cf[F_DIRECTION + k])
            st[_nv(b, 0, 3 + k, i)] = 0.0
            st[_nv(b, 1, 3 + k, i)] = hs * sh[(S_SPIN + k) * N + i]
            st[_nv(b, 2, 3 + k, i)] = 0.5 * hs * hs * qk * ii
            for q in range(3, 6):
                st[_nv(b, q, k, i)] = 0.0
                st[_nv(b, q, 3 + k, i)] = 0.0
        if spring:
            for d in range(6):
                st[(ANCHOR + d) * N + i] = st[_nv(b, 0, d, i)]
        i += b.bd
    b = fresh(b)
    put(b, U_TK, 1 - get(b, U_TK))
    put(b, U_PRIMED, 1)
    return status


@cuda.jit(device=True)
def _moved_far(b):
    """Whether a sphere moved more than half the skin since the list was built (the block's vote)."""
    N = b.N
    st = b.st
    disp = 0.0
    i = b.tid
    while i < b.n:
        dx = st[_nv(b, 0, 0, i)] - st[REF * N + i]
        dy = st[_nv(b, 0, 1, i)] - st[(REF + 1) * N + i]
        dz = st[_nv(b, 0, 2, i)] - st[(REF + 2) * N + i]
        disp = max(disp, dx * dx + dy * dy + dz * dz)
        i += b.bd
    skin = b.cf[F_SKIN]
    return block_max(disp, b.tid, b.bd, b.red) > 0.25 * skin * skin


@cuda.jit(device=True)
def _rebuild(b, table):
    """The pair list rebuilt at the current positions; a full list stops the case at once (run_gear
    returns: the vector rescaled to the step). Returns the status (also in the thread's slot)."""
    N = b.N
    i = b.tid
    while i < b.n:
        for k in range(3):
            b.sh[(S_X + k) * N + i] = b.st[_nv(b, 0, k, i)]
        i += b.bd
    sync(b.bd)
    status = rebuild(b, table, get(b, U_LB), get(b, U_TK))
    b = fresh(b)
    put(b, U_STATUS, status)
    if status != STATUS_OK:
        ratio = getf(b, U_RATIO)
        if ratio != 1.0:
            i = b.tid
            while i < b.n:
                for d in range(6):
                    _rescale(b, i, d, ratio)
                i += b.bd
        return status
    put(b, U_LB, 1 - get(b, U_LB))
    return status


@cuda.jit(device=True)
def _predict(b, spring):
    """Each lane's spheres' Nordsieck vector rescaled to the step and predicted a step on, into the
    block's shared memory (the springs' advance noted). A barrier after."""
    N = b.N
    st = b.st
    sh = b.sh
    ratio = getf(b, U_RATIO)
    inv_h = 1.0 / getf(b, U_HS)
    i = b.tid
    while i < b.n:
        for d in range(6):
            if ratio != 1.0:
                _rescale(b, i, d, ratio)
            p0, p1, p2, p3, p4, p5 = _predicted(b, i, d)
            if d < 3:
                sh[(S_X + d) * N + i] = p0
                sh[(S_V + d) * N + i] = p1 * inv_h
            else:
                sh[(S_SPIN + d - 3) * N + i] = p1 * inv_h
            if spring:
                # what the springs advance by: this prediction against the one they were last advanced at
                sh[(S_MOVED + d) * N + i] = p0 - st[(ANCHOR + d) * N + i]
        i += b.bd
    sync(b.bd)


@cuda.jit(device=True)
def _increments(b, table, dl):
    """The forces at the prediction (no friction cap) and the corrector's increments into ``dl``; the
    attempt's status and culprit, the container's motion at the step's end into the thread's slots. A
    barrier after."""
    now = ledger(b, THIS_STEP)
    for k in range(4):
        b.cf[now + k] = 0.0
    hs = getf(b, U_HS)
    status, culprit = pair_laws(b, table, get(b, U_LB), get(b, U_TK), NO_CAP, hs)
    put(b, U_STATUS, status)
    put(b, U_CULPRIT, culprit)
    b = fresh(b)
    xc, vc, ac = motion_at(b, getf(b, U_T) + hs)
    putf(b, U_XC, xc)
    putf(b, U_VC, vc)
    putf(b, U_AC, ac)
    i = b.tid
    while i < b.n:
        st_ = sphere_force(b, table, dl, i, get(b, U_LB), get(b, U_TK), NO_CAP, getf(b, U_HS))
        if st_ != STATUS_OK:
            put(b, U_STATUS, st_)
            put(b, U_CULPRIT, i)
        # (what the increments need, read after the sum of the forces: not held through it)
        b = fresh(b)
        N = b.N
        st = b.st
        cf = b.cf
        hs = getf(b, U_HS)
        half_h2 = 0.5 * hs * hs
        ac = getf(b, U_AC)
        im = st[IMASS * N + i]
        ii = st[IINERT * N + i]
        for k in range(3):
            # (the force and torque become the sphere's increments, in place)
            dl[i, k] = half_h2 * (dl[i, k] * im + cf[F_GRAVITY + k] - ac * cf[F_DIRECTION + k]) \
                - _predicted(b, i, k)[2]
            dl[i, 3 + k] = half_h2 * dl[i, 3 + k] * ii - _predicted(b, i, 3 + k)[2]
        i += b.bd
    sync(b.bd)


@cuda.jit(device=True)
def _implicit(b, dl, last, top):
    """The friction at the corrected slip: the touching pairs' rows level by level, then each
    sphere's floor and walls by its lane; their powers and wall force into the thread's step sums."""
    now = ledger(b, THIS_STEP)
    hs = getf(b, U_HS)
    tk = get(b, U_TK)
    b.cf[now + 1] += _implicit_pairs(b, dl, get(b, U_LB), tk, hs, last, top)
    b = fresh(b)
    cf = b.cf
    i = b.tid
    while i < b.n:
        dfx, dfy, dfz, dpf = _implicit_walls(b, dl, i, tk, hs)
        cf[now + 3] += dfx * cf[F_DIRECTION] + dfy * cf[F_DIRECTION + 1] + dfz * cf[F_DIRECTION + 2]
        cf[now + 1] += dpf
        i += b.bd


@cuda.jit(device=True)
def _error(b, dl):
    """The block's largest increment (a NaN or an overflow: infinity), every thread's."""
    N = b.N
    err = 0.0
    i = b.tid
    while i < b.n:
        ri = b.sh[S_RAD * N + i]
        for k in range(3):
            if math.fabs(dl[i, k]) > err:
                err = math.fabs(dl[i, k])
            if math.fabs(dl[i, 3 + k]) * ri > err:
                err = math.fabs(dl[i, 3 + k]) * ri
        i += b.bd
    if not (err < 1e300):
        err = math.inf
    return block_max(err, b.tid, b.bd, b.red)


@cuda.jit(device=True)
def _accept(b, dl, spring):
    """An accepted step: the prediction corrected into the Nordsieck vector, the history's new buffer
    current, the clock on, this thread's ledger by the trapezoid over the step."""
    N = b.N
    st = b.st
    i = b.tid
    while i < b.n:
        for d in range(6):
            dd = dl[i, d]
            p0, p1, p2, p3, p4, p5 = _predicted(b, i, d)
            st[_nv(b, 0, d, i)] = p0 + _C0 * dd
            st[_nv(b, 1, d, i)] = p1 + _C1 * dd
            st[_nv(b, 2, d, i)] = p2 + _C2 * dd
            st[_nv(b, 3, d, i)] = p3 + _C3 * dd
            st[_nv(b, 4, d, i)] = p4 + _C4 * dd
            st[_nv(b, 5, d, i)] = p5 + _C5 * dd
            if spring:
                st[(ANCHOR + d) * N + i] = p0
        i += b.bd
    b = fresh(b)
    hs = getf(b, U_HS)
    put(b, U_TK, 1 - get(b, U_TK))
    putf(b, U_T, getf(b, U_T) + hs)
    put(b, U_STEPS, get(b, U_STEPS) + 1)
    cf = b.cf
    run = ledger(b, RUNNING)
    integ = ledger(b, INTEGRANDS)
    now = ledger(b, THIS_STEP)
    vc = getf(b, U_VC)
    fd = cf[now + 3]
    cf[run] += 0.5 * (vc * fd + cf[integ]) * hs
    cf[run + 1] += 0.5 * (cf[now] + cf[integ + 1]) * hs
    cf[run + 2] += 0.5 * (cf[now + 1] + cf[integ + 2]) * hs
    if spring:
        cf[run + 2] += cf[now + 2]
    cf[run + 3] += 0.5 * (fd + cf[integ + 3]) * hs
    cf[integ] = vc * fd
    cf[integ + 1] = cf[now]
    cf[integ + 2] = cf[now + 1]
    cf[integ + 3] = fd
