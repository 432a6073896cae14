"""What the time loops write at the end of each sample interval: the kernel channels of
:class:`~pdamper.kernels.bundles.Samples` (wall force, energies, frames, the coupled structure).
A channel with no rows is skipped, so a run computes only what its recorders read."""

from __future__ import annotations

import math

from ..jit import njit
from .forces import elastic_energy
from .structure import record_coupled

__all__ = ["record_sample"]


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
    record_coupled(k, drive, samples.structure)
