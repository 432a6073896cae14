"""Cost of one time step of a damper system (single core, kernel only).

Usage: python benchmarks/step_cost.py [--dt 1e-6] [--steps 200000]

Drives examples/cuboid_36.toml at X = 14 mm with velocity Verlet at a fixed step (default
1 us, the step LIGGGHTS is compared at) until the bed is in the rolling collect-and-collide
state, then times the kernel alone over --steps steps (best of 3) and prints microseconds per
step with the number of contacts at that moment. :func:`measure` does the same for any case
(``benchmarks/run.py`` uses it for every system of its table).
"""

from __future__ import annotations

import argparse
import math
import dataclasses
import time
from pathlib import Path

import numpy as np

from pdamper.config import load_case
from pdamper.schema import replace
from pdamper.simulation import Simulation

ROOT = Path(__file__).resolve().parent.parent


def measure(case, *, dt=1e-6, steps=200_000, warm_cycles=0.2, repeats=3) -> dict:
    """Run ``case`` with Verlet at ``dt`` [s] for ``warm_cycles`` drive cycles (compile, settle,
    set the bed in motion), then time ``steps`` more kernel steps ``repeats`` times; return the
    best microseconds per step and the contacts at the end."""
    case = dataclasses.replace(case, cycles=warm_cycles, drop_cycles=0,
                               numerics=dataclasses.replace(case.numerics, integrator="verlet", time_step=dt))
    sim = Simulation(case)
    sim.run()
    verlet = sim.stepper
    best = float("inf")
    # whole samples from a sample boundary past the run's end (kernel only, nothing recorded)
    interval = verlet.sample_interval
    samples = max(1, round(steps / verlet.sub))
    steps = samples * verlet.sub
    k_start = int(math.ceil((case.duration + 1.0) / interval))
    for _ in range(repeats):
        t = time.perf_counter()
        verlet.advance(sim.samples, k_start * interval, (k_start + samples) * interval, False)
        best = min(best, time.perf_counter() - t)
        k_start += samples
    m = sim.pairs.row[-1]
    return {"us_per_step": best / steps * 1e6, "particles": sim.n, "dt": verlet.dt, "search": sim.engine.search_name,
            "pairs_listed": int(m), "pairs_touching": int(np.count_nonzero(sim.pairs.approach_speed[:m])),
            "walls_touching": int(np.count_nonzero(sim.walls.approach_speed))}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dt", type=float, default=1e-6, help="time step [s]")
    ap.add_argument("--steps", type=int, default=200000)
    args = ap.parse_args()
    case = replace(load_case(ROOT / "examples" / "cuboid_36.toml"), {"drive.stroke": 0.014})
    r = measure(case, dt=args.dt, steps=args.steps, warm_cycles=2.2)
    print(f"36-sphere cuboid, verlet, dt = {r['dt'] * 1e6:.3g} us: {r['us_per_step']:.3f} us/step "
          f"(pairs in list {r['pairs_listed']}, touching {r['pairs_touching']}, touching walls {r['walls_touching']})")


if __name__ == "__main__":
    main()
