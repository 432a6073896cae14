"""Cylindrical container with its axis against gravity: floor, lid and the concave curved wall
(paper Sect. 6.3: R = 39 mm, inner height 11 mm).

Container frame: axis along y through x = z = 0, floor at y = 0, lid at y = H.
The curved wall is concave: its Hertz radius enters as 1/R* = 1/r - 1/R.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..schema import convert_fields, param
from .shape import ShapeBase, polygon_circle, register_shape
from .walls import CYLINDER_INSIDE, PLANE, cylinder_inside, plane

__all__ = ["Cylinder"]


@register_shape
@dataclass(frozen=True, kw_only=True)
class Cylinder(ShapeBase):
    """Inner dimensions of a cylindrical container.

    Parameters
    ----------
    radius : float
        R [m] of the curved wall.
    height : float
        H [m] floor to lid.
    """

    radius: float = param(0.039, dimension="length", paper="39 mm")
    height: float = param(0.011, dimension="length", paper="11 mm")
    shape: str = param("cylinder", kind="tag")
    length_keys = ("radius",)

    def __post_init__(self):
        convert_fields(self, "container")
        for name in ("radius", "height"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0 and np.isfinite(v)):
                raise InputError(f"container.{name} = {shown(v)} m; must be a positive length (paper: R = 39 mm, H = 11 mm)")

    @property
    def drive_length(self) -> float:
        """L = 2R [m] used in the clearance, eq. (6)."""
        return 2.0 * self.radius

    def bounding_box(self):
        """(lo, hi) corners [m] of the box around the inside."""
        return np.array([-self.radius, 0.0, -self.radius]), np.array([self.radius, self.height, self.radius])

    def length_along(self, direction) -> float:
        """2R [m]: every horizontal chord through the axis."""
        return 2.0 * self.radius if (direction[0] or direction[2]) else 0.0

    def outline(self, view: str):
        """Top view: the circle of the curved wall; side view: the rectangle 2R x H."""
        if view == "top":
            return [polygon_circle(0.0, 0.0, self.radius)]
        return super().outline(view)

    def end_contacts(self, position, radius, along, length: float, gap):
        """The round wall: a sphere touches it ahead (behind) when it is at the curved wall within
        60 deg of the drive axis on the + (-) side."""
        rho = np.hypot(position[:, :, 0], position[:, :, 2])
        at_wall = rho + radius >= length / 2 - gap
        ahead = np.abs(along) >= 0.5 * rho              # within 60 deg of the drive axis
        return np.any(at_wall & ahead & (along < 0), axis=1), np.any(at_wall & ahead & (along > 0), axis=1)

    def volume(self) -> float:
        """pi R^2 H [m^3]."""
        return float(np.pi * self.radius**2 * self.height)

    def describe(self) -> str:
        return f"cylinder R = {self.radius * 1e3:g} mm, H = {self.height * 1e3:g} mm"

    def walls(self):
        """(kinds, data, names): floor, lid, curved wall."""
        rows = [plane((0, 1, 0), 0.0), plane((0, -1, 0), -self.height),
                cylinder_inside((0, 0, 0), (0, 1, 0), self.radius)]
        kinds = np.array([PLANE, PLANE, CYLINDER_INSIDE], dtype=np.int64)
        return kinds, np.array(rows), ["floor", "lid", "curved"]

    def floor_sites(self, radius: float, spacing: float) -> np.ndarray:
        """Sites (x, z) of one layer for spheres of ``radius`` at centre distance >= ``spacing``,
        ordered from -x outwards.

        Two packings are tried and the one holding more spheres is used: a hexagonal lattice
        and concentric rings (outer ring against the wall, then inwards, a sphere in the middle
        if there is room). For the paper's R = 39 mm and r = 5 mm they hold 37 and 44.
        """
        hexa = self._hex_sites(radius, spacing)
        rings = self._ring_sites(radius, spacing)
        pts = rings if len(rings) > len(hexa) else hexa
        if len(pts) == 0:
            return np.zeros((0, 2))
        order = np.lexsort((np.abs(pts[:, 1]), pts[:, 0]))
        return pts[order]

    def _hex_sites(self, radius, spacing):
        rmax = self.radius - radius
        if rmax < 0:
            return np.zeros((0, 2))
        row = spacing * np.sqrt(3.0) / 2.0
        n = int(np.ceil(self.radius / min(spacing, row))) + 2
        pts = [(i * spacing + 0.5 * spacing * (j % 2), j * row)
               for j in range(-n, n + 1) for i in range(-n, n + 1)
               if (i * spacing + 0.5 * spacing * (j % 2)) ** 2 + (j * row) ** 2 <= rmax * rmax + 1e-15]
        return np.array(pts) if pts else np.zeros((0, 2))

    def _ring_sites(self, radius, spacing):
        rho = self.radius - radius
        pts = []
        k = 0
        while rho >= 0:
            if rho < spacing / 2:
                pts.append((0.0, 0.0))
                break
            n = int(np.floor(np.pi / np.arcsin(min(1.0, spacing / (2 * rho))) + 1e-9))
            off = 0.5 * (k % 2) * 2 * np.pi / n
            th = off + 2 * np.pi * np.arange(n) / n
            pts.extend(zip(rho * np.cos(th), rho * np.sin(th)))
            rho -= spacing
            k += 1
        return np.array(pts) if pts else np.zeros((0, 2))

    def max_particles(self, radius: float) -> int:
        """Spheres of ``radius`` that fit on the floor in one layer with the packings of
        :meth:`floor_sites` (a geometric count: 44 for R = 39 mm, r = 5 mm; the paper quotes
        N_p,max = 48 for the clearance of eq. (6), which is what theory should use)."""
        return int(len(self.floor_sites(radius, 2 * radius)))

    def clearance_capacity(self, radius: float) -> int:
        """N_p,max [-] of the clearance law, eq. (6), as the paper counts it for the cylinder: the
        floor area over the square a sphere covers, ``round(pi R^2 / (2r)^2)`` (48 for R = 39 mm,
        r = 5 mm). Theory (X_opt, the design, the studies' h) uses this count, not the geometric
        :meth:`max_particles`."""
        return int(round(np.pi * self.radius**2 / (2 * radius) ** 2))

    def mesh(self, segments: int = 48):
        """(vertices, quads) of the inner surface (side wall as ``segments`` quads), for VTK and plots."""
        th = np.linspace(0, 2 * np.pi, segments, endpoint=False)
        ring = np.column_stack([self.radius * np.cos(th), np.zeros(segments), self.radius * np.sin(th)])
        top = ring.copy()
        top[:, 1] = self.height
        v = np.vstack([ring, top])
        quads = np.array([[i, (i + 1) % segments, segments + (i + 1) % segments, segments + i] for i in range(segments)])
        return v, quads
