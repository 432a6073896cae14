"""Bouncing collect-and-collide: the block law without rolling, for comparison (beyond the paper).

The law the paper starts from (Bannerman et al.; Sack et al., weightless dampers): the bed is
one block that leaves the pushing wall at the container's maximum velocity V (θ = Ωt = 0,
``x_c = 0``), flies on at constant V and hits the far wall perfectly inelastically. Its
position is ``Xθ``, the far wall is at ``X sin θ + h``, so the impact phase solves

    θ_i - sin θ_i = h/X,

the relative speed at impact is ``V (1 - cos θ_i)`` and, with two impacts per cycle,

    Ẽ_diss = m_bed V² (1 - cos θ_i)²,     η* = (1 - cos θ_i)² / π.

The optimum puts the impact at θ_i = π: ``X_opt = h/π`` with ``η*_max = 4/π``. For ``X < h/π``
the block cannot reach the far wall by θ = π and the functions return NaN.

Reference: the paper's Sect. 1 and its refs. [3] (Bannerman et al.) and [30] (Sack et al.);
docs/theory.md.
"""

from __future__ import annotations

import math

import numpy as np

from . import bounds
from ..units import quantities
from ._common import as_output, positive, positive_array, solve_phase

__all__ = [
    "ETA_MAX_BOUNCING",
    "impact_phase_bouncing",
    "optimal_stroke_bouncing",
    "eta_bouncing",
    "energy_per_cycle_bouncing",
]

#: Maximum reduced loss factor of the bouncing law: ``(1 - cos π)² / π = 4/π``.
ETA_MAX_BOUNCING = 4.0 / math.pi


def _gap(th):
    return th - np.sin(th)


def _gap_slope(th):
    return 2.0 * np.sin(th / 2) ** 2  # 1 - cos θ without cancellation


@quantities(stroke="length", clearance="length")
def impact_phase_bouncing(stroke, clearance):
    """Impact phase θ_i [rad] of the bouncing block, from ``θ_i - sin θ_i = h/X``.

    Parameters
    ----------
    stroke : float or array_like
        Stroke X [m], > 0.
    clearance : float or array_like
        Clearance h [m], > 0 (broadcast against ``stroke``).

    Returns
    -------
    float or numpy.ndarray
        θ_i in (0, π]; NaN where ``X < h/π``.

    Examples
    --------
    >>> round(impact_phase_bouncing(0.03 / math.pi, 0.03) / math.pi, 12)
    1.0
    """
    x = positive_array("stroke", stroke, "m", "0.015 (15 mm)")
    h = positive_array("clearance", clearance, "m", "0.03 (30 mm)")
    x, h = np.broadcast_arrays(x, h)
    return as_output(solve_phase(_gap, _gap_slope, h / x), stroke, clearance)


@quantities(clearance="length")
def optimal_stroke_bouncing(clearance):
    """Optimal stroke of the bouncing law X_opt = h/π [m].

    >>> round(optimal_stroke_bouncing(0.03) * 1e3, 4)  # mm
    9.5493
    """
    h = positive_array("clearance", clearance, "m", "0.03 (30 mm)")
    return as_output(h / math.pi, clearance)


@quantities(stroke="length", clearance="length")
def eta_bouncing(stroke, clearance):
    """Reduced loss factor η* = (1 - cos θ_i)²/π [-] of the bouncing law; NaN for X < h/π.

    >>> round(eta_bouncing(0.03 / math.pi, 0.03), 12) == round(4 / math.pi, 12)
    True
    """
    theta = np.asarray(impact_phase_bouncing(stroke, clearance))
    return as_output((2.0 * np.sin(theta / 2) ** 2) ** 2 / math.pi, stroke, clearance)


@quantities(stroke="length", clearance="length", frequency="frequency", bed_mass="mass")
def energy_per_cycle_bouncing(stroke, clearance, *, frequency: float, bed_mass: float):
    """Energy dissipated per cycle Ẽ_diss = m_bed V² (1 - cos θ_i)² [J]; NaN for X < h/π.

    Parameters
    ----------
    stroke, clearance
        As in :func:`impact_phase_bouncing` [m].
    frequency : float
        Drive frequency f [Hz]; V = 2πf X.
    bed_mass : float
        Mass of all spheres m_bed [kg].
    """
    m = positive("bed_mass", bed_mass, "kg", "0.149 (149 g)")
    v = np.asarray(bounds.velocity_amplitude(stroke, frequency))
    return as_output(math.pi * m * v**2 * np.asarray(eta_bouncing(stroke, clearance)),
                     stroke, clearance)
