"""Cost of one Gear force evaluation (accepted or rejected step), kernel only, in whole runs of the
36-sphere cuboid at a small and a large stroke; optionally against another checkout in the same
run, the two alternated.

    python benchmarks/gear_step.py [--strokes 3 30] [--repeats 3] [--baseline OLD_CHECKOUT/src]

Each measurement is a fresh process (its kernels loaded from its own cache, warmed by a first
process that is not counted): the bed settles, is driven for 1 s, then 2 s more are timed
(``Simulation.advance``; the time per force evaluation is the wall time over accepted + rejected
steps). With ``--baseline`` the same is run with ``PYTHONPATH`` at the other checkout's sources
(its own kernel cache), A and B in turn, and the ratio of the medians is printed. The step counts
of the two are printed too: a change that keeps the arithmetic takes the same steps.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

_CHILD = r"""
import json, sys, time
from pdamper.config import load_case
from pdamper.schema import replace
from pdamper.simulation import Simulation
out = {}
for x in json.loads(sys.argv[1]):
    case = replace(load_case(sys.argv[2]), {"drive.stroke": x * 1e-3, "run.cycles": 6})
    sim = Simulation(case)
    sim.settle()
    sim.advance(1000)
    st = sim.stepper
    s0, r0 = st.steps, st.rejected
    t = time.perf_counter()
    sim.advance(2000)
    dt = time.perf_counter() - t
    n = st.steps - s0 + st.rejected - r0
    out[str(x)] = {"us_per_eval": dt / n * 1e6, "evals": n}
print(json.dumps(out))
"""


def measure(src: str | None, strokes, cache: str) -> dict:
    env = {**os.environ, "PDAMPER_CACHE_DIR": cache}
    env.pop("NUMBA_CACHE_DIR", None)
    if src:
        env["PYTHONPATH"] = src
    p = subprocess.run([sys.executable, "-c", _CHILD, json.dumps(strokes), str(ROOT / "examples" / "cuboid_36.toml")],
                       env=env, capture_output=True, text=True, check=True)
    return json.loads(p.stdout.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--strokes", type=float, nargs="+", default=[3.0, 30.0], help="strokes [mm]")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--baseline", help="the src/ directory of another checkout to compare with")
    args = ap.parse_args(argv)
    trees = {"this": str(ROOT / "src")}
    if args.baseline:
        trees["baseline"] = args.baseline
    with tempfile.TemporaryDirectory() as tmp:
        caches = {k: str(Path(tmp) / k) for k in trees}
        for k, src in trees.items():
            measure(src, args.strokes, caches[k])  # compile, not counted
        runs = {k: [] for k in trees}
        for _ in range(args.repeats):
            for k, src in trees.items():
                runs[k].append(measure(src, args.strokes, caches[k]))
    for x in args.strokes:
        key = str(x)
        line = [f"X = {x:g} mm:"]
        med = {}
        for k in trees:
            vals = [r[key]["us_per_eval"] for r in runs[k]]
            med[k] = statistics.median(vals)
            line.append(f"{k} {med[k]:.3f} us per evaluation (runs {', '.join(f'{v:.3f}' for v in vals)}; "
                        f"{runs[k][0][key]['evals']} evaluations)")
        if "baseline" in med:
            line.append(f"ratio this/baseline {med['this'] / med['baseline']:.3f}")
        print(" ".join(line))


if __name__ == "__main__":
    main()
