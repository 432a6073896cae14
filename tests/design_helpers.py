"""The 25 kg / 3 Hz frame the structure-design tests share (examples/frame_3hz.toml's mode)."""

import math
from pathlib import Path

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
