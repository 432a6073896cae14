"""Direct (all-pairs) vs link-cell construction of the Verlet list, per step of a driven bed.

Usage: python benchmarks/neighbours.py [--quick]

Runs a damper with N spheres (36 in the paper's cuboid; 100 and 200 in longer/wider boxes,
stacked in layers where they do not fit one) with each search method and prints the
microseconds per step and their ratio. The result sets ``pdamper.engine.build.CELLS_THRESHOLD``.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

from pdamper.excitation import HarmonicDrive
from pdamper.geometry import Cuboid
from pdamper.params import Case, Container, InitialState, Numerics, ParticleSet
from pdamper.simulation import Simulation

BOXES = {
    36: Cuboid(length=0.120, width=0.0404, height=0.040),
    100: Cuboid(length=0.250, width=0.0606, height=0.040),
    200: Cuboid(length=0.250, width=0.1010, height=0.040),
    1000: Cuboid(length=0.250, width=0.1010, height=0.100),
}


def run(n, search, cycles):
    case = Case(particles=(ParticleSet(count=n),), container=Container(geometry=BOXES[n]),
                drive=HarmonicDrive(stroke=0.015), cycles=cycles, drop_cycles=0,
                numerics=Numerics(neighbour_search=search),
                initial=InitialState(layers="auto", settle_time=0.05))
    res = Simulation(case).run()
    return res.wall_time_s / res.steps * 1e6


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    cycles = 0.5 if args.quick else 1.0
    sizes = [36, 100, 200] if args.quick else [36, 100, 200, 1000]
    run(36, "direct", 0.1)
    run(36, "cells", 0.1)
    print("| spheres | direct [us/step] | cells [us/step] | direct / cells |")
    print("|---|---|---|---|")
    for n in sizes:
        d = run(n, "direct", cycles)
        c = run(n, "cells", cycles)
        print(f"| {n} | {d:.2f} | {c:.2f} | {d / c:.2f} |", flush=True)


if __name__ == "__main__":
    main()
