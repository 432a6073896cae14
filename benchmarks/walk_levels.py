"""How deep is the GPU's implicit pair walk? Its rows and levels, counted on the CPU engine.

    python benchmarks/walk_levels.py [--cases 41 1 0 ...] [--cycles 20] [--fps 100] [--json out.json]

Gear's implicit friction pass corrects the touching pairs one row after another, in the CPU's order
(sphere ``i`` ascending, then its partners ``j > i`` ascending): a Gauss-Seidel sweep, in which a row
reads the increments the rows before it wrote. The GPU kernel walks the rows level by level
(:func:`pdamper.kernels.gpu.gear._implicit_pairs_by_level`): a row's level is one more than the last
level of either of its spheres, and the rows of one level run together. So the walk takes as many
rounds as the deepest level, not as many as there are rows; on the H200 (docs/performance.md) the
walk's rows cost 1,734 cycles each, one after another, and set each case's cost.

This counts, without a GPU, what the level walk has to do: each case of fig4 (seed 0) runs on the
CPU engine with its trajectory recorded at ``--fps`` frames a second; in every frame the touching
pairs (centres closer than the two radii: what the kernel's rows hold, all of fig4's pairs having
friction) in the kernel's order give the rows, and the rule above their levels. Per case: the mean
rows and levels a frame, their ratio, and the Gear steps of the run. The frames are the bed as the
recording sees it, not every step: a mean over the run, not the step-by-step count the GPU's
``profile`` part measures (which also says the rows a step: the two can be held side by side).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
import warnings
from pathlib import Path

import numpy as np

BENCH = Path(__file__).resolve().parent


def _gpu():
    """``benchmarks/gpu.py``, whose fig4 cases this counts (imported when a count runs)."""
    sys.path.insert(0, str(BENCH))
    import gpu

    return gpu


def fig4_cases():
    """fig4's 80 ``(setting, stroke, case)`` at seed 0, as ``benchmarks/gpu.py`` runs them."""
    return _gpu().fig4_cases(False)


def levels_of(pairs):
    """The level of each row ``(i, j)`` of ``pairs``, in their order: one more than the last level of
    either sphere (the rule of :func:`pdamper.kernels.gpu.gear._implicit_pairs_by_level`)."""
    last = {}
    out = []
    for i, j in pairs:
        level = max(last.get(int(i), 0), last.get(int(j), 0)) + 1
        last[int(i)] = last[int(j)] = level
        out.append(level)
    return out


def rows_and_levels(position, radius):
    """The touching pairs of one frame in the kernel's order, and the deepest level of the walk.
    ``position`` (N, 3) [m], ``radius`` (N,) [m]; returns ``(rows, levels)``."""
    d = np.linalg.norm(position[:, None, :] - position[None, :, :], axis=2)
    i, j = np.nonzero(np.triu(d < radius[:, None] + radius[None, :], k=1))  # i ascending, then j
    levels = levels_of(zip(i, j))
    return len(levels), max(levels, default=0)


def count(case, cycles, fps):
    """The mean rows and levels a frame of ``case`` run for ``cycles`` with ``fps`` frames a second."""
    from pdamper.run import run_case

    recording = dataclasses.replace(case.recording, trajectory_fps=min(fps, case.recording.sample_rate))
    case = dataclasses.replace(case, cycles=cycles, drop_cycles=0, recording=recording)
    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = run_case(case)
    tr = result.trajectory
    counted = [rows_and_levels(p, tr["radius"]) for p in tr["position"]]
    rows = np.array([r for r, _ in counted], dtype=float)
    levels = np.array([v for _, v in counted], dtype=float)
    return {"frames": len(counted), "steps": int(result.steps), "rows_mean": float(rows.mean()),
            "rows_max": int(rows.max()), "levels_mean": float(levels.mean()), "levels_max": int(levels.max()),
            "levels_per_row": float(levels.sum() / max(rows.sum(), 1.0)), "wall_s": time.perf_counter() - t}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", type=int, nargs="*", help="indices into fig4's 80 cases (36 spheres 0-39, 44 spheres "
                    "40-79, strokes ascending); default all")
    ap.add_argument("--cycles", type=float, default=20.0, help="cycles of each run (fig4's: 20)")
    ap.add_argument("--fps", type=float, default=100.0, help="frames a second of the recorded trajectory")
    ap.add_argument("--json", type=Path, help="also write every case's counts here")
    args = ap.parse_args(argv)
    if args.cycles <= 0 or args.fps <= 0:
        ap.error("--cycles and --fps must be positive")
    cases = fig4_cases()
    picked = range(len(cases)) if not args.cases else args.cases
    wrong = _gpu().beyond_fig4(picked, len(cases))
    if wrong:
        ap.error(f"--cases {wrong}")
    out = []
    for k in picked:
        label, stroke, case = cases[k]
        row = {"case": k, "setting": label, "stroke_m": stroke, **count(case, args.cycles, args.fps)}
        out.append(row)
        print(f"walk_levels: case {k:2d} ({label}, {1e3 * stroke:6.3f} mm): {row['steps']:8d} steps, "
              f"{row['rows_mean']:5.1f} rows a frame (max {row['rows_max']}), {row['levels_mean']:5.1f} levels "
              f"(max {row['levels_max']}), {row['levels_per_row']:.2f} levels a row ({row['wall_s']:.1f} s)", flush=True)
        if args.json:
            args.json.write_text(json.dumps({"cycles": args.cycles, "fps": args.fps, "cases": out}, indent=1))
    rows = sum(r["rows_mean"] for r in out)
    levels = sum(r["levels_mean"] for r in out)
    print(f"walk_levels: {len(out)} cases: {levels / max(rows, 1e-300):.2f} levels a row over all "
          f"(the level walk's depth against the one-row-at-a-time walk)", flush=True)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
