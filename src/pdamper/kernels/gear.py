r"""Variable-step fifth-order Gear predictor-corrector (the paper's integrator, its ref. [9]).

Each sphere has six second-order degrees of freedom: its position and a rotation "angle" vector
whose rate is the spin (only the spin enters the physics). They are carried as a Nordsieck
vector of scaled derivatives ``r_k = h^k / k! d^k x / dt^k``, k = 0..5, in ``nord[k, i, dof]``.

Per step: Pascal-triangle prediction, forces at the predicted positions and velocities
(``v = r_1 / h``), the corrector ``r_k += c_k Delta`` with ``Delta = h^2/2 a - r_2^pred`` and
Gear's coefficients for velocity-dependent forces
``c = (3/20, 251/360, 1, 11/18, 1/6, 1/60)`` (Allen & Tildesley, Computer Simulation of
Liquids, App. E).

**Friction at the corrected slip.** The tanh friction law (eq. 2) has the slope ``mu F_N tau``
in the slip; during an impact that is a tangential damping with a relaxation time well below a
microsecond, and evaluated at the *predicted* slip (plain Gear) the error control has to follow
it: at large strokes most of Gear's steps went there (5.5x more steps than without friction at
50 mm), and the energy ledger still did not close at mu = 1. So after the forces at the predicted
state, every touching contact's friction is evaluated again at the slip the corrector will give
(:func:`_implicit_friction`): linearised in the slip, ``ds = dc / (1 + a K c)`` with ``dc`` the
explicit corrector's slip increment, ``c`` the law's secant coefficient at the predicted slip,
``K`` the contact's inverse tangential mass and ``a = c_1 h / 2``; the force ``-c (s + ds)`` is
clipped to the Coulomb limit ``mu F_N``. Contacts are visited in list order (pairs, floor, other
walls) and each sees the increments already changed by those before it: one Gauss-Seidel sweep,
not a converged solve. What this evaluates is one linearisation of the law: the coefficient
comes from the predicted slip (a contact whose slip grows out of the smooth range gets up to
1/tanh(1) = 1.31x the law's force at its corrected slip; one whose slip shrinks gets less), and
for a body with several contacts those visited early are moved off ``-c (s + ds)`` by the later
ones (a review measured up to 6 % of mu F_N on a three-sphere pile at ``a K c`` ~ 6). The error
control sees what is left. The friction power for the ledger is taken per contact at its slip
when it is visited, not after the sweep (docs/integrators.md: taking it after the sweep was
tried and did not improve the ledger). The explicit step's friction cap of :mod:`pdamper.kernels.forces` is off for Gear's steps.

**Error control.** ``|Delta|`` estimates the local error of a step [m] (spin DOFs are scaled by
the radius). A step whose error exceeds 4x the tolerance is rejected and retried shorter; after
an accepted step the next is ``h (tol/err)^(1/6)``, times 0.9, within [0.2, 1.5] h and within
[dt_min, dt_max]. Steps end exactly on sample boundaries, where the Nordsieck vector is rescaled
(``r_k *= (h_new/h_old)^k``).

Reference: Gear, C. W. (1971). Numerical Initial Value Problems in Ordinary Differential
Equations. Prentice-Hall.
"""

from __future__ import annotations

import math

from .drive import drive_motion
from .forces import STATUS_LIST_OVERFLOW, STATUS_NAN, STATUS_OK, STATUS_WALL_OVERFLOW, compute_forces
from .jit import njit
from .neighbours import max_displacement_sq, rebuild_lists
from .record import record_sample

__all__ = ["run_gear", "GEAR_C"]

#: Corrector coefficients of the 6-value Gear scheme for second-order equations with
#: velocity-dependent forces.
GEAR_C = (3.0 / 20.0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0)


@njit
def _rescale(nord, ratio):
    nf = nord.reshape(6, -1)
    f = 1.0
    for k in range(1, 6):
        f *= ratio
        for m in range(nf.shape[1]):
            nf[k, m] *= f


@njit
def _unpack(nord, inv_h, pos, vel, omg):
    """Positions, velocities and spins from the Nordsieck vector (scaled to step 1/inv_h)."""
    for i in range(pos.shape[0]):
        for c in range(3):
            pos[i, c] = nord[0, i, c]
            vel[i, c] = nord[1, i, c] * inv_h
            omg[i, c] = nord[1, i, 3 + c] * inv_h


@njit(inline="always")
def _correct(nord, pred, i, c, dlt):
    """Corrected Nordsieck vector of degree of freedom (i, c): prediction + Gear's c_k x increment."""
    nord[0, i, c] = pred[0, i, c] + GEAR_C[0] * dlt
    nord[1, i, c] = pred[1, i, c] + GEAR_C[1] * dlt
    nord[2, i, c] = pred[2, i, c] + GEAR_C[2] * dlt
    nord[3, i, c] = pred[3, i, c] + GEAR_C[3] * dlt
    nord[4, i, c] = pred[4, i, c] + GEAR_C[4] * dlt
    nord[5, i, c] = pred[5, i, c] + GEAR_C[5] * dlt


#: compute_forces' step argument that switches its explicit friction cap off (the implicit pass
#: below takes its place).
_NO_CAP = 1e-300


@njit(inline="always")
def _slip_update(c, lim, kk, a, tx, ty, tz, dcx, dcy, dcz):
    """Friction force of a contact evaluated at its corrected slip, linearly implicit.

    ``(tx, ty, tz)`` is the predicted slip, ``(dcx, dcy, dcz)`` the tangential slip increment that
    the explicit corrector gives, ``c`` the law's secant coefficient ``mu F_N tanh(tau s)/s`` at the
    predicted slip, ``kk`` the contact's inverse tangential mass (1/m + r^2/I of both bodies) and
    ``a = c_1 h / 2`` the corrector's velocity increment per unit acceleration. The slip increment
    solves ``ds = dc - a kk c ds``; the force ``-c (s + ds)`` is clipped to the Coulomb limit
    ``lim = mu F_N``. Returns the force change against the explicit ``-c s`` and the new force."""
    den = 1.0 / (1.0 + a * kk * c)
    fx = -c * (tx + dcx * den)
    fy = -c * (ty + dcy * den)
    fz = -c * (tz + dcz * den)
    fm = math.sqrt(fx * fx + fy * fy + fz * fz)
    if fm > lim:
        sc = lim / fm
        fx *= sc
        fy *= sc
        fz *= sc
    return fx + c * tx, fy + c * ty, fz + c * tz, fx, fy, fz


@njit(inline="always")
def _contact_row(fr, q):
    """Normal, slip, secant coefficient and slip speed of recorded friction contact ``q``."""
    tx = fr[q, 3]
    ty = fr[q, 4]
    tz = fr[q, 5]
    return fr[q, 0], fr[q, 1], fr[q, 2], tx, ty, tz, fr[q, 6], math.sqrt(tx * tx + ty * ty + tz * tz)


@njit
def _implicit_friction(rad, inv_m, inv_i, dv, dw, hs, fr_i, fr, fr_n):
    """Re-evaluate the friction of every contact that :func:`~pdamper.kernels.forces.compute_forces`
    recorded (``fr_i``, ``fr``, ``fr_n``) at its corrected slip (linearly implicit in the slip,
    Gauss-Seidel over the contacts) and add the change to the Gear increments ``dv`` (positions)
    and ``dw`` (angles) in place.

    The explicit Gear corrector evaluates the tanh law at the *predicted* slip; during an impact
    its slope ``mu F_N tau`` relaxes the slip within a fraction of a microsecond, and the error
    control then has to follow that relaxation. Evaluated at the corrected slip, an isolated
    sticking contact's force is whatever keeps it sticking (up to ``mu F_N``), smooth in time;
    one Gauss-Seidel sweep only approximates that where a body has several contacts (module
    docstring).

    Returns ``(dfx, dfy, dfz, dp_f)``: the change of the walls' force on the particles [N] and of
    the friction power [W].
    """
    g = GEAR_C[1] / hs
    a = 0.5 * GEAR_C[1] * hs
    hh = 0.5 * hs * hs
    dfx = 0.0
    dfy = 0.0
    dfz = 0.0
    dpf = 0.0
    # ---- particle pairs: n from i to j, slip (v_i - v_j) + (r_i w_i + r_j w_j) x n
    for q in range(fr_n[0]):
        i = fr_i[q, 0]
        j = fr_i[q, 1]
        ri = rad[i]
        rj = rad[j]
        nx, ny, nz, tx, ty, tz, c, vt = _contact_row(fr, q)
        # slip increment of the explicit corrector (same formula on the velocity increments)
        ux = g * (dv[i, 0] - dv[j, 0])
        uy = g * (dv[i, 1] - dv[j, 1])
        uz = g * (dv[i, 2] - dv[j, 2])
        ex = g * (ri * dw[i, 0] + rj * dw[j, 0])
        ey = g * (ri * dw[i, 1] + rj * dw[j, 1])
        ez = g * (ri * dw[i, 2] + rj * dw[j, 2])
        dcx = ux + ey * nz - ez * ny
        dcy = uy + ez * nx - ex * nz
        dcz = uz + ex * ny - ey * nx
        dcn = dcx * nx + dcy * ny + dcz * nz
        kk = inv_m[i] + inv_m[j] + ri * ri * inv_i[i] + rj * rj * inv_i[j]
        gx, gy, gz, fx, fy, fz = _slip_update(c, fr[q, 7], kk, a, tx, ty, tz,
                                              dcx - dcn * nx, dcy - dcn * ny, dcz - dcn * nz)
        # power: the new force on the corrected slip, minus the explicit c s^2
        dpf += -(fx * (tx + dcx - dcn * nx + a * kk * gx) + fy * (ty + dcy - dcn * ny + a * kk * gy)
                 + fz * (tz + dcz - dcn * nz + a * kk * gz)) - c * vt * vt
        dv[i, 0] += hh * inv_m[i] * gx
        dv[i, 1] += hh * inv_m[i] * gy
        dv[i, 2] += hh * inv_m[i] * gz
        dv[j, 0] -= hh * inv_m[j] * gx
        dv[j, 1] -= hh * inv_m[j] * gy
        dv[j, 2] -= hh * inv_m[j] * gz
        cx = ny * gz - nz * gy
        cy = nz * gx - nx * gz
        cz = nx * gy - ny * gx
        si = hh * inv_i[i] * ri
        sj = hh * inv_i[j] * rj
        dw[i, 0] += si * cx
        dw[i, 1] += si * cy
        dw[i, 2] += si * cz
        dw[j, 0] += sj * cx
        dw[j, 1] += sj * cy
        dw[j, 2] += sj * cz
    # ---- the floor: n = +y, slip (v_x + r w_z, 0, v_z - r w_x)
    for q in range(fr_n[0], fr_n[1]):
        i = fr_i[q, 0]
        ri = rad[i]
        tx = fr[q, 3]
        tz = fr[q, 5]
        c = fr[q, 6]
        vt = math.sqrt(tx * tx + tz * tz)
        dcx = g * (dv[i, 0] + ri * dw[i, 2])
        dcz = g * (dv[i, 2] - ri * dw[i, 0])
        kk = inv_m[i] + ri * ri * inv_i[i]
        gx, gy, gz, fx, fy, fz = _slip_update(c, fr[q, 7], kk, a, tx, 0.0, tz, dcx, 0.0, dcz)
        dpf += -(fx * (tx + dcx + a * kk * gx) + fz * (tz + dcz + a * kk * gz)) - c * vt * vt
        dv[i, 0] += hh * inv_m[i] * gx
        dv[i, 2] += hh * inv_m[i] * gz
        si = hh * inv_i[i] * ri
        dw[i, 0] -= si * gz
        dw[i, 2] += si * gx
        dfx += gx
        dfz += gz
    # ---- the other walls: n into the container, slip v - r w x n
    for q in range(fr_n[1], fr_n[2]):
        i = fr_i[q, 0]
        ri = rad[i]
        nx, ny, nz, tx, ty, tz, c, vt = _contact_row(fr, q)
        ux = g * dv[i, 0]
        uy = g * dv[i, 1]
        uz = g * dv[i, 2]
        ex = g * dw[i, 0]
        ey = g * dw[i, 1]
        ez = g * dw[i, 2]
        dcx = ux - ri * (ey * nz - ez * ny)
        dcy = uy - ri * (ez * nx - ex * nz)
        dcz = uz - ri * (ex * ny - ey * nx)
        dcn = dcx * nx + dcy * ny + dcz * nz
        dcx -= dcn * nx
        dcy -= dcn * ny
        dcz -= dcn * nz
        kk = inv_m[i] + ri * ri * inv_i[i]
        gx, gy, gz, fx, fy, fz = _slip_update(c, fr[q, 7], kk, a, tx, ty, tz, dcx, dcy, dcz)
        dpf += -(fx * (tx + dcx + a * kk * gx) + fy * (ty + dcy + a * kk * gy) + fz * (tz + dcz + a * kk * gz)) \
            - c * vt * vt
        dv[i, 0] += hh * inv_m[i] * gx
        dv[i, 1] += hh * inv_m[i] * gy
        dv[i, 2] += hh * inv_m[i] * gz
        si = hh * inv_i[i] * ri
        dw[i, 0] -= si * (ny * gz - nz * gy)
        dw[i, 1] -= si * (nz * gx - nx * gz)
        dw[i, 2] -= si * (nx * gy - ny * gx)
        dfx += gx
        dfy += gy
        dfz += gz
    return dfx, dfy, dfz, dpf


@njit
def _copy_wall_history(src_v, src_d, dst_v, dst_d, floor, wl_i, wl_w, n_wl):
    """Copy the wall-contact history (approach speed, damping parameter) that the force loop can
    change -- the floor column and the listed wall candidates -- from ``src_*`` to ``dst_*``."""
    if floor >= 0:
        for i in range(src_v.shape[0]):
            dst_v[i, floor] = src_v[i, floor]
            dst_d[i, floor] = src_d[i, floor]
    for q in range(n_wl):
        i = wl_i[q]
        w = wl_w[q]
        dst_v[i, w] = src_v[i, w]
        dst_d[i, w] = src_d[i, w]


@njit
def run_gear(t_end, h_try, t0, ts, record, prime, tol, dt_min, dt_max, nord, pred, hist_p, hist_w, h_state,
             fr_i, fr, fr_n,
             pos, vel, omg, rad, mass, inv_m, inv_i, mat,
             force, torque, gvec, dvec, drive_kind, drive_par, drive_tab,
             nmat, estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit,
             skin, use_cells, lo, cell, ncell, head, nxt, counts, ref,
             row, pi_, pj, pvin, pd, pk, pmp, pms, row2, pj2, pvin2, pd2,
             wall_kind, wall_data, floor, wl_i, wl_w, nwl, wk, wmp, wvin, wd, wrs,
             ledger, sig, eng, traj_every, traj, max_steps):
    """Advance from ``t0`` to ``t_end`` [s] (or ``max_steps`` accepted steps).

    ``pred`` (shape of ``nord``) receives the predicted Nordsieck vector of each step, which the
    corrector writes back into ``nord`` when the step is accepted; ``hist_p`` (2, list capacity)
    and ``hist_w`` (2, N, walls) hold the contact history before each step, restored when the
    step is rejected.
    ``h_state[0]`` is the step the Nordsieck vector is scaled to; ``h_try`` the next step to
    try. Samples (interval ``ts``) are written as in :func:`pdamper.kernels.verlet.run_verlet`
    when ``record`` is true (sample k ends at ``(k + 1) ts``).

    Returns ``(status, accepted_steps, culprit, t, h_next, rejected_steps)``.
    """
    n = rad.shape[0]
    skin2 = 0.25 * skin * skin
    n_wl = nwl[0]
    t = t0
    h = h_try
    hs = h_state[0]
    steps = 0
    rejected = 0
    # integrands at the start of the step (kept between calls in ledger[4:8])
    q_w = ledger[4]
    q_n = ledger[5]
    q_f = ledger[6]
    q_i = ledger[7]
    if prime:
        r = rebuild_lists(pos, rad, mass, mat, nmat, estar, skin, use_cells, lo, cell, ncell, head, nxt, counts,
                          row, pi_, pj, pvin, pd, pk, pmp, pms, row2, pj2, pvin2, pd2,
                          wall_kind, wall_data, wl_i, wl_w, floor, ref)
        if r < 0:
            return (STATUS_LIST_OVERFLOW if r == -1 else STATUS_WALL_OVERFLOW), 0, -1, t, h, 0
        n_wl = r
        nwl[0] = r
        compute_forces(pos, vel, omg, rad, mass, force, torque, row, pi_, pj, pvin, pd, pk, pmp, pms,
                       wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk, wmp, wvin, wd, wrs,
                       estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, h, fr_i[:0], fr[:0], fr_n)
        xc, vc, ac = drive_motion(drive_kind, drive_par, drive_tab, t)
        hs = h
        for i in range(n):
            for c in range(3):
                nord[0, i, c] = pos[i, c]
                nord[1, i, c] = hs * vel[i, c]
                nord[2, i, c] = 0.5 * hs * hs * (force[i, c] * inv_m[i] + gvec[c] - ac * dvec[c])
                nord[0, i, 3 + c] = 0.0
                nord[1, i, 3 + c] = hs * omg[i, c]
                nord[2, i, 3 + c] = 0.5 * hs * hs * torque[i, c] * inv_i[i]
                for k in range(3, 6):
                    nord[k, i, c] = 0.0
                    nord[k, i, 3 + c] = 0.0
    while t < t_end - 1e-12 * ts and steps < max_steps:
        # step length: end on the next sample boundary or t_end
        # (a step that would stop just short of the boundary is stretched onto it, so no
        # boundary is ever passed over or approached by a sliver of a step)
        kb = math.floor(t / ts + 1e-9) + 1
        tb = kb * ts
        hh = h
        if hh > tb - t or tb - t - hh < 1e-3 * hh:
            hh = tb - t
        if hh > t_end - t:
            hh = t_end - t
        if hh != hs:
            _rescale(nord, hh / hs)
            hs = hh
        # neighbour lists at the current positions
        for i in range(n):
            for c in range(3):
                pos[i, c] = nord[0, i, c]
        if max_displacement_sq(pos, ref) > skin2:
            r = rebuild_lists(pos, rad, mass, mat, nmat, estar, skin, use_cells, lo, cell, ncell, head, nxt, counts,
                              row, pi_, pj, pvin, pd, pk, pmp, pms, row2, pj2, pvin2, pd2,
                              wall_kind, wall_data, wl_i, wl_w, floor, ref)
            if r < 0:
                h_state[0] = hs
                return (STATUS_LIST_OVERFLOW if r == -1 else STATUS_WALL_OVERFLOW), steps, -1, t, h, rejected
            n_wl = r
            nwl[0] = r
        # predict into ``pred`` (the Nordsieck vector itself stays as it was, so a rejected
        # step has nothing to restore): Pascal-triangle prediction
        nf = nord.reshape(6, 6 * n)
        sf = pred.reshape(6, 6 * n)
        for m in range(6 * n):
            r0 = nf[0, m]
            r1 = nf[1, m]
            r2 = nf[2, m]
            r3 = nf[3, m]
            r4 = nf[4, m]
            r5 = nf[5, m]
            sf[0, m] = r0 + r1 + r2 + r3 + r4 + r5
            sf[1, m] = r1 + 2.0 * r2 + 3.0 * r3 + 4.0 * r4 + 5.0 * r5
            sf[2, m] = r2 + 3.0 * r3 + 6.0 * r4 + 10.0 * r5
            sf[3, m] = r3 + 4.0 * r4 + 10.0 * r5
            sf[4, m] = r4 + 5.0 * r5
            sf[5, m] = r5
        inv_h = 1.0 / hs
        _unpack(pred, inv_h, pos, vel, omg)
        # contact history as it was, in case the step is rejected
        npair = row[n]
        for a in range(npair):
            hist_p[0, a] = pvin[a]
            hist_p[1, a] = pd[a]
        _copy_wall_history(wvin, wd, hist_w[0], hist_w[1], floor, wl_i, wl_w, n_wl)
        tn = t + hs
        fwx, fwy, fwz, p_n, p_f, status, culprit = compute_forces(
            pos, vel, omg, rad, mass, force, torque, row, pi_, pj, pvin, pd, pk, pmp, pms,
            wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk, wmp, wvin, wd, wrs,
            estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, _NO_CAP, fr_i, fr, fr_n)
        xc, vc, ac = drive_motion(drive_kind, drive_par, drive_tab, tn)
        half_h2 = 0.5 * hs * hs
        for i in range(n):
            for c in range(3):
                force[i, c] = half_h2 * (force[i, c] * inv_m[i] + gvec[c] - ac * dvec[c]) - pred[2, i, c]
                torque[i, c] = half_h2 * torque[i, c] * inv_i[i] - pred[2, i, 3 + c]
        dfx, dfy, dfz, dpf = _implicit_friction(rad, inv_m, inv_i, force, torque, hs, fr_i, fr, fr_n)
        fwx += dfx
        fwy += dfy
        fwz += dfz
        p_f += dpf
        err = 0.0
        for i in range(n):
            for c in range(3):
                if math.fabs(force[i, c]) > err:
                    err = math.fabs(force[i, c])
                if math.fabs(torque[i, c]) * rad[i] > err:
                    err = math.fabs(torque[i, c]) * rad[i]
        if not (err < 1e300):
            h_state[0] = hs
            return STATUS_NAN, steps, culprit, t, h, rejected
        if err > 4.0 * tol and hs > dt_min * 1.000001:
            # reject: restore the contact history (the Nordsieck vector was not touched), retry shorter
            for a in range(npair):
                pvin[a] = hist_p[0, a]
                pd[a] = hist_p[1, a]
            _copy_wall_history(hist_w[0], hist_w[1], wvin, wd, floor, wl_i, wl_w, n_wl)
            fac = 0.9 * (tol / err) ** (1.0 / 6.0)
            if fac < 0.2:
                fac = 0.2
            h = hs * fac
            if h < dt_min:
                h = dt_min
            rejected += 1
            continue
        # accept: correct the prediction into the Nordsieck vector (the corrector increments of
        # the positions are in force, those of the rotation angles in torque)
        for i in range(n):
            for c in range(3):
                _correct(nord, pred, i, c, force[i, c])
                _correct(nord, pred, i, 3 + c, torque[i, c])
        t = tn
        steps += 1
        # trapezoidal sums over the (variable) steps: with unequal steps the end-point rule
        # does not telescope and would bias the ledger
        fd = fwx * dvec[0] + fwy * dvec[1] + fwz * dvec[2]
        ledger[0] += 0.5 * (vc * fd + q_w) * hs
        ledger[1] += 0.5 * (p_n + q_n) * hs
        ledger[2] += 0.5 * (p_f + q_f) * hs
        ledger[3] += 0.5 * (fd + q_i) * hs
        q_w = vc * fd
        q_n = p_n
        q_f = p_f
        q_i = fd
        if status != STATUS_OK:
            h_state[0] = hs
            return status, steps, culprit, t, h, rejected
        ledger[4] = q_w
        ledger[5] = q_n
        ledger[6] = q_f
        ledger[7] = q_i
        # next step
        fac = 1.5 if err <= 0.0 else 0.9 * (tol / err) ** (1.0 / 6.0)
        if fac > 1.5:
            fac = 1.5
        if fac < 0.2:
            fac = 0.2
        if not (hs < h and fac >= 1.0):
            h = hs * fac
        if h > dt_max:
            h = dt_max
        if h < dt_min:
            h = dt_min
        if record and math.fabs(t - tb) <= 1e-9 * ts:
            _unpack(nord, inv_h, pos, vel, omg)
            record_sample(kb - 1, ts, vc, dvec, gvec, pos, vel, omg, mass, rad, inv_i,
                          row, pi_, pj, pk, wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk,
                          ledger, sig, eng, traj_every, traj)
    # leave the state in pos/vel/omg
    _unpack(nord, 1.0 / hs, pos, vel, omg)
    h_state[0] = hs
    return STATUS_OK, steps, -1, t, h, rejected
