"""The linear single-degree-of-freedom oscillator: the structure without a damper (beyond the paper).

``M x'' + c x' + K x = F0 sin(Ω t)`` with ``c = 2 ζ sqrt(K M)``, ``ω = sqrt(K/M)``,
``ω_d = ω sqrt(1 - ζ²)``. Closed forms used as test oracles for the coupled structure
(:mod:`pdamper.kernels.structure`) and as the "without damper" / "equivalent solid mass"
curves of the free-decay and frequency-response plots. Textbook results (e.g. Rao,
*Mechanical Vibrations*, Sects. 2.6 and 3.4).
"""

from __future__ import annotations

import math

import numpy as np

from ..units import quantities
from ._common import positive

__all__ = ["natural_frequency", "free_decay", "steady_amplitude", "oscillator_response"]


def _check_zeta(damping_ratio) -> float:
    from ..errors import InputError, shown

    z = float(damping_ratio)
    if not (0.0 <= z < 1.0):
        raise InputError(f"damping_ratio = {shown(damping_ratio)} is not allowed: it must be in [0, 1) "
                         "(an underdamped structure, e.g. 0.005)")
    return z


@quantities(mass="mass", stiffness="N/m")
def natural_frequency(mass: float, stiffness: float) -> float:
    """Undamped natural frequency f_n = sqrt(K/M) / 2π [Hz].

    >>> round(natural_frequency(7.0, 7.0 * (4 * math.pi) ** 2), 6)
    2.0
    """
    m = positive("mass", mass, "kg", "7")
    k = positive("stiffness", stiffness, "N/m", "1105")
    return math.sqrt(k / m) / (2.0 * math.pi)


@quantities(t="time", mass="mass", stiffness="N/m", damping_ratio="dimensionless", displacement="length")
def free_decay(t, *, mass: float, stiffness: float, damping_ratio: float, displacement: float):
    """Free decay from rest at ``displacement`` X0 [m]:
    ``x(t) = X0 e^{-ζωt} (cos ω_d t + ζ/sqrt(1-ζ²) sin ω_d t)`` [m].

    >>> float(free_decay(0.0, mass=1.0, stiffness=1.0, damping_ratio=0.01, displacement=0.01))
    0.01
    """
    x, _, _ = oscillator_response(t, mass=mass, stiffness=stiffness, damping_ratio=damping_ratio,
                                  displacement=displacement)
    return x


@quantities(force_frequency="frequency", mass="mass", stiffness="N/m", damping_ratio="dimensionless", force_amplitude="force")
def steady_amplitude(force_frequency, *, mass: float, stiffness: float, damping_ratio: float,
                     force_amplitude: float):
    """Steady-state amplitude |X| = (F0/K) / sqrt((1 - r²)² + (2ζr)²) [m], r = Ω/ω.

    >>> round(steady_amplitude(2.0, mass=1.0, stiffness=(4 * math.pi) ** 2, damping_ratio=0.01,
    ...                        force_amplitude=1.0) * (4 * math.pi) ** 2, 6)  # 1/(2 zeta) at r = 1
    50.0
    """
    k = positive("stiffness", stiffness, "N/m", "1105")
    z = _check_zeta(damping_ratio)
    w = math.sqrt(k / positive("mass", mass, "kg", "7"))
    r = 2.0 * math.pi * np.asarray(force_frequency, dtype=float) / w
    out = abs(force_amplitude) / k / np.sqrt((1.0 - r * r) ** 2 + (2.0 * z * r) ** 2)
    return float(out) if np.ndim(force_frequency) == 0 else out


@quantities(t="time", mass="mass", stiffness="N/m", damping_ratio="dimensionless", force_amplitude="force", force_frequency="frequency", displacement="length", velocity="velocity")
def oscillator_response(t, *, mass: float, stiffness: float, damping_ratio: float,
                        force_amplitude: float = 0.0, force_frequency: float = 0.0,
                        displacement: float = 0.0, velocity: float = 0.0):
    """Position [m], velocity [m/s] and acceleration [m/s²] at times ``t`` [s] of the oscillator
    started at ``x(0) = displacement``, ``x'(0) = velocity`` and forced by ``F0 sin(Ω t)``:
    the steady solution ``X sin(Ω t - φ)`` plus the decaying free motion that meets the start.
    """
    m = positive("mass", mass, "kg", "7")
    k = positive("stiffness", stiffness, "N/m", "1105")
    z = _check_zeta(damping_ratio)
    t = np.asarray(t, dtype=float)
    w = math.sqrt(k / m)
    wd = w * math.sqrt(1.0 - z * z)
    c = 2.0 * z * math.sqrt(k * m)
    W = 2.0 * math.pi * force_frequency
    # particular (steady) solution as a complex amplitude: x_p = Im(Xc e^{iΩt})
    Xc = force_amplitude / complex(k - m * W * W, c * W) if force_amplitude else 0j
    xp = np.imag(Xc * np.exp(1j * W * t))
    vp = np.imag(1j * W * Xc * np.exp(1j * W * t))
    xp0, vp0 = Xc.imag, (1j * W * Xc).imag
    A = displacement - xp0
    B = (velocity - vp0 + z * w * A) / wd
    e = np.exp(-z * w * t)
    cs, sn = np.cos(wd * t), np.sin(wd * t)
    xh = e * (A * cs + B * sn)
    vh = e * ((-z * w * A + wd * B) * cs + (-z * w * B - wd * A) * sn)
    x = xp + xh
    v = vp + vh
    a = (force_amplitude * np.sin(W * t) - c * v - k * x) / m
    return x, v, a
