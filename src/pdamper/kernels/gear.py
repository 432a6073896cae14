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
it: at large strokes most of plain Gear's steps go there (5.5x the steps of a run without friction
at 50 mm), and its energy ledger does not close at mu = 1. So after the forces at the predicted
state, every touching contact's friction is evaluated again at the slip the corrector will give
(:func:`_implicit_friction`, with :func:`~pdamper.kernels.contact.corrected_friction`): linearised in
the slip, ``ds = dc / (1 + a K c)`` with ``dc`` the
explicit corrector's slip increment, ``c`` the law's secant coefficient at the predicted slip,
``K`` the contact's inverse tangential mass and ``a = c_1 h / 2``; the force ``-c (s + ds)`` is
clipped to the Coulomb limit ``mu F_N``. Contacts are visited in list order (pairs, floor, other
walls) and each sees the increments already changed by those before it: one Gauss-Seidel sweep,
not a converged solve. What this evaluates is one linearisation of the law: the coefficient
comes from the predicted slip (a contact whose slip grows out of the smooth range gets up to
1/tanh(1) = 1.31x the law's force at its corrected slip; one whose slip shrinks gets less), and
for a body with several contacts those visited early are moved off ``-c (s + ds)`` by the later
ones (up to 6 % of mu F_N, measured on a three-sphere pile at ``a K c`` ~ 6). The error
control sees what is left. The friction power for the ledger is taken per contact at its slip
when it is visited, not after the sweep (taking it after the sweep does not improve the ledger:
docs/integrators.md). The explicit step's friction cap
(:data:`~pdamper.kernels.contact.FRICTION_CAP`) is off for Gear's steps.

**The tangential spring** (``contact.tangential = "spring"``, :mod:`pdamper.contact.tangential_spring`)
records no friction rows, so the implicit pass does nothing: the spring is not the stiff slope
``mu F_N tau`` that pass exists for, but a stiffness like the normal one, which the error control
resolves as it resolves the Hertz spring. Each force evaluation advances the springs by the
contact points' displacement from the predicted state they were last advanced at to the step's
prediction (``gear.anchor``, ``gear.moved``), so the springs follow the positions the forces are
evaluated at; a rejected step restores them with the rest of the contact history, and the energy a
spring dissipates in a step is added to the ledger as it is (not by the trapezoid of the powers).

**Error control.** ``|Delta|`` estimates the local error of a step [m] (spin DOFs are scaled by
the radius). A step whose error exceeds 4x the tolerance is rejected and retried shorter; after
an accepted step the next is ``h (tol/err)^(1/6)``, times 0.9, within [0.2, 1.5] h and within
[dt_min, dt_max]. Steps end exactly on sample boundaries, where the Nordsieck vector is rescaled
(``r_k *= (h_new/h_old)^k``).

**On a coupled structure** the structure is advanced by the same step as under Verlet
(:func:`~pdamper.kernels.structure.structure_step`), once per step with Gear's ``h`` at the end
of the step, with the wall force at the predicted state; after the implicit friction pass has
changed the wall force, the step is repeated from the saved state with the corrected force and
the spheres' increments follow the changed container acceleration (``-h^2/2 Delta a_s d``). A
rejected step restores the saved structure with the contact history.

Reference: Gear, C. W. (1971). Numerical Initial Value Problems in Ordinary Differential
Equations. Prentice-Hall.
"""

from __future__ import annotations

import math

from ..jit import njit
from .contact import corrected_friction, floor_slip, keeps_history, pair_point_velocity, scatter, wall_point_velocity
from .drive import drive_motion, is_coupled
from .forces import (FLOOR, SPHERE, STATUS_LIST_OVERFLOW, STATUS_NAN, STATUS_OK, STATUS_WALL_OVERFLOW,
                     compute_forces, no_friction_record, split_add, wall_type_of)
from .neighbours import max_displacement_sq, rebuild_lists
from .record import integrate_split, record_sample
from .structure import advance_structure, ground_on_bed

__all__ = ["run_gear", "GEAR_C", "predict_dof", "step_to_boundary", "shorter_step", "next_step"]

#: Corrector coefficients of the 6-value Gear scheme for second-order equations with
#: velocity-dependent forces.
GEAR_C = (3.0 / 20.0, 251.0 / 360.0, 1.0, 11.0 / 18.0, 1.0 / 6.0, 1.0 / 60.0)

#: compute_forces' step argument that switches its explicit friction cap off (the implicit pass
#: takes its place).
_NO_CAP = 1e-300


@njit(inline="always")
def predict_dof(r0, r1, r2, r3, r4, r5):
    """One degree of freedom's Nordsieck vector predicted a step on (the Pascal triangle). Scalars
    only: the CPU's :func:`_predict` and the GPU engine (:mod:`pdamper.kernels.gpu.gear`) compile
    the same function, as they do the step control below."""
    return (r0 + r1 + r2 + r3 + r4 + r5, r1 + 2.0 * r2 + 3.0 * r3 + 4.0 * r4 + 5.0 * r5,
            r2 + 3.0 * r3 + 6.0 * r4 + 10.0 * r5, r3 + 4.0 * r4 + 10.0 * r5, r4 + 5.0 * r5, r5)


@njit(inline="always")
def step_to_boundary(t, ts, h, t_end):
    """The step from ``t`` [s]: ``h``, ended on the next sample boundary (interval ``ts``) or
    ``t_end`` -- a step that would stop just short of the boundary is stretched onto it, so no
    boundary is ever passed over or approached by a sliver of a step. Returns ``(kb, tb, step)``:
    the boundary's number and time [s] and the step [s]."""
    kb = int(math.floor(t / ts + 1e-9)) + 1  # (an integer on every target: CUDA's floor is a float)
    tb = kb * ts
    hh = h
    if hh > tb - t or tb - t - hh < 1e-3 * hh:
        hh = tb - t
    if hh > t_end - t:
        hh = t_end - t
    return kb, tb, hh


@njit(inline="always")
def shorter_step(hs, tol, err, h_min):
    """The step to retry after a step ``hs`` [s] was rejected with error ``err`` [m] (tolerance
    ``tol``): ``0.9 (tol/err)^(1/6)`` of it, at least 0.2 of it and ``h_min``."""
    fac = 0.9 * (tol / err) ** (1.0 / 6.0)
    if fac < 0.2:
        fac = 0.2
    h = hs * fac
    if h < h_min:
        h = h_min
    return h


@njit(inline="always")
def next_step(hs, h, tol, err, h_min, h_max):
    """The step to try after step ``hs`` [s] was accepted with error ``err`` [m] (``h``: the step
    that was to be tried, which a step shortened onto a sample boundary does not shrink):
    ``0.9 (tol/err)^(1/6)`` of ``hs`` within [0.2, 1.5] of it and [``h_min``, ``h_max``]."""
    fac = 1.5 if err <= 0.0 else 0.9 * (tol / err) ** (1.0 / 6.0)
    if fac > 1.5:
        fac = 1.5
    if fac < 0.2:
        fac = 0.2
    if not (hs < h and fac >= 1.0):
        h = hs * fac
    if h > h_max:
        h = h_max
    if h < h_min:
        h = h_min
    return h


@njit
def _rescale(nord, ratio):
    """The Nordsieck vector rescaled to a step ``ratio`` times the one it is scaled to
    (``r_k *= ratio^k``), in flat loops."""
    nf = nord.reshape(6, -1)
    f = 1.0
    for k in range(1, 6):
        f *= ratio
        for m in range(nf.shape[1]):
            nf[k, m] *= f


@njit
def _predict(nord, pred, ratio, inv_h, bodies):
    """Rescale the Nordsieck vector to the new step (``r_k *= ratio^k``, skipped when ``ratio`` is
    1), predict it into ``pred`` (Pascal triangle) and unpack the predicted positions, velocities
    and spins into ``bodies``. The rescaling and the prediction run as flat loops over all degrees
    of freedom, which LLVM vectorises (twice as fast as one loop over spheres and components with
    the unpacking in it; the same arithmetic per value, so bit-identical)."""
    if ratio != 1.0:
        _rescale(nord, ratio)
    nf = nord.reshape(6, -1)
    pf = pred.reshape(6, -1)
    for m in range(nf.shape[1]):
        pf[0, m], pf[1, m], pf[2, m], pf[3, m], pf[4, m], pf[5, m] = predict_dof(nf[0, m], nf[1, m], nf[2, m], nf[3, m],
                                                                                nf[4, m], nf[5, m])
    _unpack(pred, inv_h, bodies)


@njit
def _unpack(nord, inv_h, bodies):
    """Positions, velocities and spins from the Nordsieck vector (scaled to step 1/inv_h)."""
    pos = bodies.position
    vel = bodies.velocity
    omg = bodies.spin
    for i in range(pos.shape[0]):
        for c in range(3):
            pos[i, c] = nord[0, i, c]
            vel[i, c] = nord[1, i, c] * inv_h
            omg[i, c] = nord[1, i, 3 + c] * inv_h


@njit
def _correct(nord, pred, increments):
    """The corrected Nordsieck vector: the prediction plus Gear's ``c_k`` times each degree of
    freedom's increment (``increments`` is (N, 6): positions, then angles), in flat loops."""
    nf = nord.reshape(6, -1)
    pf = pred.reshape(6, -1)
    d = increments.reshape(-1)
    for k in range(6):
        ck = GEAR_C[k]
        for m in range(d.shape[0]):
            nf[k, m] = pf[k, m] + ck * d[m]


@njit(inline="always")
def _record_row(rows, q):
    """Normal, slip, secant coefficient and slip speed of recorded friction contact ``q``."""
    tx = rows[q, 3]
    ty = rows[q, 4]
    tz = rows[q, 5]
    return rows[q, 0], rows[q, 1], rows[q, 2], tx, ty, tz, rows[q, 6], math.sqrt(tx * tx + ty * ty + tz * tz)


@njit(inline="always")
def floor_friction_step(cf, lim, tx, tz, ux, uz, ex, ez, ri, g, a, kk):
    """The implicit friction correction of one floor contact (n = +y): the corrected force's
    increment ``(gx, gz)`` and its power term, for the slip ``(tx, 0, tz)``, secant coefficient
    ``cf``, limit ``lim``, the sphere's velocity and spin increments ``(ux, uz)``, ``(ex, ez)``,
    Gear's ``g`` and ``a`` and the contact's inverse mass ``kk``. The CPU's pass and the GPU's
    kernel both call it."""
    vt = math.sqrt(tx * tx + tz * tz)
    sx, sz = floor_slip(ux, uz, ex, ez, ri)
    dcx = g * sx
    dcz = g * sz
    gx, gy, gz, fx, fy, fz = corrected_friction(cf, lim, kk, a, tx, 0.0, tz, dcx, 0.0, dcz)
    return gx, gz, -(fx * (tx + dcx + a * kk * gx) + fz * (tz + dcz + a * kk * gz)) - cf * vt * vt


@njit(inline="always")
def wall_friction_step(cf, lim, n, t, u, e, ri, g, a, kk):
    """The implicit friction correction of one contact with a wall of normal ``n`` (into the
    container): as :func:`floor_friction_step`, with the slip ``t`` and the sphere's velocity and
    spin increments ``u``, ``e`` (each a tuple ``(x, y, z)``); returns ``(gx, gy, gz, power term)``."""
    nx, ny, nz = n
    tx, ty, tz = t
    ux, uy, uz = u
    ex, ey, ez = e
    vt = math.sqrt(tx * tx + ty * ty + tz * tz)
    dcx, dcy, dcz, dcn = wall_point_velocity(g * ux, g * uy, g * uz, g * ex, g * ey, g * ez, ri, nx, ny, nz)
    dcx -= dcn * nx
    dcy -= dcn * ny
    dcz -= dcn * nz
    gx, gy, gz, fx, fy, fz = corrected_friction(cf, lim, kk, a, tx, ty, tz, dcx, dcy, dcz)
    return gx, gy, gz, (-(fx * (tx + dcx + a * kk * gx) + fy * (ty + dcy + a * kk * gy) + fz * (tz + dcz + a * kk * gz))
                        - cf * vt * vt)


@njit
def _implicit_friction(bodies, dv, dw, hs, record, split):
    """Re-evaluate the friction of every contact that :func:`~pdamper.kernels.forces.compute_forces`
    recorded at its corrected slip (linearly implicit in the slip, Gauss-Seidel over the
    contacts) and add the change to the Gear increments ``dv`` (positions) and ``dw`` (angles) in
    place.

    The explicit Gear corrector evaluates the tanh law at the *predicted* slip; during an impact
    its slope ``mu F_N tau`` relaxes the slip within a fraction of a microsecond, and the error
    control then has to follow that relaxation. Evaluated at the corrected slip, an isolated
    sticking contact's force is whatever keeps it sticking (up to ``mu F_N``), smooth in time;
    one Gauss-Seidel sweep only approximates that where a body has several contacts (module
    docstring).

    Returns ``(dfx, dfy, dfz, dp_f)``: the change of the walls' force on the spheres [N] and of
    the friction power [W]; with the ledger split by contact type (``split``), the change of each
    type's friction power is added to ``split.power`` too.
    """
    rad = bodies.radius
    inv_m = bodies.inv_mass
    inv_i = bodies.inv_inertia
    ids = record.bodies
    fr = record.rows
    ends = record.ends
    g = GEAR_C[1] / hs
    a = 0.5 * GEAR_C[1] * hs
    hh = 0.5 * hs * hs
    dfx = 0.0
    dfy = 0.0
    dfz = 0.0
    dpf = 0.0
    # ---- sphere pairs: n from i to j, slip (v_i - v_j) + (r_i w_i + r_j w_j) x n
    for q in range(ends[0]):
        i = ids[q, 0]
        j = ids[q, 1]
        ri = rad[i]
        rj = rad[j]
        nx, ny, nz, tx, ty, tz, c, vt = _record_row(fr, q)
        # slip increment of the explicit corrector (the same kinematics on the velocity increments)
        dcx, dcy, dcz, dcn = pair_point_velocity(
            g * (dv[i, 0] - dv[j, 0]), g * (dv[i, 1] - dv[j, 1]), g * (dv[i, 2] - dv[j, 2]),
            g * (ri * dw[i, 0] + rj * dw[j, 0]), g * (ri * dw[i, 1] + rj * dw[j, 1]),
            g * (ri * dw[i, 2] + rj * dw[j, 2]), nx, ny, nz)
        kk = inv_m[i] + inv_m[j] + ri * ri * inv_i[i] + rj * rj * inv_i[j]
        gx, gy, gz, fx, fy, fz = corrected_friction(c, fr[q, 7], kk, a, tx, ty, tz,
                                                    dcx - dcn * nx, dcy - dcn * ny, dcz - dcn * nz)
        # power: the new force on the corrected slip, minus the explicit c s^2
        dp = -(fx * (tx + dcx - dcn * nx + a * kk * gx) + fy * (ty + dcy - dcn * ny + a * kk * gy)
               + fz * (tz + dcz - dcn * nz + a * kk * gz)) - c * vt * vt
        dpf += dp
        split_add(split, SPHERE, 0.0, dp, 0.0)
        scatter(dv, dw, i, j, (gx, gy, gz), (nx, ny, nz), (gx, gy, gz), hh * inv_m[i], hh * inv_m[j],
                hh * inv_i[i] * ri, hh * inv_i[j] * rj)
    # ---- the floor: n = +y, slip (v_x + r w_z, 0, v_z - r w_x)
    for q in range(ends[0], ends[1]):
        i = ids[q, 0]
        ri = rad[i]
        kk = inv_m[i] + ri * ri * inv_i[i]
        gx, gz, dp = floor_friction_step(fr[q, 6], fr[q, 7], fr[q, 3], fr[q, 5], dv[i, 0], dv[i, 2], dw[i, 0],
                                         dw[i, 2], ri, g, a, kk)
        dpf += dp
        split_add(split, FLOOR, 0.0, dp, 0.0)
        scatter(dv, dw, i, -1, (gx, 0.0, gz), (0.0, 1.0, 0.0), (gx, 0.0, gz), hh * inv_m[i], 0.0,
                -(hh * inv_i[i] * ri), 0.0)
        dfx += gx
        dfz += gz
    # ---- the other walls: n into the container, slip v - r w x n
    for q in range(ends[1], ends[2]):
        i = ids[q, 0]
        ri = rad[i]
        nx = fr[q, 0]
        ny = fr[q, 1]
        nz = fr[q, 2]
        kk = inv_m[i] + ri * ri * inv_i[i]
        gx, gy, gz, dp = wall_friction_step(fr[q, 6], fr[q, 7], (nx, ny, nz), (fr[q, 3], fr[q, 4], fr[q, 5]),
                                            (dv[i, 0], dv[i, 1], dv[i, 2]), (dw[i, 0], dw[i, 1], dw[i, 2]), ri, g, a,
                                            kk)
        dpf += dp
        split_add(split, wall_type_of(split, -1 - ids[q, 1]), 0.0, dp, 0.0)
        scatter(dv, dw, i, -1, (gx, gy, gz), (nx, ny, nz), (gx, gy, gz), hh * inv_m[i], 0.0, -(hh * inv_i[i] * ri),
                0.0)
        dfx += gx
        dfy += gy
        dfz += gz
    return dfx, dfy, dfz, dpf


@njit
def _copy_wall_history(src_v, src_d, dst_v, dst_d, walls):
    """Copy the wall-contact history (approach speed, damping parameter) that the force loop can
    change -- the floor column and the listed wall candidates -- from ``src_*`` to ``dst_*``."""
    floor = walls.floor
    if floor >= 0:
        for i in range(src_v.shape[0]):
            dst_v[i, floor] = src_v[i, floor]
            dst_d[i, floor] = src_d[i, floor]
    cand_i = walls.candidate_body
    cand_w = walls.candidate_wall
    for q in range(walls.n_candidates[0]):
        i = cand_i[q]
        w = cand_w[q]
        dst_v[i, w] = src_v[i, w]
        dst_d[i, w] = src_d[i, w]


@njit
def _copy_tangential(hp, hw, npair, pairs, walls, save):
    """Save the tangential history that a step can change (the first ``npair`` pairs' rows, the
    floor column, the wall candidates) into rows 2... of Gear's saved pair and wall history
    ``hp``, ``hw``, or restore it from there (``save`` false)."""
    pt = pairs.tangential
    wt = walls.tangential
    nt = pt.shape[1]
    for a in range(npair):
        for c in range(nt):
            if save:
                hp[2 + c, a] = pt[a, c]
            else:
                pt[a, c] = hp[2 + c, a]
    floor = walls.floor
    if floor >= 0:
        for i in range(wt.shape[0]):
            for c in range(nt):
                if save:
                    hw[2 + c, i, floor] = wt[i, floor, c]
                else:
                    wt[i, floor, c] = hw[2 + c, i, floor]
    cand_i = walls.candidate_body
    cand_w = walls.candidate_wall
    for q in range(walls.n_candidates[0]):
        i = cand_i[q]
        w = cand_w[q]
        for c in range(nt):
            if save:
                hw[2 + c, i, w] = wt[i, w, c]
            else:
                wt[i, w, c] = hw[2 + c, i, w]


@njit
def _copy_structure(src, dst):
    for r in range(src.shape[0]):
        for c in range(src.shape[1]):
            dst[r, c] = src[r, c]


@njit
def run_gear(span, bodies, gear, pairs, walls, search, table, drive, samples):
    """Advance from ``span.t0`` to ``span.t_end`` [s] (or ``span.max_steps`` accepted steps);
    ``span`` is a :class:`~pdamper.kernels.bundles.GearSpan`, ``gear`` the
    :class:`~pdamper.kernels.bundles.GearState`.

    ``gear.predicted`` receives the predicted Nordsieck vector of each step, which the corrector
    writes back into ``gear.nordsieck`` when the step is accepted; the saved pair, wall and
    structure state is restored when the step is rejected. ``gear.step[0]`` is the step the
    Nordsieck vector is scaled to; ``span.h_try`` the next step to try. Samples (interval
    ``span.interval``) are written as in :func:`pdamper.kernels.verlet.run_verlet` when
    ``span.record`` is true (sample k ends at ``(k + 1) interval``).

    Returns ``(status, accepted_steps, culprit, t, h_next, rejected_steps)``.
    """
    pos = bodies.position
    vel = bodies.velocity
    omg = bodies.spin
    rad = bodies.radius
    inv_m = bodies.inv_mass
    inv_i = bodies.inv_inertia
    force = bodies.force
    torque = bodies.torque
    nord = gear.nordsieck
    pred = gear.predicted
    hist_p = gear.saved_pair_history
    hist_w = gear.saved_wall_history
    record = gear.friction
    dlt = gear.increments
    dlt_x = dlt[:, 0:3]
    dlt_a = dlt[:, 3:6]
    gvec = drive.gravity
    dvec = drive.direction
    coupled = is_coupled(drive)
    spring = keeps_history(table.tangential)
    anchor = gear.anchor.reshape(-1)
    mvf = gear.moved.reshape(-1)
    sums = samples.sums
    ts = span.interval
    tol = span.tolerance
    t_end = span.t_end
    n = rad.shape[0]
    skin2 = 0.25 * search.skin * search.skin
    t = span.t0
    h = span.h_try
    hs = gear.step[0]
    steps = 0
    rejected = 0
    # integrands at the start of the step (kept between calls in gear.integrands)
    q_w = gear.integrands[0]
    q_n = gear.integrands[1]
    q_f = gear.integrands[2]
    q_i = gear.integrands[3]
    if span.prime:
        r = rebuild_lists(bodies, pairs, walls, search, table)
        if r < 0:
            return (STATUS_LIST_OVERFLOW if r == -1 else STATUS_WALL_OVERFLOW), 0, -1, t, h, 0
        for m in range(mvf.shape[0]):
            mvf[m] = 0.0
        compute_forces(bodies, pairs, walls, table, h, 0.0, gear.moved, no_friction_record(), samples.split)
        xc, vc, ac = drive_motion(drive, t)
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
        if spring:
            a0 = nord[0].reshape(-1)
            for m in range(anchor.shape[0]):
                anchor[m] = a0[m]
    while t < t_end - 1e-12 * ts and steps < span.max_steps:
        # step length: end on the next sample boundary or t_end
        kb, tb, hh = step_to_boundary(t, ts, h, t_end)
        ratio = 1.0
        if hh != hs:
            ratio = hh / hs
            hs = hh
        # neighbour lists at the current positions (the Nordsieck vector's first row)
        if max_displacement_sq(nord[0], search.reference) > skin2:
            for i in range(n):
                for c in range(3):
                    pos[i, c] = nord[0, i, c]
            r = rebuild_lists(bodies, pairs, walls, search, table)
            if r < 0:
                gear.step[0] = hs
                _rescale(nord, ratio)
                return (STATUS_LIST_OVERFLOW if r == -1 else STATUS_WALL_OVERFLOW), steps, -1, t, h, rejected
        # rescale to the step, predict into ``predicted`` (the Nordsieck vector itself stays as
        # it was, so a rejected step has nothing to restore) and unpack the prediction
        inv_h = 1.0 / hs
        _predict(nord, pred, ratio, inv_h, bodies)
        if spring:
            # what the springs advance by: this prediction against the one they were last advanced at
            p0 = pred[0].reshape(-1)
            for m in range(mvf.shape[0]):
                mvf[m] = p0[m] - anchor[m]
        # contact history as it was, in case the step is rejected
        npair = pairs.row[n]
        pvin = pairs.approach_speed
        pd = pairs.damping
        for a in range(npair):
            hist_p[0, a] = pvin[a]
            hist_p[1, a] = pd[a]
        _copy_wall_history(walls.approach_speed, walls.damping, hist_w[0], hist_w[1], walls)
        if spring:
            _copy_tangential(hist_p, hist_w, npair, pairs, walls, True)
        tn = t + hs
        fwx, fwy, fwz, p_n, p_f, e_f, status, culprit = compute_forces(bodies, pairs, walls, table, _NO_CAP, hs,
                                                                       gear.moved, record, samples.split)
        if coupled:
            _copy_structure(drive.state, gear.saved_structure)
            advance_structure(drive, tn, hs, fwx * dvec[0] + fwy * dvec[1] + fwz * dvec[2])
        xc, vc, ac = drive_motion(drive, tn)
        half_h2 = 0.5 * hs * hs
        for i in range(n):
            for c in range(3):
                dlt[i, c] = half_h2 * (force[i, c] * inv_m[i] + gvec[c] - ac * dvec[c]) - pred[2, i, c]
                dlt[i, 3 + c] = half_h2 * torque[i, c] * inv_i[i] - pred[2, i, 3 + c]
        dfx, dfy, dfz, dpf = _implicit_friction(bodies, dlt_x, dlt_a, hs, record, samples.split)
        fwx += dfx
        fwy += dfy
        fwz += dfz
        p_f += dpf
        if coupled:
            # the structure again, with the wall force after the friction pass; the spheres
            # follow the change of the container's acceleration
            _copy_structure(gear.saved_structure, drive.state)
            advance_structure(drive, tn, hs, fwx * dvec[0] + fwy * dvec[1] + fwz * dvec[2])
            xc, vc, ac2 = drive_motion(drive, tn)
            da = half_h2 * (ac2 - ac)
            for i in range(n):
                for c in range(3):
                    dlt[i, c] -= da * dvec[c]
        err = 0.0
        for i in range(n):
            for c in range(3):
                if math.fabs(dlt[i, c]) > err:
                    err = math.fabs(dlt[i, c])
                if math.fabs(dlt[i, 3 + c]) * rad[i] > err:
                    err = math.fabs(dlt[i, 3 + c]) * rad[i]
        if not (err < 1e300):
            gear.step[0] = hs
            return STATUS_NAN, steps, culprit, t, h, rejected
        if err > 4.0 * tol and hs > span.h_min * 1.000001:
            # reject: restore the contact history (the Nordsieck vector was not touched), retry shorter
            for a in range(npair):
                pvin[a] = hist_p[0, a]
                pd[a] = hist_p[1, a]
            _copy_wall_history(hist_w[0], hist_w[1], walls.approach_speed, walls.damping, walls)
            if spring:
                _copy_tangential(hist_p, hist_w, npair, pairs, walls, False)
            if coupled:
                _copy_structure(gear.saved_structure, drive.state)
            h = shorter_step(hs, tol, err, span.h_min)
            rejected += 1
            continue
        # accept: correct the prediction into the Nordsieck vector
        _correct(nord, pred, dlt)
        if coupled:
            # under a ground acceleration, its inertial force's work on the bed (the ground's frame)
            sums[0] += ground_on_bed(drive, bodies.mass, nord[1], inv_h, vc, hs)
        if spring:
            p0 = pred[0].reshape(-1)
            for m in range(anchor.shape[0]):
                anchor[m] = p0[m]
        t = tn
        steps += 1
        # trapezoidal sums over the (variable) steps: with unequal steps the end-point rule
        # does not telescope and would bias the ledger
        fd = fwx * dvec[0] + fwy * dvec[1] + fwz * dvec[2]
        sums[0] += 0.5 * (vc * fd + q_w) * hs
        sums[1] += 0.5 * (p_n + q_n) * hs
        sums[2] += 0.5 * (p_f + q_f) * hs
        if spring:
            sums[2] += e_f
        sums[3] += 0.5 * (fd + q_i) * hs
        integrate_split(samples.split, hs, True, spring)
        q_w = vc * fd
        q_n = p_n
        q_f = p_f
        q_i = fd
        if status != STATUS_OK:
            gear.step[0] = hs
            return status, steps, culprit, t, h, rejected
        gear.integrands[0] = q_w
        gear.integrands[1] = q_n
        gear.integrands[2] = q_f
        gear.integrands[3] = q_i
        # next step
        h = next_step(hs, h, tol, err, span.h_min, span.h_max)
        if span.record and math.fabs(t - tb) <= 1e-9 * ts:
            _unpack(nord, inv_h, bodies)
            record_sample(kb - 1, samples, bodies, pairs, walls, drive, xc, vc)
    # leave the state in the bodies
    _unpack(nord, 1.0 / hs, bodies)
    gear.step[0] = hs
    return STATUS_OK, steps, -1, t, h, rejected
