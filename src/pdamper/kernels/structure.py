"""The structure the container rides on: a single-degree-of-freedom oscillator, two-way coupled.

Drive kind :data:`~pdamper.kernels.drive.DRIVE_STRUCTURE` (3). The structure (mass ``M`` including the empty
container, stiffness ``K``, viscous damping ``c``, external force ``F0 sin(Ω t)``) moves along
the drive direction; the particles feel ``-m a_s d`` in the container frame as with a
prescribed drive, and the structure feels the bed through the walls (Newton 3):

    M a_s = F0 sin(Ω t) - c v_s - K x_s - F_w,

``F_w`` being the sum of the wall forces *on the particles* along the drive at the same time.

Arrays of the :class:`~pdamper.kernels.bundles.Drive` bundle (see
:class:`pdamper.excitation.CoupledStructure`):

``drive.par`` = (M [kg], K [N/m], c [N s/m], F0 [N], Ω [rad/s]).

``drive.state`` (2 x 5, mutable, the state carried between calls):
row 0 = (x_s [m], v_s [m/s], a_s [m/s^2], F_ext at the last step [N], -);
row 1 = (work of the external force since t = 0 [J], energy dissipated by c [J], -, -, -).

Time stepping (:func:`structure_step`): velocity Verlet with the linear damping solved
implicitly (trapezoidal), ``x' = x + dt (v + dt/2 a)``,
``v' = v + dt/2 (a + a')``, ``a' = (F(t') - c v' - K x' - F_w(t'))/M``. ``F_w(t')`` comes from the
particles' positions and predicted velocities at ``t'``, which do not depend on the structure's
state (they live in the container frame), so the bed force enters without lag. During the
settling phase (``t <= dt/2``) the structure is held at its initial state.
"""

from __future__ import annotations

import math

from ..jit import njit

__all__ = ["structure_step", "record_structure", "run_structure_alone"]


@njit
def structure_step(drive, t, dt, fw):
    """Advance the structure in ``drive.state`` from ``t - dt`` to ``t`` [s] with the wall force
    ``fw`` [N] on the spheres along the drive at ``t``; held (no change) during settling,
    ``t <= dt/2``."""
    if t <= 0.5 * dt:
        return
    par = drive.par
    st = drive.state
    m, k, c, f0, om = par[0], par[1], par[2], par[3], par[4]
    h = 0.5 * dt
    x, v, a = st[0, 0], st[0, 1], st[0, 2]
    xn = x + dt * (v + h * a)
    fe = f0 * math.sin(om * t)
    vn = (v + h * a + h * (fe - k * xn - fw) / m) / (1.0 + h * c / m)
    an = (fe - c * vn - k * xn - fw) / m
    st[1, 0] += h * (st[0, 3] * v + fe * vn)
    st[1, 1] += h * c * (v * v + vn * vn)
    st[0, 0] = xn
    st[0, 1] = vn
    st[0, 2] = an
    st[0, 3] = fe


@njit
def record_structure(k, state, out):
    """Write sample ``k``: (x_s, v_s, external work, damping loss) at the interval end into
    ``out[k]`` (``Samples.structure``), when it has that row."""
    if k < 0 or k >= out.shape[0]:
        return
    out[k, 0] = state[0, 0]
    out[k, 1] = state[0, 1]
    out[k, 2] = state[1, 0]
    out[k, 3] = state[1, 1]


@njit
def run_structure_alone(n_steps, dt, t0, sub, drive, out):
    """The structure without a bed (``F_w = 0``): ``n_steps`` steps of ``dt`` from ``t0``,
    recording every ``sub`` steps into ``out`` as :func:`record_structure` (the same step
    function the coupled loops use)."""
    for s in range(n_steps):
        t = t0 + (s + 1) * dt
        structure_step(drive, t, dt, 0.0)
        if (s + 1) % sub == 0:
            record_structure((s + 1) // sub - 1, drive.state, out)
