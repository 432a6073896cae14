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

from ..errors import InputError, shown
from ..units import quantities
from ._common import positive

__all__ = ["SHAPES", "container_length", "clearance"]

#: The paper's two containers and the size their L along the drive is read from: (the size's
#: keyword, L over it, an example). Any other shape answers its own L
#: (:attr:`pdamper.geometry.ShapeBase.drive_length`); ``pdamper theory`` and ``design`` ask it.
_PAPER_LENGTHS = {"cuboid": ("length", 1.0, "0.12 (120 mm)", "its inner length along the drive"),
                  "cylinder": ("container_radius", 2.0, "0.039 (39 mm)", "its inner radius; the clearance uses L = 2R")}
#: Container shapes the clearance formula of the paper names (eq. 6, Sect. 6.3).
SHAPES = tuple(_PAPER_LENGTHS)


@quantities(length="length", container_radius="length", radius="length")
def container_length(shape: str, length: float | None = None, container_radius: float | None = None, *,
                     radius: float | None = None) -> float:
    """Inner length L [m] of the paper's containers along the drive, as used in eq. (6): the
    cuboid's ``length``, the cylinder's ``2 container_radius`` (Sect. 6.3). A container of any
    registered shape answers its own (``shape.drive_length``, :mod:`pdamper.geometry`).

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
    if shape not in _PAPER_LENGTHS:
        raise InputError(f"shape = {shown(shape)} is unknown; use one of {', '.join(SHAPES)}")
    key, factor, example, what = _PAPER_LENGTHS[shape]
    sizes = {"length": length, "container_radius": container_radius}
    for other, value in sizes.items():
        if other != key and value is not None:
            owner = next(s for s, spec in _PAPER_LENGTHS.items() if spec[0] == other)
            raise InputError(f"{other} = {shown(value)} applies to the {owner} only; the {shape} takes {key} ({what})")
    if sizes[key] is None:
        raise InputError(f"the {shape} needs {key} ({what}, e.g. {example} m)")
    return factor * positive(key, sizes[key], "m", example)


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
        raise InputError(f"{name} = {shown(value)} is not allowed: {name} must be a whole number "
                         ">= 1 of spheres, e.g. 36")
    return int(value)
