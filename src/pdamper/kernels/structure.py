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

**N modes** (drive kind :data:`~pdamper.kernels.drive.DRIVE_MODAL`, 4;
:class:`pdamper.excitation.ModalStructure`): modal coordinates q_k, k = 1..N, with

    m_k q_k'' + c_k q_k' + k_k q_k = phi_k(force) F0 sin(Omega t) - phi_k(damper) F_w,

the container (damper point) at ``x_c = sum_k phi_k(damper) q_k`` (velocity and acceleration from
the same sums). Each mode takes the step above (:func:`modal_step`); for one mode with
``phi = 1`` the arithmetic is the single-mode step's.

``drive.par`` = (F0 [N], Omega [rad/s]); ``drive.table`` (N x 6), one row per mode:
(m_k [kg], k_k [N/m], c_k [N s/m], phi_k(damper), phi_k(force), phi_k(response)).

``drive.state`` (2 + N x 5): row 0 = (x_c, v_c, a_c, F_ext at the last step, velocity of the force
point at the last step); row 1 = (external work [J], modal damping loss [J], displacement of the
response point [m], ground acceleration now [m/s^2] (a load in time), the ground's power on the bed
at the last step [W] (:func:`ground_work`)); row 2 + k = (q_k, q_k',
q_k'', -, -).

**A load in time** (drive kind :data:`~pdamper.kernels.drive.DRIVE_MODAL_LOAD`, 5; the loads of
:mod:`pdamper.structure.loads`): the N modes of the modal structure (one mode for the
single-degree-of-freedom structure, every shape 1) under one function of time f(t),

    m_k q_k'' + c_k q_k' + k_k q_k = b_k f(t) - phi_k(damper) F_w,

``b_k = phi_k(force)`` for a force at the force point, ``b_k = -L_k`` for a ground acceleration
f = a_g (``L_k = phi_k^T M r``, the mode's participation; the displacements are then relative to
the ground and the container's acceleration is the damper point's plus a_g: ``state[1, 3]``). Each
mode takes the step of :func:`structure_step` (:func:`loaded_step`). ``drive.table`` (N x 7): the
rows of the N modes above and ``b_k``; ``drive.par`` = (form, ground): ``form`` :data:`LOAD_LINEAR`
or :data:`LOAD_SINE`, ``ground`` 1.0 for a ground acceleration, else 0.0. ``drive.load`` (K x 4),
rows by increasing time t_j, f(t) given by the last row with ``t_j <= t`` (0 before the first):

- :data:`LOAD_LINEAR`: rows (t_j, f_j, s_j, -), ``f = f_j + s_j (t - t_j)`` (piecewise linear
  through samples; a last row of zeros ends it);
- :data:`LOAD_SINE`: rows (t_j, A_j, Omega_j, phi_j), ``f = A_j sin(Omega_j (t - t_j) + phi_j)``
  (a stepped sine: a frequency a row, each phase continuing the last).

The external work is ``int f(t) sum_k b_k q_k' dt`` (trapezoidal), the power the load puts into
the modes. Under a ground acceleration everything is kept in the ground's frame, where the ground's
inertial force ``-m a_g`` acts on every mass: on the structure's (the container's carried mass
included: it is in ``L_k``) through ``b_k``, and on the bed, whose share the time loops add
(:func:`ground_work`, with the bed's momentum along the drive in the ground's frame at each step's
end): the external work is then the load's work on the whole system (the relative input energy of
earthquake engineering), and the coupled ledger closes under it as under a force; the bed's ledger
adds the bed's share to its ``work`` (what is done on the bed from outside it), and closes too. ``state[1, 4]``
keeps the ground's power on the bed at the last step (the trapezoid's other end).
"""

from __future__ import annotations

import math

import numpy as np
from numba.extending import overload

from ..jit import JIT, njit
from .bundles import CoupledMotion, marker_class
from .drive import is_loaded, is_modal

__all__ = ["structure_step", "modal_step", "loaded_step", "load_value", "LOAD_LINEAR", "LOAD_SINE", "record_structure", "run_structure_alone", "advance_structure",
           "record_coupled", "is_ground", "ground_work", "ground_on_bed"]


#: Form of a load table (``drive.par[0]`` of a load in time): piecewise linear through samples.
LOAD_LINEAR = 0
#: Form of a load table: a sine a row (a stepped sine).
LOAD_SINE = 1


@njit
def structure_step(drive, t, dt, fw):
    """Advance the structure in ``drive.state`` from ``t - dt`` to ``t`` [s] with the wall force
    ``fw`` [N] on the spheres along the drive at ``t``; held (no change) during settling,
    ``t <= dt/2``."""
    if t <= 0.5 * dt:
        return
    if is_loaded(drive):
        loaded_step(drive, t, dt, fw)
        return
    if is_modal(drive):
        modal_step(drive, t, dt, fw)
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
def modal_step(drive, t, dt, fw):
    """Advance the N modes of a modal structure (kind 4) from ``t - dt`` to ``t`` [s], each by
    the step of :func:`structure_step` with its generalised force ``phi_f F(t) - phi_d fw``;
    then the damper point's (x, v, a), the force point's velocity, the response point's
    displacement, the external work (trapezoidal, ``F v_force``) and the modal damping loss."""
    par = drive.par
    _modes_step(drive, dt, fw, par[0] * math.sin(par[1] * t), 4)


@njit
def load_value(load, form, t):
    """f(t) of the load table ``load`` of ``form`` (:data:`LOAD_LINEAR`, :data:`LOAD_SINE`; the
    module docstring): the last row with ``t_j <= t``, 0 before the first row."""
    if t < load[0, 0]:
        return 0.0
    j = np.searchsorted(load[:, 0], t, side="right") - 1
    s = t - load[j, 0]
    if form == LOAD_SINE:
        return load[j, 1] * math.sin(load[j, 2] * s + load[j, 3])
    return load[j, 1] + load[j, 2] * s


@njit
def loaded_step(drive, t, dt, fw):
    """Advance the N modes of a modal structure under a load in time (kind 5) from ``t - dt`` to
    ``t`` [s]: :func:`modal_step` with the generalised force ``b_k f(t) - phi_k(damper) fw``
    (module docstring; the power ``f sum_k b_k q_k'``); the ground acceleration (``par[1]`` f) in
    ``state[1, 3]``."""
    par = drive.par
    fe = load_value(drive.load, par[0], t)
    _modes_step(drive, dt, fw, fe, 6)
    drive.state[1, 3] = par[1] * fe


@njit
def is_ground(drive):
    """True for a coupled structure under a ground acceleration (``drive.par[1]`` of a load in time):
    the time loops then add the ground's work on the bed (:func:`ground_work`)."""
    return is_loaded(drive) and drive.par[1] != 0.0


@njit
def ground_work(drive, momentum, dt):
    """Add the work of the ground's inertial force on the bed over the step of ``dt`` [s] that ended now
    to the external work (``state[1, 0]``; module docstring): the power ``-a_g P`` with the ground's
    acceleration now (``state[1, 3]``) and ``momentum`` P, the bed's momentum along the drive in the
    ground's frame [kg m/s], trapezoidal as the structure's own work (the power at the last step in
    ``state[1, 4]``). Returns the work [J] (the bed's ledger adds it to its ``work``)."""
    st = drive.state
    p = -st[1, 3] * momentum
    w = 0.5 * dt * (st[1, 4] + p)
    st[1, 0] += w
    st[1, 4] = p
    return w


@njit
def ground_on_bed(drive, mass, velocity, scale, vc, dt):
    """Under a ground acceleration (:func:`is_ground`; nothing otherwise), add its work on the bed over
    the step of ``dt`` [s] that ended now (:func:`ground_work`), the bed's momentum along the drive in
    the ground's frame being ``sum_i m_i (scale v_i . d + vc)``: ``mass`` (N,) [kg], ``velocity`` (N, >= 3)
    the spheres' velocities in the container frame over ``scale`` (Verlet: the velocities and 1; Gear:
    its Nordsieck row ``r_1`` and ``1/h``), ``vc`` the container's velocity relative to the ground [m/s].
    Returns the work [J] (0 without a ground acceleration), which the bed's ledger adds to its ``work``."""
    if not is_ground(drive):
        return 0.0
    d = drive.direction
    p = 0.0
    m_bed = 0.0
    for i in range(mass.shape[0]):
        p += mass[i] * (velocity[i, 0] * d[0] + velocity[i, 1] * d[1] + velocity[i, 2] * d[2])
        m_bed += mass[i]
    return ground_work(drive, scale * p + m_bed * vc, dt)


@njit
def _modes_step(drive, dt, fw, fe, col):
    """The modes' step under the force ``fe`` on each mode by the table's column ``col`` (4: the
    force point's shape, 6: the load's b_k) and the wall force ``fw`` at the damper: each mode by
    the step of :func:`structure_step`; then the damper point's (x, v, a), the loaded point's
    velocity ``sum_k tab[k, col] q_k'``, the response point's displacement, the external work
    (trapezoidal) and the modal damping loss."""
    tab = drive.table
    st = drive.state
    h = 0.5 * dt
    x = 0.0
    v = 0.0
    a = 0.0
    vf = 0.0
    xr = 0.0
    loss = 0.0
    for j in range(tab.shape[0]):
        m, k, c = tab[j, 0], tab[j, 1], tab[j, 2]
        pd, pf, pr = tab[j, 3], tab[j, col], tab[j, 5]
        q, qd, qdd = st[2 + j, 0], st[2 + j, 1], st[2 + j, 2]
        g = pf * fe - pd * fw
        qn = q + dt * (qd + h * qdd)
        qdn = (qd + h * qdd + h * (g - k * qn) / m) / (1.0 + h * c / m)
        qddn = (g - c * qdn - k * qn) / m
        loss += h * c * (qd * qd + qdn * qdn)
        st[2 + j, 0] = qn
        st[2 + j, 1] = qdn
        st[2 + j, 2] = qddn
        x += pd * qn
        v += pd * qdn
        a += pd * qddn
        vf += pf * qdn
        xr += pr * qn
    st[1, 0] += h * (st[0, 3] * st[0, 4] + fe * vf)
    st[1, 1] += loss
    st[1, 2] = xr
    st[0, 0] = x
    st[0, 1] = v
    st[0, 2] = a
    st[0, 3] = fe
    st[0, 4] = vf


@njit
def structure_energy(drive):
    """Mechanical energy of the structure now [J]: 1/2 M v^2 + 1/2 K x^2 (one mode) or
    sum_k 1/2 m_k q_k'^2 + 1/2 k_k q_k^2 (N modes)."""
    st = drive.state
    if is_modal(drive):
        tab = drive.table
        e = 0.0
        for j in range(tab.shape[0]):
            e += 0.5 * tab[j, 0] * st[2 + j, 1] * st[2 + j, 1] + 0.5 * tab[j, 1] * st[2 + j, 0] * st[2 + j, 0]
        return e
    return 0.5 * drive.par[0] * st[0, 1] * st[0, 1] + 0.5 * drive.par[1] * st[0, 0] * st[0, 0]


@njit
def response_displacement(drive):
    """Displacement of the response point now [m] (one mode: the structure's own, x_s)."""
    if is_modal(drive):
        return drive.state[1, 2]
    return drive.state[0, 0]


@njit
def record_structure(k, drive, out):
    """Write sample ``k``: (x_s, v_s, external work, damping loss, the structure's mechanical
    energy, the response point's displacement) at the interval end into ``out[k]``
    (``Samples.structure``, columns ``STRUCTURE_COLUMNS``), then the modal coordinates q_k (one
    mode: x_s) where ``out`` has more columns, when it has that row."""
    if k < 0 or k >= out.shape[0]:
        return
    state = drive.state
    out[k, 0] = state[0, 0]
    out[k, 1] = state[0, 1]
    out[k, 2] = state[1, 0]
    out[k, 3] = state[1, 1]
    out[k, 4] = structure_energy(drive)
    out[k, 5] = response_displacement(drive)
    # the modal coordinates, where the array has their columns (one mode: x_s)
    if is_modal(drive):
        for j in range(min(out.shape[1] - 6, state.shape[0] - 2)):
            out[k, 6 + j] = state[2 + j, 0]
    elif out.shape[1] > 6:
        out[k, 6] = state[0, 0]


@njit
def run_structure_alone(n_steps, dt, t0, sub, drive, out):
    """The structure without a bed (``F_w = 0``): ``n_steps`` steps of ``dt`` from ``t0``,
    recording every ``sub`` steps into ``out`` as :func:`record_structure` (the same step
    function the coupled loops use)."""
    for s in range(n_steps):
        t = t0 + (s + 1) * dt
        structure_step(drive, t, dt, 0.0)
        if (s + 1) % sub == 0:
            record_structure((s + 1) // sub - 1, drive, out)


def advance_structure(drive, t, dt, fw):
    """:func:`structure_step` on a coupled drive, nothing on a prescribed one -- decided by the
    type of ``drive.coupling`` when the calling kernel is compiled, so a prescribed drive's kernels
    hold no structure code (compiled kernels only)."""
    raise NotImplementedError("advance_structure is compiled into the kernels")


def record_coupled(k, drive, out):
    """:func:`record_structure` on a coupled drive, nothing on a prescribed one (compiled kernels
    only, as :func:`advance_structure`)."""
    raise NotImplementedError("record_coupled is compiled into the kernels")


@overload(advance_structure, inline="always", jit_options=JIT)
def _advance_structure(drive, t, dt, fw):
    if marker_class(drive, "coupling") is CoupledMotion:
        def impl(drive, t, dt, fw):
            structure_step(drive, t, dt, fw)
    else:
        def impl(drive, t, dt, fw):
            return
    return impl


@overload(record_coupled, inline="always", jit_options=JIT)
def _record_coupled(k, drive, out):
    if marker_class(drive, "coupling") is CoupledMotion:
        def impl(k, drive, out):
            record_structure(k, drive, out)
    else:
        def impl(k, drive, out):
            return
    return impl
