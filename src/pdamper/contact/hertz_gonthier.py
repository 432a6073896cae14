r"""Hertz normal contact with the nonlinear damping of Gonthier et al. (2004), paper eq. (1).

.. math::

    F_N = k\,\delta^{3/2}\,(1 + d\,\dot\delta), \qquad F_N \ge 0,

    k = \tfrac43 E^* \sqrt{R^*}, \qquad d = \frac{1-\varepsilon^2}{\varepsilon\, v_{in}},

with the overlap :math:`\delta` [m], its rate :math:`\dot\delta` [m/s] (positive while
approaching), the effective modulus :math:`1/E^* = (1-\nu_1^2)/E_1 + (1-\nu_2^2)/E_2`, the
effective radius :math:`1/R^* = 1/r_1 + 1/r_2` (flat wall: :math:`R^* = r`; concave wall of
radius R: :math:`1/R^* = 1/r - 1/R`), and :math:`v_{in}` the normal approach speed at the first
touch of that contact, kept as contact history.

The force is clipped at zero: a contact never pulls.

**Guard for resting contacts.** As :math:`v_{in}\to 0` the damping parameter diverges. pdamper
uses :math:`v_{in} \leftarrow \max(v_{in}, v_\text{floor})`, and raises :math:`v_{in}` to any
larger approach speed the contact sees later (see :mod:`pdamper.kernels.forces`), with the default
:data:`V_IN_FLOOR` = 1 mm/s. Below that speed a contact is slightly less dissipative than
Gonthier's law says; a sphere resting on the floor then sits in a damped Hertz well whose
damping rate ``g d`` is bounded, so explicit integrators stay stable. Tested in
``tests/contact/test_hertz_gonthier.py`` (a sphere dropped from rest settles and stays).

**Registered damping choices** (:mod:`pdamper.contact.damping`): ``"calibrated"`` and
``"gonthier"`` share the kernel functions :func:`touch` (``d = chi / v_in``) and
:func:`normal_force`; they differ only in the coefficient ``chi(eps)`` the kernels are given.

**What epsilon you get.** The law is scale-free: the outgoing/incoming speed ratio of an impact
depends only on ``chi = d v_in``. Gonthier's ``chi = (1 - eps^2)/eps`` damps a little too much:
an impact rebounds with a lower ratio than the nominal eps (0.6 gives 0.577, 0.7 gives 0.6696,
4.3 % low; 0.9 gives 0.876; measured by an independent ODE solve, see
``tests/contact/test_hertz_gonthier.py``); near eps = 1 the loss 1 - eps is 4/3 of the nominal. pdamper therefore offers two
damping choices (``ContactModel.damping``):

- ``"calibrated"`` (default): ``chi(eps)`` is the exact inverse of the impact's restitution, so an
  isolated impact rebounds with the epsilon you asked for.
  The map is tabulated in ``data/gonthier_calibration.csv`` (:func:`compute_calibration`).
- ``"gonthier"``: the paper's formula ``d = (1 - eps^2)/(eps v_in)`` as written.

References
----------
Gonthier, Y., McPhee, J., Lange, C., Piedboeuf, J.-C. (2004). A regularized contact model with
asymmetric damping and dwell-time dependent friction. Multibody Syst. Dyn. 11, 209-233.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..jit import njit
from .damping import DampingLaw
from .hertz import hertz_stiffness

__all__ = ["V_IN_FLOOR", "LAWS", "HertzGonthier", "chi_for_restitution", "restitution_for_chi", "compute_calibration", "hertz_stiffness", "effective_radius", "damping_parameter",
           "contact_time", "peak_overlap", "normal_force", "touch"]

#: Default floor on the approach speed used in the damping parameter [m/s].
V_IN_FLOOR = 1e-3

_CALIBRATION_FILE = __import__("pathlib").Path(__file__).with_name("data") / "gonthier_calibration.csv"


def restitution_for_chi(chi: float) -> float:
    """Speed ratio out/in of one Hertz-Gonthier impact with ``chi = d v_in`` (dimensionless ODE
    ``u'' = -u^1.5 (1 + chi u')``, ``u(0) = 0``, ``u'(0) = 1``, solved to 1e-10)."""
    from scipy.integrate import solve_ivp

    def rhs(_t, y):
        u, du = y
        f = max(u, 0.0) ** 1.5 * (1.0 + chi * du)
        return [du, -max(f, 0.0)]

    def leave(_t, y):
        return y[0]

    leave.terminal = True
    leave.direction = -1
    sol = solve_ivp(rhs, [0.0, 1e3], [0.0, 1.0], events=leave, rtol=1e-10, atol=1e-12, first_step=1e-6,
                    method="DOP853")
    if sol.y_events[0].size == 0:
        return 0.0
    return float(-sol.y_events[0][0][1])


def compute_calibration(n: int = 120) -> np.ndarray:
    """Table (n+1, 2) of (chi, epsilon) from chi = 0 to 200, epsilon decreasing from 1."""
    chis = np.concatenate([[0.0], np.geomspace(1e-5, 200.0, n)])
    return np.column_stack([chis, [restitution_for_chi(c) for c in chis]])


def _calibration() -> np.ndarray:
    global _CAL
    try:
        return _CAL
    except NameError:
        _CAL = np.loadtxt(_CALIBRATION_FILE, delimiter=",", skiprows=1)
        return _CAL


def chi_for_restitution(eps, damping: str = "calibrated"):
    """chi = d v_in [-] giving restitution ``eps`` (array or scalar in (0, 1]).

    ``damping="gonthier"`` returns Gonthier's ``(1 - eps^2)/eps``; ``"calibrated"`` inverts the
    exact impact restitution (log-linear interpolation in the tabulated map, error < 1e-4)."""
    e = np.clip(np.asarray(eps, dtype=float), 1e-6, 1.0)
    if damping == "gonthier":
        return ((1.0 - e * e) / e)[()]
    tab = _calibration()
    chi, er = tab[:, 0], tab[:, 1]
    # interpolate chi against epsilon; use Gonthier's form as the variable where it is smooth
    g = (1.0 - er * er) / np.maximum(er, 1e-12)
    ratio = np.ones_like(chi)
    ratio[1:] = chi[1:] / g[1:]
    order = np.argsort(er)
    r = np.interp(e, er[order], ratio[order])
    return (r * (1.0 - e * e) / e)[()]


def effective_radius(r1: float, r2: float | None = None, *, concave_radius: float | None = None) -> float:
    """R* [m]: sphere-sphere ``1/(1/r1 + 1/r2)``, flat wall (``r2=None``) ``r1``,
    concave wall of radius R ``1/(1/r1 - 1/R)``."""
    if concave_radius is not None:
        return 1.0 / (1.0 / r1 - 1.0 / concave_radius)
    if r2 is None:
        return float(r1)
    return 1.0 / (1.0 / r1 + 1.0 / r2)


def damping_parameter(restitution: float, v_in: float, v_floor: float = V_IN_FLOOR) -> float:
    """Gonthier's d = (1 - eps^2)/(eps * max(v_in, v_floor)) [s/m]."""
    return (1.0 - restitution**2) / (restitution * max(v_in, v_floor))


def contact_time(m_star: float, r_star: float, e_star: float, v: float) -> float:
    """Duration [s] of an undamped Hertz impact at approach speed v [m/s]:
    ``2.87 (m*^2 / (R* E*^2 v))^(1/5)`` (Johnson, Contact Mechanics, ch. 11)."""
    return 2.868265 * (m_star**2 / (r_star * e_star**2 * v)) ** 0.2


def peak_overlap(m_star: float, k: float, v: float) -> float:
    """Largest overlap [m] of an undamped Hertz impact: (15 m* v^2 / (16 k))^(2/5)... with k = 4/3 E* sqrt(R*).

    Energy balance ``1/2 m* v^2 = 2/5 k delta^(5/2)``.
    """
    return (1.25 * m_star * v * v / k) ** 0.4


@njit
def normal_force(k, delta, delta_dot, d):
    """Scalar eq. (1): k delta^1.5 (1 + d delta_dot), clipped at 0. Returns (F_N, F_damp) where
    F_damp is the damping part actually applied (for the energy ledger)."""
    fe = k * delta * math.sqrt(delta)
    f = fe * (1.0 + d * delta_dot)
    if f < 0.0:
        return 0.0, -fe
    return f, fe * d * delta_dot


@njit
def touch(chi, v_in, k, m_star):
    """Gonthier's damping parameter ``d = chi / v_in`` [s/m] of a contact that starts (or is struck
    harder than before) at approach speed ``v_in`` [m/s] (already floored)."""
    return chi / v_in


class HertzGonthier(NamedTuple):
    """Kernel marker of eq. (1) with Gonthier's damping (see :mod:`pdamper.contact.damping`)."""


#: The damping choices of this law (``contact.damping``).
LAWS = (
    DampingLaw(name="calibrated", marker=HertzGonthier, touch=touch, force=normal_force,
               coefficient=lambda eps: chi_for_restitution(eps, "calibrated"),
               summary="eq. (1), Gonthier's damping with chi(eps) calibrated so an impact rebounds at eps (default)"),
    DampingLaw(name="gonthier", marker=HertzGonthier, touch=touch, force=normal_force,
               coefficient=lambda eps: chi_for_restitution(eps, "gonthier"),
               summary="eq. (1) as written, d = (1 - eps^2)/(eps v_in) (rebounds up to 4 % below eps)"),
)

