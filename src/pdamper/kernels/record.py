"""What the time loops write at the end of each sample interval: the kernel channels of
:class:`~pdamper.kernels.bundles.Samples` (wall force, energies, frames, the coupled structure).
A channel with no rows is skipped, so a run computes only what its recorders read; the ledger's
split by contact type (``samples.split``) is compiled in only when a run asks for it."""

from __future__ import annotations

import math

from numba.extending import overload

from ..jit import JIT, njit
from .forces import _is_split, elastic_energy
from .structure import record_coupled

__all__ = ["record_sample", "integrate_split", "record_split"]


def integrate_split(split, dt, trapezoid, spring):
    """Add the last force evaluation's dissipation by contact type (``split.power``) over a step of
    ``dt`` [s] to ``split.sums``, as the integrators add the totals to ``samples.sums``: Verlet the
    power times the step, Gear (``trapezoid``) the trapezoid with the powers of the last accepted step
    (``split.last``, updated); a tangential spring's loss (``spring``) as it is. Compiled kernels only:
    nothing for the empty marker (:class:`~pdamper.kernels.bundles.SplitOff`)."""
    raise NotImplementedError("integrate_split is compiled into the kernels")


def record_split(k, split):
    """Write the split's running sums into row ``k`` of its record (compiled kernels only; nothing for
    the empty marker)."""
    raise NotImplementedError("record_split is compiled into the kernels")


@overload(integrate_split, inline="always", jit_options=JIT)
def _integrate_split(split, dt, trapezoid, spring):
    if not _is_split(split):
        return lambda split, dt, trapezoid, spring: None

    def impl(split, dt, trapezoid, spring):
        p = split.power
        q = split.last
        s = split.sums
        for k in range(p.shape[0]):
            if trapezoid:
                s[k, 0] += 0.5 * (p[k, 0] + q[k, 0]) * dt
                s[k, 1] += 0.5 * (p[k, 1] + q[k, 1]) * dt
                q[k, 0] = p[k, 0]
                q[k, 1] = p[k, 1]
            else:
                s[k, 0] += p[k, 0] * dt
                s[k, 1] += p[k, 1] * dt
            if spring:
                s[k, 1] += p[k, 2]

    return impl


@overload(record_split, inline="always", jit_options=JIT)
def _record_split(k, split):
    if not _is_split(split):
        return lambda k, split: None

    def impl(k, split):
        rec = split.record
        if k < rec.shape[0]:
            for c in range(split.sums.shape[0]):
                rec[k, c, 0] = split.sums[c, 0]
                rec[k, c, 1] = split.sums[c, 1]

    return impl


@njit
def record_sample(k, samples, bodies, pairs, walls, drive, xc, vc):
    """Write sample ``k`` (container position ``xc`` [m] and velocity ``vc`` [m/s] at its end):
    the mean wall force along
    the drive over the interval (impulse / interval) [N], the energies, every ``frame_every``-th
    sample a frame (positions, velocities, spins) and the coupled structure's state; reset the
    impulse sum."""
    sums = samples.sums
    if k < 0:
        sums[3] = 0.0
        return
    wall_force = samples.wall_force
    if k < wall_force.shape[0]:
        wall_force[k] = sums[3] / samples.interval
    sums[3] = 0.0
    pos = bodies.position
    vel = bodies.velocity
    omg = bodies.spin
    eng = samples.energy
    if k < eng.shape[0]:
        dvec = drive.direction
        gvec = drive.gravity
        mass = bodies.mass
        inv_i = bodies.inv_inertia
        ekin = 0.0
        erot = 0.0
        epot = 0.0
        for i in range(pos.shape[0]):
            ux = vel[i, 0] + vc * dvec[0]
            uy = vel[i, 1] + vc * dvec[1]
            uz = vel[i, 2] + vc * dvec[2]
            ekin += 0.5 * mass[i] * (ux * ux + uy * uy + uz * uz)
            erot += 0.5 / inv_i[i] * (omg[i, 0] ** 2 + omg[i, 1] ** 2 + omg[i, 2] ** 2)
            epot -= mass[i] * (gvec[0] * pos[i, 0] + gvec[1] * pos[i, 1] + gvec[2] * pos[i, 2])
        # the potential energy is the lab frame's: the spheres are raised with the container by
        # xc d.(-g) too. A horizontal drive has g.d = 0 (within rounding, left out so that the
        # ledger of such a run is exactly what it is without this term)
        gd = gvec[0] * dvec[0] + gvec[1] * dvec[1] + gvec[2] * dvec[2]
        if abs(gd) > 1e-12 * math.sqrt(gvec[0] ** 2 + gvec[1] ** 2 + gvec[2] ** 2):
            m_bed = 0.0
            for i in range(pos.shape[0]):
                m_bed += mass[i]
            epot -= m_bed * gd * xc
        eng[k, 0] = ekin
        eng[k, 1] = erot
        eng[k, 2] = epot
        eng[k, 3] = elastic_energy(bodies, pairs, walls)
        eng[k, 4] = sums[0]
        eng[k, 5] = sums[1]
        eng[k, 6] = sums[2]
    every = samples.frame_every
    if every > 0 and (k + 1) % every == 0:
        f = (k + 1) // every - 1
        traj = samples.frames
        if f < traj.shape[0]:
            for i in range(pos.shape[0]):
                for c in range(3):
                    traj[f, i, c] = pos[i, c]
                    traj[f, i, 3 + c] = vel[i, c]
                    traj[f, i, 6 + c] = omg[i, c]
    record_split(k, samples.split)
    record_coupled(k, drive, samples.structure)
