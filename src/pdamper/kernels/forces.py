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

from numba.extending import overload

from ..contact.hertz import hertz_energy
from ..contact.tangential_spring import spring_energy
from ..geometry.walls import wall_distance
from ..jit import JIT, njit
from .bundles import ContactConstants, ContactGeometry, ContactSplit, FrictionRecord
from .contact import (FRICTION_CAP, contact, damping_at_touch, drop_history, floor_slip, keeps_history, law_force,
                      note_friction_row, pair_point_velocity, scatter, wall_point_velocity)

__all__ = ["compute_forces", "pair_geometry", "elastic_energy", "no_friction_record", "split_add", "split_clear",
           "wall_type_of", "wall_row", "touching_contacts",
           "SPHERE", "FLOOR", "STATUS_OK", "STATUS_OVERLAP", "STATUS_NAN", "STATUS_LIST_OVERFLOW",
           "STATUS_WALL_OVERFLOW"]

#: Rows of the contact types (:data:`pdamper.kernels.bundles.CONTACT_TYPES`) the loops know by
#: themselves: sphere pairs and the floor (the other walls' from ``ContactSplit.wall_type``).
SPHERE = 0
FLOOR = 1

STATUS_OK = 0
STATUS_LIST_OVERFLOW = 1
STATUS_WALL_OVERFLOW = 2
STATUS_OVERLAP = 3
STATUS_NAN = 4


def _is_split(split_type) -> bool:
    """Whether a numba type is a :class:`~pdamper.kernels.bundles.ContactSplit` (not the empty marker)."""
    return getattr(split_type, "instance_class", None) is ContactSplit


def split_add(split, kind, p_n, p_f, e_f):
    """Add a contact's damping power ``p_n`` [W], tanh friction power ``p_f`` [W] and spring loss ``e_f``
    [J] to row ``kind`` of the split's ``power`` (compiled kernels only: nothing for the empty marker
    :class:`~pdamper.kernels.bundles.SplitOff`, resolved when the kernel is compiled)."""
    raise NotImplementedError("split_add is compiled into the kernels")


def split_clear(split):
    """Zero the split's ``power`` before a force evaluation (compiled kernels only; as :func:`split_add`)."""
    raise NotImplementedError("split_clear is compiled into the kernels")


def wall_type_of(split, w):
    """Wall ``w``'s row of :data:`~pdamper.kernels.bundles.CONTACT_TYPES` (compiled kernels only; 0
    for the empty marker, whose :func:`split_add` ignores it)."""
    raise NotImplementedError("wall_type_of is compiled into the kernels")


def wall_row(split, w):
    """What Gear's friction record holds as the second body of a contact with wall ``w``: ``-1 - w`` with
    the split (its implicit pass then finds the wall's type), -1 without it (compiled kernels only)."""
    raise NotImplementedError("wall_row is compiled into the kernels")


@overload(wall_row, inline="always", jit_options=JIT)
def _wall_row(split, w):
    if not _is_split(split):
        return lambda split, w: -1
    return lambda split, w: -1 - w


@overload(split_add, inline="always", jit_options=JIT)
def _split_add(split, kind, p_n, p_f, e_f):
    if not _is_split(split):
        return lambda split, kind, p_n, p_f, e_f: None

    def impl(split, kind, p_n, p_f, e_f):
        p = split.power
        p[kind, 0] += p_n
        p[kind, 1] += p_f
        p[kind, 2] += e_f

    return impl


@overload(split_clear, inline="always", jit_options=JIT)
def _split_clear(split):
    if not _is_split(split):
        return lambda split: None

    def impl(split):
        p = split.power
        for r in range(p.shape[0]):
            for c in range(p.shape[1]):
                p[r, c] = 0.0

    return impl


@overload(wall_type_of, inline="always", jit_options=JIT)
def _wall_type_of(split, w):
    if not _is_split(split):
        return lambda split, w: 0
    return lambda split, w: split.wall_type[w]


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
def compute_forces(bodies, pairs, walls, table, dt, step, moved, record, split):
    """Zero and fill ``bodies.force`` [N] and ``bodies.torque`` [N m]; update the contact history
    in ``pairs`` and ``walls`` in place. With the ledger split by contact type (``split`` a
    :class:`~pdamper.kernels.bundles.ContactSplit`, not the empty marker), ``split.power`` receives the
    dissipated powers by contact type too (sphere pairs, the floor, each wall's type).

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
    split_clear(split)
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
                ed = drop_history(tlaw, pth, a)
                e_f += ed
                split_add(split, SPHERE, 0.0, 0.0, ed)
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
        split_add(split, SPHERE, pn, pf, ef)
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
                    ed = drop_history(tlaw, wth, i * nw + floor)
                    e_f += ed
                    split_add(split, FLOOR, 0.0, 0.0, ed)
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
            split_add(split, FLOOR, pn, pf, ef)
            if ff > 0.0 and m < room:
                note_friction_row(record, m, i, wall_row(split, floor), 0.0, 1.0, 0.0, tx, 0.0, tz, ff, lim)
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
                ed = drop_history(tlaw, wth, i * nw + w)
                e_f += ed
                split_add(split, wall_type_of(split, w), 0.0, 0.0, ed)
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
        split_add(split, wall_type_of(split, w), pn, pf, ef)
        if ff > 0.0 and m < room:
            note_friction_row(record, m, i, wall_row(split, w), nx, ny, nz, tx, ty, tz, ff, lim)
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


@njit
def touching_contacts(bodies, pairs, walls, table, wall_type, ends, normal_force, kind):
    """The contacts touching now and the normal force of each, into the rows of ``ends`` (M, 2) int,
    ``normal_force`` (M,) [N] and ``kind`` (M,) int (M: the listed pairs, the spheres and the wall
    candidates, enough by construction); returns how many rows it wrote.

    A row is ``(i, j)``: spheres ``i < j``, or sphere ``i`` and wall ``w`` as ``j = -1 - w``; ``kind``
    its row of :data:`~pdamper.kernels.bundles.CONTACT_TYPES` (sphere pairs, the floor, then
    ``wall_type[w]``). Touching: the bodies overlap (the force loops' test). The normal force is the
    damping law's at the present overlap and approach rate with the contact's damping parameter as
    the force loops keep it (a contact that started since they last ran: the one it starts with),
    pushing when positive. Nothing is changed: what a Python recorder asks for at a sample's end
    (the ``"contacts"`` channel of :mod:`pdamper.recorders.base`)."""
    pos = bodies.position
    vel = bodies.velocity
    rad = bodies.radius
    mass = bodies.mass
    first = pairs.first
    second = pairs.second
    pvin = pairs.approach_speed
    pd = pairs.damping
    pk = pairs.stiffness
    pmp = pairs.material_pair
    wall_kind = walls.kind
    wall_data = walls.data
    wvin = walls.approach_speed
    wd = walls.damping
    wk = walls.stiffness
    wmp = walls.material_pair
    wrs = walls.effective_radius
    n = pos.shape[0]
    m = 0
    for a in range(pairs.row[n]):
        i = first[a]
        j = second[a]
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        cut = rad[i] + rad[j]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 >= cut * cut:
            continue
        # the force loop's geometry (its overlap and approach rate, to the bit)
        nx, ny, nz, delta, ddot, tx, ty, tz, vt = pair_geometry(
            dx, dy, dz, d2, cut, vel[i, 0] - vel[j, 0], vel[i, 1] - vel[j, 1], vel[i, 2] - vel[j, 2], 0.0, 0.0, 0.0)
        normal_force[m] = _normal_force(table, pk[a], pmp[a], rad[i] * rad[j] / cut, pairs.friction_cap[a] / FRICTION_CAP,
                                        delta, ddot, pvin[a], pd[a])
        ends[m, 0] = i
        ends[m, 1] = j
        kind[m] = SPHERE
        m += 1
    floor = walls.floor
    if floor >= 0:
        for i in range(n):
            delta = rad[i] - pos[i, 1]
            if delta <= 0.0:
                continue
            normal_force[m] = _normal_force(table, wk[i, floor], wmp[i, floor], wrs[i, floor], mass[i], delta,
                                            -vel[i, 1], wvin[i, floor], wd[i, floor])
            ends[m, 0] = i
            ends[m, 1] = -1 - floor
            kind[m] = FLOOR
            m += 1
    for c in range(walls.n_candidates[0]):
        i = walls.candidate_body[c]
        w = walls.candidate_wall[c]
        s, nx, ny, nz = wall_distance(wall_kind[w], wall_data, w, pos[i, 0], pos[i, 1], pos[i, 2])
        delta = rad[i] - s
        if delta <= 0.0:
            continue
        ddot = -(vel[i, 0] * nx + vel[i, 1] * ny + vel[i, 2] * nz)
        normal_force[m] = _normal_force(table, wk[i, w], wmp[i, w], wrs[i, w], mass[i], delta, ddot, wvin[i, w],
                                        wd[i, w])
        ends[m, 0] = i
        ends[m, 1] = -1 - w
        kind[m] = wall_type[w]
        m += 1
    return m


@njit(inline="always")
def _normal_force(table, k, mp, r_star, m_star, delta, ddot, v_in, d):
    """The damping law's normal force [N] of a contact now, with its damping parameter as
    :func:`pdamper.kernels.contact.contact` would hold it (fixed anew when it starts or is struck
    harder than before), its history left as it is."""
    if v_in == 0.0 or ddot > v_in:
        d = damping_at_touch(table, ddot, mp, k, r_star, m_star)
    fn, fdamp = law_force(table.law, k, delta, ddot, d)
    return fn
