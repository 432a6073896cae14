"""The container's motion along the drive direction, evaluated inside the time loops; both
integrators call :func:`drive_motion` and, on a coupled structure, advance it with the same
:func:`pdamper.kernels.structure.structure_step`.

``drive.kind`` (the named constants below; a drive names its compiled motion in
:data:`DRIVE_KINDS`, which :func:`pdamper.engine.build.drive_bundle` translates)
DRIVE_STILL: at rest. DRIVE_HARMONIC: harmonic ``x = X sin(Omega t + phase)`` with ``par = (X, Omega,
phase)``. DRIVE_SAMPLED: piecewise cubic through samples, ``table`` rows ``(t_k, c0, c1, c2, c3)`` so that
``x = c0 + c1 s + c2 s^2 + c3 s^3`` with ``s = t - t_k`` on ``[t_k, t_{k+1})``.
DRIVE_STRUCTURE: the coupled structure (:mod:`pdamper.kernels.structure`): ``(x, v, a)`` is read from
``state[0, 0:3]``, which the time loop advances. DRIVE_MODAL: the coupled modal structure of N modes (the
same module; ``(x, v, a)`` of the damper point in ``state[0, 0:3]`` as for DRIVE_STRUCTURE). Before ``t = 0`` (the settling phase) the
container is at rest at ``x(0)`` with zero speed.
"""

from __future__ import annotations

import math

import numpy as np

from numba.extending import overload

from ..jit import JIT, njit
from .bundles import CoupledMotion, marker_class

__all__ = ["drive_motion", "harmonic_motion", "is_coupled", "is_modal", "DRIVE_STILL", "DRIVE_HARMONIC",
           "DRIVE_SAMPLED", "DRIVE_STRUCTURE", "DRIVE_MODAL", "DRIVE_KINDS"]

#: Drive kind of a container at rest.
DRIVE_STILL = 0
#: Drive kind of the harmonic motion ``par = (X, Omega, phase)``.
DRIVE_HARMONIC = 1
#: Drive kind of the piecewise cubic through samples (``table``).
DRIVE_SAMPLED = 2
#: Drive kind of the coupled structure (:mod:`pdamper.kernels.structure`).
DRIVE_STRUCTURE = 3
#: Drive kind of the coupled modal structure of N modes (:mod:`pdamper.kernels.structure`).
DRIVE_MODAL = 4
#: The compiled motions by the name a drive's ``kernel_drive()`` gives them.
DRIVE_KINDS = {"rest": DRIVE_STILL, "harmonic": DRIVE_HARMONIC, "spline": DRIVE_SAMPLED,
               "structure": DRIVE_STRUCTURE, "modal": DRIVE_MODAL}


def is_coupled(drive):
    """True for a drive the bed's force moves (the coupled structure): the time loops advance its
    state and record it. Compiled kernels only: a constant of the drive's
    :attr:`~pdamper.kernels.bundles.Drive.coupling` marker."""
    return isinstance(drive.coupling, CoupledMotion)


@overload(is_coupled, inline="always", jit_options=JIT)
def _is_coupled(drive):
    coupled = marker_class(drive, "coupling") is CoupledMotion

    def impl(drive):
        return coupled

    return impl


@njit
def is_modal(drive):
    """True for the coupled structure of N modes (:func:`pdamper.kernels.structure.modal_step`)."""
    return drive.kind == DRIVE_MODAL


@njit(inline="always")
def harmonic_motion(x, omega, phase, t):
    """The harmonic container motion ``x = X sin(Omega t + phase)`` at time ``t`` [s]: (position [m],
    velocity [m/s], acceleration [m/s^2]); before ``t = 0`` at rest at ``x(0)``. Scalars only, so
    the CPU kernels (:func:`drive_motion`) and the GPU engine (:mod:`pdamper.kernels.gpu`) compile
    the same function."""
    if t < 0.0:
        return x * math.sin(phase), 0.0, 0.0
    ph = omega * t + phase
    s = math.sin(ph)
    return x * s, x * omega * math.cos(ph), -x * omega * omega * s


@njit
def drive_motion(drive, t):
    """Container (position [m], velocity [m/s], acceleration [m/s^2]) along the drive at time t [s]."""
    kind = drive.kind
    par = drive.par
    if kind == DRIVE_HARMONIC:
        return harmonic_motion(par[0], par[1], par[2], t)
    if kind == DRIVE_SAMPLED:
        tab = drive.table
        n = tab.shape[0]
        if t <= tab[0, 0]:
            return tab[0, 1], 0.0, 0.0
        k = np.searchsorted(tab[:, 0], t) - 1
        if k >= n - 1:
            k = n - 2
        s = t - tab[k, 0]
        if t > tab[n - 1, 0]:
            # past the last sample: hold the last position
            s = tab[n - 1, 0] - tab[k, 0]
            x = tab[k, 1] + s * (tab[k, 2] + s * (tab[k, 3] + s * tab[k, 4]))
            return x, 0.0, 0.0
        x = tab[k, 1] + s * (tab[k, 2] + s * (tab[k, 3] + s * tab[k, 4]))
        v = tab[k, 2] + s * (2.0 * tab[k, 3] + 3.0 * s * tab[k, 4])
        a = 2.0 * tab[k, 3] + 6.0 * s * tab[k, 4]
        return x, v, a
    if kind == DRIVE_STRUCTURE or kind == DRIVE_MODAL:
        st = drive.state
        return st[0, 0], st[0, 1], st[0, 2]
    return 0.0, 0.0, 0.0
