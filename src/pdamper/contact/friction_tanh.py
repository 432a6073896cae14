r"""Regularised Coulomb friction with a hyperbolic tangent, paper eq. (2) (after Ambrosio [1]).

.. math::

    \mathbf F_R = -\mu\,|F_N|\,\tanh(\tau |\mathbf v_t|)\,\frac{\mathbf v_t}{|\mathbf v_t|},

with :math:`\mathbf v_t` the relative tangential velocity at the contact point (it includes
both partners' spin, :math:`\boldsymbol\omega\times r\mathbf n`, and, because pdamper
integrates in the container frame, the moving wall's velocity), acting at the contact point so
it also makes a torque.

**Smoothing parameter.** :math:`\tau` [s/m] sets the slip speed ``~1/tau`` below which
friction is weaker than Coulomb. Default :data:`DEFAULT_TAU` = 1000 s/m: friction reaches
76 % of :math:`\mu F_N` at 1 mm/s slip and 99.9 % at 4 mm/s, far below the bed's speeds
(~0.1 m/s) yet the tangential relaxation time ``(2/7)/(mu g tau)`` stays ~0.3 ms, well above
the time step, so explicit integrators remain stable. A larger tau sharpens stick-slip but
needs a smaller step (stability needs roughly ``mu g tau dt < 4/7`` for a rolling sphere).
``tests/contact/test_friction_tanh.py`` shows the rolling speed 2V/7 does not depend on tau
over 1e2 ... 1e4 s/m.

**Choice.** ``contact.tangential = "tanh"`` (the default, the paper's law); the alternative is the
tangential spring of :mod:`pdamper.contact.tangential_spring`. The law keeps no state between
steps.

Reference: Ambrosio, J. A. C. (2003). Impact of rigid and flexible multibody systems:
deformation description and contact models. Virtual Nonlinear Multibody Systems, 57-81.
"""

from __future__ import annotations

from typing import NamedTuple

from ..jit import njit
from .tangential import TangentialLaw

__all__ = ["DEFAULT_TAU", "friction_factor", "tanh_pos", "TANH_SATURATION", "TanhFriction", "LAW"]

#: Default smoothing parameter tau [s/m].
DEFAULT_TAU = 1000.0


# Rational minimax approximation of tanh on [0, 7.9053] (the coefficients Eigen uses for its
# vectorised tanh): x P(x^2) / Q(x^2), relative error < 3e-7; beyond 7.9053 tanh = 1 - 3e-7 is
# taken as 1. No exp, no branch but the clamp: cheaper than libm on the contact hot path.
_TP = (4.89352455891786e-03, 6.37261928875436e-04, 1.48572235717979e-05, 5.12229709037114e-08,
       -8.60467152213735e-11, 2.00018790482477e-13, -2.76076847742355e-16)
_TQ = (4.89352518554385e-03, 2.26843463243900e-03, 1.18534705686654e-04, 1.19825839466702e-06)
#: Beyond this argument the approximation returns 1.
TANH_SATURATION = 7.90531110763549805


@njit
def _tanh_ratio(x):
    """tanh(x)/x for 0 <= x <= TANH_SATURATION (rational approximation, relative error < 3e-7)."""
    # Estrin's scheme: shorter dependency chains than Horner, same polynomials
    x2 = x * x
    x4 = x2 * x2
    x8 = x4 * x4
    p = ((_TP[0] + _TP[1] * x2) + (_TP[2] + _TP[3] * x2) * x4) + ((_TP[4] + _TP[5] * x2) + _TP[6] * x4) * x8
    q = (_TQ[0] + _TQ[1] * x2) + (_TQ[2] + _TQ[3] * x2) * x4
    return p / q


@njit
def tanh_pos(x):
    """tanh(x) for x >= 0 to a relative error below 3e-7 (see :data:`TANH_SATURATION`)."""
    if x >= TANH_SATURATION:
        return 1.0
    return x * _tanh_ratio(x)


@njit
def friction_factor(mu, tau, vt_mag):
    """Scalar -|F_R|/(|F_N| |v_t|) factor: the friction vector is ``-factor * F_N * v_t``.

    For slow slip it tends to ``mu tau`` (the friction force ``-factor F_N v_t`` then vanishes
    with v_t). tanh is evaluated by :func:`tanh_pos` (relative error < 3e-7).
    """
    x = tau * vt_mag
    if x >= TANH_SATURATION:
        return mu / vt_mag
    # tanh(x)/v = tau tanh(x)/x: finite (mu tau) as the slip vanishes, no division by v
    return mu * tau * _tanh_ratio(x)


class TanhFriction(NamedTuple):
    """Kernel marker of this law (see :mod:`pdamper.contact.tangential`)."""


#: The tangential choice of this law (``contact.tangential``).
LAW = TangentialLaw(name="tanh", marker=TanhFriction, history=False,
                    summary="regularised Coulomb friction -mu F_N tanh(tau |v_t|) v_t/|v_t| (the paper's eq. 2)")
