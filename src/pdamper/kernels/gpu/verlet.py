"""Velocity Verlet for a batch of cases on the GPU: one thread block per case, threads over spheres.

The step is :func:`pdamper.kernels.verlet.run_verlet`'s, with the same expressions in the same
order per sphere: half kick and drift (``x += dt (v + dt/2 a)``, velocities predicted to the full
step), the contact forces at the new positions, the container's acceleration as a pseudo-force,
the half kick with the new accelerations. The contact law, the contact-point kinematics, the walls'
distance and :func:`~pdamper.kernels.contact.scatter` are the CPU kernels' own compiled functions
(:mod:`pdamper.kernels.gpu`).

**One step of a block** (two barriers):

1. a list rebuild when a sphere moved more than half the skin in the previous step (each thread
   builds its spheres' rows, carries the history over, then finds the owner entry of each pair it
   does not own);
2. the drift of each thread's spheres, which flags a rebuild for the next step; barrier;
3. the contact law of every *owned* pair (:mod:`.batch`), its result stored in the owner's row;
   barrier;
4. each sphere sums its pairs in ascending partner order (the CPU pair loop's order for it), then
   the floor and the other walls (computed here: a sphere-wall contact concerns one thread), and
   takes the half kick.

The energy ledger and the wall force's impulse are summed by each thread for its own spheres and
added up over the block at the end of each sample (a sum of sums: equal to the CPU's running
sums to rounding, not bit for bit). A failed step (an overlap beyond the limit, a non-finite
velocity, a full list row) stops its case; the others go on.

A launch advances every case by at most ``max_steps`` steps, and with ``max_cycles`` no further than
the step on which its block has run that many cycles; the state, the clock and each thread's
running sums stay in the bundles, so the next launch goes on where it stopped.
"""

from __future__ import annotations

import math

from numba import cuda, float64, int64

from ...contact.hertz import hertz_energy, hertz_stiffness
from ...contact.tangential_spring import spring_energy
from ...geometry.walls import wall_distance
from ..bundles import ContactConstants, ContactGeometry, ContactTable
from ..contact import (FRICTION_CAP, contact, drop_history, floor_slip, keeps_history, pair_point_velocity, scatter,
                       wall_point_velocity)
from ..drive import parametric_motion
from ..forces import STATUS_LIST_OVERFLOW, STATUS_NAN, STATUS_OK, STATUS_OVERLAP, pair_geometry
from . import targets  # noqa: F401  (registers the damping law's dispatch for the CUDA target)
from .batch import FLAG_MOVED, FLAG_PRIMED, FLAG_STARTED
from .probe import clock

__all__ = ["verlet_kernel", "batch_verlet", "out_of_time", "MAX_THREADS", "REDUCED"]

#: Threads of a block at most (the shared buffer of the block sums is sized for it).
MAX_THREADS = 256
#: Values summed over a block at the end of a sample: impulse, work, damping, friction, kinetic,
#: rotational, potential and elastic energy.
REDUCED = 8

_KERNEL = []


def verlet_kernel():
    """The batch Verlet kernel (compiled when first launched, once per damping law: the law's
    marker is an argument, and its type picks the law; cached on disk by numba-cuda)."""
    if not _KERNEL:
        _KERNEL.append(cuda.jit(cache=True)(batch_verlet))
    return _KERNEL[0]


@cuda.jit(device=True)
def out_of_time(start, max_cycles):
    """Whether a launch bounded by time has used its ``max_cycles`` (> 0; 0: bounded by steps alone)
    since ``start``, both by the block's cycle counter (:func:`.probe.clock`: the host's nanoseconds
    in the simulator). Bounded by time, each case of a launch takes as many steps as its own step's
    cost allows, so that a cheap case does not wait for the batch's slowest at every launch, as it
    does when every case takes the same number of steps. Read by thread 0 once a step."""
    return max_cycles > 0 and clock() - start >= max_cycles


@cuda.jit(device=True)
def _case_time(g, dt, settle, seg_steps, seg_samples, interval):
    """The time [s] at the end of step ``g`` (counted from 1 at the start of the settling; 0: the
    start), as the CPU engine's clock gives it: the settling from ``-settle dt``, the drive in
    segments of ``seg_samples`` samples whose clock restarts at their first sample
    (:meth:`pdamper.simulation.Simulation.advance`)."""
    if g <= settle:
        return float(-settle) * dt + float(g) * dt
    q = g - settle
    j = (q - 1) // seg_steps
    return float(j * seg_samples) * interval + float(q - j * seg_steps) * dt


@cuda.jit(device=True)
def _motion(mo, c, t):
    """The container's (position, velocity, acceleration) along the drive at ``t`` (the kernels'
    own function of the drive's kind number and parameters)."""
    return parametric_motion(mo.kind[c], mo.par[c, 0], mo.par[c, 1], mo.par[c, 2], t)


@cuda.jit(device=True)
def _rebuild(c, tid, bd, n, sp, li, modulus, nmat, row0, tlaw):
    """Rebuild this thread's rows into the other buffer, carrying the owned pairs' history over;
    after a barrier, the owner entry of every pair a row does not own; then swap the buffers.
    Every thread of the block calls it. Returns ``(status, culprit)`` (a full row: list overflow)."""
    pos = sp.position
    rad = sp.radius
    mass = sp.mass
    partner = li.partner
    plen = li.length
    pvin = li.approach_speed
    pd = li.damping
    pth = li.tangential
    nt = pth.shape[4]
    spring = keeps_history(tlaw)
    skin = li.skin[c]
    cap_rows = partner.shape[3]
    b = li.buffer[c]
    nb = 1 - b
    status = STATUS_OK
    culprit = -1
    i = tid
    while i < n:
        m = 0
        for j in range(n):
            if j == i:
                continue
            lo = i if i < j else j
            hi = j if i < j else i
            # the CPU build's test, in the pair's own orientation (both rows agree)
            dx = pos[c, hi, 0] - pos[c, lo, 0]
            dy = pos[c, hi, 1] - pos[c, lo, 1]
            dz = pos[c, hi, 2] - pos[c, lo, 2]
            cut = (rad[c, lo] + skin) + rad[c, hi]
            if dx * dx + dy * dy + dz * dz < cut * cut:
                if m >= cap_rows:
                    status = STATUS_LIST_OVERFLOW
                    culprit = i
                    break
                partner[c, nb, i, m] = j
                v = 0.0
                d = 0.0
                if j > i:
                    e_old = -1
                    for e in range(plen[c, b, i]):
                        if partner[c, b, i, e] == j:
                            v = pvin[c, b, i, e]
                            d = pd[c, b, i, e]
                            e_old = e
                            break
                    if spring:
                        # the tangential history too (transfer_history's), zero for a new pair
                        for q in range(nt):
                            pth[c, nb, i, m, q] = pth[c, b, i, e_old, q] if e_old >= 0 else 0.0
                    mp = row0 + sp.material[c, i] * nmat + sp.material[c, j]
                    li.material_pair[c, i, m] = mp
                    rs = rad[c, i] * rad[c, j] / (rad[c, i] + rad[c, j])
                    li.stiffness[c, i, m] = hertz_stiffness(modulus[mp], rs)
                    li.friction_cap[c, i, m] = FRICTION_CAP * mass[c, i] * mass[c, j] / (mass[c, i] + mass[c, j])
                pvin[c, nb, i, m] = v
                pd[c, nb, i, m] = d
                m += 1
        plen[c, nb, i] = m
        for k in range(3):
            sp.reference[c, i, k] = pos[c, i, k]
        i += bd
    cuda.syncthreads()
    i = tid
    while i < n:
        for e in range(plen[c, nb, i]):
            j = partner[c, nb, i, e]
            if j < i:
                for q in range(plen[c, nb, j]):
                    if partner[c, nb, j, q] == i:
                        li.slot[c, i, e] = q
                        break
        i += bd
    cuda.syncthreads()
    if tid == 0:
        li.buffer[c] = nb
    cuda.syncthreads()
    return status, culprit


@cuda.jit(device=True)
def _prime_contacts(c, tid, bd, n, sp, li, table, nmat, row0, dt):
    """The contacts at the start of a run (the CPU's priming evaluation): the lists built, the owned
    pairs' law evaluated with the springs not advanced (nothing moved; ``dt``: the tanh law's friction
    guard's step), then a barrier. Every thread of the block calls it. Returns ``(status, culprit)``
    of the rebuild."""
    mv = sp.moved
    i = tid
    while i < n:
        for k in range(6):
            mv[c, i, k] = 0.0
        i += bd
    st, cu = _rebuild(c, tid, bd, n, sp, li, table.modulus, nmat, row0, table.tangential)
    _pair_laws(c, tid, bd, n, sp, li, table, dt, 0.0)
    cuda.syncthreads()
    return st, cu


@cuda.jit(device=True)
def _pair_laws(c, tid, bd, n, sp, li, table, dt, step):
    """The contact law of every pair this thread's spheres own (the CPU pair loop's arithmetic:
    :func:`~pdamper.kernels.forces.pair_geometry`, the contact points' displacement for a law with
    history, :func:`~pdamper.kernels.contact.contact`), its result kept in the owner's row; a pair
    that opened has its history dropped. ``dt``: the tanh law's friction guard's step, ``step``: the
    step taken (as :func:`~pdamper.kernels.forces.compute_forces`). Returns ``(p_normal,
    p_friction, e_friction, status, culprit)``."""
    pos = sp.position
    vel = sp.velocity
    omg = sp.spin
    rad = sp.radius
    mv = sp.moved
    b = li.buffer[c]
    partner = li.partner
    pvin = li.approach_speed
    pd = li.damping
    friction = table.friction
    limit = table.overlap_limit
    tlaw = table.tangential
    spring = keeps_history(tlaw)
    p_n = 0.0
    p_f = 0.0
    e_f = 0.0
    status = STATUS_OK
    culprit = -1
    i = tid
    while i < n:
        ri = rad[c, i]
        th = li.tangential[c, b, i]
        for e in range(li.length[c, b, i]):
            j = partner[c, b, i, e]
            if j < i:
                continue
            dx = pos[c, j, 0] - pos[c, i, 0]
            dy = pos[c, j, 1] - pos[c, i, 1]
            dz = pos[c, j, 2] - pos[c, i, 2]
            rj = rad[c, j]
            cut = ri + rj
            d2 = dx * dx + dy * dy + dz * dz
            if d2 >= cut * cut:
                if pvin[c, b, i, e] != 0.0:
                    pvin[c, b, i, e] = 0.0
                    e_f += drop_history(tlaw, th, e)
                continue
            nx, ny, nz, delta, ddot, tx, ty, tz, vt = pair_geometry(
                dx, dy, dz, d2, cut, vel[c, i, 0] - vel[c, j, 0], vel[c, i, 1] - vel[c, j, 1],
                vel[c, i, 2] - vel[c, j, 2], ri * omg[c, i, 0] + rj * omg[c, j, 0],
                ri * omg[c, i, 1] + rj * omg[c, j, 1], ri * omg[c, i, 2] + rj * omg[c, j, 2])
            if delta > limit * min(ri, rj):
                status = STATUS_OVERLAP
                culprit = i
            dsx = dsy = dsz = 0.0
            if spring:
                dsx, dsy, dsz, dsn = pair_point_velocity(
                    mv[c, i, 0] - mv[c, j, 0], mv[c, i, 1] - mv[c, j, 1], mv[c, i, 2] - mv[c, j, 2],
                    ri * mv[c, i, 3] + rj * mv[c, j, 3], ri * mv[c, i, 4] + rj * mv[c, j, 4],
                    ri * mv[c, i, 5] + rj * mv[c, j, 5], nx, ny, nz)
            cap = li.friction_cap[c, i, e]
            mp = li.material_pair[c, i, e]
            fn, ftx, fty, ftz, ff, lim, vin, dd, pn, pf, ef = contact(
                table, th, e, ContactConstants(mp, friction[mp], li.stiffness[c, i, e], ri * rj / cut, cap / FRICTION_CAP,
                                               cap),
                ContactGeometry(delta, ddot, nx, ny, nz, tx, ty, tz, vt, dsx, dsy, dsz), pvin[c, b, i, e],
                pd[c, b, i, e], dt, step)
            pvin[c, b, i, e] = vin
            pd[c, b, i, e] = dd
            p_n += pn
            p_f += pf
            e_f += ef
            r = li.result[c, i, e]
            r[0] = -fn * nx + ftx
            r[1] = -fn * ny + fty
            r[2] = -fn * nz + ftz
            r[3] = nx
            r[4] = ny
            r[5] = nz
            r[6] = ftx
            r[7] = fty
            r[8] = ftz
            r[9] = tx
            r[10] = ty
            r[11] = tz
            r[12] = ff
            r[13] = lim
        i += bd
    return p_n, p_f, e_f, status, culprit


@cuda.jit(device=True)
def _note_wall(r, nx, ny, nz, tx, ty, tz, c, lim):
    """A sphere-wall contact's friction row (the normal, the slip, c, the Coulomb limit)."""
    r[0] = nx
    r[1] = ny
    r[2] = nz
    r[3] = tx
    r[4] = ty
    r[5] = tz
    r[6] = c
    r[7] = lim


@cuda.jit(device=True)
def _sphere_force(c, i, sp, li, wl, table, dt, step, lin, ang):
    """Force and torque on sphere ``i`` into ``lin[0]``, ``ang[0]``: its pairs in ascending partner
    order (the owned pairs' results), the floor, then the other walls (their contact law here: each
    concerns this sphere alone; the CPU wall loops' arithmetic). Returns ``(p_normal, p_friction,
    e_friction, fwx, fwy, fwz, status)`` of its wall contacts (the force of the walls on it [N])."""
    pos = sp.position
    vel = sp.velocity
    omg = sp.spin
    mv = sp.moved
    b = li.buffer[c]
    pvin = li.approach_speed
    res = li.result
    friction = table.friction
    limit = table.overlap_limit
    tlaw = table.tangential
    spring = keeps_history(tlaw)
    wvin = wl.approach_speed
    wd = wl.damping
    wth = wl.tangential[c, i]
    floor = wl.floor[c]
    for k in range(3):
        lin[0, k] = 0.0
        ang[0, k] = 0.0
    ri = sp.radius[c, i]
    for e in range(li.length[c, b, i]):
        j = li.partner[c, b, i, e]
        if j > i:
            if pvin[c, b, i, e] != 0.0:
                r = res[c, i, e]
                scatter(lin, ang, 0, -1, (r[0], r[1], r[2]), (r[3], r[4], r[5]), (r[6], r[7], r[8]), 1.0, 0.0, ri,
                        0.0)
        else:
            q = li.slot[c, i, e]
            if pvin[c, b, j, q] != 0.0:
                r = res[c, j, q]
                scatter(lin, ang, 0, -1, (-r[0], -r[1], -r[2]), (r[3], r[4], r[5]), (r[6], r[7], r[8]), 1.0, 0.0, ri,
                        0.0)
    p_n = 0.0
    p_f = 0.0
    e_f = 0.0
    fwx = 0.0
    fwy = 0.0
    fwz = 0.0
    status = STATUS_OK
    mi = sp.mass[c, i]
    if floor >= 0:
        delta = ri - pos[c, i, 1]
        if delta <= 0.0:
            if wvin[c, i, floor] != 0.0:
                wvin[c, i, floor] = 0.0
                e_f += drop_history(tlaw, wth, floor)
        else:
            if delta > limit * ri:
                status = STATUS_OVERLAP
            ddot = -vel[c, i, 1]
            tx, tz = floor_slip(vel[c, i, 0], vel[c, i, 2], omg[c, i, 0], omg[c, i, 2], ri)
            vt = math.sqrt(tx * tx + tz * tz)
            dsx = dsz = 0.0
            if spring:
                dsx, dsz = floor_slip(mv[c, i, 0], mv[c, i, 2], mv[c, i, 3], mv[c, i, 5], ri)
            mp = wl.material_pair[c, i, floor]
            fn, ftx, fty, ftz, ff, lim, vin, dd, pn, pf, ef = contact(
                table, wth, floor,
                ContactConstants(mp, friction[mp], wl.stiffness[c, i, floor], wl.effective_radius[c, i, floor], mi,
                                 FRICTION_CAP * mi),
                ContactGeometry(delta, ddot, 0.0, 1.0, 0.0, tx, 0.0, tz, vt, dsx, 0.0, dsz), wvin[c, i, floor],
                wd[c, i, floor], dt, step)
            wvin[c, i, floor] = vin
            wd[c, i, floor] = dd
            p_n += pn
            p_f += pf
            e_f += ef
            _note_wall(wl.row[c, i, floor], 0.0, 1.0, 0.0, tx, 0.0, tz, ff, lim)
            scatter(lin, ang, 0, -1, (ftx, fn, ftz), (0.0, 1.0, 0.0), (ftx, 0.0, ftz), 1.0, 0.0, -ri, 0.0)
            fwx += ftx
            fwy += fn
            fwz += ftz
    wdata = wl.data[c]
    for w in range(wl.count[c]):
        if w == floor:
            continue
        s, nx, ny, nz = wall_distance(wl.kind[c, w], wdata, w, pos[c, i, 0], pos[c, i, 1], pos[c, i, 2])
        delta = ri - s
        if delta <= 0.0:
            if wvin[c, i, w] != 0.0:
                wvin[c, i, w] = 0.0
                e_f += drop_history(tlaw, wth, w)
            continue
        if delta > limit * ri:
            status = STATUS_OVERLAP
        vx = vel[c, i, 0]
        vy = vel[c, i, 1]
        vz = vel[c, i, 2]
        ddot = -(vx * nx + vy * ny + vz * nz)
        cvx, cvy, cvz, cn = wall_point_velocity(vx, vy, vz, omg[c, i, 0], omg[c, i, 1], omg[c, i, 2], ri, nx, ny, nz)
        tx = cvx - cn * nx
        ty = cvy - cn * ny
        tz = cvz - cn * nz
        vt = math.sqrt(tx * tx + ty * ty + tz * tz)
        dsx = dsy = dsz = 0.0
        if spring:
            dsx, dsy, dsz, dsn = wall_point_velocity(mv[c, i, 0], mv[c, i, 1], mv[c, i, 2], mv[c, i, 3], mv[c, i, 4],
                                                     mv[c, i, 5], ri, nx, ny, nz)
        mp = wl.material_pair[c, i, w]
        fn, ftx, fty, ftz, ff, lim, vin, dd, pn, pf, ef = contact(
            table, wth, w,
            ContactConstants(mp, friction[mp], wl.stiffness[c, i, w], wl.effective_radius[c, i, w], mi,
                             FRICTION_CAP * mi),
            ContactGeometry(delta, ddot, nx, ny, nz, tx, ty, tz, vt, dsx, dsy, dsz), wvin[c, i, w], wd[c, i, w], dt,
            step)
        wvin[c, i, w] = vin
        wd[c, i, w] = dd
        p_n += pn
        p_f += pf
        e_f += ef
        fx = fn * nx + ftx
        fy = fn * ny + fty
        fz = fn * nz + ftz
        _note_wall(wl.row[c, i, w], nx, ny, nz, tx, ty, tz, ff, lim)
        scatter(lin, ang, 0, -1, (fx, fy, fz), (nx, ny, nz), (ftx, fty, ftz), 1.0, 0.0, -ri, 0.0)
        fwx += fx
        fwy += fy
        fwz += fz
    return p_n, p_f, e_f, fwx, fwy, fwz, status


@cuda.jit(device=True)
def _elastic(c, i, sp, li, wl, spring):
    """Energy [J] in the Hertz springs of sphere ``i``'s owned pairs and its walls, and in their
    tangential springs under a law with history (``spring``)."""
    pos = sp.position
    rad = sp.radius
    b = li.buffer[c]
    ri = rad[c, i]
    e_el = 0.0
    for e in range(li.length[c, b, i]):
        j = li.partner[c, b, i, e]
        if j > i:
            dx = pos[c, j, 0] - pos[c, i, 0]
            dy = pos[c, j, 1] - pos[c, i, 1]
            dz = pos[c, j, 2] - pos[c, i, 2]
            delta = ri + rad[c, j] - math.sqrt(dx * dx + dy * dy + dz * dz)
            if delta > 0.0:
                e_el += hertz_energy(li.stiffness[c, i, e], delta)
    floor = wl.floor[c]
    wdata = wl.data[c]
    for w in range(wl.count[c]):
        if w == floor:
            delta = ri - pos[c, i, 1]
        else:
            s, nx, ny, nz = wall_distance(wl.kind[c, w], wdata, w, pos[c, i, 0], pos[c, i, 1], pos[c, i, 2])
            delta = ri - s
        if delta > 0.0:
            e_el += hertz_energy(wl.stiffness[c, i, w], delta)
    if spring:
        # the tangential springs (elastic_energy's): the owned pairs' rows and the walls'
        th = li.tangential[c, b, i]
        for e in range(li.length[c, b, i]):
            if li.partner[c, b, i, e] > i and th[e, 3] > 0.0:
                e_el += spring_energy(th[e, 0], th[e, 1], th[e, 2], th[e, 3])
        wth = wl.tangential[c, i]
        for w in range(wl.count[c]):
            if wth[w, 3] > 0.0:
                e_el += spring_energy(wth[w, 0], wth[w, 1], wth[w, 2], wth[w, 3])
    return e_el


@cuda.jit(device=True)
def _record_sample(c, tid, bd, n, kk, sp, li, wl, mo, ct, rec, red, s_i, s_w, s_n, s_f, xc, vc, spring):
    """Sample ``kk`` of case ``c`` (:func:`pdamper.kernels.record.record_sample`): the block's sums of the
    threads' impulse and ledger (``s_i``, ``s_w``, ``s_n``, ``s_f``), the energies, a frame; every thread
    of the block calls it (the container at ``xc`` [m], moving at ``vc`` [m/s])."""
    pos = sp.position
    vel = sp.velocity
    omg = sp.spin
    inv_i = sp.inv_inertia
    gvx = mo.gravity[c, 0]
    gvy = mo.gravity[c, 1]
    gvz = mo.gravity[c, 2]
    dvx = mo.direction[c, 0]
    dvy = mo.direction[c, 1]
    dvz = mo.direction[c, 2]
    ekin = 0.0
    erot = 0.0
    epot = 0.0
    eel = 0.0
    erec = kk < rec.energy_rows[c]
    if erec:
        i = tid
        while i < n:
            mi = sp.mass[c, i]
            ux = vel[c, i, 0] + vc * dvx
            uy = vel[c, i, 1] + vc * dvy
            uz = vel[c, i, 2] + vc * dvz
            ekin += 0.5 * mi * (ux * ux + uy * uy + uz * uz)
            erot += 0.5 / inv_i[c, i] * (omg[c, i, 0] ** 2 + omg[c, i, 1] ** 2 + omg[c, i, 2] ** 2)
            epot -= mi * (gvx * pos[c, i, 0] + gvy * pos[c, i, 1] + gvz * pos[c, i, 2])
            eel += _elastic(c, i, sp, li, wl, spring)
            i += bd
    red[0, tid] = s_i
    red[1, tid] = s_w
    red[2, tid] = s_n
    red[3, tid] = s_f
    red[4, tid] = ekin
    red[5, tid] = erot
    red[6, tid] = epot
    red[7, tid] = eel
    cuda.syncthreads()
    h = 1
    while h < bd:
        h *= 2
    h //= 2
    while h > 0:
        if tid < h and tid + h < bd:
            for q in range(REDUCED):
                red[q, tid] += red[q, tid + h]
        cuda.syncthreads()
        h //= 2
    if tid == 0:
        if kk < rec.wall_force_rows[c]:
            rec.wall_force[c, kk] = red[0, 0] / ct.sample_interval[c]
        if erec:
            epot = red[6, 0]
            # the lab frame's potential energy (record_sample): the bed raised with the container
            gd = gvx * dvx + gvy * dvy + gvz * dvz
            if abs(gd) > 1e-12 * math.sqrt(gvx ** 2 + gvy ** 2 + gvz ** 2):
                epot -= rec.bed_mass[c] * gd * xc
            rec.energy[c, kk, 0] = red[4, 0]
            rec.energy[c, kk, 1] = red[5, 0]
            rec.energy[c, kk, 2] = epot
            rec.energy[c, kk, 3] = red[7, 0]
            rec.energy[c, kk, 4] = red[1, 0]
            rec.energy[c, kk, 5] = red[2, 0]
            rec.energy[c, kk, 6] = red[3, 0]
    every = rec.frame_every[c]
    if every > 0 and (kk + 1) % every == 0:
        f = (kk + 1) // every - 1
        if f < rec.frame_rows[c]:
            i = tid
            while i < n:
                for k in range(3):
                    rec.frames[c, f, i, k] = pos[c, i, k]
                    rec.frames[c, f, i, 3 + k] = vel[c, i, k]
                    rec.frames[c, f, i, 6 + k] = omg[c, i, k]
                i += bd
    cuda.syncthreads()


def batch_verlet(sp, li, wl, tb, law, tlaw, mo, ct, rec, nmat, row0, max_steps, max_cycles):
    """Advance every case of the batch by at most ``max_steps`` steps: block ``c`` is case ``c``;
    with ``max_cycles`` > 0, also no further than the step on which its block's clock passes that
    many cycles (:func:`out_of_time`).

    ``sp``, ``li``, ``wl``, ``mo``, ``ct``, ``rec``: the batch's bundles (:mod:`.batch`); ``tb`` the
    contact table's arrays and constants of every case (rows ``row0[c]`` on; ``nmat[c]`` materials),
    ``law`` and ``tlaw`` the damping and tangential laws' markers (their types pick the laws when the
    kernel is compiled)."""
    c = cuda.blockIdx.x
    tid = cuda.threadIdx.x
    bd = cuda.blockDim.x
    flags = cuda.shared.array(7, int64)
    red = cuda.shared.array((REDUCED, MAX_THREADS), float64)
    lin = cuda.local.array((1, 3), float64)
    ang = cuda.local.array((1, 3), float64)
    # the batch's contact table, with these laws' markers
    table = ContactTable(law, tlaw, 0, tb[0], tb[1], tb[2], tb[3], tb[4], tb[5], tb[6], tb[7], tb[8], tb[9], tb[10])
    spring = keeps_history(tlaw)
    mv = sp.moved
    n = sp.count[c]
    pos = sp.position
    vel = sp.velocity
    omg = sp.spin
    inv_m = sp.inv_mass
    inv_i = sp.inv_inertia
    acc = sp.acceleration
    alp = sp.angular_acceleration
    accp = sp.previous_acceleration
    alpp = sp.previous_angular_acceleration
    gvx = mo.gravity[c, 0]
    gvy = mo.gravity[c, 1]
    gvz = mo.gravity[c, 2]
    dvx = mo.direction[c, 0]
    dvy = mo.direction[c, 1]
    dvz = mo.direction[c, 2]
    dt = ct.dt[c]
    half = 0.5 * dt
    sub = ct.sub[c]
    settle = ct.settle_steps[c]
    total = ct.total_steps[c]
    seg_steps = ct.segment_steps[c]
    seg_samples = ct.segment_samples[c]
    interval = ct.interval[c]
    skin = li.skin[c]
    skin2 = 0.25 * skin * skin
    g = ct.step[c]
    # this thread's running sums: work, damping, friction, impulse
    s_w = ct.partials[c, tid, 0]
    s_n = ct.partials[c, tid, 1]
    s_f = ct.partials[c, tid, 2]
    s_i = ct.partials[c, tid, 3]
    # flags: 0 status, 1 + (g % 2) a rebuild is due after step g (two slots: the step after
    # reads one while this step's drift writes the other), 3 culprit, 4 primed, 5 started, 6 the
    # launch's time is up (thread 0 writes it before a step's last barrier, every thread reads it
    # at the top of the next, a barrier of that step before thread 0 writes it again)
    if tid == 0:
        flags[0] = ct.status[c]
        flags[1 + (g + 1) % 2] = ct.flags[c, FLAG_MOVED]
        flags[1 + g % 2] = 0
        flags[3] = -1
        flags[4] = ct.flags[c, FLAG_PRIMED]
        flags[5] = ct.flags[c, FLAG_STARTED]
        flags[6] = 0
    cuda.syncthreads()
    if flags[0] != STATUS_OK:
        return
    status = STATUS_OK
    culprit = -1
    done = 0
    start = clock()
    while g < total and done < max_steps and flags[6] == 0:
        # ---- the drive starts: velocities relative to the container jump, the sums restart
        if g == settle and flags[5] == 0:
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
        # ---- the initial accelerations (run_verlet's priming): lists and forces at the start
        if flags[4] == 0:
            st, cu = _prime_contacts(c, tid, bd, n, sp, li, table, nmat[c], row0[c], dt)
            if st != STATUS_OK:
                status = st
                culprit = cu
            xc, vc, ac = _motion(mo, c, _case_time(g, dt, settle, seg_steps, seg_samples, interval))
            i = tid
            while i < n:
                _sphere_force(c, i, sp, li, wl, table, dt, 0.0, lin, ang)
                im = inv_m[c, i]
                ii = inv_i[c, i]
                a0 = lin[0, 0] * im + gvx - ac * dvx
                acc[c, i, 0] = a0
                accp[c, i, 0] = a0
                a0 = lin[0, 1] * im + gvy - ac * dvy
                acc[c, i, 1] = a0
                accp[c, i, 1] = a0
                a0 = lin[0, 2] * im + gvz - ac * dvz
                acc[c, i, 2] = a0
                accp[c, i, 2] = a0
                for k in range(3):
                    w0 = ang[0, k] * ii
                    alp[c, i, k] = w0
                    alpp[c, i, k] = w0
                i += bd
            if status != STATUS_OK:
                flags[0] = status
                flags[3] = culprit
            cuda.syncthreads()
            if tid == 0:
                flags[4] = 1
                flags[1 + (g + 1) % 2] = 0
            cuda.syncthreads()
            if flags[0] != STATUS_OK:
                break
        t = _case_time(g + 1, dt, settle, seg_steps, seg_samples, interval)
        # ---- rebuild the lists when a sphere moved too far in the previous step
        mslot = 1 + (g + 1) % 2
        if flags[mslot] != 0:
            st, cu = _rebuild(c, tid, bd, n, sp, li, table.modulus, nmat[c], row0[c], tlaw)
            if st != STATUS_OK:
                status = st
                culprit = cu
        # ---- drift with the half-step velocity; velocities predicted to the full step
        disp = 0.0
        i = tid
        while i < n:
            if spring:
                # what the drift moves and turns the sphere by: the springs advance by it
                for k in range(3):
                    mv[c, i, k] = dt * (vel[c, i, k] + half * acc[c, i, k])
                    mv[c, i, 3 + k] = dt * (omg[c, i, k] + half * alp[c, i, k])
            for k in range(3):
                a = acc[c, i, k]
                x = pos[c, i, k] + dt * (vel[c, i, k] + half * a)
                pos[c, i, k] = x
                vel[c, i, k] = vel[c, i, k] + half * (3.0 * a - accp[c, i, k])
                omg[c, i, k] = omg[c, i, k] + half * (3.0 * alp[c, i, k] - alpp[c, i, k])
                dd = x - sp.reference[c, i, k]
                disp = max(disp, dd * dd)
            i += bd
        if 3.0 * disp > skin2:
            flags[1 + g % 2] = 1
        cuda.syncthreads()
        if tid == 0:
            flags[mslot] = 0
        # ---- the owned pairs' contact law
        p_n, p_f, e_f, st, cu = _pair_laws(c, tid, bd, n, sp, li, table, dt, dt)
        if st != STATUS_OK:
            status = st
            culprit = cu
        cuda.syncthreads()
        # ---- each sphere's force and torque, the half kick with the new accelerations
        xc, vc, ac = _motion(mo, c, t)
        gx = gvx - ac * dvx
        gy = gvy - ac * dvy
        gz = gvz - ac * dvz
        fwx = 0.0
        fwy = 0.0
        fwz = 0.0
        vsum = 0.0
        i = tid
        while i < n:
            pn, pf, ef, wx, wy, wz, st = _sphere_force(c, i, sp, li, wl, table, dt, dt, lin, ang)
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
                an = lin[0, k] * im + (gx if k == 0 else (gy if k == 1 else gz))
                vn = vel[c, i, k] + half * (an - 2.0 * acc[c, i, k] + accp[c, i, k])
                vel[c, i, k] = vn
                accp[c, i, k] = acc[c, i, k]
                acc[c, i, k] = an
                wn = ang[0, k] * ii
                omg[c, i, k] = omg[c, i, k] + half * (wn - 2.0 * alp[c, i, k] + alpp[c, i, k])
                alpp[c, i, k] = alp[c, i, k]
                alp[c, i, k] = wn
                vsum += math.fabs(vn)
            i += bd
        if not (vsum < 1e6):
            status = STATUS_NAN
            if culprit < 0:
                culprit = tid
        if status != STATUS_OK:
            flags[0] = status
            flags[3] = culprit
        fd = fwx * dvx + fwy * dvy + fwz * dvz
        s_w += vc * fd * dt
        s_n += p_n * dt
        s_f += p_f * dt
        if spring:
            s_f += e_f
        s_i += fd * dt
        g += 1
        done += 1
        if tid == 0 and out_of_time(start, max_cycles):
            flags[6] = 1
        cuda.syncthreads()
        if flags[0] != STATUS_OK:
            break
        # ---- a sample ends: the block's sums, the energies, a frame
        if g > settle and g % sub == 0:
            kk = g // sub - 1 - rec.settle_samples[c]
            _record_sample(c, tid, bd, n, kk, sp, li, wl, mo, ct, rec, red, s_i, s_w, s_n, s_f, xc, vc, spring)
            s_i = 0.0
    # ---- leave the clock, the flags and the running sums for the next launch
    ct.partials[c, tid, 0] = s_w
    ct.partials[c, tid, 1] = s_n
    ct.partials[c, tid, 2] = s_f
    ct.partials[c, tid, 3] = s_i
    cuda.syncthreads()
    if tid == 0:
        ct.step[c] = g
        ct.flags[c, FLAG_MOVED] = flags[1 + (g + 1) % 2]
        ct.flags[c, FLAG_STARTED] = flags[5]
        ct.flags[c, FLAG_PRIMED] = flags[4]
        if flags[0] != STATUS_OK:
            ct.status[c] = flags[0]
            ct.culprit[c] = flags[3]
            ct.fail_step[c] = g

