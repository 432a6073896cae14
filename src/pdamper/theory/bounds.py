"""Excitation kinematics and the operating bounds of a horizontally driven particle damper.

The container moves as ``x_c = X sin(Ωt)`` with ``Ω = 2πf``, so its velocity amplitude is
``V = XΩ`` and its acceleration amplitude ``A = XΩ²`` (paper, Sect. 2). Two bounds frame the
rolling regime of the paper:

* **upper** (Sect. 4.2): the bed stays on the floor while ``A < g``, i.e. ``X < g/Ω²``;
  above it the bed fluidises and ends in the bouncing collect-and-collide mode;
* **lower** (Sect. 6.2): with the container tilted by α the bed collects at the low wall and
  leaves it only if ``A cos α > g sin α``, i.e. ``A > g tan α`` (3° gives 0.51 m/s²). The paper
  asks for ``A cos α >> g sin α`` at the operating point.

Reference: "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities", Nonlinear Dynamics, Sects. 2, 4.2 and 6.2.
"""

from __future__ import annotations

import math
import numbers

from ..errors import InputError
from ..units import quantities
from ._common import as_output, positive, positive_array

__all__ = [
    "GRAVITY",
    "angular_frequency",
    "velocity_amplitude",
    "acceleration_amplitude",
    "max_stroke_no_liftoff",
    "min_acceleration_tilt",
    "min_stroke_tilt",
]

#: Gravitational acceleration used by the paper [m/s²].
GRAVITY = 9.81


#: "A cos α >> g sin α" (Sect. 6.2) read as: A at least this many times g tan α. A heuristic: the
#: paper's 36-sphere case (factor 3.7 at 3°) still loses much of its peak to a 3° tilt.
TILT_MARGIN = 10.0

@quantities(frequency="frequency")
def angular_frequency(frequency: float) -> float:
    """Angular frequency Ω = 2πf [rad/s] of the drive frequency ``frequency`` f [Hz].

    >>> round(angular_frequency(2.0), 6)
    12.566371
    """
    return 2.0 * math.pi * positive("frequency", frequency, "Hz", "2.0")


@quantities(stroke="length", frequency="frequency")
def velocity_amplitude(stroke, frequency: float):
    """Container velocity amplitude V = XΩ [m/s] for stroke X [m] and frequency f [Hz].

    ``stroke`` may be an array; the result has its shape.

    >>> round(velocity_amplitude(0.012, 2.0), 6)
    0.150796
    """
    x = positive_array("stroke", stroke, "m", "0.012 (12 mm)")
    return as_output(x * angular_frequency(frequency), stroke)


@quantities(stroke="length", frequency="frequency")
def acceleration_amplitude(stroke, frequency: float):
    """Container acceleration amplitude A = XΩ² [m/s²] for stroke X [m] and frequency f [Hz].

    >>> round(acceleration_amplitude(0.012, 2.0), 4)
    1.895
    """
    x = positive_array("stroke", stroke, "m", "0.012 (12 mm)")
    return as_output(x * angular_frequency(frequency) ** 2, stroke)


@quantities(frequency="frequency", gravity="acceleration")
def max_stroke_no_liftoff(frequency: float, *, gravity: float = GRAVITY) -> float:
    """Largest stroke X = g/Ω² [m] for which A < g, so the bed stays on the floor (Sect. 4.2).

    >>> round(max_stroke_no_liftoff(2.0), 5)
    0.06212
    """
    g = positive("gravity", gravity, "m/s^2", "9.81")
    return g / angular_frequency(frequency) ** 2


@quantities(tilt="angle", gravity="acceleration")
def min_acceleration_tilt(tilt: float, *, gravity: float = GRAVITY) -> float:
    """Smallest acceleration amplitude g tan α [m/s²] that lifts the bed off the low wall.

    From ``A cos α > g sin α`` (Sect. 6.2) for a container tilted by α about its pitch (z) axis.

    Parameters
    ----------
    tilt : float
        Tilt α [rad], ``0 <= α < π/2``.
    gravity : float
        g [m/s²].

    Examples
    --------
    >>> round(min_acceleration_tilt(math.radians(3)), 3)
    0.514
    """
    g = positive("gravity", gravity, "m/s^2", "9.81")
    return g * math.tan(_tilt(tilt))


@quantities(tilt="angle", frequency="frequency", gravity="acceleration")
def min_stroke_tilt(tilt: float, frequency: float, *, gravity: float = GRAVITY) -> float:
    """Smallest stroke X = g tan α / Ω² [m] at which the bed leaves the low wall (Sect. 6.2).

    >>> round(min_stroke_tilt(math.radians(3), 2.0) * 1e3, 2)  # mm
    3.26
    """
    return min_acceleration_tilt(tilt, gravity=gravity) / angular_frequency(frequency) ** 2


def _tilt(tilt) -> float:
    real = isinstance(tilt, numbers.Real) and not isinstance(tilt, bool)
    if not real or not math.isfinite(tilt) or not 0 <= tilt < math.pi / 2:
        shown = f"{tilt:g} rad ({math.degrees(tilt):g} deg)" if real else repr(tilt)
        raise InputError(f"tilt = {shown} is outside [0, 90 deg): give the tilt angle in radians "
                         "(a bare number is radians; 3 degrees is 0.0524 rad or '3deg')")
    return float(tilt)
