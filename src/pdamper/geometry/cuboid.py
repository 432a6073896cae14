"""Cuboid container: six planar walls (paper: inner 120 x 40.4 x 40 mm).

Container frame: x in [-L/2, L/2] along the length (the drive direction of the paper),
y in [0, H] from the floor up, z in [-W/2, W/2] across.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..schema import convert_fields, param
from .walls import PLANE, plane

__all__ = ["Cuboid"]


@dataclass(frozen=True, kw_only=True)
class Cuboid:
    """Inner dimensions of a cuboid container.

    Parameters
    ----------
    length : float
        L [m] along x (the paper's drive direction).
    width : float
        w [m] along z.
    height : float
        h [m] along y (floor to lid).
    """

    length: float = param(0.120, dimension="length", paper="120 mm")
    width: float = param(0.0404, dimension="length", paper="40.4 mm")
    height: float = param(0.040, dimension="length", paper="40 mm")
    shape: str = param("cuboid", kind="tag")

    def __post_init__(self):
        convert_fields(self, "container")
        for name in ("length", "width", "height"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0 and np.isfinite(v)):
                raise InputError(f"container.{name} = {v!r} m; must be a positive length (paper: 120 x 40.4 x 40 mm)")

    @property
    def drive_length(self) -> float:
        """L [m] used in the clearance, eq. (6)."""
        return self.length

    def walls(self):
        """(kinds, data, names) of the six walls: -x, +x, floor, lid, -z, +z."""
        L, W, H = self.length, self.width, self.height
        rows = [plane((1, 0, 0), -L / 2), plane((-1, 0, 0), -L / 2),
                plane((0, 1, 0), 0.0), plane((0, -1, 0), -H),
                plane((0, 0, 1), -W / 2), plane((0, 0, -1), -W / 2)]
        names = ["-x", "+x", "floor", "lid", "-z", "+z"]
        return np.full(6, PLANE, dtype=np.int64), np.array(rows), names

    def floor_sites(self, radius: float, spacing: float) -> np.ndarray:
        """Square-lattice sites (x, z) of one layer, ordered from the -x wall outwards.

        Columns of ``floor(W/spacing)`` sites across the width, as the paper packs 12 x 4 = 48
        spheres of r = 5 mm on 120 x 40.4 mm.
        """
        nx = int(np.floor((self.length - 2 * radius) / spacing + 1e-9)) + 1
        nz = int(np.floor((self.width - 2 * radius) / spacing + 1e-9)) + 1
        if (self.length < 2 * radius) or (self.width < 2 * radius):
            return np.zeros((0, 2))
        x0 = -self.length / 2 + radius
        zspan = (nz - 1) * spacing
        z0 = -zspan / 2
        xs = x0 + spacing * np.arange(nx)
        zs = z0 + spacing * np.arange(nz)
        X, Z = np.meshgrid(xs, zs, indexing="ij")
        return np.column_stack([X.ravel(), Z.ravel()])

    def max_particles(self, radius: float) -> int:
        """N_p,max [-]: spheres of ``radius`` covering the floor in one square layer."""
        return int(np.floor(self.length / (2 * radius) + 1e-9) * np.floor(self.width / (2 * radius) + 1e-9))

    def clearance_capacity(self, radius: float) -> int:
        """N_p,max [-] of the clearance law, eq. (6): for the cuboid the floor lattice of
        :meth:`max_particles` (48 for 120 x 40.4 mm, r = 5 mm)."""
        return self.max_particles(radius)

    def mesh(self):
        """(vertices (8, 3), quads (6, 4)) of the inner box, for VTK and plots."""
        L, W, H = self.length, self.width, self.height
        v = np.array([[x, y, z] for x in (-L / 2, L / 2) for y in (0.0, H) for z in (-W / 2, W / 2)])
        quads = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
        return v, quads
