"""The tuned mass damper in closed form: the numbers a particle damper is compared with when it is
handed to an engineer who thinks in TMDs (beyond the paper; docs/structure.md, "The damper as an
equivalent TMD").

A TMD of mass ratio mu = m_a phi_d^2 / m_k on a mode k of modal mass m_k (phi_d its shape at the
damper) under a harmonic force, the mode itself undamped (Den Hartog, *Mechanical Vibrations*, 4th
ed. 1956, Sect. 3.3; Brock 1946 for the damping):

- the optimal tuning (the two fixed points of the amplification curve at equal height)
  ``f_opt = omega_a / omega_k = 1 / (1 + mu)``;
- the optimal damping ratio of the absorber (the curve flat at the fixed points, averaged)
  ``zeta_opt = sqrt(3 mu / (8 (1 + mu)^3))``;
- the peak amplification then, the height of the fixed points
  ``|X| / X_st = sqrt(1 + 2 / mu)``; a mode of damping ratio zeta alone peaks at 1 / (2 zeta), so the
  optimal TMD is worth ``zeta_eq = 1 / (2 sqrt(1 + 2 / mu))`` of equivalent damping.

Under a white-noise ground acceleration, minimising the mode's mean-square displacement (Warburton,
*Earthquake Eng. Struct. Dyn.* 10, 381-401, 1982, Table I):
``f_opt = sqrt(1 - mu / 2) / (1 + mu)``, ``zeta_opt = sqrt(mu (1 - mu / 4) / (4 (1 + mu) (1 - mu / 2)))``.

A mass ``m_a`` fixed at the damper (a TMD locked, or a bed locked to its container) only detunes
the mode: ``omega' / omega_k = 1 / sqrt(1 + mu)``.
"""

from __future__ import annotations

import numpy as np

from ..units import quantities

__all__ = ["den_hartog_tuning", "den_hartog_damping", "den_hartog_peak", "den_hartog_equivalent_damping",
           "warburton_tuning", "warburton_damping", "added_mass_detuning"]


@quantities(mu="dimensionless")
def den_hartog_tuning(mu):
    """Den Hartog's optimal frequency ratio omega_a / omega_k = 1 / (1 + mu) [-] of a TMD of mass
    ratio ``mu`` under a harmonic force.

    >>> round(float(den_hartog_tuning(0.05)), 4)
    0.9524
    """
    mu = np.asarray(mu, dtype=float)
    return 1.0 / (1.0 + mu)


@quantities(mu="dimensionless")
def den_hartog_damping(mu):
    """Den Hartog's optimal damping ratio of the absorber, sqrt(3 mu / (8 (1 + mu)^3)) [-].

    >>> round(float(den_hartog_damping(0.05)), 4)
    0.1273
    """
    mu = np.asarray(mu, dtype=float)
    return np.sqrt(3.0 * mu / (8.0 * (1.0 + mu) ** 3))


@quantities(mu="dimensionless")
def den_hartog_peak(mu):
    """The mode's peak amplification |X| / X_st = sqrt(1 + 2 / mu) with the optimal TMD [-]."""
    mu = np.asarray(mu, dtype=float)
    with np.errstate(divide="ignore"):
        return np.sqrt(1.0 + 2.0 / mu)


@quantities(mu="dimensionless")
def den_hartog_equivalent_damping(mu):
    """The damping ratio a mode alone would need to peak as low as with the optimal TMD of mass ratio
    ``mu``: 1 / (2 sqrt(1 + 2 / mu)) [-] (0 for mu = 0).

    >>> round(float(den_hartog_equivalent_damping(0.01)), 4)
    0.0353
    """
    mu = np.asarray(mu, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(mu > 0, 0.5 / np.sqrt(1.0 + 2.0 / np.where(mu > 0, mu, 1.0)), 0.0)


@quantities(mu="dimensionless")
def warburton_tuning(mu):
    """Warburton's optimal frequency ratio under a white-noise ground acceleration (the mode's
    displacement variance least): sqrt(1 - mu / 2) / (1 + mu) [-]."""
    mu = np.asarray(mu, dtype=float)
    return np.sqrt(1.0 - mu / 2.0) / (1.0 + mu)


@quantities(mu="dimensionless")
def warburton_damping(mu):
    """Warburton's optimal absorber damping ratio under a white-noise ground acceleration:
    sqrt(mu (1 - mu / 4) / (4 (1 + mu) (1 - mu / 2))) [-]."""
    mu = np.asarray(mu, dtype=float)
    return np.sqrt(mu * (1.0 - mu / 4.0) / (4.0 * (1.0 + mu) * (1.0 - mu / 2.0)))


@quantities(mu="dimensionless")
def added_mass_detuning(mu):
    """The mode's frequency with a mass of ratio ``mu`` fixed at the damper, over its own:
    1 / sqrt(1 + mu), minus 1 (negative: the mode is lowered) [-].

    >>> round(float(added_mass_detuning(0.0125)), 5)
    -0.00619
    """
    mu = np.asarray(mu, dtype=float)
    return 1.0 / np.sqrt(1.0 + mu) - 1.0
