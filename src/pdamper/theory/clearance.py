"""Clearance of a single-layer particle bed, eq. (6) of the paper.

The clearance h is the free length between the collected particle bed and the opposite
container wall along the drive. With N_p of the N_p,max spheres that cover the floor in one
layer, eq. (6) gives ``h = L (1 - N_p / N_p,max)``. For the cylinder with its axis against
gravity the paper (Sect. 6.3) uses the same formula with ``L = 2R``.

Reference: "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities", Nonlinear Dynamics, Sects. 4.2 and 6.3.
"""

from __future__ import annotations

import math
import numbers
import warnings

from ..errors import InputError
from ..units import quantities
from ._common import positive

__all__ = ["SHAPES", "container_length", "clearance"]

#: Container shapes the clearance formula knows.
SHAPES = ("cuboid", "cylinder")


@quantities(length="length", container_radius="length", radius="length")
def container_length(shape: str, length: float | None = None, container_radius: float | None = None, *,
                     radius: float | None = None) -> float:
    """Inner length L [m] of the container along the drive, as used in eq. (6).

    Parameters
    ----------
    shape : {"cuboid", "cylinder"}
        Container shape.
    length : float, optional
        Inner length of the cuboid along the drive [m]; required for the cuboid only.
    container_radius : float, optional
        Inner radius R of the cylinder [m]; required for the cylinder only (``L = 2R``).
    radius : float, optional
        Deprecated: the old name of ``container_radius`` (warns).

    Returns
    -------
    float
        L [m].

    Examples
    --------
    >>> container_length("cuboid", length=0.12)
    0.12
    >>> round(container_length("cylinder", container_radius="39mm"), 6)
    0.078
    """
    if radius is not None:
        if container_radius is not None:
            raise InputError("radius is the old name of container_radius; give container_radius only")
        warnings.warn("container_length(radius=...) is deprecated; use container_radius=...",
                      DeprecationWarning, stacklevel=3)
        container_radius = radius
    radius = container_radius
    if shape not in SHAPES:
        raise InputError(f"shape = {shape!r} is unknown; use one of {', '.join(SHAPES)}")
    if shape == "cuboid":
        if radius is not None:
            raise InputError(f"container_radius = {radius!r} applies to the cylinder only; "
                             "for the cuboid give its inner length along the drive")
        if length is None:
            raise InputError("the cuboid needs its inner length along the drive "
                             "(length, e.g. 0.12 m = 120 mm)")
        return positive("length", length, "m", "0.12 (120 mm)")
    if length is not None:
        raise InputError(f"length = {length!r} applies to the cuboid only; the cylinder takes "
                         "its container_radius R and uses L = 2R")
    if radius is None:
        raise InputError("the cylinder needs its inner radius (container_radius, e.g. 0.039 m = 39 mm); "
                         "the clearance uses L = 2R")
    return 2.0 * positive("container_radius", radius, "m", "0.039 (39 mm)")


@quantities(length="length")
def clearance(length: float, particles: int, max_particles: int) -> float:
    """Clearance h [m] of the particle bed, eq. (6): ``h = L (1 - N_p / N_p,max)``.

    Parameters
    ----------
    length : float
        Inner container length L along the drive [m] (cylinder: ``L = 2R``, see
        :func:`container_length`).
    particles : int
        Number of spheres N_p, ``1 <= N_p <= N_p,max``.
    max_particles : int
        Number of spheres N_p,max that cover the floor in one layer.

    Returns
    -------
    float
        h [m]; 0 for a full layer.

    Examples
    --------
    >>> round(clearance(0.12, 36, 48), 9), round(clearance(0.12, 44, 48), 9)
    (0.03, 0.01)
    """
    length = positive("length", length, "m", "0.12 (120 mm)")
    n_max = _count("max_particles", max_particles)
    n = _count("particles", particles)
    if n > n_max:
        raise InputError(f"particles = {n} exceeds max_particles = {n_max}: the theory covers "
                         f"one layer at most; use 1 to {n_max} particles")
    return length * (1.0 - n / n_max)


def _count(name: str, value) -> int:
    if (isinstance(value, bool) or not isinstance(value, numbers.Real)
            or not math.isfinite(value) or value != int(value) or value < 1):
        raise InputError(f"{name} = {value!r} is not allowed: {name} must be a whole number "
                         ">= 1 of spheres, e.g. 36")
    return int(value)
