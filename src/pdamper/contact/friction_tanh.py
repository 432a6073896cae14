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

Reference: Ambrosio, J. A. C. (2003). Impact of rigid and flexible multibody systems:
deformation description and contact models. Virtual Nonlinear Multibody Systems, 57-81.
"""

from __future__ import annotations

import math

from ..kernels.jit import njit

__all__ = ["DEFAULT_TAU", "friction_factor"]

#: Default smoothing parameter tau [s/m].
DEFAULT_TAU = 1000.0


@njit
def friction_factor(mu, tau, vt_mag):
    """Scalar -|F_R|/(|F_N| |v_t|) factor: the friction vector is ``-factor * F_N * v_t``.

    Returns 0 for ``vt_mag == 0`` (the limit of tanh(tau v)/v is tau, but times v_t = 0).
    """
    if vt_mag <= 0.0:
        return 0.0
    return mu * math.tanh(tau * vt_mag) / vt_mag
