"""Cuboid container: six planar walls (paper: inner 120 x 40.4 x 40 mm).

Container frame: x in [-L/2, L/2] along the length (the drive direction of the paper),
y in [0, H] from the floor up, z in [-W/2, W/2] across.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..schema import convert_fields, param
from .shape import GAP, ShapeBase, register_shape
from .walls import PLANE, plane

__all__ = ["Cuboid"]


@register_shape
@dataclass(frozen=True, kw_only=True)
class Cuboid(ShapeBase):
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
    length_keys = ("length",)

    def __post_init__(self):
        convert_fields(self, "container")
        for name in ("length", "width", "height"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and v > 0 and np.isfinite(v)):
                raise InputError(f"container.{name} = {shown(v)} m; must be a positive length (paper: 120 x 40.4 x 40 mm)")

    @property
    def drive_length(self) -> float:
        """L [m] used in the clearance, eq. (6)."""
        return self.length

    def row_capacity(self, radius: float) -> int:
        """Spheres side by side across the width: floor(w / 2r)."""
        return int(math.floor(self.width / (2 * radius) + 1e-9))

    def walls(self):
        """(kinds, data, names) of the six walls: x_min, x_max, floor, lid, z_min, z_max."""
        L, W, H = self.length, self.width, self.height
        rows = [plane((1, 0, 0), -L / 2), plane((-1, 0, 0), -L / 2),
                plane((0, 1, 0), 0.0), plane((0, -1, 0), -H),
                plane((0, 0, 1), -W / 2), plane((0, 0, -1), -W / 2)]
        names = ["x_min", "x_max", "floor", "lid", "z_min", "z_max"]
        return np.full(6, PLANE, dtype=np.int64), np.array(rows), names

    def bounding_box(self):
        """(lo, hi) corners [m] of the inside."""
        return (np.array([-self.length / 2, 0.0, -self.width / 2]),
                np.array([self.length / 2, self.height, self.width / 2]))

    def length_along(self, direction) -> float:
        """The chord [m] through the floor's centre along the horizontal part of ``direction``."""
        dx, dz = abs(float(direction[0])), abs(float(direction[2]))
        n = math.hypot(dx, dz)
        if n == 0:
            return 0.0
        return min(self.length * n / dx if dx > 0 else math.inf, self.width * n / dz if dz > 0 else math.inf)

    def describe(self) -> str:
        return f"cuboid {self.length * 1e3:g} x {self.width * 1e3:g} x {self.height * 1e3:g} mm"

    def layer_sites(self, radius: float, jitter: float, n_needed: int | None = None):
        """One layer of the initial block: rows across the width, columns from the -x wall, each
        site with jitter room (jx, jz) where the container leaves some (the paper's 48 spheres of
        r = 5 mm fill 120 mm x 40.4 mm with no room to spare)."""
        r = radius
        # rows across the width as columns along the length: as many as fit side by side
        # (row_capacity; a width of exactly k diameters holds k), with 1 um gaps and jitter room
        # only where the width leaves some
        nz = self.row_capacity(r)
        if nz < 1:
            return np.zeros((0, 2)), 0.0, 0.0
        spare_z = self.width - 2 * r * nz
        gz = max(0.0, min(GAP, spare_z / (nz + 1)))
        jz = max(0.0, min(jitter, (spare_z - gz * (nz + 1)) / (2 * nz)))
        sz = 2 * r + gz + 2 * jz
        # columns along the length: as many as needed (all that fit without overlap when not
        # told), with 1 um gaps and jitter room only where the length leaves some
        nx_full = int(np.floor(self.length / (2 * r) + 1e-9))
        if nx_full < 1:
            return np.zeros((0, 2)), 0.0, 0.0
        nx_need = min(nx_full, int(np.ceil(n_needed / nz))) if n_needed else nx_full
        spare = self.length - 2 * r * nx_need
        gx = max(0.0, min(GAP, spare / (nx_need + 1)))
        jx = max(0.0, min(jitter, (spare - gx * (nx_need + 1)) / (2 * nx_need)))
        sx = 2 * r + 2 * jx + gx
        nx = min(nx_full, int(np.floor((self.length - 2 * r - 2 * jx - 2 * gx) / sx + 1e-9)) + 1)
        xs = -self.length / 2 + r + jx + gx + sx * np.arange(nx)
        zs = (np.arange(nz) - (nz - 1) / 2) * sz
        X, Z = np.meshgrid(xs, zs, indexing="ij")
        return np.column_stack([X.ravel(), Z.ravel()]), jx, jz

    def jitter(self, rng, m: int, jx: float, jz: float):
        """(m, 2) offsets uniform in the rectangle [-jx, jx] x [-jz, jz]."""
        return np.column_stack([rng.uniform(-jx, jx, m), rng.uniform(-jz, jz, m)])

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
