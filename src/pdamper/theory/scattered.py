"""Scattered state, eqs. (7)-(8) of the paper: an empirical law for strokes below X_opt.

In the scattered (gas-like) state the spheres hit the walls at random phases. The paper
assumes the dissipated energy grows with the swept volume (X), falls with the clearance h
and scales with the kinetic energy of the bed:

    E_diss = κ (X/h) ½ m_bed V²            (7)
    η*     = κ X/h                         (8)

with an empirical factor κ (κ = 1 in the paper's Fig. 4). The law is meant for ``X < X_opt``;
above X_opt the bed rolls (:mod:`pdamper.theory.rolling`).

Reference: "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities", Nonlinear Dynamics, Sect. 5.1.
"""

from __future__ import annotations

import math

from ..units import quantities
from ._common import as_output, positive, positive_array
from .bounds import velocity_amplitude

__all__ = ["eta_scattered", "energy_per_cycle_scattered"]


@quantities(stroke="length", clearance="length", kappa="dimensionless")
def eta_scattered(stroke, clearance, kappa: float = 1.0):
    """Reduced loss factor η* = κ X/h [-] of the scattered state, eq. (8).

    Parameters
    ----------
    stroke : float or array_like
        Stroke X [m], > 0.
    clearance : float or array_like
        Clearance h [m], > 0 (broadcast against ``stroke``).
    kappa : float
        Empirical scaling factor κ [-], > 0.

    Returns
    -------
    float or numpy.ndarray
        η* [-]; a float for scalar inputs.

    Examples
    --------
    >>> round(eta_scattered(0.006, 0.030), 12)
    0.2
    """
    x = positive_array("stroke", stroke, "m", "0.006 (6 mm)")
    h = positive_array("clearance", clearance, "m", "0.03 (30 mm)")
    k = positive("kappa", kappa, "[-]", "1.0")
    return as_output(k * x / h, stroke, clearance)


@quantities(stroke="length", clearance="length", frequency="frequency", bed_mass="mass", kappa="dimensionless")
def energy_per_cycle_scattered(stroke, clearance, *, frequency: float, bed_mass: float,
                               kappa: float = 1.0):
    """Energy dissipated per cycle Ẽ_diss = 2π E_diss = π κ (X/h) m_bed V² [J], eqs. (4), (7).

    Parameters
    ----------
    stroke, clearance, kappa
        As in :func:`eta_scattered`.
    frequency : float
        Drive frequency f [Hz]; V = 2πf X.
    bed_mass : float
        Mass of all spheres m_bed [kg].

    Examples
    --------
    >>> e = energy_per_cycle_scattered(0.006, 0.030, frequency=2.0, bed_mass=0.149)
    >>> round(e * 1e3, 4)  # mJ
    0.5322
    """
    m = positive("bed_mass", bed_mass, "kg", "0.149 (149 g)")
    v = velocity_amplitude(stroke, frequency)
    return math.pi * m * v**2 * eta_scattered(stroke, clearance, kappa)
