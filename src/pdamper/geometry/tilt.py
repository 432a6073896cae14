r"""Container tilt: the rotation from the container frame to the lab frame.

The container frame has x along the container's length (the paper's longitudinal axis),
y along its height (against gravity when untilted) and z across its width. A tilt is three
small angles about the container's own x, y and z axes, applied **in the order x, then y,
then z** (intrinsic rotations), i.e. ``Q = Rx(a_x) @ Ry(a_y) @ Rz(a_z)`` maps container
coordinates to lab coordinates. For the paper's angles (0.1 deg, 3 deg) the order changes
results by O(a^2) only.

A tilt about z (pitch) lowers the -x or +x end wall, about x (roll) a side wall, about y
(yaw) turns the drive direction against the container's length (paper Sect. 6.2).

pdamper integrates the particles in the container frame, so the tilt enters only as the
direction of gravity and of the drive seen from the container: ``g_c = Q^T g_lab``,
``d_c = Q^T d_lab``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["rotation", "container_vectors"]


def _rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rotation(tilt) -> np.ndarray:
    """Q (3x3) from container to lab frame for tilt angles ``(a_x, a_y, a_z)`` [rad]."""
    ax, ay, az = (float(a) for a in tilt)
    return _rx(ax) @ _ry(ay) @ _rz(az)


def container_vectors(tilt, gravity: float, drive_direction):
    """Gravity [m/s^2] and the unit drive direction, both in the container frame.

    ``drive_direction`` is the drive's unit direction in the lab frame (y up), or a number: an
    angle [rad] in the lab's horizontal plane from the lab x axis towards the lab z axis;
    gravity is ``-gravity`` along lab y.
    """
    q = rotation(tilt)
    g_lab = np.array([0.0, -gravity, 0.0])
    if np.ndim(drive_direction) == 0:
        a = float(drive_direction)
        d_lab = np.array([np.cos(a), 0.0, np.sin(a)])
    else:
        d_lab = np.asarray(drive_direction, dtype=float)
    return q.T @ g_lab, q.T @ d_lab
