"""Cost of one time step of the paper's 36-sphere cuboid (single core).

Usage: python benchmarks/step_cost.py [--dt 1e-6] [--steps 200000]

Drives examples/cuboid_36.toml at X = 14 mm with velocity Verlet at a fixed step (default
1 us, the step LIGGGHTS is quoted at) until the bed is in the rolling collect-and-collide
state, then times the kernel alone over --steps steps (best of 3) and prints microseconds per
step with the number of contacts at that moment.
"""

from __future__ import annotations

import argparse
import dataclasses
import time
from pathlib import Path

import numpy as np

from pdamper.config import load_case
from pdamper.params import with_stroke
from pdamper.simulation import Simulation

ROOT = Path(__file__).resolve().parent.parent


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dt", type=float, default=1e-6, help="time step [s]")
    ap.add_argument("--steps", type=int, default=200000)
    args = ap.parse_args()
    base = load_case(ROOT / "examples" / "cuboid_36.toml")
    case = dataclasses.replace(with_stroke(base, 0.014), cycles=2.2, drop_cycles=2,
                               numerics=dataclasses.replace(base.numerics, integrator="verlet", time_step=args.dt))
    sim = Simulation(case)
    sim.run(analyse=False)  # compiles (or loads the cache) and brings the bed into motion
    sub = int(round(1e-3 / sim.dt))
    sig = np.zeros((10**7, 1))
    eng = np.zeros((10**7, 7))
    traj = np.zeros((1, 1, 9))
    best = float("inf")
    for _ in range(3):
        t = time.perf_counter()
        sim._advance(args.steps, 1.1, 10**8, sub, False, 0, sig, eng, 0, traj)
        best = min(best, time.perf_counter() - t)
    m = sim.row[-1]
    print(f"36-sphere cuboid, verlet, dt = {sim.dt * 1e6:.3g} us: {best / args.steps * 1e6:.3f} us/step "
          f"(pairs in list {m}, touching {np.count_nonzero(sim.pvin[:m])}, wall candidates {sim.nwl[0]}, "
          f"touching walls {np.count_nonzero(sim.wvin)})")


if __name__ == "__main__":
    main()
