"""Contact forces of all sphere pairs and sphere-wall contacts, in the container frame.

Three loops -- the listed pairs, the floor, the other walls' candidates -- each work out the
geometry of a contact (normal, overlap, approach rate, slip at the contact point) and hand it to
the one contact law, :func:`pdamper.kernels.contact.contact`, with the contact's row of the
tangential history; then they apply its force and torque to the bodies. A contact that opens has
its history cleared (the tangential history only where the law keeps one). The floor, which every
resting sphere touches, has its own direct loop (its normal is +y, so there is no candidate list
and no distance function): about three times cheaper per contact than the general wall loop.

Conventions: pair normal n points from i to j, the overlap is ``delta = r_i + r_j - |x_j - x_i|``
and its rate ``delta_dot = (v_i - v_j).n`` (> 0 approaching). Wall normals point into the
container. Friction acts at ``r_i n`` from each centre (the contact point), making torques.
"""

from __future__ import annotations

import math

import numpy as np

from ..contact.hertz import hertz_energy
from ..contact.tangential_spring import spring_energy
from ..geometry.walls import wall_distance
from ..jit import njit
from .bundles import ContactConstants, ContactGeometry, FrictionRecord
from .contact import (FRICTION_CAP, contact, drop_history, floor_slip, keeps_history, note_friction_row,
                      pair_point_velocity, scatter, wall_point_velocity)

__all__ = ["compute_forces", "pair_geometry", "elastic_energy", "no_friction_record", "STATUS_OK", "STATUS_OVERLAP", "STATUS_NAN",
           "STATUS_LIST_OVERFLOW", "STATUS_WALL_OVERFLOW"]

STATUS_OK = 0
STATUS_LIST_OVERFLOW = 1
STATUS_WALL_OVERFLOW = 2
STATUS_OVERLAP = 3
STATUS_NAN = 4


@njit
def no_friction_record():
    """A friction record with no rows: the force loops write nothing into it (Verlet; Gear's
    priming evaluation)."""
    return FrictionRecord(np.zeros((0, 2), dtype=np.int64), np.zeros((0, 8)), np.zeros(3, dtype=np.int64))


@njit(inline="always")
def pair_geometry(dx, dy, dz, d2, cut, rvx, rvy, rvz, wx, wy, wz):
    """A touching sphere pair's contact geometry: from ``d = x_j - x_i`` (its square ``d2``), the
    contact distance ``cut = r_i + r_j``, the relative velocity ``v_i - v_j`` and ``w = r_i w_i +
    r_j w_j``: the unit normal from i to j, the overlap, its rate (> 0 approaching), the tangential
    slip at the contact point and its length. Scalars only: the CPU pair loop and the GPU engine's
    (:mod:`pdamper.kernels.gpu.verlet`) compile the same function."""
    dist = math.sqrt(d2)
    inv = 1.0 / dist
    nx = dx * inv
    ny = dy * inv
    nz = dz * inv
    ddot = rvx * nx + rvy * ny + rvz * nz
    # slip at the contact point: v_i - v_j + (r_i w_i + r_j w_j) x n, tangential part
    cvx, cvy, cvz, cn = pair_point_velocity(rvx, rvy, rvz, wx, wy, wz, nx, ny, nz)
    tx = cvx - cn * nx
    ty = cvy - cn * ny
    tz = cvz - cn * nz
    return nx, ny, nz, cut - dist, ddot, tx, ty, tz, math.sqrt(tx * tx + ty * ty + tz * tz)


@njit
def compute_forces(bodies, pairs, walls, table, dt, step, moved, record):
    """Zero and fill ``bodies.force`` [N] and ``bodies.torque`` [N m]; update the contact history
    in ``pairs`` and ``walls`` in place.

    ``dt`` [s] is the current step of the tanh law's friction guard
    (:data:`~pdamper.kernels.contact.FRICTION_CAP`; Gear passes a vanishing step), ``step`` [s] the
    step being taken (a spring's damping), ``moved`` (N, 6) what each sphere moved [m] and turned
    [rad] since a tangential law with history last advanced its springs (the contact points'
    displacements follow from it; zeros for the evaluation that primes a run; read by such a law
    only). Every touching friction contact is written into ``record``
    (:class:`~pdamper.kernels.bundles.FrictionRecord`; pairs, then the floor, then the other walls,
    ``record.ends`` their end rows) while it has room: its capacity (listed pairs + spheres + wall
    candidates) is enough by construction, and a record of no rows (Verlet) takes none.

    Returns ``(fwx, fwy, fwz, p_normal, p_friction, e_friction, status, culprit)``: the total
    force of the walls on the spheres [N], the power [W] dissipated by normal damping and by the
    tanh law's friction, the energy [J] a tangential law with history dissipated over ``step``, a
    status code (``STATUS_OVERLAP`` when an overlap exceeds ``table.overlap_limit`` x r) and the
    sphere concerned.
    """
    # the arrays the loops index, named once (a bundle's field read inside a loop costs a
    # reference count per read where numba cannot prove it away)
    pos = bodies.position
    vel = bodies.velocity
    omg = bodies.spin
    rad = bodies.radius
    mass = bodies.mass
    force = bodies.force
    torque = bodies.torque
    friction = table.friction
    row = pairs.row
    first = pairs.first
    second = pairs.second
    pvin = pairs.approach_speed
    pd = pairs.damping
    pk = pairs.stiffness
    pmp = pairs.material_pair
    pcap = pairs.friction_cap
    pth = pairs.tangential
    tlaw = table.tangential
    spring = keeps_history(tlaw)
    mv = moved
    wall_kind = walls.kind
    wall_data = walls.data
    wvin = walls.approach_speed
    wd = walls.damping
    wk = walls.stiffness
    wmp = walls.material_pair
    wrs = walls.effective_radius
    cand_i = walls.candidate_body
    cand_w = walls.candidate_wall
    nw = wall_kind.shape[0]
    n = pos.shape[0]
    # the wall contacts' tangential history with one row per (sphere, wall): row i * nw + w
    wth = walls.tangential.reshape((n * nw, walls.tangential.shape[2]))
    room = record.rows.shape[0]
    collect = room > 0
    limit = table.overlap_limit
    m = 0
    for i in range(n):
        force[i, 0] = 0.0
        force[i, 1] = 0.0
        force[i, 2] = 0.0
        torque[i, 0] = 0.0
        torque[i, 1] = 0.0
        torque[i, 2] = 0.0
    p_n = 0.0
    p_f = 0.0
    e_f = 0.0
    status = STATUS_OK
    culprit = -1
    # ---- sphere pairs: one flat loop over the list (no short inner loops whose exits mispredict)
    for a in range(row[n]):
        i = first[a]
        j = second[a]
        ri = rad[i]
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        rj = rad[j]
        cut = ri + rj
        d2 = dx * dx + dy * dy + dz * dz
        if d2 >= cut * cut:
            if pvin[a] != 0.0:
                pvin[a] = 0.0
                e_f += drop_history(tlaw, pth, a)
            continue
        nx, ny, nz, delta, ddot, tx, ty, tz, vt = pair_geometry(
            dx, dy, dz, d2, cut, vel[i, 0] - vel[j, 0], vel[i, 1] - vel[j, 1], vel[i, 2] - vel[j, 2],
            ri * omg[i, 0] + rj * omg[j, 0], ri * omg[i, 1] + rj * omg[j, 1], ri * omg[i, 2] + rj * omg[j, 2])
        if delta > limit * min(ri, rj):
            status = STATUS_OVERLAP
            culprit = i
        dsx = dsy = dsz = 0.0
        if spring:
            # the contact points' relative displacement, from the spheres' (the slip's kinematics)
            dsx, dsy, dsz, dsn = pair_point_velocity(
                mv[i, 0] - mv[j, 0], mv[i, 1] - mv[j, 1], mv[i, 2] - mv[j, 2], ri * mv[i, 3] + rj * mv[j, 3],
                ri * mv[i, 4] + rj * mv[j, 4], ri * mv[i, 5] + rj * mv[j, 5], nx, ny, nz)
        cap = pcap[a]
        mp = pmp[a]
        fn, ftx, fty, ftz, ff, lim, pvin[a], pd[a], pn, pf, ef = contact(
            table, pth, a, ContactConstants(mp, friction[mp], pk[a], ri * rj / cut, cap / FRICTION_CAP, cap),
            ContactGeometry(delta, ddot, nx, ny, nz, tx, ty, tz, vt, dsx, dsy, dsz), pvin[a], pd[a], dt, step)
        p_n += pn
        p_f += pf
        e_f += ef
        if ff > 0.0 and m < room:
            note_friction_row(record, m, i, j, nx, ny, nz, tx, ty, tz, ff, lim)
            m += 1
        # torque on i: (r_i n) x Ft ; on j: (-r_j n) x (-Ft) = r_j n x Ft
        scatter(force, torque, i, j, (-fn * nx + ftx, -fn * ny + fty, -fn * nz + ftz), (nx, ny, nz), (ftx, fty, ftz),
                1.0, 1.0, ri, rj)
    if collect:
        record.ends[0] = m
    # ---- the floor: n = +y, so the signed distance is y, the approach speed -v_y, the slip
    #      (v_x + r w_z, 0, v_z - r w_x) and the torque of the friction (-r F_z, 0, r F_x)
    fwx = 0.0
    fwy = 0.0
    fwz = 0.0
    floor = walls.floor
    if floor >= 0:
        for i in range(n):
            ri = rad[i]
            delta = ri - pos[i, 1]
            if delta <= 0.0:
                if wvin[i, floor] != 0.0:
                    wvin[i, floor] = 0.0
                    e_f += drop_history(tlaw, wth, i * nw + floor)
                continue
            if delta > limit * ri:
                status = STATUS_OVERLAP
                culprit = i
            ddot = -vel[i, 1]
            vx = vel[i, 0]
            wz = omg[i, 2]
            vz = vel[i, 2]
            wx = omg[i, 0]
            tx, tz = floor_slip(vx, vz, wx, wz, ri)
            vt = math.sqrt(tx * tx + tz * tz)
            dsx = dsz = 0.0
            if spring:
                dsx, dsz = floor_slip(mv[i, 0], mv[i, 2], mv[i, 3], mv[i, 5], ri)
            mi = mass[i]
            mp = wmp[i, floor]
            fn, ftx, fty, ftz, ff, lim, wvin[i, floor], wd[i, floor], pn, pf, ef = contact(
                table, wth, i * nw + floor,
                ContactConstants(mp, friction[mp], wk[i, floor], wrs[i, floor], mi, FRICTION_CAP * mi),
                ContactGeometry(delta, ddot, 0.0, 1.0, 0.0, tx, 0.0, tz, vt, dsx, 0.0, dsz), wvin[i, floor],
                wd[i, floor], dt, step)
            p_n += pn
            p_f += pf
            e_f += ef
            if ff > 0.0 and m < room:
                note_friction_row(record, m, i, -1, 0.0, 1.0, 0.0, tx, 0.0, tz, ff, lim)
                m += 1
            # (the tangential force has no y part: the slip has none, and neither has a spring)
            scatter(force, torque, i, -1, (ftx, fn, ftz), (0.0, 1.0, 0.0), (ftx, 0.0, ftz), 1.0, 0.0, -ri, 0.0)
            fwx += ftx
            fwy += fn
            fwz += ftz
    if collect:
        record.ends[1] = m
    # ---- the other walls, from the candidate list
    for c in range(walls.n_candidates[0]):
        i = cand_i[c]
        w = cand_w[c]
        s, nx, ny, nz = wall_distance(wall_kind[w], wall_data, w, pos[i, 0], pos[i, 1], pos[i, 2])
        ri = rad[i]
        delta = ri - s
        if delta <= 0.0:
            if wvin[i, w] != 0.0:
                wvin[i, w] = 0.0
                e_f += drop_history(tlaw, wth, i * nw + w)
            continue
        if delta > limit * ri:
            status = STATUS_OVERLAP
            culprit = i
        vx = vel[i, 0]
        vy = vel[i, 1]
        vz = vel[i, 2]
        ddot = -(vx * nx + vy * ny + vz * nz)
        # slip at the contact point: v_i + w_i x (-r_i n), tangential part
        wy = omg[i, 1]
        wz = omg[i, 2]
        wx = omg[i, 0]
        cvx, cvy, cvz, cn = wall_point_velocity(vx, vy, vz, wx, wy, wz, ri, nx, ny, nz)
        tx = cvx - cn * nx
        ty = cvy - cn * ny
        tz = cvz - cn * nz
        vt = math.sqrt(tx * tx + ty * ty + tz * tz)
        dsx = dsy = dsz = 0.0
        if spring:
            dsx, dsy, dsz, dsn = wall_point_velocity(mv[i, 0], mv[i, 1], mv[i, 2], mv[i, 3], mv[i, 4], mv[i, 5], ri,
                                                     nx, ny, nz)
        mi = mass[i]
        mp = wmp[i, w]
        fn, ftx, fty, ftz, ff, lim, wvin[i, w], wd[i, w], pn, pf, ef = contact(
            table, wth, i * nw + w, ContactConstants(mp, friction[mp], wk[i, w], wrs[i, w], mi, FRICTION_CAP * mi),
            ContactGeometry(delta, ddot, nx, ny, nz, tx, ty, tz, vt, dsx, dsy, dsz), wvin[i, w], wd[i, w], dt, step)
        p_n += pn
        p_f += pf
        e_f += ef
        if ff > 0.0 and m < room:
            note_friction_row(record, m, i, -1, nx, ny, nz, tx, ty, tz, ff, lim)
            m += 1
        fx = fn * nx + ftx
        fy = fn * ny + fty
        fz = fn * nz + ftz
        # torque: (-r_i n) x Ft
        scatter(force, torque, i, -1, (fx, fy, fz), (nx, ny, nz), (ftx, fty, ftz), 1.0, 0.0, -ri, 0.0)
        fwx += fx
        fwy += fy
        fwz += fz
    if collect:
        record.ends[2] = m
    return fwx, fwy, fwz, p_n, p_f, e_f, status, culprit


@njit
def elastic_energy(bodies, pairs, walls):
    """Energy [J] stored in the contacts' springs: the sum of
    :func:`~pdamper.contact.hertz.hertz_energy` over the touching contacts, plus the energy of the
    tangential springs in the tangential history (:func:`~pdamper.contact.tangential_spring.spring_energy`;
    none under a law without history, whose history stays zero)."""
    pos = bodies.position
    rad = bodies.radius
    first = pairs.first
    second = pairs.second
    pk = pairs.stiffness
    pth = pairs.tangential
    cand_i = walls.candidate_body
    cand_w = walls.candidate_wall
    wall_kind = walls.kind
    wall_data = walls.data
    wk = walls.stiffness
    e = 0.0
    n = pos.shape[0]
    for a in range(pairs.row[n]):
        i = first[a]
        j = second[a]
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        delta = rad[i] + rad[j] - math.sqrt(dx * dx + dy * dy + dz * dz)
        if delta > 0.0:
            e += hertz_energy(pk[a], delta)
    for c in range(walls.n_candidates[0]):
        i = cand_i[c]
        w = cand_w[c]
        s, nx, ny, nz = wall_distance(wall_kind[w], wall_data, w, pos[i, 0], pos[i, 1], pos[i, 2])
        delta = rad[i] - s
        if delta > 0.0:
            e += hertz_energy(wk[i, w], delta)
    floor = walls.floor
    if floor >= 0:
        for i in range(n):
            delta = rad[i] - pos[i, 1]
            if delta > 0.0:
                e += hertz_energy(wk[i, floor], delta)
    # the tangential springs: every listed pair's row and every (sphere, wall) row
    et = 0.0
    for a in range(pairs.row[n]):
        if pth[a, 3] > 0.0:
            et += spring_energy(pth[a, 0], pth[a, 1], pth[a, 2], pth[a, 3])
    wth = walls.tangential.reshape((-1, walls.tangential.shape[2]))
    for r in range(wth.shape[0]):
        if wth[r, 3] > 0.0:
            et += spring_energy(wth[r, 0], wth[r, 1], wth[r, 2], wth[r, 3])
    return e + et
