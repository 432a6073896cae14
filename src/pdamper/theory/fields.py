"""The damper's fields from the paper's laws: eta* and the effective mass over s = X / X_opt.

The closed-form counterpart of the measured fields (:class:`pdamper.analysis.fields.DamperFields`):
the scattered law (eq. 8) below X_opt, the rolling law (eq. 14) from X_opt on, with the rolling
bed's effective mass (:func:`pdamper.theory.rolling.rolling_mass_ratio`, eqs. 10-12). The design
for a structure (:mod:`pdamper.design.search`) puts them into the energy balance
(:mod:`pdamper.theory.balance`).
"""

from __future__ import annotations

import numpy as np

from ..units import quantities
from .rolling import ETA_MAX, X_OPT_OVER_H, eta_rolling, rolling_mass_ratio

__all__ = ["SCATTERED_MASS_RATIO", "closed_form_fields"]

#: Effective mass over bed mass assumed in the scattered state (the scattered law, eq. 8, gives
#: none): the rolling law's value at X_opt, 2/7, so the mass is continuous across the jump.
SCATTERED_MASS_RATIO = 2.0 / 7.0
#: The rolling-law tables: s = X / X_opt from 1 to this (eta* ~ s^(-4/3) far above).
_S_TOP = 1.0e3

_TABLES: dict = {}


def _rolling_tables():
    """(log s, eta*(s), m_eff/m_bed (s)) of the rolling law on s = X/X_opt in [1, _S_TOP] (cached)."""
    if "rolling" not in _TABLES:
        s = np.geomspace(1.0, _S_TOP, 800)
        h = 1.0
        x = s * X_OPT_OVER_H * h
        eta = np.asarray(eta_rolling(x, h), dtype=float)
        eta[0] = ETA_MAX
        _TABLES["rolling"] = (np.log(s), eta, rolling_mass_ratio(s))
    return _TABLES["rolling"]


@quantities(stroke_over_x_opt="dimensionless", kappa="dimensionless")
def closed_form_fields(stroke_over_x_opt, kappa: float = 1.0):
    """The damper's fields from the paper's laws as functions of s = X / X_opt: (eta*, m_eff/m_bed).

    eta* = kappa 0.4075 s (scattered, eq. 8) below X_opt, the rolling law (eq. 14) from X_opt
    on (its tables, interpolated in log s); m_eff/m_bed from :func:`rolling_mass_ratio` above
    X_opt and :data:`SCATTERED_MASS_RATIO` (assumed) below. Beyond s = 1000 eta* falls as s^(-4/3).

    >>> e, m = closed_form_fields([0.5, 1.0, 1.2])
    >>> [round(float(v), 3) for v in e], [round(float(v), 3) for v in m]
    ([0.204, 0.909, 0.887], [0.286, 0.286, 0.543])
    """
    s = np.asarray(stroke_over_x_opt, dtype=float)
    ls, eta_r, mu_r = _rolling_tables()
    lg = np.log(np.maximum(s, 1e-300))
    eta_roll = np.interp(lg, ls, eta_r) * np.where(s > _S_TOP, (np.maximum(s, 1.0) / _S_TOP) ** (-4.0 / 3.0), 1.0)
    eta = np.where(s < 1.0, kappa * X_OPT_OVER_H * s, eta_roll)
    mu = np.where(s < 1.0, SCATTERED_MASS_RATIO, np.interp(lg, ls, mu_r))
    return eta, mu
