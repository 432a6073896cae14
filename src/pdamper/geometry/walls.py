"""Wall primitives, defined once as compiled signed-distance functions.

A container is a list of primitives, each a row of ``wall_kind`` (int) and ``wall_data``
(7 floats), in the container frame (x along the length, y up against gravity, z across):

- ``PLANE`` (0): ``data = (nx, ny, nz, offset, 0, 0, 0)``; ``n`` is the unit normal pointing
  *into* the container, the signed distance of a point p is ``n.p - offset`` (> 0 inside).
- ``CYLINDER_INSIDE`` (1): ``data = (cx, cy, cz, ax, ay, az, R)``: a point on the axis, the
  unit axis and the radius; signed distance ``R - |p_perp|`` (> 0 inside), normal towards the axis.
- ``BOX_OUTSIDE`` (2): ``data = (cx, cy, cz, hx, hy, hz, 0)``: a solid axis-aligned box (an inner
  plate, :mod:`.baffles`) with centre c and half sizes h (``inf`` for a box that runs through
  the container); signed distance from its surface (> 0 outside, where the spheres are), normal
  from the nearest surface point (an edge or corner included) to the point.

Every wall force (and the initial-state checks, and the VTK mesh) uses :func:`wall_distance`.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit

__all__ = ["PLANE", "CYLINDER_INSIDE", "BOX_OUTSIDE", "wall_distance", "wall_distances", "plane", "cylinder_inside",
           "box_outside"]

PLANE = 0
CYLINDER_INSIDE = 1
BOX_OUTSIDE = 2


def plane(normal, offset: float) -> np.ndarray:
    """Row of wall data for a plane with inward normal ``normal`` at ``n.p = offset``."""
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    return np.array([n[0], n[1], n[2], offset, 0.0, 0.0, 0.0])


def cylinder_inside(point, axis, radius: float) -> np.ndarray:
    """Row of wall data for the inside of a cylinder (concave wall)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    c = np.asarray(point, dtype=float)
    return np.array([c[0], c[1], c[2], a[0], a[1], a[2], float(radius)])


def box_outside(centre, half_size) -> np.ndarray:
    """Row of wall data for the outside of a solid axis-aligned box (half sizes may be inf)."""
    c = np.asarray(centre, dtype=float)
    h = np.asarray(half_size, dtype=float)
    return np.array([c[0], c[1], c[2], h[0], h[1], h[2], 0.0])


@njit
def _box_distance(data, w, px, py, pz):
    qx = abs(px - data[w, 0]) - data[w, 3]
    qy = abs(py - data[w, 1]) - data[w, 4]
    qz = abs(pz - data[w, 2]) - data[w, 5]
    sx = 1.0 if px >= data[w, 0] else -1.0
    sy = 1.0 if py >= data[w, 1] else -1.0
    sz = 1.0 if pz >= data[w, 2] else -1.0
    ox = max(qx, 0.0)
    oy = max(qy, 0.0)
    oz = max(qz, 0.0)
    out = math.sqrt(ox * ox + oy * oy + oz * oz)
    if out > 0.0:
        inv = 1.0 / out
        return out, sx * ox * inv, sy * oy * inv, sz * oz * inv
    # inside the box: the nearest face
    if qx >= qy and qx >= qz:
        return qx, sx, 0.0, 0.0
    if qy >= qz:
        return qy, 0.0, sy, 0.0
    return qz, 0.0, 0.0, sz


@njit
def wall_distance(kind, data, w, px, py, pz):
    """Signed distance [m] of point (px, py, pz) from wall ``w`` (row of ``data``; > 0 inside)
    and the unit normal (nx, ny, nz) pointing from the wall into the container at the nearest point.

    Returns ``(s, nx, ny, nz)``.
    """
    if kind == 0:
        nx = data[w, 0]
        ny = data[w, 1]
        nz = data[w, 2]
        return nx * px + ny * py + nz * pz - data[w, 3], nx, ny, nz
    if kind == 2:
        return _box_distance(data, w, px, py, pz)
    # inside of a cylinder
    dx = px - data[w, 0]
    dy = py - data[w, 1]
    dz = pz - data[w, 2]
    ax = data[w, 3]
    ay = data[w, 4]
    az = data[w, 5]
    t = dx * ax + dy * ay + dz * az
    qx = dx - t * ax
    qy = dy - t * ay
    qz = dz - t * az
    rho = math.sqrt(qx * qx + qy * qy + qz * qz)
    # (within rounding of the axis the radial direction is noise: take the on-axis branch)
    if rho > 1e-9 * data[w, 6]:
        inv = 1.0 / rho
        return data[w, 6] - rho, -qx * inv, -qy * inv, -qz * inv
    # on the axis: any direction perpendicular to it will do
    if abs(ax) < 0.9:
        nx, ny, nz = 1.0 - ax * ax, -ax * ay, -ax * az
    else:
        nx, ny, nz = -ay * ax, 1.0 - ay * ay, -ay * az
    nrm = math.sqrt(nx * nx + ny * ny + nz * nz)
    return data[w, 6], nx / nrm, ny / nrm, nz / nrm


@njit
def wall_distances(kinds, data, points):
    """Signed distances (n_points, n_walls) and normals (n_points, n_walls, 3) for many points."""
    n = points.shape[0]
    nw = kinds.shape[0]
    s = np.empty((n, nw))
    nrm = np.empty((n, nw, 3))
    for i in range(n):
        for w in range(nw):
            d, nx, ny, nz = wall_distance(kinds[w], data, w, points[i, 0], points[i, 1], points[i, 2])
            s[i, w] = d
            nrm[i, w, 0] = nx
            nrm[i, w, 1] = ny
            nrm[i, w, 2] = nz
    return s, nrm
