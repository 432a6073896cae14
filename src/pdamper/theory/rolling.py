"""Rolling collect-and-collide, eqs. (9)-(17) of the paper.

The bed moves as one block of spheres. It is pushed by a wall until the container reaches its
maximum velocity V at phase ``θ = Ωt = 0`` (where ``x_c = 0``), leaves that wall without
spin, switches at once to rolling on the floor (``φ' = (x_p' - x_c')/r``) and keeps its kinetic
energy (9) until it hits the opposite wall, where it stops relative to the container
(perfectly inelastic). With ``I = 2/5 m r²`` per sphere this gives

    x_p'  = V/7 (2 cos θ + sqrt(25 + 10 sin² θ))                   (10)
    Δx'   = x_p' - x_c' = V/7 (sqrt(25 + 10 sin² θ) - 5 cos θ)    (11)
    ∫_0^{t_i} x_p' dt = X sin θ_i + h                              (12)
    Ẽ_diss = m_bed V²/35 (sqrt(25 + 10 sin² θ_i) - 5 cos θ_i)²     (14)
    η*     = Ẽ_diss / (π m_bed V²)                                 (4), (5) with V* = V

Because ``sqrt(25 + 10 sin² θ) = 5 sqrt(1 - m sin² θ)`` with ``m = -0.4``, the integral in (12)
is ``X/7 (2 sin θ + 5 E(θ | m))`` with E the incomplete elliptic integral of the second kind,
and (12) becomes

    h/X = 5/7 (E(θ_i | -0.4) - sin θ_i),

increasing in θ_i. The bed must hit the far wall by ``θ_i = π`` (otherwise it would not leave
the pushing wall at ``x_c = 0`` in the next half cycle; the paper observes the scattered state
instead). The optimum is the stroke that puts the impact at π, eq. (17):
``X_opt / h = 7 / (10 E(-0.4)) = 0.40752`` (the paper rounds to 0.4), where
``η*_max = 20/(7π) = 0.909``, eqs. (15)-(16). X_opt does not depend on the frequency.

For strokes below X_opt this law does not apply: its functions return NaN there (use the
scattered law, :mod:`pdamper.theory.scattered`, or :func:`eta_theory` for the paper's
combined curve).

The effective mass of the rolling bed, :func:`rolling_mass_ratio` (beyond the paper): the first
harmonic of the container's force on the bed in phase with its acceleration, from the kinematics
of eqs. (10)-(12); 2/7 of the bed's mass at X_opt, tending to 1 far above.

Reference: "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities", Nonlinear Dynamics, Sect. 5.2.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ellipe, ellipeinc

from ..errors import InputError
from ..units import quantities
from ._common import as_output, positive, positive_array, solve_phase
from . import bounds
from .scattered import eta_scattered

__all__ = [
    "ELLIPTIC_PARAMETER",
    "X_OPT_OVER_H",
    "ETA_MAX",
    "bed_velocity",
    "relative_velocity",
    "bed_position",
    "clearance_over_stroke",
    "impact_phase_rolling",
    "optimal_stroke",
    "eta_rolling",
    "energy_per_cycle_rolling",
    "eta_theory",
    "rolling_mass_ratio",
]

#: Parameter m of ``E(θ | m)`` in the reduced eq. (12):
#: ``sqrt(25 + 10 sin²θ) = 5 sqrt(1 - m sin²θ)``.
ELLIPTIC_PARAMETER = -0.4

#: Optimal stroke over clearance, eq. (17), from (12) at ``θ_i = π``: ``7 / (10 E(-0.4))``.
X_OPT_OVER_H = 7.0 / (10.0 * float(ellipe(ELLIPTIC_PARAMETER)))

#: Maximum reduced loss factor of the rolling law, eq. (16): ``20/(7π)``.
ETA_MAX = 20.0 / (7.0 * math.pi)


@quantities(phase="angle", velocity_amplitude="velocity")
def bed_velocity(phase, velocity_amplitude: float = 1.0):
    """Absolute bed velocity x_p' [m/s] during the rolling phase, eq. (10).

    Parameters
    ----------
    phase : float or array_like
        Drive phase θ = Ωt [rad] since the bed left the pushing wall, 0 <= θ <= θ_i.
    velocity_amplitude : float
        Container velocity amplitude V [m/s]; the default 1 gives x_p'/V.

    Examples
    --------
    >>> bed_velocity(0.0), round(bed_velocity(math.pi), 12)
    (1.0, 0.428571428571)
    """
    th = np.asarray(phase, dtype=float)
    out = velocity_amplitude / 7.0 * (2.0 * np.cos(th) + np.sqrt(25.0 + 10.0 * np.sin(th) ** 2))
    return as_output(out, phase)


@quantities(phase="angle", velocity_amplitude="velocity")
def relative_velocity(phase, velocity_amplitude: float = 1.0):
    """Bed velocity relative to the container Δx'_cp = x_p' - x_c' [m/s], eq. (11).

    Evaluated in a form free of cancellation at small θ:
    ``sqrt(25 + 10 s²) - 5 cos θ = 10 s² / (sqrt(25 + 10 s²) + 5) + 10 sin²(θ/2)``, s = sin θ.

    Examples
    --------
    >>> relative_velocity(0.0), round(relative_velocity(math.pi), 12)
    (0.0, 1.428571428571)
    """
    th = np.asarray(phase, dtype=float)
    s2 = np.sin(th) ** 2
    root = np.sqrt(25.0 + 10.0 * s2)
    out = velocity_amplitude / 7.0 * (10.0 * s2 / (root + 5.0) + 10.0 * np.sin(th / 2) ** 2)
    return as_output(out, phase)


@quantities(phase="angle", stroke="length")
def bed_position(phase, stroke: float = 1.0):
    """Bed position x_p [m] during the rolling phase, the integral of eq. (10).

    ``x_p = X/7 (2 sin θ + 5 E(θ | -0.4))``, measured in the lab frame from where the bed
    leaves the pushing wall (``x_c = 0`` at θ = 0). The pushing wall is at ``X sin θ``, the
    impacting wall at ``X sin θ + h``. The default ``stroke = 1`` gives x_p / X.

    Examples
    --------
    >>> bed_position(0.0)
    0.0
    """
    th = np.asarray(phase, dtype=float)
    out = stroke / 7.0 * (2.0 * np.sin(th) + 5.0 * ellipeinc(th, ELLIPTIC_PARAMETER))
    return as_output(out, phase)


@quantities(phase="angle")
def clearance_over_stroke(phase):
    """Clearance over stroke h/X [-] for which the bed hits the far wall at θ_i, eq. (12).

    ``h/X = 5/7 (E(θ_i | -0.4) - sin θ_i)``: eq. (12) with θ = Ωt. Increasing in θ_i from 0 at
    θ_i = 0 to ``1 / X_OPT_OVER_H`` at θ_i = π. The inverse is :func:`impact_phase_rolling`.

    Examples
    --------
    >>> round(1 / clearance_over_stroke(math.pi), 5)
    0.40752
    """
    th = np.asarray(phase, dtype=float)
    return as_output(_gap(th), phase)


def _gap(th):
    return 5.0 / 7.0 * (ellipeinc(th, ELLIPTIC_PARAMETER) - np.sin(th))


def _gap_slope(th):
    # d/dθ of _gap: 5/7 (sqrt(1 + 0.4 sin²θ) - cos θ), written without cancellation.
    s2 = np.sin(th) ** 2
    return 5.0 / 7.0 * (0.4 * s2 / (np.sqrt(1.0 + 0.4 * s2) + 1.0) + 2.0 * np.sin(th / 2) ** 2)


@quantities(stroke="length", clearance="length")
def impact_phase_rolling(stroke, clearance):
    """Impact phase θ_i = Ωt_i [rad] of the rolling bed on the far wall, eq. (12) solved for t_i.

    Parameters
    ----------
    stroke : float or array_like
        Stroke X [m], > 0. A whole sweep is solved in one vectorised call.
    clearance : float or array_like
        Clearance h [m], > 0 (broadcast against ``stroke``).

    Returns
    -------
    float or numpy.ndarray
        θ_i in (0, π] [rad]; NaN where ``X < X_opt`` (the bed cannot reach the far wall by
        θ = π, so the rolling law does not apply).

    Examples
    --------
    >>> round(impact_phase_rolling(optimal_stroke(0.03), 0.03) / math.pi, 12)
    1.0
    >>> math.isnan(impact_phase_rolling(0.01, 0.03))
    True
    """
    x = positive_array("stroke", stroke, "m", "0.015 (15 mm)")
    h = positive_array("clearance", clearance, "m", "0.03 (30 mm)")
    x, h = np.broadcast_arrays(x, h)
    return as_output(solve_phase(_gap, _gap_slope, h / x), stroke, clearance)


@quantities(clearance="length")
def optimal_stroke(clearance):
    """Optimal stroke X_opt [m] of the rolling law, eq. (17): ``X_OPT_OVER_H * h``.

    The stroke at which the bed hits the far wall at θ_i = π, where η* is largest (16).
    It depends on the clearance only, not on the frequency.

    Examples
    --------
    >>> round(optimal_stroke(0.030) * 1e3, 3)  # mm
    12.226
    """
    h = positive_array("clearance", clearance, "m", "0.03 (30 mm)")
    return as_output(X_OPT_OVER_H * h, clearance)


@quantities(stroke="length", clearance="length")
def eta_rolling(stroke, clearance):
    """Reduced loss factor η* [-] of the rolling law, from eqs. (14), (4), (5).

    ``η* = (sqrt(25 + 10 sin²θ_i) - 5 cos θ_i)² / (35π)``; ``η* = 20/(7π)`` at X_opt, falling
    for larger strokes; NaN for ``X < X_opt``.

    Examples
    --------
    >>> round(eta_rolling(optimal_stroke(0.03), 0.03), 4)
    0.9095
    >>> round(eta_rolling(0.05, 0.03), 4)
    0.3729
    """
    theta = impact_phase_rolling(stroke, clearance)
    return as_output(7.0 / (5.0 * math.pi) * np.asarray(relative_velocity(theta)) ** 2,
                     stroke, clearance)


@quantities(stroke="length", clearance="length", frequency="frequency", bed_mass="mass")
def energy_per_cycle_rolling(stroke, clearance, *, frequency: float, bed_mass: float):
    """Energy dissipated per cycle Ẽ_diss [J] of the rolling law, eq. (14).

    ``Ẽ_diss = m_bed V²/35 (sqrt(25 + 10 sin²θ_i) - 5 cos θ_i)²`` with V = 2πf X; at X_opt it
    equals ``20/7 m_bed V²``, eq. (15). NaN for ``X < X_opt``.

    Parameters
    ----------
    stroke, clearance
        As in :func:`impact_phase_rolling` [m].
    frequency : float
        Drive frequency f [Hz].
    bed_mass : float
        Mass of all spheres m_bed [kg].

    Examples
    --------
    >>> e = energy_per_cycle_rolling(0.015, 0.030, frequency=2.0, bed_mass=0.149)
    >>> round(e * 1e3, 3)  # mJ
    14.66
    """
    m = positive("bed_mass", bed_mass, "kg", "0.149 (149 g)")
    v = bounds.velocity_amplitude(stroke, frequency)
    bracket = 7.0 * np.asarray(relative_velocity(impact_phase_rolling(stroke, clearance)))
    return as_output(m * np.asarray(v) ** 2 * bracket**2 / 35.0, stroke, clearance)


@quantities(stroke="length", clearance="length", kappa="dimensionless")
def eta_theory(stroke, clearance, kappa: float = 1.0):
    """The paper's analytical η* curve (Fig. 4, "ana. formulas") [-].

    The scattered law (8) for ``X < X_opt`` and the rolling law (14) for ``X >= X_opt``; the
    curve jumps at X_opt from ``κ X_OPT_OVER_H`` to ``20/(7π)``.

    Examples
    --------
    >>> round(eta_theory(0.006, 0.03), 6), round(eta_theory(0.05, 0.03), 4)
    (0.2, 0.3729)
    """
    x = positive_array("stroke", stroke, "m", "0.015 (15 mm)")
    h = positive_array("clearance", clearance, "m", "0.03 (30 mm)")
    x, h = np.broadcast_arrays(x, h)
    rolling = np.asarray(eta_rolling(x, h))
    out = np.where(np.isnan(rolling), eta_scattered(x, h, kappa), rolling)
    return as_output(out, stroke, clearance)


@quantities(stroke_over_x_opt="dimensionless")
def rolling_mass_ratio(stroke_over_x_opt):
    """Effective mass over bed mass, m_eff / m_bed [-], of the paper's rolling bed (eqs. 10-12).

    The bed's centre moves with the container while a wall pushes it and with eq. (10) while it
    rolls (from theta = 0 to the impact phase theta_i of eq. 12; the other half cycle mirrored).
    The container's force on the bed is m_bed x_p''; its first harmonic in phase with the
    container's acceleration is m_eff = m_bed (1/pi) int u(theta) cos(theta) dtheta / V over a
    cycle, u the bed's velocity (item 1's definition of the effective mass). It is 2/7 at X_opt
    (the bed rolls the whole half cycle: a rolling sphere follows 2/7 of the floor's
    acceleration) and tends to 1 far above (the bed rides with the walls).

    >>> round(float(rolling_mass_ratio(1.0)), 4), round(float(rolling_mass_ratio(1000.0)), 2)
    (0.2857, 1.0)
    """
    s = np.atleast_1d(np.asarray(stroke_over_x_opt, dtype=float))
    if np.any(~(s >= 1.0)):
        raise InputError("rolling_mass_ratio: the rolling law holds for X >= X_opt (stroke_over_x_opt >= 1)")
    ti = np.asarray(impact_phase_rolling(s * X_OPT_OVER_H, 1.0), dtype=float).reshape(s.shape)
    theta = ti[:, None] * np.linspace(0.0, 1.0, 2001)[None, :]  # the rolling phase, 0 .. theta_i
    rolling = (2.0 * np.cos(theta) + np.sqrt(25.0 + 10.0 * np.sin(theta) ** 2)) / 7.0
    pushed = (math.pi - ti) / 2.0 - np.sin(2.0 * ti) / 4.0  # int cos^2 from theta_i to pi: the bed on the wall
    out = 2.0 / math.pi * (np.trapezoid(rolling * np.cos(theta), theta, axis=1) + pushed)
    return out if np.ndim(stroke_over_x_opt) else out[0]
