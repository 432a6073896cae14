"""What the time loops write at the end of each sample interval (signals, energies, frames)."""

from __future__ import annotations

from .forces import elastic_energy
from .jit import njit

__all__ = ["record_sample", "N_ENERGY"]

#: Columns of the energy ledger: kinetic (lab frame), rotational, potential, elastic,
#: work done by the container, dissipated by normal damping, dissipated by friction [J].
N_ENERGY = 7


@njit
def record_sample(k, interval, vc, dvec, gvec, pos, vel, omg, mass, rad, inv_i,
                  row, pi_, pj, pk, wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk,
                  ledger, sig, eng, traj_every, traj):
    """Write sample ``k``: the mean wall force along the drive over the interval (impulse /
    interval) [N] into ``sig[k, 0]``, the energies into ``eng[k]``, and every ``traj_every``-th
    sample a frame (positions, velocities, spins) into ``traj``; reset the impulse sum."""
    if k < 0 or k >= sig.shape[0]:
        ledger[3] = 0.0
        return
    sig[k, 0] = ledger[3] / interval
    ledger[3] = 0.0
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
    eng[k, 0] = ekin
    eng[k, 1] = erot
    eng[k, 2] = epot
    eng[k, 3] = elastic_energy(pos, rad, row, pi_, pj, pk, wl_i, wl_w, n_wl, floor, wall_kind, wall_data, wk)
    eng[k, 4] = ledger[0]
    eng[k, 5] = ledger[1]
    eng[k, 6] = ledger[2]
    if traj_every > 0 and (k + 1) % traj_every == 0:
        f = (k + 1) // traj_every - 1
        if f < traj.shape[0]:
            for i in range(pos.shape[0]):
                for c in range(3):
                    traj[f, i, c] = pos[i, c]
                    traj[f, i, 3 + c] = vel[i, c]
                    traj[f, i, 6 + c] = omg[i, c]
