r"""Hertz elasticity: the elastic part that every normal contact law of :mod:`pdamper.contact`
shares (the laws differ in their damping, :mod:`.damping`).

.. math::

    k = \tfrac43 E^* \sqrt{R^*}, \qquad F_\text{el} = k\,\delta^{3/2}, \qquad
    U = \int_0^\delta F_\text{el}\,\mathrm d\delta = \tfrac25 k\,\delta^{5/2},

with the effective modulus :math:`E^*` [Pa], the effective radius :math:`R^*` [m] (see
:func:`pdamper.contact.hertz_gonthier.effective_radius`) and the overlap :math:`\delta` [m].
The kernels take the stiffness of every contact (pair lists, wall lists) and the energy stored
in the springs (the energy ledger) from here; both are compiled, so the kernels inline them and
Python code calls them with floats.

Reference: Johnson, K. L. (1985). Contact Mechanics, ch. 4 (eq. 4.22 and 4.23). Cambridge
University Press.
"""

from __future__ import annotations

import math

from ..jit import njit

__all__ = ["hertz_stiffness", "hertz_energy"]


@njit(inline="always")
def hertz_stiffness(e_star, r_star):
    """k = 4/3 E* sqrt(R*) [N/m^1.5] of a contact of effective modulus ``e_star`` [Pa] and
    effective radius ``r_star`` [m]."""
    return 4.0 / 3.0 * e_star * math.sqrt(r_star)


@njit(inline="always")
def hertz_energy(k, overlap):
    """Elastic energy [J] ``2/5 k delta^(5/2)`` of a Hertz contact of stiffness ``k`` [N/m^1.5] at
    overlap ``overlap`` [m] (> 0)."""
    return 0.4 * k * overlap * overlap * math.sqrt(overlap)
