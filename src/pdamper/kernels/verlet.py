"""Fixed-step velocity Verlet for spheres in a moving container (container frame).

Per step: half kick, drift, (rebuild lists if a sphere moved more than half the skin), forces
at the new positions with the velocities predicted to the full step (``v_half + a_old dt/2``,
needed by the velocity-dependent damping and friction), the container's motion (a coupled
structure is advanced first, :func:`~pdamper.kernels.structure.structure_step`), half kick.
The container's acceleration enters as the pseudo-force ``-m a_c(t) d``.

The loop also accumulates what the recorders need: the impulse of the wall forces along the
drive over each sample interval, and the energy ledger (work of the container, dissipation by
normal damping and by friction -- the tanh law's power times the step, a tangential spring's
loss of the step as it is), in ``samples.sums``; under a ground acceleration, the work of the
ground's inertial force on the bed, into the structure's external work
(:func:`~pdamper.kernels.structure.ground_on_bed`). A tangential spring advances by the displacement
the drift gives the contact point (``state.moved``), so it follows the positions exactly; the
priming evaluation does not advance it.
"""

from __future__ import annotations

import math

from ..jit import njit
from .contact import keeps_history
from .drive import drive_motion, is_coupled
from .forces import (STATUS_LIST_OVERFLOW, STATUS_NAN, STATUS_OK, STATUS_WALL_OVERFLOW, compute_forces,
                     no_friction_record)
from .neighbours import max_displacement_sq, rebuild_lists
from .record import integrate_split, record_sample
from .structure import advance_structure, ground_on_bed

__all__ = ["run_verlet"]


@njit
def run_verlet(span, bodies, state, pairs, walls, search, table, drive, samples):
    """Advance ``span.steps`` steps of ``span.dt`` [s] from ``span.t0``
    (:class:`~pdamper.kernels.bundles.VerletSpan`); ``state`` is the
    :class:`~pdamper.kernels.bundles.VerletState`. Arrays are updated in place.

    ``samples.sums`` carries the running sums between calls. When ``span.record`` is true,
    sample ``k = (step0 + s + 1) // sub - 1 - skip_samples`` of the run is written at the end
    of every ``sub``-th step (:func:`~pdamper.kernels.record.record_sample`).

    With ``span.prime`` true, the accelerations at ``t0`` are computed first (the first call of a
    run), so the first half kick uses the true initial forces.

    Returns ``(status, steps_done, culprit)``.
    """
    # no friction record: that is for Gear's implicit pass (compute_forces writes none)
    no_record = no_friction_record()
    dt = span.dt
    t0 = span.t0
    sub = span.sub
    pos = bodies.position
    vel = bodies.velocity
    omg = bodies.spin
    inv_m = bodies.inv_mass
    inv_i = bodies.inv_inertia
    acc = state.acceleration
    alp = state.angular_acceleration
    gvec = drive.gravity
    dvec = drive.direction
    sums = samples.sums
    n = pos.shape[0]
    half = 0.5 * dt
    skin2 = 0.25 * search.skin * search.skin
    # loop-invariant, so the compiled loop of a prescribed drive carries no structure step
    coupled = is_coupled(drive)
    spring = keeps_history(table.tangential)
    mv = state.moved
    if span.prime:
        r = rebuild_lists(bodies, pairs, walls, search, table)
        if r == -1:
            return STATUS_LIST_OVERFLOW, 0, -1
        if r == -2:
            return STATUS_WALL_OVERFLOW, 0, -1
        for i in range(n):
            for c in range(6):
                mv[i, c] = 0.0
        compute_forces(bodies, pairs, walls, table, dt, 0.0, mv, no_record, samples.split)
        xc, vc, ac = drive_motion(drive, t0)
        for i in range(n):
            for c in range(3):
                acc[i, c] = bodies.force[i, c] * inv_m[i] + gvec[c] - ac * dvec[c]
                alp[i, c] = bodies.torque[i, c] * inv_i[i]
                state.previous_acceleration[i, c] = acc[i, c]
                state.previous_angular_acceleration[i, c] = alp[i, c]
    # flat views (3N) of the per-sphere vectors: simple, vectorisable loops
    x = pos.reshape(-1)
    v = vel.reshape(-1)
    w = omg.reshape(-1)
    a = acc.reshape(-1)
    al = alp.reshape(-1)
    ap = state.previous_acceleration.reshape(-1)
    alp_ = state.previous_angular_acceleration.reshape(-1)
    x0 = search.reference.reshape(-1)
    f = bodies.force.reshape(-1)
    tq = bodies.torque.reshape(-1)
    m3 = 3 * n
    moved = max_displacement_sq(pos, search.reference) > skin2
    for s in range(span.steps):
        t = t0 + (s + 1) * dt
        # -- neighbour lists, when a sphere moved more than ~half the skin since the last build
        #    (decided during the previous drift; lists change before anything moves, so an
        #    overflow can be resumed)
        if moved:
            r = rebuild_lists(bodies, pairs, walls, search, table)
            if r == -1:
                return STATUS_LIST_OVERFLOW, s, -1
            if r == -2:
                return STATUS_WALL_OVERFLOW, s, -1
        # -- drift with the half-step velocity v + dt/2 a; the velocities the damping and
        #    friction see are predicted to the full step with a linearly extrapolated
        #    acceleration: v + dt/2 a + dt/2 (2 a - a_prev)
        if spring:
            # what the drift moves and turns each sphere by: the springs advance by it
            for i in range(n):
                for c in range(3):
                    mv[i, c] = dt * (vel[i, c] + half * acc[i, c])
                    mv[i, 3 + c] = dt * (omg[i, c] + half * alp[i, c])
        disp = 0.0
        for k in range(m3):
            x[k] += dt * (v[k] + half * a[k])
            v[k] += half * (3.0 * a[k] - ap[k])
            w[k] += half * (3.0 * al[k] - alp_[k])
            dd = x[k] - x0[k]
            disp = max(disp, dd * dd)
        # a component moved more than skin/(2 sqrt 3) in some direction: rebuild next step
        moved = 3.0 * disp > skin2
        fwx, fwy, fwz, p_n, p_f, e_f, status, culprit = compute_forces(bodies, pairs, walls, table, dt, dt, mv,
                                                                       no_record, samples.split)
        fd = fwx * dvec[0] + fwy * dvec[1] + fwz * dvec[2]
        if coupled:
            advance_structure(drive, t, dt, fd)
        xc, vc, ac = drive_motion(drive, t)
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
        sums[0] += vc * fd * dt
        if coupled:
            # under a ground acceleration, its inertial force's work on the bed (the ground's frame)
            sums[0] += ground_on_bed(drive, bodies.mass, vel, 1.0, vc, dt)
        sums[1] += p_n * dt
        sums[2] += p_f * dt
        if spring:
            sums[2] += e_f
        sums[3] += fd * dt
        integrate_split(samples.split, dt, False, spring)
        if bad:
            return STATUS_NAN, s + 1, culprit
        if status != STATUS_OK:
            return status, s + 1, culprit
        g = span.step0 + s + 1
        if span.record and g % sub == 0:
            record_sample(g // sub - 1 - span.skip_samples, samples, bodies, pairs, walls, drive, xc, vc)
    return STATUS_OK, span.steps, -1
