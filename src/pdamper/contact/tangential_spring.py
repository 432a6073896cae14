r"""Incremental tangential spring with Mindlin's stiffness and a Coulomb cap (``contact.tangential =
"spring"``): contacts that store tangential elastic energy while they stick.

**The law.** Each touching contact keeps its tangential spring force :math:`\mathbf F_s` (on body
*i*) between steps. In a step of length :math:`\Delta t`, with the overlap :math:`\delta`, the unit
normal :math:`\mathbf n` and the slip :math:`\mathbf v_t` (the tangential velocity of *i*'s contact
point relative to *j*'s, spins included):

1. *Stiffness* (Mindlin 1949, no micro-slip):

   .. math::

       k_t = 8\,G^*\sqrt{R^*\delta}, \qquad
       \frac1{G^*} = \frac{2-\nu_1}{G_1} + \frac{2-\nu_2}{G_2}, \qquad G = \frac{E}{2(1+\nu)},

   the tangential stiffness of a Hertz contact of radius :math:`a = \sqrt{R^*\delta}` that does not
   slip anywhere. It is the stiffness of LIGGGHTS' ``model hertz tangential history`` (its
   ``St = 8 Geff sqrt(reff deltan)``), the second code pdamper is validated against, and of
   LAMMPS' ``mindlin`` and EDEM's Hertz-Mindlin (no slip): with it the ratio of tangential to
   normal stiffness is Mindlin's :math:`2(1-\nu)/(2-\nu)` (0.82 for steel), which sets how far a
   contact twists before it slips and the tangential rebound of an oblique impact (Maw, Barber &
   Fawcett 1976). Cundall & Strack's constant stiffness would need a value chosen by hand, and a
   linear spring beside the Hertz normal law rings at a frequency that does not follow the contact.

2. *Rotation* of :math:`\mathbf F_s` onto the current tangent plane, keeping its magnitude (the
   contact turns; the stored force turns with it).

3. *Change of stiffness and of the cap*. When the overlap decreases (:math:`k_t < k_t^\text{old}`)
   the stored force is scaled by :math:`k_t/k_t^\text{old}` (Mindlin & Deresiewicz 1953 unloading,
   as LAMMPS' ``mindlin_rescale``); when it grows the force is kept. The spring's energy
   :math:`U = |\mathbf F_s|^2/(2k_t)` then never grows without work: unloading takes away
   :math:`(1 - k_t/k_t^\text{old})\,U` and loading :math:`|\mathbf F_s|^2 (1/k_t^\text{old} -
   1/k_t)/2`, both counted as dissipated (a spring loaded at one stiffness and released at a larger
   one returns less than it took: the law is hysteretic, never creative). A stored force above the
   current Coulomb limit (the normal force fell) slips back onto it, and the energy it loses is
   dissipated too.

4. *Increment* by the displacement of the contact point over the step, on the current tangent
   plane: :math:`\mathbf F_\text{tr} = \mathbf F_s - k_t\,\Delta\mathbf s`, with
   :math:`\Delta\mathbf s` the motion of *i*'s contact point relative to *j*'s that the integrator
   gave the bodies since the spring was last advanced (their displacements and rotations, the
   kernels' ``moved``: velocity Verlet's drift; Gear's predicted state against the one the springs
   were last advanced at). The spring then follows the positions exactly; a slip times the step
   (:math:`\mathbf v_t\,\Delta t` at the end of the step, as the integrator's velocity) would lead
   them by half a step and act as a numerical damping :math:`k_t\Delta t/2` that no ledger sees,
   and under Gear would not follow its predicted positions either.

5. *Coulomb cap* on the pushing part of the normal force: if :math:`|\mathbf F_\text{tr}| >
   \mu\max(F_N, 0) = L` the spring is scaled back onto the cap (gross slip), and the slip beyond the
   elastic part, :math:`(|\mathbf F_\text{tr}| - L)/k_t`, dissipates :math:`L\,(|\mathbf
   F_\text{tr}| - L)/k_t` (in steady sliding exactly :math:`L\,|\Delta\mathbf s|`).

6. *Tangential damping* (optional, ``contact.tangential_damping``, **on by default as in
   LIGGGHTS**): :math:`-c\,\mathbf v_t` on top of the spring, with LIGGGHTS'

   .. math::

       \gamma_t = 2\sqrt{5/6}\,|\beta|\sqrt{k_t\,m^*}, \qquad
       \beta = \frac{\ln\varepsilon}{\sqrt{\ln^2\varepsilon + \pi^2}},

   :math:`\varepsilon` the coefficient of restitution of the contact (read, like the normal damping,
   at its approach speed when it starts) and :math:`m^*` its effective mass. :math:`c = \gamma_t`
   unless the total would exceed the cap, then the largest :math:`c \le \gamma_t` with
   :math:`|\mathbf F_s - c\,\mathbf v_t| \le L`: the total tangential force never exceeds the
   Coulomb limit, and while the spring sits on the cap and the contact slides, :math:`c = 0`. The
   damping dissipates :math:`c\,|\mathbf v_t|^2\Delta t`.

The force on body *i* is :math:`\mathbf F_s - c\,\mathbf v_t` (on *j* the opposite), acting at the
contact point. The history is dropped when the contact opens (the energy still stored is
dissipated; the next touch starts from a relaxed spring) and carried over when the neighbour list
is rebuilt.

**Energy.** The spring's stored energy :math:`U = |\mathbf F_s|^2/(2k_t)` is part of the ledger's
``elastic`` column; steps 3, 5 and 6 (and a spring dropped when its contact opens) are its
``friction`` column, so the ledger closes as with the default law. The elastic part of the
increment is conservative: :math:`U(\mathbf F_\text{tr}) - U(\mathbf F_s)` is exactly the work of
the mean force, :math:`-\tfrac12(\mathbf F_s + \mathbf F_\text{tr})\cdot\Delta\mathbf s`, so a
contact loaded and unloaded below the cap at constant stiffness returns what it stored, to
round-off. The loss of a step is counted so that the balance over the step is exact with the mean
of the spring forces at its two ends, :math:`U_\text{new} - U_\text{old} + \text{loss} =
-\tfrac12(\mathbf F_\text{old} + \mathbf F_\text{new})\cdot\Delta\mathbf s` (undamped), which is
the work velocity Verlet does with them (its kinetic energy and the springs' then telescope over
the steps, as for the Hertz spring) and what Gear's trapezoidal ledger assumes: the slip at the cap
works at the mean of the forces before and after the step (exactly :math:`L|\Delta\mathbf s|` when
sliding on), and a change of the stored force at the step's start (step 3) also does the work of
the change over half the step. That last term is of the order of the step and may be negative; the
law's own losses (step 3 alone, with no displacement) never are. Counted at the end-of-step force
instead, the ledger of a 36-sphere bed was 3-5x worse than with the tanh law at the same step
(docs/engine.md section 5).

**Where this differs from LIGGGHTS 3.8** (``tangential_model_history.h``, ``normal_model_hertz.h``),
for cross-code comparisons:

- LIGGGHTS stores the tangential *displacement* :math:`\boldsymbol\xi` and applies
  :math:`-k_t(\delta)\,\boldsymbol\xi` with the *current* stiffness. Unloading is then the same as
  here (the force follows :math:`k_t` at fixed :math:`\boldsymbol\xi`), but loading is not: as the
  overlap grows at no slip its force grows with :math:`k_t` and the spring gains the energy
  :math:`\tfrac12\,\Delta k_t\,\xi^2` from nothing; here the force is kept.
- LIGGGHTS projects :math:`\boldsymbol\xi` onto the new tangent plane without restoring its length
  (the stored force shrinks by the cosine of the contact's rotation in each step); here the
  magnitude is kept.
- LIGGGHTS caps the spring at :math:`\mu|F_N|` with the whole normal force, damping included and
  taken as an absolute value (a Tsuji contact that pulls at its end keeps friction), and adds the
  tangential damping only while the spring is below the cap, so its total tangential force can
  exceed the Coulomb limit by up to :math:`\gamma_t|\mathbf v_t|`. Here the cap is
  :math:`\mu\max(F_N, 0)` and the damping is limited so that the total never exceeds it.
- LIGGGHTS reads :math:`\beta` from one restitution per type pair; here from the contact's COR
  law at its approach speed (the same for a constant COR).
- LIGGGHTS' velocity Verlet advances the displacement by the slip at the half-step velocity times
  the step, which is its drift's displacement; pdamper by the drift's displacement too (Verlet), or
  by Gear's predicted motion (step 4).

**Scalar functions, one law for every target.** :func:`spring_force` and the small functions
beside it take and return plain floats, use the ``math`` module only and raise nothing, so the CPU
kernels (:mod:`pdamper.kernels.contact`) and a GPU device function compile the very same code.

References
----------
Mindlin, R. D. (1949). Compliance of elastic bodies in contact. J. Appl. Mech. 16, 259-268.

Mindlin, R. D., Deresiewicz, H. (1953). Elastic spheres in contact under varying oblique forces.
J. Appl. Mech. 20, 327-344.

Cundall, P. A., Strack, O. D. L. (1979). A discrete numerical model for granular assemblies.
Geotechnique 29, 47-65.

Maw, N., Barber, J. R., Fawcett, J. N. (1976). The oblique impact of elastic spheres. Wear 38,
101-114.

Di Renzo, A., Di Maio, F. P. (2004). Comparison of contact-force models for the simulation of
collisions in DEM-based granular flow codes. Chem. Eng. Sci. 59, 525-541.

Thornton, C., Cummins, S. J., Cleary, P. W. (2011). An investigation of the comparative behaviour
of alternative contact force models during elastic oblique impacts. Powder Technol. 210, 189-197.

Kloss, C., Goniva, C., Hager, A., Amberger, S., Pirker, S. (2012). Models, algorithms and
validation for opensource DEM and CFD-DEM. Progress in Computational Fluid Dynamics 12, 140-152
(LIGGGHTS).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from ..jit import njit
from .hertz_tsuji import damping_ratio as _normal_damping_ratio
from .tangential import TangentialLaw

__all__ = ["SpringFriction", "LAW", "spring_stiffness", "spring_damping", "spring_force", "spring_energy",
           "damping_ratio"]


def damping_ratio(eps):
    """LIGGGHTS' tangential damping ratio ``2 sqrt(5/6) |beta(eps)|`` [-] for coefficients of
    restitution ``eps`` in (0, 1] (0 for eps = 1): ``gamma_t = ratio sqrt(k_t m*)``. It is the
    normal ratio of Tsuji's law (:func:`pdamper.contact.hertz_tsuji.damping_ratio`) without its
    factor sqrt(3/2), which comes from that law's stiffness ``k = 2/3 S_n``."""
    return _normal_damping_ratio(eps) / math.sqrt(1.5)


@njit
def spring_stiffness(g_star, r_star, delta):
    """Mindlin's tangential stiffness ``k_t = 8 G* sqrt(R* delta)`` [N/m] of a contact of effective
    shear modulus ``g_star`` [Pa] and effective radius ``r_star`` [m] at overlap ``delta`` [m]."""
    return 8.0 * g_star * math.sqrt(r_star * delta)


@njit
def spring_damping(ratio, kt, m_star):
    """Tangential damping coefficient ``gamma_t = ratio sqrt(k_t m*)`` [N s/m] (``ratio`` from
    :func:`damping_ratio`, 0: no damping)."""
    return ratio * math.sqrt(kt * m_star)


@njit
def spring_energy(fx, fy, fz, kt):
    """Energy [J] stored in a spring of stiffness ``kt`` [N/m] holding the force ``(fx, fy, fz)``
    [N]: ``|F|^2 / (2 k_t)``; 0 for ``kt <= 0`` (no spring)."""
    if kt > 0.0:
        return 0.5 * (fx * fx + fy * fy + fz * fz) / kt
    return 0.0


@njit
def spring_force(kt, gt, lim, stored, kt_old, normal, moved, slip, dt):
    """One step of the tangential spring at one contact (the module docstring's steps 2-6).

    Parameters (floats, and vectors as tuples ``(x, y, z)`` of floats): the contact's stiffness
    ``kt`` [N/m] (:func:`spring_stiffness`) and damping coefficient ``gt`` [N s/m]
    (:func:`spring_damping`) now; the Coulomb limit ``lim = mu max(F_N, 0)`` [N]; the stored spring
    force ``stored`` [N] on body *i* and the stiffness ``kt_old`` [N/m] it was stored with (both 0
    for a new contact); the unit normal ``normal``; the displacement ``moved`` [m] of *i*'s contact
    point relative to *j*'s since the spring was stored (its normal part is removed here; zeros: the
    force at the current state, the spring not advanced); the slip ``slip`` [m/s] now (tangential
    velocity of *i*'s contact point relative to *j*'s, without normal part) and the step ``dt``
    [s], for the damping.

    Returns ``(fx, fy, fz, sx, sy, sz, loss)``: the tangential force on body *i* [N] (spring plus
    damping, ``|F| <= lim``), the new stored spring force [N] (store it with ``kt``), and the
    energy [J] the step dissipated (change of stiffness and cap, slip, damping), counted so that
    the spring's balance over the step is exact with the mean of its forces at the step's ends:
    ``U(F_new) - U(F_old) + loss = -(F_old + F_new)/2 . ds + (damping loss)``, the work velocity
    Verlet (and Gear's trapezoidal ledger) does with them. It is the law's own dissipation (each
    part >= 0) plus the work of the change of the stored force at the step's start over half the
    step, a term of the order of the step that may be negative.
    """
    sx, sy, sz = stored
    nx, ny, nz = normal
    dx, dy, dz = moved
    tx, ty, tz = slip
    # the displacement on the current tangent plane
    dn = dx * nx + dy * ny + dz * nz
    qx = dx - dn * nx
    qy = dy - dn * ny
    qz = dz - dn * nz
    if not lim > 0.0:
        # the contact does not push: no friction, and what the spring held is dissipated (less the
        # work it does over the first half of the step, as everywhere below)
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, spring_energy(sx, sy, sz, kt_old) - 0.5 * (sx * qx + sy * qy + sz * qz)
    ox = sx
    oy = sy
    oz = sz
    loss = 0.0
    s2 = sx * sx + sy * sy + sz * sz
    if s2 > 0.0 and kt_old > 0.0:
        # onto the current tangent plane, keeping the magnitude
        sn = sx * nx + sy * ny + sz * nz
        sx -= sn * nx
        sy -= sn * ny
        sz -= sn * nz
        p2 = sx * sx + sy * sy + sz * sz
        f = math.sqrt(s2 / p2) if p2 > 0.0 else 0.0
        if kt < kt_old:
            # unloading: the force follows the stiffness (Mindlin-Deresiewicz)
            f *= kt / kt_old
        # a normal force that fell below what the spring holds: it slips back to the cap
        p2 *= f * f
        if p2 > lim * lim:
            f *= lim / math.sqrt(p2)
        sx *= f
        sy *= f
        sz *= f
        e0 = 0.5 * s2 / kt_old
        s2 = sx * sx + sy * sy + sz * sz
        loss = e0 - 0.5 * s2 / kt
        # the stored force changed at the start of the step and the bodies felt the old one over
        # its first half: the step's energy balance is the mean of the forces at its two ends
        loss += 0.5 * ((sx - ox) * qx + (sy - oy) * qy + (sz - oz) * qz)
    # the increment
    ex = sx - kt * qx
    ey = sy - kt * qy
    ez = sz - kt * qz
    e2 = ex * ex + ey * ey + ez * ez
    lim2 = lim * lim
    if e2 > lim2:
        # gross slip: back onto the cap; the slip beyond the elastic part, (F_tr - F_s) / k_t, does
        # work at the mean of the spring forces before and after the step (lim |ds| when sliding on)
        f = lim / math.sqrt(e2)
        loss += 0.5 * (1.0 - f) * ((sx + f * ex) * ex + (sy + f * ey) * ey + (sz + f * ez) * ez) / kt
        sx = ex * f
        sy = ey * f
        sz = ez * f
        s2 = lim2
    else:
        sx = ex
        sy = ey
        sz = ez
        s2 = e2
    # damping on the slip, limited so that the total stays within the cap
    c = gt
    v2 = tx * tx + ty * ty + tz * tz
    fx = sx - c * tx
    fy = sy - c * ty
    fz = sz - c * tz
    if fx * fx + fy * fy + fz * fz > lim2:
        # the largest c with |F_s - c v|^2 = lim^2 (|F_s| <= lim, so the root is >= 0), in the
        # form that does not cancel
        st = sx * tx + sy * ty + sz * tz
        room = max(lim2 - s2, 0.0)
        root = math.sqrt(st * st + v2 * room)
        if st > 0.0:
            c = (st + root) / v2
        elif root - st > 0.0:
            c = room / (root - st)
        else:
            c = 0.0
        c = min(c, gt)
        fx = sx - c * tx
        fy = sy - c * ty
        fz = sz - c * tz
    loss += c * v2 * dt
    return fx, fy, fz, sx, sy, sz, loss


class SpringFriction(NamedTuple):
    """Kernel marker of this law (see :mod:`pdamper.contact.tangential`)."""


#: The tangential choice of this law (``contact.tangential``).
LAW = TangentialLaw(name="spring", marker=SpringFriction, history=True,
                    summary="incremental tangential spring k_t = 8 G* sqrt(R* delta) with a Coulomb cap mu F_N "
                            "(Mindlin, as LIGGGHTS' tangential history)")
