"""Where the container is at given times: its displacement, velocity and drive direction.

Used by everything that draws or writes particles in the lab frame (VTK export, motion figures,
the motion-mode classifier).
"""

from __future__ import annotations

import numpy as np

from .tilt import container_vectors

__all__ = ["container_track"]


def container_track(trajectory: dict, case) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(displacement (F, 3) [m], velocity (F, 3) [m/s], drive direction d (3,)) of the container at
    the trajectory's frames, in the container's axes: the recorded ``container_position`` and
    ``container_velocity`` when the trajectory has them (a coupled structure's motion included),
    else x_c d and v_c d of the case's prescribed drive."""
    _, dvec = container_vectors(case.container.tilt, case.gravity, case.drive.lab_direction())
    if "container_position" in trajectory and "container_velocity" in trajectory:
        return (np.asarray(trajectory["container_position"], dtype=float),
                np.asarray(trajectory["container_velocity"], dtype=float), dvec)
    xc, vc, _ = case.drive.motion(np.asarray(trajectory["time"], dtype=float))
    return np.outer(xc, dvec), np.outer(vc, dvec), dvec
