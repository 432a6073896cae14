r"""Hertz normal contact with the viscoelastic damping of Tsuji et al. (1992), as LIGGGHTS'
``model hertz`` evaluates it (damping choice ``contact.damping = "tsuji"``).

.. math::

    F_N = k\,\delta^{3/2} + c\,\delta^{1/4}\,\dot\delta, \qquad
    k = \tfrac43 E^*\sqrt{R^*}, \qquad
    c = \alpha(\varepsilon)\,\sqrt{k\,m^*},

    \alpha(\varepsilon) = 2\sqrt{\tfrac56}\,\sqrt{\tfrac32}\;|\beta|, \qquad
    \beta = \frac{\ln\varepsilon}{\sqrt{\ln^2\varepsilon + \pi^2}},

with the overlap :math:`\delta` [m], its rate :math:`\dot\delta` [m/s] (> 0 approaching), the
effective modulus and radius as in :mod:`pdamper.contact.hertz_gonthier` and the effective mass
:math:`m^*` (a sphere on a wall: its own mass). This is LIGGGHTS' ``gamma_n = -2 sqrt(5/6) beta
sqrt(S_n m*)`` with ``S_n = 2 E* sqrt(R* delta)``, written with pdamper's Hertz stiffness:
``S_n = 3/2 k delta^(1/2)``.

**Restitution.** In units of the impact (overlap scale ``(m* v^2/k)^(2/5)``) the law becomes
``u'' = -u^1.5 - alpha u^(1/4) u'``: the rebound speed ratio depends on ``alpha`` alone, not on
the impact speed, and with the ``beta`` above it equals ``eps`` to within the integration error
(``tests/contact/test_damping_laws.py`` measures it over eps = 0.5 ... 0.95). As in LIGGGHTS with
its default ``limitForce off``, the force is **not** clipped at zero: near the end of a contact the
damping term pulls a little, and that pull is part of what makes the rebound equal ``eps``.
Clipped, the same ``alpha`` rebounds higher (measured by the same ODE solve: 0.550 for eps = 0.5,
0.632 for 0.6, 0.718 for 0.7, 0.808 for 0.8, 0.902 for 0.9). Friction sees only the pushing part of
the normal force (:func:`pdamper.kernels.contact.contact`).

The contact's damping parameter ``c`` is fixed when it starts, like Gonthier's ``d``: a COR law
that depends on the impact speed (a table, Thornton) is read at the first-touch approach speed.

References
----------
Tsuji, Y., Tanaka, T., Ishida, T. (1992). Lagrangian numerical simulation of plug flow of
cohesionless particles in a horizontal pipe. Powder Technology 71, 239-250.

Kloss, C., Goniva, C., Hager, A., Amberger, S., Pirker, S. (2012). Models, algorithms and
validation for opensource DEM and CFD-DEM. Progress in Computational Fluid Dynamics 12, 140-152
(LIGGGHTS; its ``normal_model_hertz.h``).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit import njit
from .damping import DampingLaw

__all__ = ["HertzTsuji", "LAWS", "damping_ratio", "touch", "normal_force"]

_SQRT_5_6 = math.sqrt(5.0 / 6.0)


def damping_ratio(eps):
    """alpha(eps) = 2 sqrt(5/6) sqrt(3/2) |beta(eps)| [-] for coefficients of restitution in (0, 1]."""
    e = np.clip(np.asarray(eps, dtype=float), 1e-6, 1.0)
    log_e = np.log(e)
    beta = log_e / np.sqrt(log_e * log_e + np.pi * np.pi)
    return (2.0 * _SQRT_5_6 * math.sqrt(1.5) * np.abs(beta))[()]


@njit
def touch(alpha, v_in, k, m_star):
    """Damping coefficient ``c = alpha sqrt(k m*)`` [N s/m^1.25] of a contact (``v_in`` unused:
    the law is speed-free)."""
    return alpha * math.sqrt(k * m_star)


@njit
def normal_force(k, delta, delta_dot, c):
    """``k delta^1.5 + c delta^0.25 delta_dot`` [N], not clipped (see the module docstring).
    Returns (F_N, F_damp), the damping part for the energy ledger."""
    root = math.sqrt(delta)
    fd = c * math.sqrt(root) * delta_dot
    return k * delta * root + fd, fd


class HertzTsuji(NamedTuple):
    """Kernel marker of this law (see :mod:`pdamper.contact.damping`)."""


#: The damping choice of this law (``contact.damping``).
LAWS = (
    DampingLaw(name="tsuji", marker=HertzTsuji, touch=touch, force=normal_force, coefficient=damping_ratio,
               summary="Hertz with Tsuji's viscoelastic damping c delta^(1/4) delta_dot, as LIGGGHTS' model hertz"),
)
