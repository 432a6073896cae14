"""Fixed-step velocity Verlet for spheres in a moving container (container frame).

Per step: half kick, drift, (rebuild lists if a particle moved more than half the skin),
forces at the new positions with the velocities predicted to the full step
(``v_half + a_old dt/2``, needed by the velocity-dependent damping and friction), half kick.
The container's acceleration enters as the pseudo-force ``-m a_c(t) d_c``.

The loop also accumulates the recorded signals: the impulse of the wall forces along the drive
over each sample interval, and the energy ledger (work of the container, dissipation by normal
damping and by friction).
"""

from __future__ import annotations

import math

from .drive import drive_motion
from .forces import STATUS_LIST_OVERFLOW, STATUS_NAN, STATUS_OK, STATUS_WALL_OVERFLOW, compute_forces
from .jit import njit
from .neighbours import max_displacement_sq, rebuild_lists
from .record import record_sample

__all__ = ["run_verlet"]


@njit
def run_verlet(n_steps, dt, t0, step0, sub, record, rec_offset, prime,
               pos, vel, omg, acc, alp, acc_prev, alp_prev, rad, mass, inv_m, inv_i, mat,
               force, torque, gvec, dvec, drive_kind, drive_par, drive_tab,
               nmat, estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit,
               skin, use_cells, lo, cell, ncell, head, nxt, counts, ref,
               row, pj, pvin, pd, pk, pmp, row2, pj2, pvin2, pd2,
               wall_kind, wall_data, wl_i, wl_w, nwl, wk, wmp, wvin, wd, wrs,
               ledger, sig, eng, traj_every, traj):
    """Advance ``n_steps`` steps of ``dt`` [s] from time ``t0``; ``step0`` is the global step
    count (samples end every ``sub`` steps). Arrays are updated in place.

    ``ledger`` = [work by container, dissipated by damping, by friction, impulse accumulator,
    n_wl] carries the running sums between calls. When ``record`` is true, sample ``k`` of the
    run (``k = (step0 + s + 1) // sub - 1 - rec_offset``) is written to ``sig``/``eng`` and every
    ``traj_every``-th sample to ``traj``.

    With ``prime`` true, the accelerations at ``t0`` are computed first (the first call of a
    run), so the first half kick uses the true initial forces.

    Returns ``(status, steps_done, culprit)``.
    """
    n = pos.shape[0]
    half = 0.5 * dt
    skin2 = 0.25 * skin * skin
    n_wl = nwl[0]
    if prime:
        r = rebuild_lists(pos, rad, mat, nmat, estar, skin, use_cells, lo, cell, ncell, head, nxt, counts,
                          row, pj, pvin, pd, pk, pmp, row2, pj2, pvin2, pd2,
                          wall_kind, wall_data, wl_i, wl_w, ref)
        if r == -1:
            return STATUS_LIST_OVERFLOW, 0, -1
        if r == -2:
            return STATUS_WALL_OVERFLOW, 0, -1
        n_wl = r
        nwl[0] = r
        compute_forces(pos, vel, omg, rad, mass, force, torque, row, pj, pvin, pd, pk, pmp,
                       wl_i, wl_w, n_wl, wall_kind, wall_data, wk, wmp, wvin, wd, wrs,
                       estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, dt)
        xc, vc, ac = drive_motion(drive_kind, drive_par, drive_tab, t0)
        for i in range(n):
            for c in range(3):
                acc[i, c] = force[i, c] * inv_m[i] + gvec[c] - ac * dvec[c]
                alp[i, c] = torque[i, c] * inv_i[i]
                acc_prev[i, c] = acc[i, c]
                alp_prev[i, c] = alp[i, c]
    for s in range(n_steps):
        t = t0 + (s + 1) * dt
        # -- neighbour lists (before anything moves, so an overflow can be resumed)
        if max_displacement_sq(pos, ref) > skin2:
            r = rebuild_lists(pos, rad, mat, nmat, estar, skin, use_cells, lo, cell, ncell, head, nxt, counts,
                              row, pj, pvin, pd, pk, pmp, row2, pj2, pvin2, pd2,
                              wall_kind, wall_data, wl_i, wl_w, ref)
            if r == -1:
                return STATUS_LIST_OVERFLOW, s, -1
            if r == -2:
                return STATUS_WALL_OVERFLOW, s, -1
            n_wl = r
            nwl[0] = r
        # -- half kick + drift; keep full-step velocity prediction in force/torque buffers' place
        for i in range(n):
            for c in range(3):
                vel[i, c] += half * acc[i, c]
                omg[i, c] += half * alp[i, c]
                pos[i, c] += dt * vel[i, c]
        # predicted full-step velocities for the velocity-dependent forces: extrapolate the
        # acceleration linearly, a(t+dt) ~ 2 a(t) - a(t-dt)
        for i in range(n):
            for c in range(3):
                da = acc[i, c] - acc_prev[i, c]
                dw = alp[i, c] - alp_prev[i, c]
                acc_prev[i, c] = acc[i, c] + da
                alp_prev[i, c] = alp[i, c] + dw
                vel[i, c] += half * acc_prev[i, c]
                omg[i, c] += half * alp_prev[i, c]
        fwx, fwy, fwz, p_n, p_f, status, culprit = compute_forces(
            pos, vel, omg, rad, mass, force, torque, row, pj, pvin, pd, pk, pmp,
            wl_i, wl_w, n_wl, wall_kind, wall_data, wk, wmp, wvin, wd, wrs,
            estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, dt)
        xc, vc, ac = drive_motion(drive_kind, drive_par, drive_tab, t)
        gx = gvec[0] - ac * dvec[0]
        gy = gvec[1] - ac * dvec[1]
        gz = gvec[2] - ac * dvec[2]
        bad = False
        for i in range(n):
            # undo the prediction, then the second half kick with the new accelerations
            for c in range(3):
                vel[i, c] -= half * acc_prev[i, c]
                omg[i, c] -= half * alp_prev[i, c]
                acc_prev[i, c] = acc[i, c]
                alp_prev[i, c] = alp[i, c]
            acc[i, 0] = force[i, 0] * inv_m[i] + gx
            acc[i, 1] = force[i, 1] * inv_m[i] + gy
            acc[i, 2] = force[i, 2] * inv_m[i] + gz
            alp[i, 0] = torque[i, 0] * inv_i[i]
            alp[i, 1] = torque[i, 1] * inv_i[i]
            alp[i, 2] = torque[i, 2] * inv_i[i]
            vel[i, 0] += half * acc[i, 0]
            vel[i, 1] += half * acc[i, 1]
            vel[i, 2] += half * acc[i, 2]
            omg[i, 0] += half * alp[i, 0]
            omg[i, 1] += half * alp[i, 1]
            omg[i, 2] += half * alp[i, 2]
            if not (math.fabs(vel[i, 0]) + math.fabs(vel[i, 1]) + math.fabs(vel[i, 2]) < 1e6):
                bad = True
                culprit = i
        fd = fwx * dvec[0] + fwy * dvec[1] + fwz * dvec[2]
        ledger[0] += vc * fd * dt
        ledger[1] += p_n * dt
        ledger[2] += p_f * dt
        ledger[3] += fd * dt
        if bad:
            return STATUS_NAN, s + 1, culprit
        if status != STATUS_OK:
            return status, s + 1, culprit
        g = step0 + s + 1
        if record and g % sub == 0:
            k = g // sub - 1 - rec_offset
            record_sample(k, sub * dt, vc, dvec, gvec, pos, vel, omg, mass, rad, inv_i,
                          row, pj, pk, wl_i, wl_w, n_wl, wall_kind, wall_data, wk,
                          ledger, sig, eng, traj_every, traj)
    return STATUS_OK, n_steps, -1
