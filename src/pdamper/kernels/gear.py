r"""Variable-step fifth-order Gear predictor-corrector (the paper's integrator, its ref. [9]).

Each sphere has six second-order degrees of freedom: its position and a rotation "angle" vector
whose rate is the spin (only the spin enters the physics). They are carried as a Nordsieck
vector of scaled derivatives ``r_k = h^k / k! d^k x / dt^k``, k = 0..5, in ``nord[k, i, dof]``.

Per step: Pascal-triangle prediction, forces at the predicted positions and velocities
(``v = r_1 / h``), the corrector ``r_k += c_k Delta`` with ``Delta = h^2/2 a - r_2^pred`` and
Gear's coefficients for velocity-dependent forces
``c = (3/20, 251/360, 1, 11/18, 1/6, 1/60)`` (Allen & Tildesley, Computer Simulation of
Liquids, App. E).

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
                       estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, h)
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
            estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, hs)
        xc, vc, ac = drive_motion(drive_kind, drive_par, drive_tab, tn)
        half_h2 = 0.5 * hs * hs
        err = 0.0
        for i in range(n):
            for c in range(3):
                dlt = half_h2 * (force[i, c] * inv_m[i] + gvec[c] - ac * dvec[c]) - pred[2, i, c]
                force[i, c] = dlt
                if math.fabs(dlt) > err:
                    err = math.fabs(dlt)
                dr = half_h2 * torque[i, c] * inv_i[i] - pred[2, i, 3 + c]
                torque[i, c] = dr
                if math.fabs(dr) * rad[i] > err:
                    err = math.fabs(dr) * rad[i]
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
