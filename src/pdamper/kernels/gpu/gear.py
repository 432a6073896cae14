"""Gear's variable-step predictor-corrector for a batch of cases on the GPU: one thread block per
case, each case with its own adaptive step (its error norm reduced over the block, its rejections
its own).

The step is :func:`pdamper.kernels.gear.run_gear`'s: the Nordsieck vector rescaled and predicted
(each thread its spheres' degrees of freedom), the neighbour rows rebuilt when a sphere moved more
than half the skin, the contact forces at the predicted state (:mod:`.verlet`'s pair and sphere
functions, with no friction cap), the corrector's increments, the friction of every touching
contact evaluated again at the corrected slip (the CPU's Gauss-Seidel sweep, in its order: the
touching pairs' rows gathered by every thread into a compact list with what does not depend on the
increments, then walked level by level, the rows that share no sphere at the same time, so that
every sphere sees its rows in the CPU's order, then the floor and the other walls, each sphere's by
its own thread, which gives the same increments since a wall row changes its own sphere alone;
calling the CPU kernels' ``corrected_friction``, kinematics and ``scatter``), the block's
largest increment as the error, a rejected step retried shorter with the contact history restored,
an accepted one corrected, its ledger summed by the trapezoid, a sample written where it ends on a
sample boundary. The clock follows the CPU stepper's spans (the settling, then segments of the
drive, each starting at its exact time).

Where the memory is: the corrector's increments live in the block's shared memory when the bed
fits (:data:`STAGED_SPHERES`; a larger bed's in global memory, with the same arithmetic), and the
prediction is not stored but recomputed from the Nordsieck vector where the step needs it (the same
operations on the same values: the same bits), a few additions against a round trip to memory.
"""

from __future__ import annotations

import math

from numba import cuda, float64, int64

from ..bundles import ContactTable
from ..contact import corrected_friction, keeps_history, pair_point_velocity, scatter
from ..forces import STATUS_NAN, STATUS_OK
from ..gear import (GEAR_C, floor_friction_step, next_step, predict_dof, shorter_step, step_to_boundary,
                    wall_friction_step)
from . import targets  # noqa: F401  (registers the damping law's dispatch for the CUDA target)
from .batch import FLAG_PRIMED, FLAG_STARTED, PAIR_ROW
from .probe import P_REBUILDS, P_ROWS, clock, lap
from .verlet import (MAX_THREADS, REDUCED, _motion, _pair_laws, _prime_contacts, _rebuild, _record_sample,
                     _sphere_force, out_of_time)

__all__ = ["gear_kernel", "batch_gear", "NO_CAP"]

#: The force loops' step argument that switches the explicit friction cap off (as the CPU's Gear).
NO_CAP = 1e-300
#: The most spheres whose corrector increments a block keeps in its shared memory (6 doubles a
#: sphere, 3 KiB a block: the implicit pair walk reads what the rows before it wrote, the error
#: norm, the walls' pass and the correction read them); a larger bed keeps them in global memory.
#: Shared memory a block takes is L1 cache its multiprocessor loses, and the step's working set
#: (the rows, the results, the spills) lives in L1: on an H200, fig4's batch took 51.1 us a step
#: with 3 KiB here, 51.4 with 12 KiB, 53.8 with the kernel before (12 KiB, the prediction stored in
#: global memory), and 57.1 against that kernel's 54.0 with 13.5 KiB more for the Nordsieck vector
#: (docs/performance.md).
STAGED_SPHERES = 64
_C0, _C1, _C2, _C3, _C4, _C5 = GEAR_C
#: The most spheres the implicit pair walk goes level by level for (the latest level of each
#: sphere is kept in the block's reduction array); a larger bed is walked by one thread.
LEVEL_SPHERES = REDUCED * MAX_THREADS
#: Whether the kernel times its phases (:mod:`.probe`): a constant of the compiled kernel, False in
#: the production kernel (its probes folded away); :func:`gear_kernel` ``(probed=True)`` compiles the
#: same source with it True.
PROBED = False

_KERNEL = {}


def gear_kernel(probed: bool = False):
    """The batch Gear kernel (compiled when first launched, once per damping law; disk-cached), or
    with ``probed`` its twin that times each phase of a step (:mod:`.probe`; not cached: numba's
    cache keys a kernel by its function's name and source, which the twins share)."""
    if probed not in _KERNEL:
        if probed:
            import types

            twin = types.FunctionType(batch_gear.__code__, dict(batch_gear.__globals__, PROBED=True),
                                      "batch_gear_probed")
            _KERNEL[probed] = cuda.jit(twin)
        else:
            _KERNEL[probed] = cuda.jit(cache=True)(batch_gear)
    return _KERNEL[probed]


@cuda.jit(device=True)
def _span(k, settle, n_samples, seg, interval):
    """Span ``k`` of the CPU stepper's clock: ``(t0, t_end, records)``: the settling first (when
    there is one), then the drive's segments."""
    if settle > 0:
        if k == 0:
            return float(-settle) * interval, 0.0, False
        k -= 1
    a = k * seg
    b = min(n_samples, a + seg)
    return float(a) * interval, float(b) * interval, True


@cuda.jit(device=True)
def _touching(c, b, i, e, li):
    """Whether entry ``e`` of sphere ``i``'s row is a pair the implicit friction pass corrects: owned
    (``j > i``), touching, with friction (``c > 0``)."""
    return li.partner[c, b, i, e] > i and li.approach_speed[c, b, i, e] != 0.0 and li.result[c, i, e, 12] > 0.0


@cuda.jit(device=True)
def _block_offset(red, tid, bd, m):
    """The block's exclusive prefix sum of ``m`` over the threads, in thread order, and its total
    (every thread calls it; a scan by doubling, one barrier a level, in two rows of ``red``)."""
    red[0, tid] = float(m)
    cuda.syncthreads()
    src = 0
    h = 1
    while h < bd:
        v = red[src, tid]
        if tid >= h:
            v += red[src, tid - h]
        red[1 - src, tid] = v
        cuda.syncthreads()
        src = 1 - src
        h *= 2
    before = int(red[src, tid]) - m
    total = int(red[src, bd - 1])
    cuda.syncthreads()
    return before, total


@cuda.jit(device=True)
def _gather_pairs(c, tid, bd, n, sp, li, gs, red, hs):
    """The touching pairs' rows of the implicit friction pass, in the CPU's order (``i`` ascending,
    then its row's entries), into the compact list ``gs.pair_rows``/``gs.pair_ends``, with what does
    not depend on the increments (:data:`~.batch.PAIR_ROW`), each by the CPU's expression. Every
    thread takes its spheres, a block's width of them at a time: it counts their rows, a scan over
    the block places them after the rows of the spheres before, then it writes them. Every thread
    of the block calls it; returns the number of rows."""
    rad = sp.radius
    inv_m = sp.inv_mass
    inv_i = sp.inv_inertia
    rows = gs.pair_rows
    ends = gs.pair_ends
    b = li.buffer[c]
    hh = 0.5 * hs * hs
    base = 0
    start = 0
    while start < n:
        i = start + tid
        m = 0
        if i < n:
            for e in range(li.length[c, b, i]):
                if _touching(c, b, i, e, li):
                    m += 1
        before, total = _block_offset(red, tid, bd, m)
        if m > 0:
            k = base + before
            ri = rad[c, i]
            for e in range(li.length[c, b, i]):
                if not _touching(c, b, i, e, li):
                    continue
                j = li.partner[c, b, i, e]
                r = li.result[c, i, e]
                rj = rad[c, j]
                tx = r[9]
                ty = r[10]
                tz = r[11]
                q = rows[c, k]
                q[0] = ri
                q[1] = rj
                q[2] = r[3]
                q[3] = r[4]
                q[4] = r[5]
                q[5] = tx
                q[6] = ty
                q[7] = tz
                q[8] = r[12]
                q[9] = r[13]
                q[10] = inv_m[c, i] + inv_m[c, j] + ri * ri * inv_i[c, i] + rj * rj * inv_i[c, j]
                q[11] = math.sqrt(tx * tx + ty * ty + tz * tz)
                q[12] = hh * inv_m[c, i]
                q[13] = hh * inv_m[c, j]
                q[14] = hh * inv_i[c, i] * ri
                q[15] = hh * inv_i[c, j] * rj
                ends[c, k, 0] = i
                ends[c, k, 1] = j
                k += 1
        base += total
        start += bd
    return base


@cuda.jit(device=True)
def _pair_row(c, k, gs, dv, dw, g, a):
    """Row ``k`` of the compact list at its corrected slip: what depends on the increments ``dv``,
    ``dw`` (the slip increment, the corrected force, the scatter into the increments of its two
    spheres); ``g = c1 / h``, ``a = c1 h / 2``. Returns its change of the friction power [W]."""
    i = gs.pair_ends[c, k, 0]
    j = gs.pair_ends[c, k, 1]
    q = gs.pair_rows[c, k]
    ri = q[0]
    rj = q[1]
    nx = q[2]
    ny = q[3]
    nz = q[4]
    tx = q[5]
    ty = q[6]
    tz = q[7]
    cf = q[8]
    kk = q[10]
    vt = q[11]
    dcx, dcy, dcz, dcn = pair_point_velocity(
        g * (dv[i, 0] - dv[j, 0]), g * (dv[i, 1] - dv[j, 1]), g * (dv[i, 2] - dv[j, 2]),
        g * (ri * dw[i, 0] + rj * dw[j, 0]), g * (ri * dw[i, 1] + rj * dw[j, 1]),
        g * (ri * dw[i, 2] + rj * dw[j, 2]), nx, ny, nz)
    gx, gy, gz, fx, fy, fz = corrected_friction(cf, q[9], kk, a, tx, ty, tz,
                                                dcx - dcn * nx, dcy - dcn * ny, dcz - dcn * nz)
    dp = -(fx * (tx + dcx - dcn * nx + a * kk * gx) + fy * (ty + dcy - dcn * ny + a * kk * gy)
           + fz * (tz + dcz - dcn * nz + a * kk * gz)) - cf * vt * vt
    scatter(dv, dw, i, j, (gx, gy, gz), (nx, ny, nz), (gx, gy, gz), q[12], q[13], q[14], q[15])
    return dp


@cuda.jit(device=True)
def _implicit_pairs(c, rows, gs, dv, dw, hs):
    """The friction of every touching sphere pair at its corrected slip, walked by one thread: the
    first part of the CPU's :func:`pdamper.kernels.gear._implicit_friction`, the same rows
    (:func:`_gather_pairs`' first ``rows`` of the compact list) in the same order (a pair's row
    changes the increments of two spheres, which the next rows read). Returns the change of the
    friction power [W]."""
    g = _C1 / hs
    a = 0.5 * _C1 * hs
    dpf = 0.0
    for k in range(rows):
        dpf += _pair_row(c, k, gs, dv, dw, g, a)
    return dpf


@cuda.jit(device=True)
def _implicit_pairs_by_level(c, tid, bd, n, rows, gs, dv, dw, red, top, hs):
    """The same walk as :func:`_implicit_pairs`, the rows that share no sphere at the same time.

    A row's level is one more than the last level of either of its spheres, taken in the CPU's
    order by one thread (the latest level of each sphere kept in the block's reduction array
    ``red``, which holds ``REDUCED x MAX_THREADS`` of them; ``top[0]`` takes the highest level to
    the block). The rows of one level touch distinct spheres, so the block's threads take them
    together, a barrier between levels; every sphere still sees its rows in the CPU's order, each
    reading what the rows before it wrote, so the increments are the single thread's to the bit.
    Each row's change of the friction power is kept in its row (column ``PAIR_ROW - 1``) and
    summed by thread 0 in the CPU's order: the same sum. Every thread of the block calls it;
    thread 0 gets the power [W], the others 0."""
    m = red.shape[1]
    ends = gs.pair_ends
    i = tid
    while i < n:
        red[i // m, i % m] = 0.0
        i += bd
    cuda.syncthreads()
    if tid == 0:
        high = 0
        for k in range(rows):
            i = ends[c, k, 0]
            j = ends[c, k, 1]
            lev = int(max(red[i // m, i % m], red[j // m, j % m])) + 1
            red[i // m, i % m] = lev
            red[j // m, j % m] = lev
            ends[c, k, 2] = lev
            high = max(high, lev)
        top[0] = high
    cuda.syncthreads()
    g = _C1 / hs
    a = 0.5 * _C1 * hs
    last = PAIR_ROW - 1
    for lev in range(1, top[0] + 1):
        k = tid
        while k < rows:
            if ends[c, k, 2] == lev:
                gs.pair_rows[c, k, last] = _pair_row(c, k, gs, dv, dw, g, a)
            k += bd
        cuda.syncthreads()
    dpf = 0.0
    if tid == 0:
        for k in range(rows):
            dpf += gs.pair_rows[c, k, last]
    cuda.syncthreads()  # (top[0] is read by every thread before anyone writes it again)
    return dpf


@cuda.jit(device=True)
def _implicit_walls(c, i, sp, wl, dl, hs):
    """The friction of sphere ``i``'s floor and other walls at their corrected slip: the rest of the
    CPU's :func:`pdamper.kernels.gear._implicit_friction`. A wall row changes its own sphere's
    increments alone, so each thread takes its spheres after all pair rows, in the CPU's order for
    each sphere (the floor, then the walls): the same increments as the CPU's one sweep. Returns
    ``(dfx, dfy, dfz, dp_f)`` of this sphere's rows."""
    rad = sp.radius
    inv_m = sp.inv_mass
    inv_i = sp.inv_inertia
    dv = dl[:, 0:3]
    dw = dl[:, 3:6]
    g = _C1 / hs
    a = 0.5 * _C1 * hs
    hh = 0.5 * hs * hs
    dfx = 0.0
    dfy = 0.0
    dfz = 0.0
    dpf = 0.0
    ri = rad[c, i]
    floor = wl.floor[c]
    if floor >= 0 and wl.approach_speed[c, i, floor] != 0.0:
        r = wl.row[c, i, floor]
        cf = r[6]
        if cf > 0.0:
            kk = inv_m[c, i] + ri * ri * inv_i[c, i]
            gx, gz, dp = floor_friction_step(cf, r[7], r[3], r[5], dv[i, 0], dv[i, 2], dw[i, 0], dw[i, 2], ri, g, a,
                                             kk)
            dpf += dp
            scatter(dv, dw, i, -1, (gx, 0.0, gz), (0.0, 1.0, 0.0), (gx, 0.0, gz), hh * inv_m[c, i], 0.0,
                    -(hh * inv_i[c, i] * ri), 0.0)
            dfx += gx
            dfz += gz
    for w in range(wl.count[c]):
        if w == floor or wl.approach_speed[c, i, w] == 0.0:
            continue
        r = wl.row[c, i, w]
        cf = r[6]
        if not (cf > 0.0):
            continue
        nx = r[0]
        ny = r[1]
        nz = r[2]
        kk = inv_m[c, i] + ri * ri * inv_i[c, i]
        gx, gy, gz, dp = wall_friction_step(cf, r[7], (nx, ny, nz), (r[3], r[4], r[5]), (dv[i, 0], dv[i, 1], dv[i, 2]),
                                            (dw[i, 0], dw[i, 1], dw[i, 2]), ri, g, a, kk)
        dpf += dp
        scatter(dv, dw, i, -1, (gx, gy, gz), (nx, ny, nz), (gx, gy, gz), hh * inv_m[c, i], 0.0,
                -(hh * inv_i[c, i] * ri), 0.0)
        dfx += gx
        dfy += gy
        dfz += gz
    return dfx, dfy, dfz, dpf


@cuda.jit(device=True)
def _rescale(nv, i, d, ratio):
    """Degree of freedom ``d`` of sphere ``i``'s Nordsieck vector ``nv`` (the case's) rescaled to a
    step ``ratio`` times the last (row q by ``ratio**q``, the CPU's ``_rescale``)."""
    f = 1.0
    for k in range(1, 6):
        f *= ratio
        nv[k, i, d] *= f


@cuda.jit(device=True)
def _predicted(nv, i, d):
    """Degree of freedom ``d`` of sphere ``i``'s Nordsieck vector ``nv`` predicted a step on (the
    CPU's ``predict_dof``): recomputed where the step needs it instead of stored and read back, a
    few additions against a global-memory round trip (the same operations on the same values: the
    same bits)."""
    return predict_dof(nv[0, i, d], nv[1, i, d], nv[2, i, d], nv[3, i, d], nv[4, i, d], nv[5, i, d])


@cuda.jit(device=True)
def _block_max(red, tid, bd, v):
    """The largest ``v`` of the block's threads (every thread calls it; all get the result)."""
    red[0, tid] = v
    cuda.syncthreads()
    h = 1
    while h < bd:
        h *= 2
    h //= 2
    while h > 0:
        if tid < h and tid + h < bd:
            if red[0, tid + h] > red[0, tid] or not (red[0, tid + h] == red[0, tid + h]):
                red[0, tid] = red[0, tid + h]
        cuda.syncthreads()
        h //= 2
    out = red[0, 0]
    cuda.syncthreads()
    return out


def batch_gear(sp, li, wl, tb, law, tlaw, mo, ct, rec, nmat, row0, gs, gc, max_steps, max_cycles):
    """Advance every case of the batch by at most ``max_steps`` attempted steps (block ``c`` is case
    ``c``), as :func:`pdamper.kernels.gear.run_gear` does over the CPU stepper's spans; with
    ``max_cycles`` > 0, also no further than the step on which its block's clock passes that many
    cycles (:func:`.verlet.out_of_time`).

    ``gs``: the Nordsieck vectors and what a rejected step restores; ``gc``: each case's Gear clock
    (:class:`pdamper.engine.cuda`); the rest as :func:`.verlet.batch_verlet`."""
    c = cuda.blockIdx.x
    tid = cuda.threadIdx.x
    bd = cuda.blockDim.x
    flags = cuda.shared.array(7, int64)
    red = cuda.shared.array((REDUCED, MAX_THREADS), float64)
    inc = cuda.shared.array((STAGED_SPHERES, 6), float64)
    top = cuda.shared.array(1, int64)
    lin = cuda.local.array((1, 3), float64)
    ang = cuda.local.array((1, 3), float64)
    table = ContactTable(law, tlaw, 0, tb[0], tb[1], tb[2], tb[3], tb[4], tb[5], tb[6], tb[7], tb[8], tb[9], tb[10])
    spring = keeps_history(tlaw)
    mv = sp.moved
    anchor = gs.anchor
    n = sp.count[c]
    pos = sp.position
    vel = sp.velocity
    omg = sp.spin
    rad = sp.radius
    inv_m = sp.inv_mass
    inv_i = sp.inv_inertia
    nord = gs.nordsieck
    gvx = mo.gravity[c, 0]
    gvy = mo.gravity[c, 1]
    gvz = mo.gravity[c, 2]
    dvx = mo.direction[c, 0]
    dvy = mo.direction[c, 1]
    dvz = mo.direction[c, 2]
    ts = gc.interval[c]
    tol = gc.tolerance[c]
    h_min = gc.h_min[c]
    h_max = gc.h_max[c]
    settle = gc.settle_samples[c]
    n_samples = gc.n_samples[c]
    seg = gc.segment_samples[c]
    n_spans = gc.spans[c]
    skin2 = 0.25 * li.skin[c] * li.skin[c]
    nt = li.tangential.shape[4]
    span = gc.span[c]
    t = gc.t[c]
    h = gc.h[c]
    hs = gc.hs[c]
    steps = ct.step[c]
    rejected = gc.rejected[c]
    s_w = ct.partials[c, tid, 0]
    s_n = ct.partials[c, tid, 1]
    s_f = ct.partials[c, tid, 2]
    s_i = ct.partials[c, tid, 3]
    q_w = gs.integrands[c, tid, 0]
    q_n = gs.integrands[c, tid, 1]
    q_f = gs.integrands[c, tid, 2]
    q_i = gs.integrands[c, tid, 3]
    if tid == 0:
        flags[0] = ct.status[c]
        flags[3] = -1
        flags[4] = ct.flags[c, FLAG_PRIMED]
        flags[5] = ct.flags[c, FLAG_STARTED]
        flags[6] = 0
    cuda.syncthreads()
    if flags[0] != STATUS_OK:
        return
    # the case's Nordsieck vector; its increments in shared memory when the bed fits
    nv = nord[c]
    if n <= STAGED_SPHERES:
        dl = inc
    else:
        dl = gs.increments[c]
    status = STATUS_OK
    culprit = -1
    done = 0
    cyc = gc.cycles
    tick = 0
    if PROBED:
        tick = clock()
    t0, t_end, recording = _span(span, settle, n_samples, seg, ts)
    start = clock()
    while span < n_spans and done < max_steps and flags[6] == 0:
        # ---- a span ends: the next one starts at its exact time (the CPU stepper's next call)
        if not (t < t_end - 1e-12 * ts):
            span += 1
            if span >= n_spans:
                break
            t0, t_end, recording = _span(span, settle, n_samples, seg, ts)
            t = t0
        # ---- the drive starts (after the settling): velocities jump, the sums restart
        if recording and flags[5] == 0:
            if flags[4] != 0:
                i = tid
                while i < n:
                    for k in range(3):
                        nv[1, i, k] = nv[1, i, k] - hs * mo.jump[c, k]
                    i += bd
            i = tid
            while i < n:
                for k in range(3):
                    vel[c, i, k] = vel[c, i, k] - mo.jump[c, k]
                i += bd
            s_w = 0.0
            s_n = 0.0
            s_f = 0.0
            s_i = 0.0
            cuda.syncthreads()
            if tid == 0:
                flags[5] = 1
            cuda.syncthreads()
        # ---- the Nordsieck vector at the start (run_gear's priming), forces with the capped friction
        if flags[4] == 0:
            st, cu = _prime_contacts(c, tid, bd, n, sp, li, table, nmat[c], row0[c], h)
            if st != STATUS_OK:
                status = st
                culprit = cu
            xc, vc, ac = _motion(mo, c, t)
            hs = h
            i = tid
            while i < n:
                _sphere_force(c, i, sp, li, wl, table, h, 0.0, lin, ang)
                im = inv_m[c, i]
                ii = inv_i[c, i]
                for k in range(3):
                    gk = gvx if k == 0 else (gvy if k == 1 else gvz)
                    dk = dvx if k == 0 else (dvy if k == 1 else dvz)
                    nv[0, i, k] = pos[c, i, k]
                    nv[1, i, k] = hs * vel[c, i, k]
                    nv[2, i, k] = 0.5 * hs * hs * (lin[0, k] * im + gk - ac * dk)
                    nv[0, i, 3 + k] = 0.0
                    nv[1, i, 3 + k] = hs * omg[c, i, k]
                    nv[2, i, 3 + k] = 0.5 * hs * hs * ang[0, k] * ii
                    for q in range(3, 6):
                        nv[q, i, k] = 0.0
                        nv[q, i, 3 + k] = 0.0
                if spring:
                    for d in range(6):
                        anchor[c, i, d] = nv[0, i, d]
                i += bd
            if status != STATUS_OK:
                flags[0] = status
                flags[3] = culprit
            cuda.syncthreads()
            if tid == 0:
                flags[4] = 1
            cuda.syncthreads()
            if flags[0] != STATUS_OK:
                break
        # ---- the step: end on the next sample boundary or the span's end
        kb, tb, hh = step_to_boundary(t, ts, h, t_end)
        ratio = 1.0
        if hh != hs:
            ratio = hh / hs
            hs = hh
        if PROBED:
            tick = lap(cyc, c, tid, 0, tick)
        # ---- neighbour rows at the current positions (the Nordsieck vector's first row)
        disp = 0.0
        i = tid
        while i < n:
            dx = nv[0, i, 0] - sp.reference[c, i, 0]
            dy = nv[0, i, 1] - sp.reference[c, i, 1]
            dz = nv[0, i, 2] - sp.reference[c, i, 2]
            disp = max(disp, dx * dx + dy * dy + dz * dz)
            i += bd
        rebuild = _block_max(red, tid, bd, disp) > skin2
        if PROBED:
            tick = lap(cyc, c, tid, 1, tick)
        if rebuild:
            if PROBED and tid == 0:
                cyc[c, P_REBUILDS] += 1
            i = tid
            while i < n:
                for k in range(3):
                    pos[c, i, k] = nv[0, i, k]
                i += bd
            cuda.syncthreads()
            st, cu = _rebuild(c, tid, bd, n, sp, li, table.modulus, nmat[c], row0[c], tlaw)
            if st != STATUS_OK:
                flags[0] = st
                flags[3] = cu
            cuda.syncthreads()
            if flags[0] != STATUS_OK:
                # a full row stops the case at once (run_gear returns): the vector rescaled to the step
                if ratio != 1.0:
                    i = tid
                    while i < n:
                        for d in range(6):
                            _rescale(nv, i, d, ratio)
                        i += bd
                break
            if PROBED:
                tick = lap(cyc, c, tid, 2, tick)
        # ---- rescale, predict, unpack; the contact history as it was
        inv_h = 1.0 / hs
        b = li.buffer[c]
        i = tid
        while i < n:
            for d in range(6):
                if ratio != 1.0:
                    _rescale(nv, i, d, ratio)
                p0, p1, p2, p3, p4, p5 = _predicted(nv, i, d)
                if d < 3:
                    pos[c, i, d] = p0
                    vel[c, i, d] = p1 * inv_h
                else:
                    omg[c, i, d - 3] = p1 * inv_h
                if spring:
                    # what the springs advance by: this prediction against the one they were last advanced at
                    mv[c, i, d] = p0 - anchor[c, i, d]
            for e in range(li.length[c, b, i]):
                gs.saved_pair[c, 0, i, e] = li.approach_speed[c, b, i, e]
                gs.saved_pair[c, 1, i, e] = li.damping[c, b, i, e]
                if spring:
                    for q in range(nt):
                        gs.saved_pair[c, 2 + q, i, e] = li.tangential[c, b, i, e, q]
            for w in range(wl.count[c]):
                gs.saved_wall[c, 0, i, w] = wl.approach_speed[c, i, w]
                gs.saved_wall[c, 1, i, w] = wl.damping[c, i, w]
                if spring:
                    for q in range(nt):
                        gs.saved_wall[c, 2 + q, i, w] = wl.tangential[c, i, w, q]
            i += bd
        tn = t + hs
        cuda.syncthreads()
        if PROBED:
            tick = lap(cyc, c, tid, 3, tick)
        # ---- forces at the prediction (no friction cap), the corrector's increments; this attempt's
        #      own status (compute_forces' on the CPU): an overlap at a rejected step's prediction is
        #      forgotten with the step, it stops the case only when the step is accepted
        p_n, p_f, e_f, status, culprit = _pair_laws(c, tid, bd, n, sp, li, table, NO_CAP, hs)
        cuda.syncthreads()
        if PROBED:
            tick = lap(cyc, c, tid, 4, tick)
        xc, vc, ac = _motion(mo, c, tn)
        half_h2 = 0.5 * hs * hs
        fwx = 0.0
        fwy = 0.0
        fwz = 0.0
        i = tid
        while i < n:
            pn, pf, ef, wx, wy, wz, st = _sphere_force(c, i, sp, li, wl, table, NO_CAP, hs, lin, ang)
            if st != STATUS_OK:
                status = st
                culprit = i
            p_n += pn
            p_f += pf
            e_f += ef
            fwx += wx
            fwy += wy
            fwz += wz
            im = inv_m[c, i]
            ii = inv_i[c, i]
            for k in range(3):
                gk = gvx if k == 0 else (gvy if k == 1 else gvz)
                dk = dvx if k == 0 else (dvy if k == 1 else dvz)
                dl[i, k] = half_h2 * (lin[0, k] * im + gk - ac * dk) - _predicted(nv, i, k)[2]
                dl[i, 3 + k] = half_h2 * ang[0, k] * ii - _predicted(nv, i, 3 + k)[2]
            i += bd
        cuda.syncthreads()
        if PROBED:
            tick = lap(cyc, c, tid, 5, tick)
        # ---- the friction at the corrected slip, in the CPU's order: the touching pairs' rows
        #      gathered by every thread into a compact list, then walked level by level (each sphere's
        #      rows in the CPU's order), then each sphere's floor and walls by its own thread (a law with history, the spring, leaves no
        #      friction rows: nothing to correct, and no block waits for the walk)
        if not spring:
            rows = _gather_pairs(c, tid, bd, n, sp, li, gs, red, hs)
            cuda.syncthreads()  # every thread's rows written before the walk reads them
            if PROBED:
                tick = lap(cyc, c, tid, 6, tick)
                if tid == 0:
                    cyc[c, P_ROWS] += rows
            # (the walk's reads wait on its own writes: the increments are in shared memory when they fit)
            if rows > 0:
                if n <= LEVEL_SPHERES:
                    p_f += _implicit_pairs_by_level(c, tid, bd, n, rows, gs, dl[:, 0:3], dl[:, 3:6], red, top, hs)
                elif tid == 0:
                    p_f += _implicit_pairs(c, rows, gs, dl[:, 0:3], dl[:, 3:6], hs)
            cuda.syncthreads()
            if PROBED:
                tick = lap(cyc, c, tid, 7, tick)
            i = tid
            while i < n:
                dfx, dfy, dfz, dpf = _implicit_walls(c, i, sp, wl, dl, hs)
                fwx += dfx
                fwy += dfy
                fwz += dfz
                p_f += dpf
                i += bd
            cuda.syncthreads()
            if PROBED:
                tick = lap(cyc, c, tid, 8, tick)
        # ---- the error: the block's largest increment
        err = 0.0
        i = tid
        while i < n:
            ri = rad[c, i]
            for k in range(3):
                if math.fabs(dl[i, k]) > err:
                    err = math.fabs(dl[i, k])
                if math.fabs(dl[i, 3 + k]) * ri > err:
                    err = math.fabs(dl[i, 3 + k]) * ri
            i += bd
        if not (err < 1e300):
            err = math.inf
        err = _block_max(red, tid, bd, err)
        done += 1
        if PROBED:
            tick = lap(cyc, c, tid, 9, tick)
        if not (err < 1e300):
            status = STATUS_NAN
            if tid == 0:
                flags[0] = status
            cuda.syncthreads()
            break
        if err > 4.0 * tol and hs > h_min * 1.000001:
            # reject: the contact history as it was, a shorter step (the Nordsieck vector is untouched)
            i = tid
            while i < n:
                for e in range(li.length[c, b, i]):
                    li.approach_speed[c, b, i, e] = gs.saved_pair[c, 0, i, e]
                    li.damping[c, b, i, e] = gs.saved_pair[c, 1, i, e]
                    if spring:
                        for q in range(nt):
                            li.tangential[c, b, i, e, q] = gs.saved_pair[c, 2 + q, i, e]
                for w in range(wl.count[c]):
                    wl.approach_speed[c, i, w] = gs.saved_wall[c, 0, i, w]
                    wl.damping[c, i, w] = gs.saved_wall[c, 1, i, w]
                    if spring:
                        for q in range(nt):
                            wl.tangential[c, i, w, q] = gs.saved_wall[c, 2 + q, i, w]
                i += bd
            h = shorter_step(hs, tol, err, h_min)
            rejected += 1
            if tid == 0 and out_of_time(start, max_cycles):
                flags[6] = 1
            cuda.syncthreads()
            if PROBED:
                tick = lap(cyc, c, tid, 10, tick)
            continue
        # ---- accept: correct the prediction into the Nordsieck vector
        i = tid
        while i < n:
            for d in range(6):
                dd = dl[i, d]
                p0, p1, p2, p3, p4, p5 = _predicted(nv, i, d)
                nv[0, i, d] = p0 + _C0 * dd
                nv[1, i, d] = p1 + _C1 * dd
                nv[2, i, d] = p2 + _C2 * dd
                nv[3, i, d] = p3 + _C3 * dd
                nv[4, i, d] = p4 + _C4 * dd
                nv[5, i, d] = p5 + _C5 * dd
                if spring:
                    anchor[c, i, d] = p0
            i += bd
        t = tn
        steps += 1
        fd = fwx * dvx + fwy * dvy + fwz * dvz
        s_w += 0.5 * (vc * fd + q_w) * hs
        s_n += 0.5 * (p_n + q_n) * hs
        s_f += 0.5 * (p_f + q_f) * hs
        if spring:
            s_f += e_f
        s_i += 0.5 * (fd + q_i) * hs
        q_w = vc * fd
        q_n = p_n
        q_f = p_f
        q_i = fd
        if status != STATUS_OK:
            flags[0] = status
            flags[3] = culprit
        h = next_step(hs, h, tol, err, h_min, h_max)
        if tid == 0 and out_of_time(start, max_cycles):
            flags[6] = 1
        cuda.syncthreads()
        if PROBED:
            tick = lap(cyc, c, tid, 11, tick)
        if flags[0] != STATUS_OK:
            break
        # ---- a sample ends on this step: the block's sums, the energies, a frame
        if recording and math.fabs(t - tb) <= 1e-9 * ts:
            kk = kb - 1
            i = tid
            while i < n:
                for k in range(3):
                    pos[c, i, k] = nv[0, i, k]
                    vel[c, i, k] = nv[1, i, k] * inv_h
                    omg[c, i, k] = nv[1, i, 3 + k] * inv_h
                i += bd
            cuda.syncthreads()
            _record_sample(c, tid, bd, n, kk, sp, li, wl, mo, ct, rec, red, s_i, s_w, s_n, s_f, xc, vc, spring)
            s_i = 0.0
            if PROBED:
                tick = lap(cyc, c, tid, 12, tick)
    # ---- the state in the bodies (once there is a Nordsieck vector); the clock, the flags and the
    #      running sums for the next launch
    if flags[4] != 0:
        i = tid
        while i < n:
            for k in range(3):
                pos[c, i, k] = nv[0, i, k]
                vel[c, i, k] = nv[1, i, k] * (1.0 / hs)
                omg[c, i, k] = nv[1, i, 3 + k] * (1.0 / hs)
            i += bd
    ct.partials[c, tid, 0] = s_w
    ct.partials[c, tid, 1] = s_n
    ct.partials[c, tid, 2] = s_f
    ct.partials[c, tid, 3] = s_i
    gs.integrands[c, tid, 0] = q_w
    gs.integrands[c, tid, 1] = q_n
    gs.integrands[c, tid, 2] = q_f
    gs.integrands[c, tid, 3] = q_i
    cuda.syncthreads()
    if tid == 0:
        if span >= n_spans or not (t < t_end - 1e-12 * ts) and span == n_spans - 1:
            span = n_spans
        gc.span[c] = span
        gc.t[c] = t
        gc.h[c] = h
        gc.hs[c] = hs
        gc.rejected[c] = rejected
        ct.step[c] = steps
        ct.flags[c, FLAG_STARTED] = flags[5]
        ct.flags[c, FLAG_PRIMED] = flags[4]
        if flags[0] != STATUS_OK:
            ct.status[c] = flags[0]
            ct.culprit[c] = flags[3]
            ct.fail_step[c] = steps
            gc.t[c] = t
