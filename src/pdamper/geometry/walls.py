"""Wall primitives, defined once as compiled signed-distance functions.

A container is a list of primitives, each a row of ``wall_kind`` (int) and ``wall_data``
(7 floats), in the container frame (x along the length, y up against gravity, z across):

- ``PLANE`` (0): ``data = (nx, ny, nz, offset, 0, 0, 0)``; ``n`` is the unit normal pointing
  *into* the container, the signed distance of a point p is ``n.p - offset`` (> 0 inside).
- ``CYLINDER_INSIDE`` (1): ``data = (cx, cy, cz, ax, ay, az, R)``: a point on the axis, the
  unit axis and the radius; signed distance ``R - |p_perp|`` (> 0 inside), normal towards the axis.

Every wall force (and the initial-state checks, and the VTK mesh) uses :func:`wall_distance`.
"""

from __future__ import annotations

import math

import numpy as np

from ..jit import njit

__all__ = ["PLANE", "CYLINDER_INSIDE", "wall_distance", "wall_distances", "plane", "cylinder_inside"]

PLANE = 0
CYLINDER_INSIDE = 1


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
