"""The 25 kg / 3 Hz frame the structure-design tests share (examples/frame_3hz.toml's mode), and the
tiny structure under a load in time the designs against a load share (1 kg at 3 Hz, one sphere in a
60 mm box, a resonant shake: :func:`tiny_load_case`)."""

import math
from pathlib import Path

import numpy as np

from pdamper.structure import CoupledStructure

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
FRAME = EXAMPLES / "frame_3hz.toml"
M, F_N, ZETA, F0 = 25.0, 3.0, 0.003, 1.5
K = M * (2 * math.pi * F_N) ** 2
#: one 5 mm steel sphere [kg]
SPHERE = 7900 * 4 / 3 * math.pi * 0.005**3


def frame():
    """The frame's mode as a single-mode structure (a nominal start: the design does not use it)."""
    return CoupledStructure(mass=M, stiffness=K, damping_ratio=ZETA, displacement=0.001)


def tiny_load_case(folder, acceleration, *, dt=0.005, length="60mm", name="tiny.toml"):
    """Write ``folder/name``: 1 kg at 3 Hz (0.5 % damping) carrying one sphere in a ``length`` box,
    shaken at its supports by the ground ``acceleration`` [m/s^2] sampled every ``dt`` [s]."""
    t = np.arange(len(acceleration)) * dt
    text = f"""[container]
length = "{length}"
[particles]
count = 1
[initial]
settle_time = "50ms"
[structure]
mass = "1kg"
natural_frequency = "3Hz"
damping_ratio = 0.005
[load]
kind = "ground_acceleration"
time = {[round(float(x), 6) for x in t]}
acceleration = {[round(float(x), 8) for x in acceleration]}
"""
    (folder / name).write_text(text)
    return folder / name


def resonant_shake(duration=2.0, strong=1.5, amplitude=0.3, dt=0.005):
    """A 3 Hz sine of ``amplitude`` [m/s^2] for the first ``strong`` s of ``duration``, every ``dt``."""
    t = np.arange(0.0, duration + dt / 2, dt)
    return amplitude * np.sin(2 * math.pi * 3.0 * t) * (t < strong)
