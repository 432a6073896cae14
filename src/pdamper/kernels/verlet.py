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

import numpy as np

from .drive import drive_motion
from .forces import STATUS_LIST_OVERFLOW, STATUS_NAN, STATUS_OK, STATUS_WALL_OVERFLOW, compute_forces
from .jit import njit
from .neighbours import max_displacement_sq, rebuild_lists
from .record import record_sample
from .structure import DRIVE_STRUCTURE, record_structure, structure_step

__all__ = ["run_verlet"]


@njit
def run_verlet(n_steps, dt, t0, step0, sub, record, rec_offset, prime,
               pos, vel, omg, acc, alp, acc_prev, alp_prev, rad, mass, inv_m, inv_i, mat,
               force, torque, gvec, dvec, drive_kind, drive_par, drive_tab,
               nmat, estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit,
               skin, use_cells, lo, cell, ncell, head, nxt, counts, ref,
               row, pi_, pj, pvin, pd, pk, pmp, pms, row2, pj2, pvin2, pd2,
               wall_kind, wall_data, floor, wl_i, wl_w, nwl, wk, wmp, wvin, wd, wrs,
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
    # no friction-contact record: that is for Gear's implicit pass (compute_forces writes none)
    no_fr_i = np.zeros((0, 2), dtype=np.int64)
    no_fr = np.zeros((0, 8))
    no_fr_n = np.zeros(3, dtype=np.int64)
    n = pos.shape[0]
    half = 0.5 * dt
    skin2 = 0.25 * skin * skin
    n_wl = nwl[0]
    if prime:
        r = rebuild_lists(pos, rad, mass, mat, nmat, estar, skin, use_cells, lo, cell, ncell, head, nxt, counts,
                          row, pi_, pj, pvin, pd, pk, pmp, pms, row2, pj2, pvin2, pd2,
                          wall_kind, wall_data, wl_i, wl_w, floor, ref)
        if r == -1:
            return STATUS_LIST_OVERFLOW, 0, -1
        if r == -2:
            return STATUS_WALL_OVERFLOW, 0, -1
        n_wl = r
        nwl[0] = r
        compute_forces(pos, vel, omg, rad, mass, force, torque, row, pi_, pj, pvin, pd, pk, pmp, pms,
                       wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk, wmp, wvin, wd, wrs,
                       estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, dt, no_fr_i, no_fr, no_fr_n)
        xc, vc, ac = drive_motion(drive_kind, drive_par, drive_tab, t0)
        for i in range(n):
            for c in range(3):
                acc[i, c] = force[i, c] * inv_m[i] + gvec[c] - ac * dvec[c]
                alp[i, c] = torque[i, c] * inv_i[i]
                acc_prev[i, c] = acc[i, c]
                alp_prev[i, c] = alp[i, c]
    # flat views (3N) of the per-particle vectors: simple, vectorisable loops
    x = pos.reshape(-1)
    v = vel.reshape(-1)
    w = omg.reshape(-1)
    a = acc.reshape(-1)
    al = alp.reshape(-1)
    ap = acc_prev.reshape(-1)
    alp_ = alp_prev.reshape(-1)
    x0 = ref.reshape(-1)
    f = force.reshape(-1)
    tq = torque.reshape(-1)
    m3 = 3 * n
    moved = max_displacement_sq(pos, ref) > skin2
    for s in range(n_steps):
        t = t0 + (s + 1) * dt
        # -- neighbour lists, when a particle moved more than ~half the skin since the last build
        #    (decided during the previous drift; lists change before anything moves, so an
        #    overflow can be resumed)
        if moved:
            r = rebuild_lists(pos, rad, mass, mat, nmat, estar, skin, use_cells, lo, cell, ncell, head, nxt, counts,
                              row, pi_, pj, pvin, pd, pk, pmp, pms, row2, pj2, pvin2, pd2,
                              wall_kind, wall_data, wl_i, wl_w, floor, ref)
            if r == -1:
                return STATUS_LIST_OVERFLOW, s, -1
            if r == -2:
                return STATUS_WALL_OVERFLOW, s, -1
            n_wl = r
            nwl[0] = r
        # -- drift with the half-step velocity v + dt/2 a; the velocities the damping and
        #    friction see are predicted to the full step with a linearly extrapolated
        #    acceleration: v + dt/2 a + dt/2 (2 a - a_prev)
        disp = 0.0
        for k in range(m3):
            x[k] += dt * (v[k] + half * a[k])
            v[k] += half * (3.0 * a[k] - ap[k])
            w[k] += half * (3.0 * al[k] - alp_[k])
            dd = x[k] - x0[k]
            disp = max(disp, dd * dd)
        # a component moved more than skin/(2 sqrt 3) in some direction: rebuild next step
        moved = 3.0 * disp > skin2
        fwx, fwy, fwz, p_n, p_f, status, culprit = compute_forces(
            pos, vel, omg, rad, mass, force, torque, row, pi_, pj, pvin, pd, pk, pmp, pms,
            wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk, wmp, wvin, wd, wrs,
            estar, mu, cor_tab, cor_py, logv0, dlogv, tau, v_floor, overlap_limit, dt, no_fr_i, no_fr, no_fr_n)
        fd = fwx * dvec[0] + fwy * dvec[1] + fwz * dvec[2]
        if drive_kind == DRIVE_STRUCTURE:
            structure_step(drive_par, drive_tab, t, dt, fd)
        xc, vc, ac = drive_motion(drive_kind, drive_par, drive_tab, t)
        gx = gvec[0] - ac * dvec[0]
        gy = gvec[1] - ac * dvec[1]
        gz = gvec[2] - ac * dvec[2]
        # -- new accelerations; correct the predicted velocities to v_half + dt/2 a_new
        vsum = 0.0
        for i in range(n):
            k = 3 * i
            im = inv_m[i]
            ii = inv_i[i]
            for c in range(3):
                an = f[k + c] * im + (gx if c == 0 else (gy if c == 1 else gz))
                v[k + c] += half * (an - 2.0 * a[k + c] + ap[k + c])
                ap[k + c] = a[k + c]
                a[k + c] = an
                wn = tq[k + c] * ii
                w[k + c] += half * (wn - 2.0 * al[k + c] + alp_[k + c])
                alp_[k + c] = al[k + c]
                al[k + c] = wn
                vsum += math.fabs(v[k + c])
        bad = not (vsum < 1e6)
        if bad:
            for k in range(m3):
                if not (math.fabs(v[k]) < 1e6):
                    culprit = k // 3
                    break
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
                          row, pi_, pj, pk, wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk,
                          ledger, sig, eng, traj_every, traj)
            if drive_kind == DRIVE_STRUCTURE:
                record_structure(k, drive_tab, sig)
    return STATUS_OK, n_steps, -1
