r"""Elastic--perfectly-plastic restitution of Thornton (1997).

Below the yield speed :math:`v_y` the impact is elastic (:math:`\varepsilon = 1`); above it

.. math::

    \varepsilon = \left[\frac{6\sqrt3}{5}\left(1-\frac16\Big(\frac{v_y}{v}\Big)^2\right)\right]^{1/2}
    \left[\frac{v_y/v}{v_y/v + 2\sqrt{\frac65-\frac15\big(\frac{v_y}{v}\big)^2}}\right]^{1/4},

with the yield speed from Hertz theory at the limiting contact pressure :math:`p_y`
(contact radius at yield ``a_y = pi p_y R*/(2 E*)``, overlap ``delta_y = a_y^2/R*``,
energy ``1/2 m* v_y^2 = 8/15 E* sqrt(R*) delta_y^(5/2)``), which for a sphere on a rigid flat
reduces to Thornton's :math:`v_y = 1.56\,(p_y^5/(E^{*4}\rho))^{1/2}`.

Reference: Thornton, C. (1997). Coefficient of restitution for collinear collisions of
elastic-perfectly plastic spheres. J. Appl. Mech. 64, 383-386.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..jit import njit
from ..schema import convert_fields, param
from .restitution import SPEED_GRID, RestitutionLaw, register_restitution

__all__ = ["ThorntonRestitution", "yield_speed", "thornton_restitution"]


@njit
def yield_speed(p_y, e_star, r_star, m_star):
    """v_y [m/s] of a contact with E* [Pa], R* [m], m* [kg] at which the peak Hertz pressure
    reaches p_y [Pa] (the one definition: the contact kernel calls it at every first touch)."""
    delta_y = r_star * (math.pi * p_y / (2.0 * e_star)) ** 2
    return math.sqrt(2.0 * (8.0 / 15.0) * e_star * math.sqrt(r_star) * delta_y ** 2.5 / m_star)


def thornton_restitution(speed, v_y: float):
    """Thornton's epsilon(v) for yield speed v_y [m/s] (vectorised)."""
    v = np.asarray(speed, dtype=float)
    out = np.ones_like(v)
    m = v > v_y
    x = v_y / v[m]
    out[m] = np.sqrt(6.0 * np.sqrt(3.0) / 5.0 * (1.0 - x * x / 6.0)) * (
        x / (x + 2.0 * np.sqrt(6.0 / 5.0 - x * x / 5.0))) ** 0.25
    return out[()]


@register_restitution
@dataclass(frozen=True, kw_only=True)
class ThorntonRestitution(RestitutionLaw):
    """Thornton (1997) epsilon(v) with a limiting contact (yield) pressure.

    Parameters
    ----------
    yield_pressure : float
        p_y [Pa], > 0 (hardened bearing steel ~ 1e9 ... 4e9 Pa; PVC ~ 1e8 Pa).
    """

    yield_pressure: float = param(dimension="pressure")
    kind: str = param("thornton", kind="tag", key="law")

    def __post_init__(self):
        convert_fields(self, "restitution")
        if not (self.yield_pressure > 0 and np.isfinite(self.yield_pressure)):
            raise InputError(f"thornton restitution: yield_pressure = {shown(self.yield_pressure)} Pa; must be > 0")

    def restitution(self, speed, *, e_star: float, r_star: float, m_star: float, **_):
        """epsilon at impact speed(s) [m/s] for a contact with E* [Pa], R* [m], m* [kg]."""
        return thornton_restitution(speed, yield_speed(self.yield_pressure, e_star, r_star, m_star))

    def kernel_table(self):
        """``(eps, p_y)``: epsilon over ``v / v_y`` on the kernels' grid and the yield pressure [Pa]; the
        kernel computes each contact's yield speed ``v_y`` from it and its E*, R*, m*."""
        return np.clip(thornton_restitution(SPEED_GRID, 1.0), 1e-6, 1.0), float(self.yield_pressure)

    def describe(self) -> str:
        return f"Thornton (1997), p_y = {self.yield_pressure / 1e9:g} GPa"
