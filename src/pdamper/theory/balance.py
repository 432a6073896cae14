"""The energy balance of a structure's mode with the damper at phase resonance (beyond the paper).

One mode of a structure (:class:`Mode`: modal mass m, stiffness k, damping c, the mode shape at
the damper phi_d, at the force phi_f) under a harmonic force F at its resonance, the damper
described by its closed-form fields (:func:`pdamper.theory.fields.closed_form_fields`). Per cycle
the force's work equals the structure's and the bed's loss (eqs. 4, 5 for the bed):

    pi |phi_f| F Q = pi c Omega Q^2 + pi eta*(X) m_bed (X Omega)^2,   X = |phi_d| Q,
    Omega^2 = k / (m + phi_d^2 m_eff(X)).

:func:`required_force` solves it for F at a stroke X; :func:`operating_points` for every X at a
force F (docs/structure.md, "Design for a structure").
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..units import quantities
from .fields import closed_form_fields

__all__ = ["Mode", "required_force", "OperatingPoint", "operating_points"]


@dataclass(frozen=True, kw_only=True)
class Mode:
    """One mode of a structure as the design sees it (SI): modal ``mass`` m, ``stiffness`` k,
    ``damping`` c, ``frequency`` f [Hz], ``damping_ratio`` zeta and the mode shape's values at the
    damper, the force and the response point (``phi_damper``, ``phi_force``, ``phi_response``)."""

    number: int
    mass: float
    stiffness: float
    damping: float
    frequency: float
    damping_ratio: float
    phi_damper: float
    phi_force: float
    phi_response: float
    modes: int = 1


@quantities(stroke="length", x_opt="length", bed_mass="mass", kappa="dimensionless")
def required_force(mode: Mode, stroke, *, x_opt: float, bed_mass: float, kappa: float = 1.0):
    """The force amplitude [N] that holds the damper at ``stroke`` X [m] at phase resonance, and
    that resonance's angular frequency Omega [rad/s]: the energy balance per cycle

        pi |phi_f| F Q = pi c Omega Q^2 + pi eta*(X) m_bed (X Omega)^2,   X = |phi_d| Q,
        Omega^2 = k / (m + phi_d^2 m_eff(X)),

    solved for F: ``F = Q (c Omega + eta*(X) m_bed phi_d^2 Omega^2) / |phi_f|``.
    """
    x = np.asarray(stroke, dtype=float)
    eta, mu = closed_form_fields(x / x_opt, kappa)
    pd2 = mode.phi_damper**2
    omega = np.sqrt(mode.stiffness / (mode.mass + pd2 * mu * bed_mass))
    q = x / abs(mode.phi_damper)
    return q * (mode.damping * omega + eta * bed_mass * pd2 * omega**2) / abs(mode.phi_force), omega


@dataclass(frozen=True, kw_only=True)
class OperatingPoint:
    """One solution of the energy balance: the damper's stroke X [m], s = X/X_opt, the state
    ("rolling" above X_opt, "scattered" below, "held at X_opt" when the force falls in the law's
    jump), whether it is stable (more amplitude, more loss than input), the resonance [Hz]."""

    stroke_m: float
    stroke_over_x_opt: float
    state: str
    stable: bool
    frequency_hz: float
    eta_star: float
    effective_mass_kg: float


@quantities(force="force", x_opt="length", bed_mass="mass", kappa="dimensionless")
def operating_points(mode: Mode, force: float, *, x_opt: float, bed_mass: float, kappa: float = 1.0,
                     refine: bool = True) -> list:
    """Every solution X of the energy balance :func:`required_force` (X) = ``force``, smallest first.

    The scattered branch (X < X_opt) and the rolling branch (X >= X_opt) are searched apart (the
    laws jump at X_opt); where the force lies inside the jump -- too much for the scattered bed at
    X_opt, too little for the rolling one -- the amplitude is held at X_opt (state "held at X_opt",
    the swaying the DEM shows there). Stable: the required force grows with X there.
    """
    from scipy.optimize import brentq

    # the bare structure's amplitude at the damper bounds the damped one (the damper only adds loss)
    x_bare = abs(mode.phi_damper) * abs(mode.phi_force) * force / max(mode.damping * 2 * math.pi * mode.frequency,
                                                                      1e-300)
    top = max(4.0 * x_bare, 2.0 * x_opt)
    out = []

    def point(x, state, stable):
        f_req, om = required_force(mode, x, x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)
        eta, mu = closed_form_fields(x / x_opt, kappa)
        return OperatingPoint(stroke_m=float(x), stroke_over_x_opt=float(x / x_opt), state=state, stable=bool(stable),
                              frequency_hz=float(om) / (2 * math.pi), eta_star=float(eta),
                              effective_mass_kg=float(mu) * bed_mass)

    for state, lo, hi in (("scattered", 1e-4 * x_opt, x_opt * (1 - 1e-12)), ("rolling", x_opt, top)):
        if hi <= lo:
            continue
        xs = np.geomspace(lo, hi, 600)
        g = required_force(mode, xs, x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)[0] - force
        for i in np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0)[0]:
            if refine:
                fun = lambda x: float(required_force(mode, x, x_opt=x_opt, bed_mass=bed_mass,  # noqa: E731
                                                     kappa=kappa)[0]) - force
                x = brentq(fun, xs[i], xs[i + 1], xtol=1e-14, rtol=1e-12)
            else:
                x = xs[i] - g[i] * (xs[i + 1] - xs[i]) / (g[i + 1] - g[i])
            out.append(point(x, state, g[i + 1] > g[i]))
    low = required_force(mode, x_opt * (1 - 1e-9), x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)[0]
    high = required_force(mode, x_opt, x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)[0]
    if low < force < high:
        out.append(point(x_opt, "held at X_opt", True))
    return sorted(out, key=lambda p: p.stroke_m)
