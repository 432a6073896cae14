"""How well a study's cases fill the workers: the idle share at the end under two orders.

    python benchmarks/schedule.py STUDY_DIR [STUDY_DIR ...] [--workers 2]

Reads the wall time each finished case took (``wall_time_s`` of the case records of a
``pdamper study`` / ``pdamper sweep`` output directory) and replays the study on ``--workers``
workers with list scheduling (the next case goes to the first free worker), once in the order of
pdamper before the cost ranking (largest stroke first, ties in grid order) and once in the order of
:func:`pdamper.studies.cost.ranked` (the a-priori cost model). The idle share at the end is
sum over workers of (end of the study - end of that worker's last case) / (workers x end of the
study). A replay, not a run: deterministic for the recorded times (a real run adds the scheduler's
latency and the machine's noise; docs/performance.md has both).
"""

from __future__ import annotations

import argparse
import heapq
from pathlib import Path


def replay(durations, workers: int) -> dict:
    """Makespan and idle share at the end of list scheduling ``durations`` in the given order."""
    free = [0.0] * workers
    for d in durations:
        t = heapq.heappop(free)
        heapq.heappush(free, t + d)
    ends = sorted(free)
    span = ends[-1]
    return {"makespan_s": span, "idle_share": sum(span - e for e in ends) / (workers * span) if span else 0.0,
            "bound_s": max(sum(durations) / workers, max(durations, default=0.0))}


def cases_of(path: Path):
    """``[(key, point, seed, case, wall_time_s)]`` of every finished case under ``path`` (a study
    directory of setting stores, or one store), in the order the study builds them."""
    from pdamper.studies.store import ResultStore
    from pdamper.studies.sweep import SweepSpec

    stores = [path] if (path / "store.json").exists() else sorted(p.parent for p in path.glob("*/store.json"))
    out = []
    for sp in stores:
        store = ResultStore.open(sp)
        recs = {r["key"]: r for r in store.records() if "wall_time_s" in r}
        base = store.case()
        from pdamper.studies.sweep import Axis

        axes = [Axis(key=a["key"], values=tuple(a["values"]), spacing=a.get("spacing", "list")) for a in store.axes]
        spec = SweepSpec(base=base, axes=axes, seeds=tuple(store.meta.get("seeds", [0])))
        for k, p, s in spec.items():
            if k in recs:
                out.append((f"{sp.name}--{k}", p, s, spec.case(p, s), float(recs[k]["wall_time_s"])))
    return out


def main(argv=None):
    from pdamper.studies.cost import ranked

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="+", type=Path)
    ap.add_argument("--workers", type=int, default=2)
    args = ap.parse_args(argv)
    rows = []
    for path in args.paths:
        cases = cases_of(path)
        wall = {c[0]: c[4] for c in cases}
        stroke_first = sorted(cases, key=lambda c: -float(c[1].get("drive.stroke", 0.0)))
        by_cost = ranked([c[:4] for c in cases])
        old = replay([wall[c[0]] for c in stroke_first], args.workers)
        new = replay([wall[c[0]] for c in by_cost], args.workers)
        rows.append({"study": str(path), "cases": len(cases), "cpu_s": sum(wall.values()), "stroke_first": old,
                     "by_cost": new})
        print(f"{path}: {len(cases)} cases, {sum(wall.values()):.1f} s of case time, {args.workers} workers; "
              f"lower bound {old['bound_s']:.1f} s")
        for name, r in (("largest stroke first", old), ("by expected cost", new)):
            print(f"  {name:22s} makespan {r['makespan_s']:7.1f} s, idle at the end {100 * r['idle_share']:5.1f} %")
    return rows


if __name__ == "__main__":
    main()
