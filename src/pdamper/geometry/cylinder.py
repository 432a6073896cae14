"""Cylindrical container with its axis against gravity: floor, lid and the concave curved wall
(paper Sect. 6.3: R = 39 mm, inner height 11 mm).

Container frame: axis along y through x = z = 0, floor at y = 0, lid at y = H.
The curved wall is concave: its Hertz radius enters as 1/R* = 1/r - 1/R (SPEC Sect. 2).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from .walls import CYLINDER_INSIDE, PLANE, cylinder_inside, plane

__all__ = ["Cylinder"]


@dataclass(frozen=True, kw_only=True)
class Cylinder:
    """Inner dimensions of a cylindrical container.

    Parameters
    ----------
    radius : float
        R [m] of the curved wall.
    height : float
        H [m] floor to lid.
    """

    radius: float = 0.039
    height: float = 0.011
    shape: str = "cylinder"

    def __post_init__(self):
        for name in ("radius", "height"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0 and np.isfinite(v)):
                raise InputError(f"container.{name} = {v!r} m; must be a positive length (paper: R = 39 mm, H = 11 mm)")

    @property
    def drive_length(self) -> float:
        """L = 2R [m] used in the clearance, eq. (6)."""
        return 2.0 * self.radius

    def walls(self):
        """(kinds, data, names): floor, lid, curved wall."""
        rows = [plane((0, 1, 0), 0.0), plane((0, -1, 0), -self.height),
                cylinder_inside((0, 0, 0), (0, 1, 0), self.radius)]
        kinds = np.array([PLANE, PLANE, CYLINDER_INSIDE], dtype=np.int64)
        return kinds, np.array(rows), ["floor", "lid", "wall"]

    def floor_sites(self, radius: float, spacing: float) -> np.ndarray:
        """Hexagonal-lattice sites (x, z) of one layer inside the circle, ordered from -x outwards."""
        rmax = self.radius - radius
        if rmax < 0:
            return np.zeros((0, 2))
        row = spacing * np.sqrt(3.0) / 2.0
        n = int(np.ceil(self.radius / min(spacing, row))) + 2
        pts = []
        for j in range(-n, n + 1):
            z = j * row
            off = 0.5 * spacing * (j % 2)
            for i in range(-n, n + 1):
                x = i * spacing + off
                if x * x + z * z <= rmax * rmax + 1e-15:
                    pts.append((x, z))
        pts = np.array(pts) if pts else np.zeros((0, 2))
        order = np.lexsort((np.abs(pts[:, 1]), pts[:, 0]))
        return pts[order]

    def max_particles(self, radius: float) -> int:
        """Spheres that fit on the floor in one hexagonal layer (a geometric count; the paper
        quotes N_p,max = 48 for R = 39 mm, r = 5 mm, which is what eq. (6) should use)."""
        return int(len(self.floor_sites(radius, 2 * radius)))

    def mesh(self, segments: int = 48):
        """(vertices, quads) of the inner surface (side wall as ``segments`` quads), for VTK and plots."""
        th = np.linspace(0, 2 * np.pi, segments, endpoint=False)
        ring = np.column_stack([self.radius * np.cos(th), np.zeros(segments), self.radius * np.sin(th)])
        top = ring.copy()
        top[:, 1] = self.height
        v = np.vstack([ring, top])
        quads = np.array([[i, (i + 1) % segments, segments + (i + 1) % segments, segments + i] for i in range(segments)])
        return v, quads
