"""Inner baffles: thin plates inside the container, across the drive, full height or with a gap.

Meyer & Seifried, "Design of robust particle dampers using inner structures and coated container
walls", Granular Matter 25 (2023) 20, doi:10.1007/s10035-022-01298-4: beams placed perpendicular
to the container's motion split the bed and smooth the transition between the motion modes, so
the damper works over a wider range of amplitudes.

A baffle here is a plate perpendicular to the container's x axis at ``position`` (its mid-plane),
``thickness`` thick, running through the whole container across (z) and from ``gap_below`` over
the floor to ``gap_above`` under the lid. Its wall is the outside of a solid box
(:data:`pdamper.geometry.walls.BOX_OUTSIDE`), so spheres also hit its edges where a gap leaves
them room. In a config file::

    [container]
    baffles = [{position = "-20mm"}, {position = "20mm", gap_below = "12mm", material = "silicone"}]

``material`` (a name of the material library or an inline table) is the plate's own; without
one the plate is of the container's material.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..schema import convert_fields, param
from .walls import BOX_OUTSIDE, box_outside

__all__ = ["Baffle", "baffle_walls", "baffle_outlines", "floor_sections"]


@dataclass(frozen=True, kw_only=True)
class Baffle:
    """One plate across the container's x axis.

    Parameters
    ----------
    position : x [m] of the plate's mid-plane (0: the middle of the container).
    thickness : t [m] > 0 (default 2 mm).
    gap_below : the gap [m] between the floor and the plate's lower edge (0: down to the floor).
    gap_above : the gap [m] between the plate's upper edge and the lid (0: up to the lid).
    material : the plate's material (a :class:`pdamper.materials.Material`), None: the container's.
    """

    position: float = param(0.0, dimension="length")
    thickness: float = param(0.002, dimension="length")
    gap_below: float = param(0.0, dimension="length")
    gap_above: float = param(0.0, dimension="length")
    material: object = param(None, kind="custom")

    def __post_init__(self):
        convert_fields(self, "container.baffles")
        for name in ("position", "thickness", "gap_below", "gap_above"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise InputError(f"container.baffles: {name} = {shown(v)}; give a finite length, e.g. '12mm'")
        if self.thickness <= 0:
            raise InputError(f"container.baffles: thickness = {shown(self.thickness)} m; must be > 0 (e.g. '2mm')")
        for name in ("gap_below", "gap_above"):
            if getattr(self, name) < 0:
                raise InputError(f"container.baffles: {name} = {shown(getattr(self, name))} m; must be >= 0 (0: no gap)")

    def check_fits(self, shape, k: int) -> None:
        """InputError when the plate does not stand inside ``shape`` (k: its number, from 1)."""
        lo, hi = shape.bounding_box()
        height = hi[1] - lo[1]
        where = f"container.baffles #{k}"
        if not (lo[0] < self.position - self.thickness / 2 and self.position + self.thickness / 2 < hi[0]):
            raise InputError(f"{where}: position = {self.position * 1e3:g} mm with thickness {self.thickness * 1e3:g} mm "
                             f"is not inside the container (x from {lo[0] * 1e3:g} to {hi[0] * 1e3:g} mm)")
        if self.gap_below + self.gap_above >= height:
            raise InputError(f"{where}: gap_below + gap_above = {(self.gap_below + self.gap_above) * 1e3:g} mm leave no "
                             f"plate in a container {height * 1e3:g} mm high")

    def box(self, height: float):
        """(centre, half sizes) [m] of the plate as a solid box in a container ``height`` high."""
        y0, y1 = self.gap_below, height - self.gap_above
        return (np.array([self.position, 0.5 * (y0 + y1), 0.0]),
                np.array([0.5 * self.thickness, 0.5 * (y1 - y0), np.inf]))


def baffle_walls(baffles, height: float):
    """(kinds, data, names) of the baffles' walls in a container ``height`` [m] high."""
    rows = [box_outside(*b.box(height)) for b in baffles]
    kinds = np.full(len(rows), BOX_OUTSIDE, dtype=np.int64)
    data = np.array(rows) if rows else np.zeros((0, 7))
    return kinds, data, [f"baffle {k + 1}" for k in range(len(rows))]


def baffle_outlines(baffles, view: str, height: float, across: tuple[float, float]):
    """Closed polygons of the plates seen from ``view`` ("top": x-z across ``across`` = (z0, z1);
    "side": x-y)."""
    out = []
    for b in baffles:
        x0, x1 = b.position - b.thickness / 2, b.position + b.thickness / 2
        y0, y1 = (b.gap_below, height - b.gap_above) if view == "side" else across
        out.append(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]))
    return out


def floor_sections(baffles, x_lo: float, x_hi: float, radius: float) -> list[tuple[float, float]]:
    """The sections ``[(a, b), ...]`` [m] of the floor along x, from ``x_lo`` to ``x_hi``, that a
    sphere of ``radius`` cannot leave along the floor: the floor is split at each baffle whose gap
    below is less than the sphere's diameter, between the plate's two faces (one section, the
    whole floor, without such a baffle).

    >>> floor_sections([Baffle(position=-0.02), Baffle(position=0.02)], -0.06, 0.06, 0.005)
    [(-0.06, -0.021), (-0.019, 0.019), (0.021, 0.06)]
    """
    cuts = sorted((b.position - b.thickness / 2, b.position + b.thickness / 2)
                  for b in baffles if b.gap_below < 2 * radius)
    edges, start = [], float(x_lo)
    for face_lo, face_hi in cuts:
        edges.append((start, float(face_lo)))
        start = float(face_hi)
    edges.append((start, float(x_hi)))
    return [(round(a, 12), round(b, 12)) for a, b in edges if b > a]
