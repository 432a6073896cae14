"""The contact law applied to one contact: one compiled function for every contact loop.

:func:`contact` takes what the geometry of a contact gives -- overlap ``delta``, approach rate
``delta_dot``, the tangential slip at the contact point: a
:class:`~pdamper.kernels.bundles.ContactGeometry` -- with the contact's constants (a
:class:`~pdamper.kernels.bundles.ContactConstants`) and history, and returns the normal force, the friction coefficient and its Coulomb limit, the updated history
and the dissipated powers. The pair loop, the floor loop and the wall loop of
:mod:`pdamper.kernels.forces` all call it; they differ only in geometry (where the normal and the
slip come from) and in which bodies receive the force, which :func:`scatter` adds to them (and to
Gear's increments in its implicit friction pass); :func:`note_friction_row` writes a contact into
Gear's friction record.

The normal damping law is the one the contact table's ``law`` marker names
(:mod:`pdamper.contact.damping`): :func:`law_touch` and :func:`law_force` resolve, when numba
compiles a kernel, to the law's own functions, so each law is compiled (and cached) on its own.
The tangential law is the one the table's ``tangential`` marker names
(:mod:`pdamper.contact.tangential`): :func:`friction` resolves to the tanh-regularised Coulomb law of
:mod:`pdamper.contact.friction_tanh` (eq. 2, the default) or to the tangential spring of
:mod:`pdamper.contact.tangential_spring`, and :func:`keeps_history` tells the loops, the neighbour
lists and Gear, when they are compiled, whether the law has per-contact history to carry
(the tanh law compiles none of it, so its kernels are what they were before the spring existed).

**Contact history.** ``v_in`` of a contact is the largest normal approach speed it has seen
since it began (floored at ``v_floor``), and the law's damping parameter is fixed from it
(Gonthier: ``d = chi(eps(v_in)) / v_in``). For a single impact the approach speed is largest at
the first touch, so this is Gonthier's first-touch speed; a resting contact that is struck again
(a bed settled against a wall when the drive starts, a chain of spheres hit by a neighbour) is
treated as a new impact at the new speed. Without that, a resting contact keeps
``d = chi / v_floor`` and its damping ``k delta^1.5 d delta_dot`` becomes too stiff for any
explicit step when it is loaded fast (a perfect-lattice start would blow up at the first
wall impact). With it the damping force never exceeds ``chi`` times the elastic force
while the contact is compressed.

The contact-point kinematics (:func:`pair_point_velocity`, :func:`wall_point_velocity`,
:func:`floor_slip`) serve the force loops (on velocities) and Gear's implicit friction pass (on
velocity increments) alike. (Their callers load the velocity components in a fixed order: with
FMA contraction on, the order of the loads decides which product of ``a*b + c*d`` is fused, and
keeping it keeps the results bit for bit.)
:func:`corrected_friction` is the linearised friction law that pass evaluates.
"""

from __future__ import annotations

import math

import numba
from numba.extending import overload

from ..contact import DAMPING_LAWS, TANGENTIAL_LAWS
from ..contact.cor_thornton import yield_speed
from ..contact.friction_tanh import TanhFriction, friction_factor
from ..contact.tangential_spring import (SpringFriction, spring_damping, spring_energy, spring_force,
                                         spring_stiffness)
from ..jit import JIT, njit

__all__ = ["FRICTION_CAP", "contact", "damping_at_touch", "tabulated", "law_touch", "law_force", "friction",
           "keeps_history", "drop_history", "note_friction_row", "scatter", "pair_point_velocity",
           "wall_point_velocity", "floor_slip", "corrected_friction"]

#: Friction stability guard: the friction force on a contact never exceeds the force that
#: would stop its tangential slip within one step, ``m_t |v_t| / dt`` with the tangential
#: effective mass ``m_t = 2/7 m*`` of two rolling spheres, times 1/2. Only contacts whose
#: tanh law is too stiff for the step (large normal force during an impact) are affected;
#: without it their slip chatters around zero and the friction work is mis-counted.
#: Velocity Verlet only: Gear's steps pass a vanishing ``dt`` (no cap) and evaluate the friction at
#: the corrected slip instead (:mod:`pdamper.kernels.gear`); only Gear's priming evaluation at the
#: start of a run (initial accelerations) passes its first step and so keeps the cap. The tanh law
#: only: the tangential spring has no slope to chatter on (its stiffness is resolved by the step as
#: the Hertz stiffness is).
FRICTION_CAP = 0.5 * 2.0 / 7.0

#: marker class -> DampingLaw (several names may share a marker: they differ only in their table)
_BY_MARKER = {law.marker: law for law in DAMPING_LAWS.values()}


#: marker class -> TangentialLaw
_TANGENTIAL_BY_MARKER = {law.marker: law for law in TANGENTIAL_LAWS.values()}


def _registered(marker_type, by_marker, kind, registry):
    """The law a marker's numba type stands for, or a TypeError naming the registry to add it to."""
    try:
        return by_marker[marker_type.instance_class]
    except (AttributeError, KeyError):
        raise TypeError(f"no {kind} law is registered for {marker_type}; register it in "
                        f"pdamper.contact.{registry}") from None


def _law_of(marker_type):
    return _registered(marker_type, _BY_MARKER, "damping", "DAMPING_LAWS")


def _tangential_law_of(marker_type):
    return _registered(marker_type, _TANGENTIAL_BY_MARKER, "tangential", "TANGENTIAL_LAWS")


def law_touch(law, coefficient, v_in, k, m_star):
    """The damping law's parameter of a contact that starts at approach speed ``v_in`` (compiled
    kernels only: resolved by the type of ``law``)."""
    raise NotImplementedError("law_touch is compiled into the kernels")


def law_force(law, k, delta, delta_dot, d):
    """The damping law's ``(F_N, F_damp)`` (compiled kernels only)."""
    raise NotImplementedError("law_force is compiled into the kernels")


@overload(law_touch, inline="always", jit_options=JIT)
def _law_touch(law, coefficient, v_in, k, m_star):
    touch = _law_of(law).touch

    def impl(law, coefficient, v_in, k, m_star):
        return touch(coefficient, v_in, k, m_star)

    return impl


@overload(law_force, inline="always", jit_options=JIT)
def _law_force(law, k, delta, delta_dot, d):
    force = _law_of(law).force

    def impl(law, k, delta, delta_dot, d):
        return force(k, delta, delta_dot, d)

    return impl


@njit
def damping_at_touch(table, v_approach, mp, k, r_star, m_star):
    """The damping parameter of a contact that starts (or is struck harder than before) at normal
    approach speed ``v_approach`` [m/s], fixed by the law in ``table`` for material pair ``mp``.

    The speed is floored at ``table.v_floor`` (see :mod:`pdamper.contact.hertz_gonthier`). The law's
    coefficient is read from row ``mp`` of ``table.coefficient`` at that speed
    (:func:`tabulated`).
    """
    v = v_approach
    if v < table.v_floor:
        v = table.v_floor
    return law_touch(table.law, tabulated(table, table.coefficient, v, mp, r_star, m_star), v, k, m_star)


@njit
def tabulated(table, tab, v, mp, r_star, m_star):
    """Row ``mp`` of a table over the contact table's log-spaced impact speeds (``tab``:
    ``table.coefficient``, ``table.tangential_damping``) at approach speed ``v`` [m/s], or at
    ``v / v_y`` for Thornton's restitution (``table.yield_pressure[mp] > 0``, ``v_y`` from the
    contact's E*, R* and m*, :func:`pdamper.contact.cor_thornton.yield_speed`), log-linearly
    interpolated and held at the table's ends."""
    x = v
    py = table.yield_pressure[mp]
    if py > 0.0:
        x = v / yield_speed(py, table.modulus[mp], r_star, m_star)
    u = (math.log(x) - table.log_speed0) / table.dlog_speed
    g = tab.shape[1]
    if u <= 0.0:
        c = tab[mp, 0]
    elif u >= g - 1:
        c = tab[mp, g - 1]
    else:
        q = int(u)
        f = u - q
        c = tab[mp, q] * (1.0 - f) + tab[mp, q + 1] * f
    return c


@njit(inline="always")
def contact(table, hist, row, constants, geometry, v_in, d, dt, step):
    """The contact law at one contact.

    Parameters: the contact table and the contact's row ``row`` of the tangential history ``hist``
    (:data:`~pdamper.kernels.bundles.TANGENTIAL_COLUMNS`; a law without history leaves it alone); the
    contact's constants ``constants``, a :class:`~pdamper.kernels.bundles.ContactConstants` (its
    material pair, friction coefficient mu [-], Hertz stiffness k [N/m^1.5], effective radius R* [m]
    and mass m* [kg], friction guard [kg], :data:`FRICTION_CAP` x m*); its geometry now ``geometry``,
    a :class:`~pdamper.kernels.bundles.ContactGeometry` (overlap delta [m] and approach rate [m/s]
    (> 0 approaching), the unit normal ``n`` (from i to j; at a wall into the container), the
    tangential slip ``t`` [m/s] at the contact point with its length, and the displacement [m] of
    i's contact point relative to j's since a spring was last advanced, which only a law with
    history reads); its history ``(v_in, d)`` (``v_in = 0``: a new contact); the step ``dt`` [s] of
    the tanh law's friction guard (Gear passes a vanishing step: no guard) and the step ``step`` [s]
    of the spring's damping. The two bundles are scalars only: every loop, CPU and GPU, builds them
    where it has worked out the contact and calls this one function.

    Returns ``(F_N, ft_x, ft_y, ft_z, c, lim, v_in, d, P_damp, P_friction, E_friction)``: the normal
    force [N] (pushing the bodies apart when positive), the tangential force on body i [N], the
    tanh law's friction coefficient ``c`` [N s/m] (the friction force is ``-c`` times the slip;
    0 for a law with history: Gear's implicit friction pass then skips the contact) and its
    Coulomb limit ``lim = mu F_N`` [N], the updated history, the power dissipated by the normal
    damping and by the tanh law's friction [W], and the energy [J] a law with history dissipated
    in this step. Friction follows the pushing part of the normal force (a law that may pull at
    the end of a contact, Tsuji's, has no friction while it pulls).
    """
    delta_dot = geometry.rate
    touched = v_in == 0.0 or delta_dot > v_in
    if touched:
        # first touch, or struck harder than ever before in this contact
        v_in = max(delta_dot, table.v_floor)
        d = damping_at_touch(table, delta_dot, constants.material_pair, constants.stiffness, constants.radius,
                             constants.mass)
    fn, fdamp = law_force(table.law, constants.stiffness, geometry.overlap, delta_dot, d)
    ftx, fty, ftz, c, lim, p_f, e_f = friction(table.tangential, table, hist, row, constants, geometry, fn, touched,
                                               v_in, dt, step)
    return fn, ftx, fty, ftz, c, lim, v_in, d, fdamp * delta_dot, p_f, e_f


def friction(law, table, hist, row, constants, geometry, fn, touched, v_in, dt, step):
    """The tangential law of marker ``law`` at one contact (compiled kernels only: resolved by the
    type of ``law``), with the normal force ``fn`` [N] and whether the contact was touched (began or
    was struck harder) in this evaluation. Returns ``(ft_x, ft_y, ft_z, c, lim, P_friction,
    E_friction)`` as :func:`contact` describes them."""
    raise NotImplementedError("friction is compiled into the kernels")


def keeps_history(law):
    """Whether the tangential law of marker ``law`` keeps a per-contact history (a constant of the
    compiled kernel; called from Python -- numba-cuda's simulator runs the GPU kernels so -- the same
    answer from the law's registration)."""
    return _tangential_law_of(numba.typeof(law)).history


@njit
def _tanh_friction(table, hist, row, constants, geometry, fn, touched, v_in, dt, step):
    """The tanh law (:mod:`pdamper.contact.friction_tanh`), with Verlet's friction guard."""
    mu = constants.friction
    cap = constants.friction_cap
    vt = geometry.slip
    ff = friction_factor(mu, table.tau, vt) * max(fn, 0.0)
    if ff * dt > cap:
        ff = cap * (1.0 / dt)
    return -ff * geometry.tx, -ff * geometry.ty, -ff * geometry.tz, ff, mu * fn, ff * vt * vt, 0.0


@njit(inline="always")
def _spring_friction(table, hist, row, constants, geometry, fn, touched, v_in, dt, step):
    """The tangential spring (:mod:`pdamper.contact.tangential_spring`) on the contact's row of
    ``hist``: its damping ratio fixed when the contact starts (or is struck harder), the stored
    force advanced by the contact point's displacement."""
    mp = constants.material_pair
    r_star = constants.radius
    m_star = constants.mass
    g = geometry
    kt = spring_stiffness(table.shear_modulus[mp], r_star, g.overlap)
    if touched:
        hist[row, 4] = tabulated(table, table.tangential_damping, v_in, mp, r_star, m_star)
    lim = constants.friction * max(fn, 0.0)
    fx, fy, fz, sx, sy, sz, loss = spring_force(kt, spring_damping(hist[row, 4], kt, m_star), lim,
                                                (hist[row, 0], hist[row, 1], hist[row, 2]), hist[row, 3],
                                                (g.nx, g.ny, g.nz), (g.dx, g.dy, g.dz), (g.tx, g.ty, g.tz), step)
    # what the next step starts from: the spring and the stiffness it is held at
    hist[row, 0], hist[row, 1], hist[row, 2], hist[row, 3] = sx, sy, sz, kt
    return fx, fy, fz, 0.0, lim, 0.0, loss


#: marker class -> the kernel function that applies the law to one contact
_FRICTION_KERNELS = {TanhFriction: _tanh_friction, SpringFriction: _spring_friction}


@overload(friction, inline="always", jit_options=JIT)
def _friction(law, table, hist, row, constants, geometry, fn, touched, v_in, dt, step):
    kernel = _FRICTION_KERNELS[_tangential_law_of(law).marker]

    def impl(law, table, hist, row, constants, geometry, fn, touched, v_in, dt, step):
        return kernel(table, hist, row, constants, geometry, fn, touched, v_in, dt, step)

    return impl


@overload(keeps_history, inline="always", jit_options=JIT)
def _keeps_history(law):
    if _tangential_law_of(law).history:
        return lambda law: True
    return lambda law: False


@njit(inline="always")
def drop_history(law, hist, row):
    """Zero row ``row`` of the tangential history ``hist`` if the law of marker ``law`` keeps one
    (a contact opened: its next touch starts from a relaxed spring); returns the energy [J] the
    dropped spring still held (dissipated), 0 for a law without history."""
    e = 0.0
    if keeps_history(law):
        e = spring_energy(hist[row, 0], hist[row, 1], hist[row, 2], hist[row, 3])
        for c in range(hist.shape[1]):
            hist[row, c] = 0.0
    return e


@njit(inline="always")
def note_friction_row(record, m, i, j, nx, ny, nz, tx, ty, tz, c, lim):
    """Write a touching friction contact into row ``m`` of Gear's friction record
    (:class:`pdamper.kernels.bundles.FrictionRecord`): bodies ``(i, j)`` (``j < 0`` at a wall),
    unit normal ``n``, slip ``t`` [m/s], friction coefficient ``c`` [N s/m], Coulomb limit ``lim`` [N]."""
    record.bodies[m, 0] = i
    record.bodies[m, 1] = j
    r = record.rows
    r[m, 0] = nx
    r[m, 1] = ny
    r[m, 2] = nz
    r[m, 3] = tx
    r[m, 4] = ty
    r[m, 5] = tz
    r[m, 6] = c
    r[m, 7] = lim


@njit(inline="always")
def scatter(lin, ang, i, j, f, n, t, li, lj, ai, aj):
    """Add a contact's force and torque to the accumulators of its bodies.

    ``lin[i] += li f`` and ``ang[i] += ai (n x t)``; for a pair (``j >= 0``) also
    ``lin[j] -= lj f`` and ``ang[j] += aj (n x t)``; ``j = -1`` is a wall. ``f`` is the force on
    ``i``, ``t`` its tangential part (the friction, acting at the contact point), ``n`` the unit
    normal, each a tuple ``(x, y, z)``. The force loops pass ``lin``, ``ang`` = force, torque and
    ``li = lj = 1``, ``ai`` the signed lever of the contact point along ``n`` (pairs: ``r_i``,
    ``r_j``; walls: ``-r_i``); Gear's implicit friction pass passes its increments and the factors
    that turn a force into them (``h^2/2 m^-1``, ``h^2/2 r / I``).
    """
    fx, fy, fz = f
    nx, ny, nz = n
    tx, ty, tz = t
    lin[i, 0] += li * fx
    lin[i, 1] += li * fy
    lin[i, 2] += li * fz
    if j >= 0:
        lin[j, 0] -= lj * fx
        lin[j, 1] -= lj * fy
        lin[j, 2] -= lj * fz
    cx = ny * tz - nz * ty
    cy = nz * tx - nx * tz
    cz = nx * ty - ny * tx
    ang[i, 0] += ai * cx
    ang[i, 1] += ai * cy
    ang[i, 2] += ai * cz
    if j >= 0:
        ang[j, 0] += aj * cx
        ang[j, 1] += aj * cy
        ang[j, 2] += aj * cz


@njit(inline="always")
def pair_point_velocity(ux, uy, uz, wx, wy, wz, nx, ny, nz):
    """Relative velocity of a sphere pair at the contact point, ``u + w x n``, and its normal
    component: ``(c_x, c_y, c_z, c.n)``, with ``u = v_i - v_j`` and ``w = r_i omega_i + r_j omega_j``
    (or their increments). The slip is ``c - (c.n) n``."""
    cx = ux + wy * nz - wz * ny
    cy = uy + wz * nx - wx * nz
    cz = uz + wx * ny - wy * nx
    return cx, cy, cz, cx * nx + cy * ny + cz * nz


@njit(inline="always")
def wall_point_velocity(ux, uy, uz, wx, wy, wz, r, nx, ny, nz):
    """Velocity of a sphere at its contact point on a wall, ``u - r (omega x n)``, and its normal
    component (``u`` the velocity relative to the wall, ``omega`` the spin, or their increments).
    The slip is ``c - (c.n) n``."""
    cx = ux - r * (wy * nz - wz * ny)
    cy = uy - r * (wz * nx - wx * nz)
    cz = uz - r * (wx * ny - wy * nx)
    return cx, cy, cz, cx * nx + cy * ny + cz * nz


@njit(inline="always")
def floor_slip(ux, uz, wx, wz, r):
    """Slip of a sphere on the floor (normal +y): ``(v_x + r omega_z, 0, v_z - r omega_x)``."""
    return ux + r * wz, uz - r * wx


@njit(inline="always")
def corrected_friction(c, lim, kk, a, tx, ty, tz, dcx, dcy, dcz):
    """Friction force of a contact evaluated at its corrected slip, linearly implicit (Gear).

    ``(tx, ty, tz)`` is the predicted slip, ``(dcx, dcy, dcz)`` the tangential slip increment that
    the explicit corrector gives, ``c`` the law's secant coefficient ``mu F_N tanh(tau s)/s`` at the
    predicted slip, ``kk`` the contact's inverse tangential mass (1/m + r^2/I of both bodies) and
    ``a = c_1 h / 2`` the corrector's velocity increment per unit acceleration. The slip increment
    solves ``ds = dc - a kk c ds``; the force ``-c (s + ds)`` is clipped to the Coulomb limit
    ``lim = mu F_N``. Returns the force change against the explicit ``-c s`` and the new force."""
    den = 1.0 / (1.0 + a * kk * c)
    fx = -c * (tx + dcx * den)
    fy = -c * (ty + dcy * den)
    fz = -c * (tz + dcz * den)
    fm = math.sqrt(fx * fx + fy * fy + fz * fz)
    if fm > lim:
        sc = lim / fm
        fx *= sc
        fy *= sc
        fz *= sc
    return fx + c * tx, fy + c * ty, fz + c * tz, fx, fy, fz
