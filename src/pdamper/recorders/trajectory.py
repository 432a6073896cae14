"""Decimated trajectories of all spheres: positions, velocities, spins (kernel channel
``"frames"``), with the container's pose at each frame."""

from __future__ import annotations

import numpy as np

from ..errors import shown

__all__ = ["TrajectoryRecorder"]


class TrajectoryRecorder:
    """Frames of all spheres at ``fps`` frames per second (every ``round(sample_rate / fps)``-th
    sample), as a dict of arrays: ``time`` [s] (frames,), ``position`` [m], ``velocity`` [m/s],
    ``spin`` [rad/s] (frames, N, 3) in the container frame, ``radius`` [m] (N,), and the
    container's pose ``container_position`` [m] and ``container_velocity`` [m/s] (frames, 3):
    ``x_c d`` and ``v_c d``, ``d`` the drive direction in the container frame."""

    channels = frozenset({"frames"})
    every = 0

    def __init__(self, fps: float, *, name: str = "trajectory"):
        if not (fps > 0):
            raise ValueError(f"TrajectoryRecorder: fps = {shown(fps)}; give frames per second > 0")
        self.fps = float(fps)
        self.name = name

    def start(self, run) -> None:
        self.run = run

    def record(self, state) -> None:  # kernel channels only
        pass

    def finalize(self, data) -> dict:
        run = self.run
        traj = data.channels["frames"]
        every = run.frame_every
        t_frames = (np.arange(traj.shape[0]) + 1) * every * run.interval
        if "structure" in data.channels:  # the container rides on the structure: its recorded motion
            at = (np.arange(traj.shape[0]) + 1) * every - 1
            xc, vc = data.channels["structure"][at, 0], data.channels["structure"][at, 1]
        else:
            xc, vc, _ = run.case.drive.motion(t_frames)
        return {"time": t_frames, "position": traj[:, :, 0:3], "velocity": traj[:, :, 3:6], "spin": traj[:, :, 6:9],
                "radius": run.radius.copy(), "container_position": np.outer(xc, run.direction),
                "container_velocity": np.outer(vc, run.direction)}
