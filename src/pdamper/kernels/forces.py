"""Contact forces of all particle pairs and particle-wall contacts, in the container frame.

The normal law is Hertz with Gonthier damping (:mod:`pdamper.contact.hertz_gonthier`), the
tangential law tanh-regularised Coulomb friction (:mod:`pdamper.contact.friction_tanh`); every
COR law reaches the kernels as a table of the dimensionless damping chi(eps(v)) over log-spaced
speeds (for Thornton's law over v / v_y, with the yield speed computed per contact at first touch).

**Contact history.** ``v_in`` of a contact is the largest normal approach speed it has seen
since it began (floored at ``v_floor``), and the damping parameter is ``d = chi(eps(v_in)) /
v_in``. For a single impact the approach speed is largest at the first touch, so this is
Gonthier's first-touch speed; a resting contact that is struck again (a bed settled against a
wall when the drive starts, a chain of spheres hit by a neighbour) is treated as a new impact
at the new speed. Without that, a resting contact keeps ``d = chi / v_floor`` and its damping
``k delta^1.5 d delta_dot`` becomes too stiff for any explicit step when it is loaded fast
(found in review: a perfect-lattice start blew up at the first wall impact). With it the
damping force never exceeds ``chi`` times the elastic force while the contact is compressed.

Conventions: pair normal n points from i to j, the overlap is ``delta = r_i + r_j - |x_j - x_i|``
and its rate ``delta_dot = (v_i - v_j).n`` (> 0 approaching). Wall normals point into the
container. Friction acts at ``r_i n`` from each centre (contact point), making torques.
"""

from __future__ import annotations

import math

from ..contact.friction_tanh import friction_factor
from ..contact.hertz_gonthier import normal_force
from ..geometry.walls import wall_distance
from .jit import njit

__all__ = ["compute_forces", "first_touch", "elastic_energy", "STATUS_OK", "STATUS_OVERLAP",
           "STATUS_NAN", "STATUS_LIST_OVERFLOW", "STATUS_WALL_OVERFLOW"]

#: Friction stability guard: the friction force on a contact never exceeds the force that
#: would stop its tangential slip within one step, ``m_t |v_t| / dt`` with the tangential
#: effective mass ``m_t = 2/7 m*`` of two rolling spheres, times 1/2. Only contacts whose
#: tanh law is too stiff for the step (large normal force during an impact) are affected;
#: without it their slip chatters around zero and the friction work is mis-counted.
#: Velocity Verlet only: Gear's steps pass a vanishing ``dt`` (no cap) and evaluate the friction at
#: the corrected slip instead (:mod:`pdamper.kernels.gear`); only Gear's priming evaluation at the
#: start of a run (initial accelerations) still passes its first step and so keeps the cap.
FRICTION_CAP = 0.5 * 2.0 / 7.0

STATUS_OK = 0
STATUS_LIST_OVERFLOW = 1
STATUS_WALL_OVERFLOW = 2
STATUS_OVERLAP = 3
STATUS_NAN = 4


@njit
def first_touch(v_approach, mp, e_star, r_star, m_star, cor_tab, cor_py, logv0, dlogv, v_floor):
    """Damping parameter d = chi / v_in [s/m] fixed at the first touch of a contact (eq. 1).

    ``v_approach`` [m/s] is the normal approach speed at first touch; it is floored at
    ``v_floor`` (see the guard in :mod:`pdamper.contact.hertz_gonthier`). ``chi`` (the
    dimensionless damping that yields the pair's coefficient of restitution, Gonthier's
    ``(1 - eps^2)/eps`` or its calibrated form) is read from row ``mp`` of ``cor_tab`` at ``v``
    (or at ``v / v_y`` for Thornton's law, ``cor_py[mp]`` > 0 being its yield pressure).
    """
    v = v_approach
    if v < v_floor:
        v = v_floor
    x = v
    py = cor_py[mp]
    if py > 0.0:
        dy = r_star * (math.pi * py / (2.0 * e_star)) ** 2
        vy = math.sqrt(2.0 * (8.0 / 15.0) * e_star * math.sqrt(r_star) * dy ** 2.5 / m_star)
        x = v / vy
    u = (math.log(x) - logv0) / dlogv
    g = cor_tab.shape[1]
    if u <= 0.0:
        chi = cor_tab[mp, 0]
    elif u >= g - 1:
        chi = cor_tab[mp, g - 1]
    else:
        k = int(u)
        f = u - k
        chi = cor_tab[mp, k] * (1.0 - f) + cor_tab[mp, k + 1] * f
    return chi / v


@njit
def compute_forces(pos, vel, omg, rad, mass, force, torque,
                   row, pi_, pj, pvin, pd, pk, pmp, pms,
                   wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk, wmp, wvin, wd, wrs,
                   estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, dt, fr_i, fr, fr_n):
    """Zero and fill ``force`` [N] and ``torque`` [N m]; update contact history in place.

    Pair arrays aligned with the list ``row``/``pj``: history ``pvin`` (approach speed at first
    touch, 0 = not touching) and ``pd`` (damping parameter), stiffness ``pk``, material-pair
    index ``pmp`` and ``pms`` = FRICTION_CAP x the pair's reduced mass [kg].

    ``floor`` is the index of the floor wall (the plane y = 0 with normal +y in the container
    frame), which every resting sphere touches: it is handled by its own direct loop over the
    particles (no candidate list, the normal known), about three times cheaper per contact than
    the general wall loop; the wall candidate list leaves it out. ``floor < 0``: no such wall.

    Returns ``(fwx, fwy, fwz, p_normal, p_friction, status, culprit)``: the total force of the
    walls on the particles [N], the power [W] dissipated by normal damping and by friction, a
    status code (``STATUS_OVERLAP`` when an overlap exceeds ``overlap_limit`` x r) and the
    particle concerned. ``dt`` [s] is the current step (for the friction guard :data:`FRICTION_CAP`).

    **Friction contacts for an implicit pass** (Gear, :mod:`pdamper.kernels.gear`): when ``fr`` has
    rows, every touching contact with friction is written down as it is computed -- ``fr_i[m] =
    (i, j)`` (``j = -1`` at a wall) and ``fr[m] = (n_x, n_y, n_z, s_x, s_y, s_z, c, mu F_N)``: the
    contact normal (pairs: from i to j; walls: into the container), the slip, the law's secant
    coefficient ``c`` (force ``-c s``) and the Coulomb limit -- pairs first, then the floor, then
    the other walls; ``fr_n`` receives the three end indices. Capacity: listed pairs + particles +
    wall candidates, which is enough by construction; a full record takes no more rows (no write
    past its end; the contacts beyond it would keep their explicit friction). With ``fr`` of no
    rows nothing is written.
    """
    collect = fr.shape[0] > 0
    m = 0
    n = pos.shape[0]
    for i in range(n):
        force[i, 0] = 0.0
        force[i, 1] = 0.0
        force[i, 2] = 0.0
        torque[i, 0] = 0.0
        torque[i, 1] = 0.0
        torque[i, 2] = 0.0
    p_n = 0.0
    p_f = 0.0
    inv_dt = 1.0 / dt
    status = STATUS_OK
    culprit = -1
    # ---- particle pairs
    # one flat loop over the list (pi_[a], pj[a]): no short inner loops whose exits mispredict
    for a in range(row[n]):
        i = pi_[a]
        j = pj[a]
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
            continue
        dist = math.sqrt(d2)
        inv = 1.0 / dist
        nx = dx * inv
        ny = dy * inv
        nz = dz * inv
        delta = cut - dist
        if delta > overlap_limit * min(ri, rj):
            status = STATUS_OVERLAP
            culprit = i
        rvx = vel[i, 0] - vel[j, 0]
        rvy = vel[i, 1] - vel[j, 1]
        rvz = vel[i, 2] - vel[j, 2]
        ddot = rvx * nx + rvy * ny + rvz * nz
        if pvin[a] == 0.0 or ddot > pvin[a]:
            # first touch, or struck harder than ever before in this contact
            pvin[a] = max(ddot, v_floor)
            pd[a] = first_touch(ddot, pmp[a], estar[pmp[a]], ri * rj / cut, pms[a] / FRICTION_CAP,
                                cor_tab, cor_py, logv0, dlogv, v_floor)
        fn, fdamp = normal_force(pk[a], delta, ddot, pd[a])
        p_n += fdamp * ddot
        # contact-point relative velocity: v_i - v_j + r_i w_i x n + r_j w_j x n
        wx = ri * omg[i, 0] + rj * omg[j, 0]
        wy = ri * omg[i, 1] + rj * omg[j, 1]
        wz = ri * omg[i, 2] + rj * omg[j, 2]
        cvx = rvx + wy * nz - wz * ny
        cvy = rvy + wz * nx - wx * nz
        cvz = rvz + wx * ny - wy * nx
        cn = cvx * nx + cvy * ny + cvz * nz
        tx = cvx - cn * nx
        ty = cvy - cn * ny
        tz = cvz - cn * nz
        vt = math.sqrt(tx * tx + ty * ty + tz * tz)
        ff = friction_factor(mu[pmp[a]], tau, vt) * fn
        if ff * dt > pms[a]:
            ff = pms[a] * inv_dt
        if ff > 0.0 and m < fr.shape[0]:
            _note(fr_i, fr, m, i, j, nx, ny, nz, tx, ty, tz, ff, mu[pmp[a]] * fn)
            m += 1
        p_f += ff * vt * vt
        ftx = -ff * tx
        fty = -ff * ty
        ftz = -ff * tz
        fx = -fn * nx + ftx
        fy = -fn * ny + fty
        fz = -fn * nz + ftz
        force[i, 0] += fx
        force[i, 1] += fy
        force[i, 2] += fz
        force[j, 0] -= fx
        force[j, 1] -= fy
        force[j, 2] -= fz
        # torque on i: (r_i n) x Ft ; on j: (-r_j n) x (-Ft) = r_j n x Ft
        cx = ny * ftz - nz * fty
        cy = nz * ftx - nx * ftz
        cz = nx * fty - ny * ftx
        torque[i, 0] += ri * cx
        torque[i, 1] += ri * cy
        torque[i, 2] += ri * cz
        torque[j, 0] += rj * cx
        torque[j, 1] += rj * cy
        torque[j, 2] += rj * cz
    # ---- the floor: n = +y, so the signed distance is y, the approach speed -v_y, the slip
    #      (v_x + r w_z, 0, v_z - r w_x) and the torque of the friction (-r F_z, 0, r F_x)
    if collect:
        fr_n[0] = m
    fwx = 0.0
    fwy = 0.0
    fwz = 0.0
    if floor >= 0:
        for i in range(n):
            ri = rad[i]
            delta = ri - pos[i, 1]
            if delta <= 0.0:
                if wvin[i, floor] != 0.0:
                    wvin[i, floor] = 0.0
                continue
            if delta > overlap_limit * ri:
                status = STATUS_OVERLAP
                culprit = i
            ddot = -vel[i, 1]
            mp = wmp[i, floor]
            if wvin[i, floor] == 0.0 or ddot > wvin[i, floor]:
                wvin[i, floor] = max(ddot, v_floor)
                wd[i, floor] = first_touch(ddot, mp, estar[mp], wrs[i, floor], mass[i],
                                           cor_tab, cor_py, logv0, dlogv, v_floor)
            fn, fdamp = normal_force(wk[i, floor], delta, ddot, wd[i, floor])
            p_n += fdamp * ddot
            tx = vel[i, 0] + ri * omg[i, 2]
            tz = vel[i, 2] - ri * omg[i, 0]
            vt = math.sqrt(tx * tx + tz * tz)
            ff = friction_factor(mu[mp], tau, vt) * fn
            if ff * dt > FRICTION_CAP * mass[i]:
                ff = FRICTION_CAP * mass[i] * inv_dt
            if ff > 0.0 and m < fr.shape[0]:
                _note(fr_i, fr, m, i, -1, 0.0, 1.0, 0.0, tx, 0.0, tz, ff, mu[mp] * fn)
                m += 1
            p_f += ff * vt * vt
            ftx = -ff * tx
            ftz = -ff * tz
            force[i, 0] += ftx
            force[i, 1] += fn
            force[i, 2] += ftz
            fwx += ftx
            fwy += fn
            fwz += ftz
            torque[i, 0] -= ri * ftz
            torque[i, 2] += ri * ftx
    if collect:
        fr_n[1] = m
    # ---- the other walls, from the candidate list
    for c in range(n_wl):
        i = wl_i[c]
        w = wl_w[c]
        s, nx, ny, nz = wall_distance(wall_kind[w], wall_data, w, pos[i, 0], pos[i, 1], pos[i, 2])
        ri = rad[i]
        delta = ri - s
        if delta <= 0.0:
            wvin[i, w] = 0.0
            continue
        if delta > overlap_limit * ri:
            status = STATUS_OVERLAP
            culprit = i
        vx = vel[i, 0]
        vy = vel[i, 1]
        vz = vel[i, 2]
        ddot = -(vx * nx + vy * ny + vz * nz)
        mp = wmp[i, w]
        if wvin[i, w] == 0.0 or ddot > wvin[i, w]:
            wvin[i, w] = max(ddot, v_floor)
            wd[i, w] = first_touch(ddot, mp, estar[mp], wrs[i, w], mass[i],
                                   cor_tab, cor_py, logv0, dlogv, v_floor)
        fn, fdamp = normal_force(wk[i, w], delta, ddot, wd[i, w])
        p_n += fdamp * ddot
        # contact point velocity: v_i + w_i x (-r_i n)
        cvx = vx - ri * (omg[i, 1] * nz - omg[i, 2] * ny)
        cvy = vy - ri * (omg[i, 2] * nx - omg[i, 0] * nz)
        cvz = vz - ri * (omg[i, 0] * ny - omg[i, 1] * nx)
        cn = cvx * nx + cvy * ny + cvz * nz
        tx = cvx - cn * nx
        ty = cvy - cn * ny
        tz = cvz - cn * nz
        vt = math.sqrt(tx * tx + ty * ty + tz * tz)
        ff = friction_factor(mu[mp], tau, vt) * fn
        if ff * dt > FRICTION_CAP * mass[i]:
            ff = FRICTION_CAP * mass[i] * inv_dt
        if ff > 0.0 and m < fr.shape[0]:
            _note(fr_i, fr, m, i, -1, nx, ny, nz, tx, ty, tz, ff, mu[mp] * fn)
            m += 1
        p_f += ff * vt * vt
        ftx = -ff * tx
        fty = -ff * ty
        ftz = -ff * tz
        fx = fn * nx + ftx
        fy = fn * ny + fty
        fz = fn * nz + ftz
        force[i, 0] += fx
        force[i, 1] += fy
        force[i, 2] += fz
        fwx += fx
        fwy += fy
        fwz += fz
        # torque: (-r_i n) x Ft
        torque[i, 0] -= ri * (ny * ftz - nz * fty)
        torque[i, 1] -= ri * (nz * ftx - nx * ftz)
        torque[i, 2] -= ri * (nx * fty - ny * ftx)
    if collect:
        fr_n[2] = m
    return fwx, fwy, fwz, p_n, p_f, status, culprit


@njit(inline="always")
def _note(fr_i, fr, m, i, j, nx, ny, nz, tx, ty, tz, c, lim):
    """Row ``m`` of the friction-contact record (see :func:`compute_forces`)."""
    fr_i[m, 0] = i
    fr_i[m, 1] = j
    fr[m, 0] = nx
    fr[m, 1] = ny
    fr[m, 2] = nz
    fr[m, 3] = tx
    fr[m, 4] = ty
    fr[m, 5] = tz
    fr[m, 6] = c
    fr[m, 7] = lim


@njit
def elastic_energy(pos, rad, row, pi_, pj, pk, wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk):
    """Energy [J] stored in the Hertz springs, sum of 2/5 k delta^(5/2)."""
    e = 0.0
    n = pos.shape[0]
    for a in range(row[n]):
        i = pi_[a]
        j = pj[a]
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        delta = rad[i] + rad[j] - math.sqrt(dx * dx + dy * dy + dz * dz)
        if delta > 0.0:
            e += 0.4 * pk[a] * delta * delta * math.sqrt(delta)
    for c in range(n_wl):
        i = wl_i[c]
        w = wl_w[c]
        s, nx, ny, nz = wall_distance(wall_kind[w], wall_data, w, pos[i, 0], pos[i, 1], pos[i, 2])
        delta = rad[i] - s
        if delta > 0.0:
            e += 0.4 * wk[i, w] * delta * delta * math.sqrt(delta)
    if floor >= 0:
        for i in range(n):
            delta = rad[i] - pos[i, 1]
            if delta > 0.0:
                e += 0.4 * wk[i, floor] * delta * delta * math.sqrt(delta)
    return e
