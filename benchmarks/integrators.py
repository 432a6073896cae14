"""Gear vs velocity Verlet on the paper's runs, at equal accuracy.

Usage: python benchmarks/integrators.py [--quick] [--strokes 13 30] [--seeds 0 1 2] [--settings verlet15 gear10]

For each integrator setting this runs the paper's 36-sphere cuboid (examples/cuboid_36.toml)
at two strokes and several seeds, and reports: wall time, steps, us/step, the energy-ledger
balance error (how well the integration conserves energy: work in = change of mechanical
energy + dissipation), the mean and spread of eta*, and the restitution error of a single
sphere-wall impact at 0.5 m/s. Accuracy is compared through the balance error and the
single-impact error (eta* of one seed is chaotic in the step size; its seed mean is what a
user sees). Prints a Markdown table; paste it into docs/integrators.md.
"""

from __future__ import annotations

import argparse
import dataclasses
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

from pdamper.config import load_case  # noqa: E402
from pdamper.schema import replace  # noqa: E402
from pdamper.run import run_case  # noqa: E402
from pdamper.simulation import Simulation  # noqa: E402


def impact_error(numerics):
    from dem_fixtures import R, still_case

    v, eps = 0.5, 0.9
    case = still_case([[-0.1 + R + 1e-6, 0.05, 0.0]], [[-v, 0.0, 0.0]], duration=2e-3, eps=eps)
    case = dataclasses.replace(case, numerics=dataclasses.replace(numerics, max_impact_speed=None))
    sim = Simulation(case)
    sim.run()
    return abs(sim.bodies.velocity[0, 0] / v - eps) / eps


SETTINGS = {
    "verlet15": ("verlet, 15 steps/contact", dict(integrator="verlet", steps_per_contact=15)),
    "verlet30": ("verlet, 30 steps/contact", dict(integrator="verlet", steps_per_contact=30)),
    "gear9": ("gear, tol 1e-9 m (default)", dict(integrator="gear", gear_tolerance=1e-9)),
    "gear10": ("gear, tol 1e-10 m", dict(integrator="gear", gear_tolerance=1e-10)),
    "gear11": ("gear, tol 1e-11 m", dict(integrator="gear", gear_tolerance=1e-11)),
}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="4 cycles, 1 seed, one stroke")
    ap.add_argument("--strokes", nargs="+", type=float, default=[13.0, 30.0], help="strokes [mm]")
    ap.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2])
    ap.add_argument("--settings", nargs="+", choices=sorted(SETTINGS), default=list(SETTINGS))
    args = ap.parse_args()
    base = load_case(ROOT / "examples" / "cuboid_36.toml")
    strokes = [0.013] if args.quick else [x * 1e-3 for x in args.strokes]
    seeds = [0] if args.quick else args.seeds
    cycles = 4 if args.quick else 20
    # compile everything once, outside the timings
    for kw in ({"integrator": "verlet"}, {"integrator": "gear"}):
        c = dataclasses.replace(base, cycles=2.5, drop_cycles=1,
                                numerics=dataclasses.replace(base.numerics, **kw))
        run_case(c)
    print(f"# Gear vs Verlet: cuboid_36, {cycles} cycles at 2 Hz, seeds {seeds}\n")
    print("| setting | stroke [mm] | wall [s] | steps | us/step | balance error | eta* mean | eta* spread | impact COR error |")
    print("|---|---|---|---|---|---|---|---|---|")
    for key in args.settings:
        name, kw = SETTINGS[key]
        num = dataclasses.replace(base.numerics, **kw)
        ierr = impact_error(num)
        for x in strokes:
            walls, steps, bal, etas = [], [], [], []
            for seed in seeds:
                case = dataclasses.replace(replace(base, {"drive.stroke": x}), cycles=cycles, numerics=num,
                                           initial=dataclasses.replace(base.initial, seed=seed))
                t = time.perf_counter()
                res = run_case(case)
                walls.append(time.perf_counter() - t)
                steps.append(res.steps)
                bal.append(res.energy.balance_error())
                etas.append(res.eta_star)
            w = statistics.mean(walls)
            st = statistics.mean(steps)
            spread = (max(etas) - min(etas)) / 2 if len(etas) > 1 else float("nan")
            print(f"| {name} | {x * 1e3:g} | {w:.2f} | {st:.0f} | {1e6 * w / st:.2f} | {max(bal):.2e} | "
                  f"{statistics.mean(etas):.3f} | ±{spread:.3f} | {ierr:.1e} |", flush=True)


if __name__ == "__main__":
    main()
