"""How wide is the CPU engine's spread of eta* at a fig4 stroke? Seeds, and round-off.

    python benchmarks/fig4_spread.py --out spread.csv [--seeds 10] [--nudges 6] \\
        [--gpu-json gpu.json] [--stroke "N_p = 36" 39.48 ...]

The GPU engine's fig4 (``benchmarks/gpu.py``) is compared with the CPU engine's seeds 0-2
(``benchmarks/data/fig4_cpu_reference.csv``); a stroke where the GPU's eta* falls outside that range
is either a GPU fault or a bed whose outcome three seeds do not span. This script tells the two apart
on the CPU engine alone, at the strokes named (``--stroke``; with ``--gpu-json``, every stroke where
its fig4 lies beyond three standard deviations of the three seeds; ``--all``: all 80):

* ``seed``: seeds 0 .. ``--seeds``-1 (other initial beds);
* ``nudge``: seed 0 (the bed the GPU ran) with Gear's tolerance changed by k parts in 10^12,
  k = 1 .. ``--nudges``: a change of the step sizes at round-off level, as the GPU's arithmetic
  (fused multiply-adds, its own ``pow``) changes them. If seed 0's outcome moves by the GPU's
  difference under such a nudge, the difference is the bed's sensitivity, not the GPU's physics.

Every case runs on the CPU (all cores, Dask, as ``pdamper study``), each row written to ``--out`` as
it finishes (an interrupted run keeps what finished; a rerun skips the rows already there).
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys
from pathlib import Path

BENCH = Path(__file__).resolve().parent
sys.path.insert(0, str(BENCH))

from gpu import append_runs, fig4_cases, read_reference  # noqa: E402

NUDGE = 1e-12


def outliers(gpu_json):
    """``[(setting, stroke)]`` of ``gpu_json``'s fig4 beyond 3 standard deviations of the CPU's seeds."""
    rows = json.loads(Path(gpu_json).read_text())["parts"]["fig4"]["strokes"]
    return [(r["setting"], r["stroke_m"]) for r in rows if "z" in r and abs(r["z"]) > 3.0]


def gpu_values(gpu_json):
    if not gpu_json:
        return {}
    rows = json.loads(Path(gpu_json).read_text())["parts"]["fig4"]["strokes"]
    return {(r["setting"], round(r["stroke_m"], 9)): r["eta_gpu"] for r in rows}


def all_strokes():
    """Every ``(setting, stroke)`` of fig4."""
    return [(label, x) for label, x, _ in fig4_cases(False)]


def fig4_case(setting, stroke):
    """fig4's case of ``setting`` at the grid stroke nearest ``stroke`` [m] (seed 0): ``(stroke, case)``."""
    from pdamper.errors import InputError

    cases = fig4_cases(False)
    x = min({c[1] for c in cases}, key=lambda g: abs(g - stroke))
    if abs(x - stroke) > 0.02 * stroke:
        raise InputError(f"--stroke {stroke * 1e3:g} mm is not on fig4's grid (nearest {x * 1e3:.4g} mm)")
    for label, xc, case in cases:
        if label == setting and xc == x:
            return x, case
    raise InputError(f"fig4 has no setting {setting!r}; it has {sorted({c[0] for c in cases})}")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", required=True, help="CSV, appended as cases finish")
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--nudges", type=int, default=6)
    ap.add_argument("--gpu-json", help="benchmarks/gpu.py's output: its fig4 outliers are the strokes run")
    ap.add_argument("--stroke", nargs=2, action="append", metavar=("SETTING", "MM"), default=[])
    ap.add_argument("--all", action="store_true", help="every stroke of both settings (80)")
    args = ap.parse_args(argv)

    from pdamper.schema import replace

    wanted = [(s, float(mm) * 1e-3) for s, mm in args.stroke]
    if args.gpu_json and not args.all:
        wanted += outliers(args.gpu_json)
    if args.all:
        wanted += all_strokes()
    if not wanted:
        ap.error("name strokes with --stroke or give --gpu-json")
    out = Path(args.out)
    done = set()
    if out.exists():
        with out.open() as f:
            done = {(r["setting"], round(float(r["stroke_m"]), 9), r["kind"], int(r["k"])) for r in csv.DictReader(f)}
    items = []
    seen = set()
    for setting, stroke in wanted:
        x, case = fig4_case(setting, stroke)
        if (setting, x) in seen:
            continue
        seen.add((setting, x))
        tol = case.numerics.gear_tolerance
        runs = [("seed", s, {"initial.seed": s}) for s in range(args.seeds)]
        runs += [("nudge", k, {"initial.seed": 0, "numerics.gear_tolerance": tol * (1.0 + k * NUDGE)})
                 for k in range(1, args.nudges + 1)]
        for kind, k, change in runs:
            if (setting, round(x, 9), kind, k) in done:
                continue
            items.append(((setting, x, kind, k), x, 0, replace(case, change)))
    append_runs(out, ["setting", "stroke_m", "kind", "k", "eta_star", "steps", "failed"], items,
                lambda key, r: [key[0], repr(key[1]), key[2], key[3], r.get("eta_star", math.nan),
                                r.get("steps", ""), r.get("failed", "")])
    summarise(out, gpu_values(args.gpu_json))


def summarise(path, gpu):
    """Per stroke: the seeds' and the nudges' eta* (range, mean, std) and the GPU's value."""
    import numpy as np

    ref = read_reference()
    groups = {}
    with Path(path).open() as f:
        for r in csv.DictReader(f):
            key = (r["setting"], round(float(r["stroke_m"]), 9))
            groups.setdefault(key, {"seed": [], "nudge": []})[r["kind"]].append(float(r["eta_star"]))
    print(f"{'setting':10s} {'X [mm]':>7s} {'GPU':>6s} {'seeds 0-2':>13s} {'seeds (n)':>20s} {'nudged seed 0 (n)':>22s}")
    def spread(v):
        v = np.array(v)
        v = v[np.isfinite(v)]
        if len(v) < 2:
            return f"{'-':>20s}" if not len(v) else f"{v[0]:.3f} (1)".rjust(20)
        return f"{v.min():.3f}-{v.max():.3f} sd {v.std(ddof=1):.3f} ({len(v)})".rjust(20)

    for (setting, x), g in sorted(groups.items()):
        r = ref.get((setting, x))
        r3 = f"{float(r['eta_min']):.3f}-{float(r['eta_max']):.3f}" if r else "-"
        eg = gpu.get((setting, x), math.nan)
        print(f"{setting:10s} {x * 1e3:7.3g} {eg:6.3f} {r3:>13s} {spread(g['seed'])}  {spread(g['nudge'])}")


if __name__ == "__main__":
    main()
