"""Direct time integration of the paper's rolling block, an oracle for eqs. (10)-(14).

The closed forms of :mod:`pdamper.theory.rolling` rest on three modelling assumptions
(paper, Sect. 5.2): the bed is one block of N spheres that leaves the pushing wall at
``θ = Ωt = 0`` with the container velocity V and no spin; it then rolls on the floor,
``φ' = (x_p' - x_c')/r``; and its kinetic energy ``½ m x_p'² + ½ I φ'²`` stays constant until
it hits the far wall (9). This module integrates those assumptions as an ordinary differential
equation instead of using the algebra: differentiating the energy with the rolling condition
gives

    x_p'' = (I/r²) Δ x_c'' / (m x_p' + (I/r²) Δ),     Δ = x_p' - x_c',

with ``x_c = X sin Ωt`` and ``I = 2/5 m r²`` (solid spheres). The impact is the first time the
bed reaches the far wall, ``x_p = x_c + h``; the energy dissipated there is the relative
kinetic energy ``½ m Δ² + ½ I (Δ/r)²``, twice per cycle (13).

Reference: "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities", Nonlinear Dynamics, Sect. 5.2, eqs. (9), (12), (13).
"""

from __future__ import annotations

import dataclasses
import math

from ..units import quantities
from ._common import positive
from .bounds import angular_frequency

__all__ = ["BlockImpact", "integrate_rolling_block"]

#: Moment of inertia of a solid sphere over m r².
SPHERE_INERTIA_FACTOR = 2.0 / 5.0


@dataclasses.dataclass(frozen=True, kw_only=True)
class BlockImpact:
    """Impact of the rolling block on the far wall, from :func:`integrate_rolling_block`.

    All fields are NaN when the block does not reach the far wall by Ωt = π.
    """

    phase: float  #: impact phase θ_i = Ωt_i [rad]
    time: float  #: impact time t_i after leaving the pushing wall [s]
    bed_velocity: float  #: absolute bed velocity just before impact x_p'(t_i) [m/s]
    relative_velocity: float  #: bed velocity relative to the container Δx'_cp(t_i) [m/s]
    energy_per_cycle: float  #: energy dissipated per cycle, two impacts, eq. (13) [J]
    eta: float  #: reduced loss factor Ẽ_diss / (π m_bed V²) [-]


@quantities(stroke="length", clearance="length", frequency="frequency", bed_mass="mass", particle_radius="length")
def integrate_rolling_block(stroke: float, clearance: float, *, frequency: float,
                            bed_mass: float = 1.0, particle_radius: float = 5e-3,
                            rtol: float = 1e-11) -> BlockImpact:
    """Integrate the rolling block from the pushing wall to the far wall.

    Parameters
    ----------
    stroke : float
        Stroke X [m].
    clearance : float
        Clearance h [m].
    frequency : float
        Drive frequency f [Hz].
    bed_mass : float
        Mass of all spheres m_bed [kg].
    particle_radius : float
        Sphere radius r [m] (it cancels from the result, as the paper notes).
    rtol : float
        Relative tolerance of the integrator.

    Returns
    -------
    BlockImpact

    Examples
    --------
    >>> hit = integrate_rolling_block(0.015, 0.030, frequency=2.0)
    >>> round(hit.phase, 6), round(hit.eta, 6)
    (2.822236, 0.881447)
    """
    x_amp = positive("stroke", stroke, "m", "0.015 (15 mm)")
    h = positive("clearance", clearance, "m", "0.03 (30 mm)")
    omega = angular_frequency(frequency)
    m = positive("bed_mass", bed_mass, "kg", "0.149 (149 g)")
    r = positive("particle_radius", particle_radius, "m", "0.005 (5 mm)")
    inertia = SPHERE_INERTIA_FACTOR * m * r**2  # I_bed, sum over the spheres [kg m²]
    v_amp = x_amp * omega

    def rhs(t, y):
        x_p, v_p = y
        v_c = v_amp * math.cos(omega * t)
        a_c = -x_amp * omega**2 * math.sin(omega * t)
        slip = v_p - v_c
        return [v_p, inertia / r**2 * slip * a_c / (m * v_p + inertia / r**2 * slip)]

    def far_wall(t, y):
        return y[0] - (x_amp * math.sin(omega * t) + h)

    far_wall.terminal = True
    far_wall.direction = 1.0

    # A little past π so that an impact exactly at π (X = X_opt) is still found.
    t_end = math.pi * (1 + 1e-9) / omega
    from scipy.integrate import solve_ivp  # here, not at import: scipy.integrate is slow to load

    sol = solve_ivp(rhs, (0.0, t_end), [0.0, v_amp], method="DOP853", rtol=rtol,
                    atol=rtol * max(h, x_amp), events=far_wall)
    if sol.t_events[0].size == 0:
        nan = float("nan")
        return BlockImpact(phase=nan, time=nan, bed_velocity=nan, relative_velocity=nan,
                           energy_per_cycle=nan, eta=nan)
    t_i = float(sol.t_events[0][0])
    v_p = float(sol.y_events[0][0][1])
    slip = v_p - v_amp * math.cos(omega * t_i)
    spin = slip / r  # rolling condition
    energy = 2.0 * (0.5 * m * slip**2 + 0.5 * inertia * spin**2)  # eq. (13)
    return BlockImpact(phase=min(omega * t_i, math.pi), time=t_i, bed_velocity=v_p,
                       relative_velocity=slip, energy_per_cycle=energy,
                       eta=energy / (math.pi * m * v_amp**2))
