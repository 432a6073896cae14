"""pdamper's performance benchmark, side by side with LIGGGHTS, in one run.

Usage: python benchmarks/run.py [--quick] [--no-liggghts] [--only PART ...] [--paper-every K]
       [--until-steady TOL] [--report docs/performance.md] [--json FILE]

Measures on this machine, in this one invocation:

1. **Step cost** (velocity Verlet, fixed dt = 1 us, kernel only, best of 3, bed in motion):
   the paper's 36- and 44-sphere cuboids, the 30-sphere cylinder, and a multi-layer bed of
   5,000 spheres (link cells; per-particle cost reported).
2. **LIGGGHTS** (when ``liggghts`` is on PATH; ``apt-get install liggghts`` installs it): the
   same 36-sphere scenario (``benchmarks/liggghts.py``: box as a moving mesh, Hertz, mu = 0.1,
   same dt) — its own loop time per step and per whole case, and the ratios to pdamper's.
3. **Cross-validation and whole cases**: eta* of LIGGGHTS (seed 0) and of pdamper (seeds 0-2,
   default integrator) at a few strokes of the 36-sphere cuboid, same cycles, with pdamper's
   default damping ("calibrated" Hertz-Gonthier) and with LIGGGHTS' own ("tsuji", the same law
   as its ``model hertz``); pdamper's energy-ledger error of each run, and that of a fixed 1 us
   Verlet step (LIGGGHTS' integrator and step) as the accuracy to match.
4. **Sweep wall time**: ``pdamper study fig4`` (2 fillings x 40 strokes x 20 cycles, one seed;
   ``--quick``: 8 strokes) on all cores, from an empty store.
5. **Until steady**: the same fig4 with ``--until-steady TOL`` (default 0.02) from an empty
   store: the time it saves and how far its eta* lies from the 20-cycle answer (part "steady").
6. **Every DEM curve of the paper** (the settings of all ``pdamper study`` names, duplicates
   removed: 27 curves x 40 strokes x 20 cycles, one seed, ~1,080 cases): a systematic sample of
   every ``--paper-every``-th stroke of every curve (default 8: 5 strokes a curve) is run on all
   cores; the wall time of the whole paper is estimated as that factor times the sample's wall
   time, and the estimator is checked in the same run on fig4, whose full sweep (item 4) is
   measured. ``--paper-every 1`` measures the whole paper.
7. **Compile and warm start**: ``pdamper run`` of a tiny case in a fresh kernel cache (compiles)
   and again (cached kernels).

Prints a table with each target and writes it to ``--report`` (Markdown). Times are wall-clock
on a shared machine: run it with nothing else running.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
sys.path.insert(0, str(BENCH))

import liggghts  # noqa: E402
from step_cost import measure  # noqa: E402

from pdamper.config import load_case  # noqa: E402
from pdamper.geometry import Cuboid  # noqa: E402
from pdamper.schema import replace  # noqa: E402

#: The targets: a Verlet step of the 36-sphere cuboid at LIGGGHTS' dt against LIGGGHTS' step,
#: a whole 20-cycle case (pdamper's default) against LIGGGHTS' whole case at its 1 us step, fig4,
#: the paper, the start.
TARGET_RATIO = 10.0
TARGET_CASE_RATIO = 50.0
TARGET_FIG4_S = 60.0
TARGET_COMPILE_S = 15.0
TARGET_WARM_S = 1.5
TARGET_PAPER_MIN = 15.0


def example(name, stroke):
    return replace(load_case(ROOT / "examples" / f"{name}.toml"), {"drive.stroke": stroke})


def big_bed(n=5000):
    """A multi-layer bed of ``n`` spheres (r = 5 mm) in a 400 x 200 mm cuboid, 100 mm high."""
    base = example("cuboid_36", 0.01)
    geo = Cuboid(length=0.4, width=0.2, height=0.1)
    parts = (dataclasses.replace(base.particles[0], count=n),)
    return dataclasses.replace(base, particles=parts,
                               container=dataclasses.replace(base.container, geometry=geo),
                               initial=dataclasses.replace(base.initial, layers="auto", settle_time=0.02),
                               numerics=dataclasses.replace(base.numerics, neighbour_search="cells"))


def step_costs(quick):
    steps = 50_000 if quick else 200_000
    rows = []
    for label, case in [("cuboid, 36 spheres, X = 14 mm", example("cuboid_36", 0.014)),
                        ("cuboid, 44 spheres, X = 4.7 mm", example("cuboid_44", 0.0047)),
                        ("cylinder, 30 spheres, X = 12 mm", example("cylinder_30", 0.012))]:
        r = measure(case, steps=steps, warm_cycles=1.0 if quick else 2.2)
        rows.append((label, r))
        print(f"  {label}: {r['us_per_step']:.3f} us/step", flush=True)
    r = measure(big_bed(), steps=500 if quick else 2000, warm_cycles=0.01, repeats=2)
    rows.append(("multi-layer bed, 5,000 spheres (cells)", r))
    print(f"  5,000 spheres: {r['us_per_step']:.1f} us/step, {1e3 * r['us_per_step'] / r['particles']:.1f} ns per "
          "particle-step", flush=True)
    return rows


#: pdamper's damping laws in the cross-check: its default, and LIGGGHTS' own (model hertz)
CROSS_LAWS = ("calibrated", "tsuji")


def cross_validation(quick, workdir, use_liggghts):
    """eta* of both codes at a few strokes, pdamper with each of :data:`CROSS_LAWS`; LIGGGHTS step
    cost from its runs."""
    from pdamper.run import run_case

    cycles = 6 if quick else 20
    strokes = (0.003, 0.014, 0.03)
    out = []
    for x in strokes:
        case = dataclasses.replace(example("cuboid_36", x), cycles=cycles)
        row = {"stroke": x, "cycles": cycles, "pdamper": {}}
        for law in CROSS_LAWS:
            c0 = dataclasses.replace(case, contact=dataclasses.replace(case.contact, damping=law))
            etas, ledger, walls = [], [], []
            for seed in (0, 1, 2):
                c = dataclasses.replace(c0, initial=dataclasses.replace(c0.initial, seed=seed))
                t = time.perf_counter()
                r = run_case(c)
                walls.append(time.perf_counter() - t)
                etas.append(r.eta_star)
                ledger.append(r.energy.balance_error())
            row["pdamper"][law] = {"eta": etas, "wall_s": statistics.mean(walls), "ledger": ledger}
        # the ledger error of a fixed 1 us step (LIGGGHTS' step, velocity Verlet as LIGGGHTS), seed 0:
        # the accuracy a whole-case comparison at "equal or better ledger error" is held to
        c = dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator="verlet", time_step=1e-6))
        t = time.perf_counter()
        rv = run_case(c)
        row["verlet_1us"] = {"eta": rv.eta_star, "ledger": rv.energy.balance_error(), "wall_s": time.perf_counter() - t}
        lig = None
        if use_liggghts:
            lig = liggghts.run(case, Path(workdir) / f"liggghts_{x * 1e3:g}mm")
        row["liggghts"] = lig
        out.append(row)
        msg = f"  X = {x * 1e3:g} mm: pdamper eta* " + "; ".join(
            f"{law} {statistics.mean(r['eta']):.3f} (seeds {min(r['eta']):.3f}-{max(r['eta']):.3f}, {r['wall_s']:.1f} s/run)"
            for law, r in row["pdamper"].items())
        msg += f"; Verlet at 1 us: ledger {row['verlet_1us']['ledger']:.1e}, {row['verlet_1us']['wall_s']:.1f} s"
        if lig:
            msg += f"; LIGGGHTS eta* {lig['eta_star']:.3f} ({lig['us_per_step']:.2f} us/step, {lig['wall_time_s']:.0f} s)"
        print(msg, flush=True)
    return out


def sweep_time(quick, workdir):
    from pdamper.studies.named import run_study
    from pdamper.studies.sweep import stroke_grid

    n = 8 if quick else 40
    t = time.perf_counter()
    ds = run_study("fig4", Path(workdir) / "fig4", strokes=tuple(stroke_grid(0.5e-3, 50e-3, n)), seeds=(0,),
                   progress=False)
    wall = time.perf_counter() - t
    peaks = {}
    for label in ds.setting.values:
        m = ds.eta_star.sel(setting=label).mean("seed").values
        i = int(m.argmax())
        peaks[str(label)] = (float(m[i]), float(ds.stroke.values[i]))
    print(f"  fig4, {2 * n} cases: {wall:.1f} s", flush=True)
    # CPU seconds of every case, [setting, stroke] (for the check of the paper estimate)
    cpu = ds.wall_time.sum("seed").values.tolist()
    return {"cases": 2 * n, "wall_s": wall, "peaks": peaks, "workers": os.cpu_count(), "case_cpu_s": cpu,
            "dataset": ds}


def steady_time(workdir, tolerance, full_store=None):
    """fig4 (40 strokes, 1 seed) with ``--until-steady tolerance`` from an empty store: wall time,
    cycles run, and how far its eta* lies from the 20-cycle answer (the store of :func:`sweep_time`,
    or one run here)."""
    import numpy as np

    from pdamper.studies.named import run_study
    from pdamper.studies.sweep import stroke_grid

    strokes = tuple(stroke_grid(0.5e-3, 50e-3, 40))
    t = time.perf_counter()
    ds = run_study("fig4", Path(workdir) / "fig4_steady", strokes=strokes, seeds=(0,), progress=False,
                   until_steady=tolerance)
    wall = time.perf_counter() - t
    full = full_store if full_store is not None else run_study("fig4", Path(workdir) / "fig4", strokes=strokes,
                                                               seeds=(0,), progress=False)
    d = (ds.eta_star - full.eta_star).values.ravel()
    err = ds.eta_star_error.values.ravel()
    within = float(np.mean(np.abs(d) <= 2 * err))
    out = {"tolerance": tolerance, "wall_s": wall, "cases": int(d.size),
           "mean_cycles": float(ds.cycles_run.mean()), "max_abs_diff": float(np.max(np.abs(d))),
           "rms_diff": float(np.sqrt(np.mean(d ** 2))), "within_2se": within,
           "steps_ratio": float(ds.steps.sum() / full.steps.sum())}
    print(f"  fig4 until steady at {tolerance:g}: {wall:.1f} s, {out['mean_cycles']:.1f} cycles on average, "
          f"eta* within {out['max_abs_diff']:.3f} of 20 cycles (rms {out['rms_diff']:.3f})", flush=True)
    return out


def paper_curves():
    """Every distinct DEM curve of the paper: ``[(label, case)]`` from the settings of all named
    studies, a setting that repeats another's physics (fig4's 36 spheres is also friction's
    mu = 0.1, restitution's eps = 0.9, ...) kept once."""
    from pdamper.studies.named import PAPER_STUDIES, study_settings

    def physics(d):
        # the material's name is a label, not physics (modulus' 'steel-mod' at 208 GPa is steel)
        if isinstance(d, dict):
            return {k: physics(v) for k, v in d.items() if k != "name"}
        if isinstance(d, (list, tuple)):
            return [physics(v) for v in d]
        return d

    seen = {}
    for name in PAPER_STUDIES:  # the shipped studies beyond the paper (vertical) are not its curves
        for label, case in study_settings(name):
            key = json.dumps(physics(dataclasses.asdict(case)), sort_keys=True, default=str)
            seen.setdefault(key, (f"{name}: {label}", case))
    return list(seen.values())


def paper_sample(quick, every):
    """Run every ``every``-th stroke of the paper's 40 (offset ``every // 2``) of every curve, one
    seed, on all cores; return the sample's wall time and per-curve CPU seconds."""
    from pdamper.studies.executor import execute
    from pdamper.studies.sweep import run_one, stroke_grid

    grid = stroke_grid(0.5e-3, 50e-3, 40)
    strokes = grid[every // 2::every]
    cycles = 6 if quick else 20
    curves = paper_curves()
    items = []
    for c, (label, case) in enumerate(curves):
        case = dataclasses.replace(case, cycles=cycles)
        for x in strokes:
            items.append((f"c{c}-X{x:.6g}", float(x), 0, replace(case, {"drive.stroke": float(x)})))
    results = {}
    t = time.perf_counter()
    execute(items, run_one, lambda key, x, s, r: results.__setitem__(key, r), progress=False)
    wall = time.perf_counter() - t
    per_curve = []
    for c, (label, _) in enumerate(curves):
        rs = [results[f"c{c}-X{x:.6g}"] for x in strokes]
        failed = sum("failed" in r for r in rs)
        cpu = sum(r.get("wall_time_s", 0.0) for r in rs)
        steps = sum(r.get("steps", 0) for r in rs)
        per_curve.append({"label": label, "cpu_s": cpu, "steps": steps, "failed": failed,
                          "slowest_s": max(r.get("wall_time_s", 0.0) for r in rs)})
    out = {"every": every, "strokes": [float(x) for x in strokes], "cycles": cycles, "curves": len(curves),
           "cases": len(items), "wall_s": wall, "per_curve": per_curve, "workers": os.cpu_count(),
           "estimate_min": every * wall / 60.0}
    print(f"  {len(items)} cases ({len(curves)} curves x {len(strokes)} strokes): {wall:.0f} s"
          + ("" if every == 1 else f"; whole paper estimated {out['estimate_min']:.0f} min"), flush=True)
    return out


def start_times():
    """Wall time of a tiny `pdamper run` in a fresh kernel cache, then again (cached)."""
    cmd = [sys.executable, "-m", "pdamper.cli", "run", str(ROOT / "examples" / "cuboid_36.toml"), "--cycles", "1", "--stroke", "3mm",
           "--set", "run.drop_cycles=0", "--set", "initial.settle_time=0.01", "--json"]
    with tempfile.TemporaryDirectory() as cache, tempfile.TemporaryDirectory() as runs:
        env = {**os.environ, "PDAMPER_CACHE_DIR": cache}
        env.pop("NUMBA_CACHE_DIR", None)
        times = []
        for _ in range(2):
            t = time.perf_counter()
            subprocess.run(cmd, env=env, cwd=runs, check=True, capture_output=True)
            times.append(time.perf_counter() - t)
    print(f"  first run (compiles): {times[0]:.1f} s; warm start: {times[1]:.2f} s", flush=True)
    return {"compile_s": times[0], "warm_s": times[1]}


def _ok(flag):
    return "met" if flag else "**not met**"


def report(res, quick, cmd):
    """The Markdown report of whatever parts ``res`` holds (all, or those of ``--only``)."""
    lines = [f"Produced by `{cmd}` on {res['machine']} ({res['date']}); {res['seconds'] / 60:.1f} min in all.", ""]
    lines += ["### CPU targets", "", "| target | measured | ratio / baseline | result |", "|---|---|---|---|"]
    steps, cross, sw, pp, st, sd = (res.get(k) for k in ("steps", "cross", "sweep", "paper", "start", "steady"))
    full = not quick
    lig = [c["liggghts"] for c in cross or () if c["liggghts"]]
    if steps:
        s36 = steps[0][1]["us_per_step"]
        if lig:
            lig_us = statistics.median(c["us_per_step"] for c in lig)
            ratio = lig_us / s36
            lines.append(f"| one 36-sphere step >= {TARGET_RATIO:g}x faster than LIGGGHTS at the same dt = 1 us | "
                         f"{s36:.3f} us/step | LIGGGHTS {lig_us:.2f} us/step: **{ratio:.1f}x** | "
                         f"{_ok(ratio >= TARGET_RATIO)} |")
        else:
            lines.append(f"| one 36-sphere step >= {TARGET_RATIO:g}x faster than LIGGGHTS | {s36:.3f} us/step | LIGGGHTS "
                         f"not run ({liggghts.INSTALL_HINT}) | not measured |")
    if cross and lig:
        for c in cross:
            if not c["liggghts"]:
                continue
            r = c["pdamper"]["calibrated"]
            ratio = c["liggghts"]["wall_time_s"] / r["wall_s"]
            led = max(r["ledger"])
            ref = c["verlet_1us"]["ledger"]
            fast = ratio >= TARGET_CASE_RATIO
            verdict = (_ok(fast and led <= ref) + ("" if led <= ref else
                       f" at equal ledger error; {'met' if fast else 'not met'} at pdamper's criterion (<= 5e-3)"))
            lines.append(f"| a whole {c['cycles']}-cycle case at {c['stroke'] * 1e3:g} mm >= {TARGET_CASE_RATIO:g}x faster "
                         f"than LIGGGHTS at 1 us, ledger error <= that of a 1 us step | {r['wall_s']:.2f} s (default "
                         f"Gear), ledger <= {led:.1e}; 1 us Verlet {c['verlet_1us']['wall_s']:.1f} s, ledger {ref:.1e} | "
                         f"LIGGGHTS {c['liggghts']['wall_time_s']:.0f} s: **{ratio:.0f}x** (1 us Verlet: "
                         f"{c['liggghts']['wall_time_s'] / c['verlet_1us']['wall_s']:.1f}x) | {verdict} |")
    if sw:
        lines.append(f"| `pdamper study fig4` (80 cases, 20 cycles, 1 seed) <= {TARGET_FIG4_S:g} s | {sw['wall_s']:.0f} s "
                     f"for {sw['cases']} cases on {sw['workers']} cores | {sw['wall_s'] / TARGET_FIG4_S:.1f}x the target | "
                     + (_ok(sw['wall_s'] <= TARGET_FIG4_S) if full else "quick run: 16 cases only") + " |")
    if sd:
        lines.append(f"| `--until-steady {sd['tolerance']:g}` on fig4: time saved, eta* moved | {sd['wall_s']:.0f} s, "
                     f"{sd['mean_cycles']:.1f} cycles on average | steps {sd['steps_ratio']:.2f}x of 20 cycles; eta* "
                     f"within {sd['max_abs_diff']:.3f} (rms {sd['rms_diff']:.3f}), {100 * sd['within_2se']:.0f} % "
                     f"within 2 standard errors | opt-in |")
    if pp:
        est = pp["estimate_min"]
        lines.append(f"| every DEM curve of the paper ({pp['curves']} curves x 40 strokes, 1 seed) <= {TARGET_PAPER_MIN:g} min | "
                     + (f"all {pp['cases']} cases, stroke by stroke: **{pp['wall_s'] / 60:.1f} min measured** | "
                        if pp["every"] == 1 else
                        f"sample of {pp['cases']} cases (1 stroke in {pp['every']}) in {pp['wall_s'] / 60:.1f} min; "
                        f"whole paper **estimated {est:.0f} min** ({pp['every']} x the sample) | ")
                     + f"{est / TARGET_PAPER_MIN:.1f}x the target | "
                     + (_ok(est <= TARGET_PAPER_MIN) + (" (estimate)" if pp["every"] > 1 else "") if full
                        else "quick run: 6 cycles") + " |")
    if st:
        lines.append(f"| first run (compile) <= {TARGET_COMPILE_S:g} s | {st['compile_s']:.1f} s | | "
                     f"{_ok(st['compile_s'] <= TARGET_COMPILE_S)} |")
        lines.append(f"| later start (cached) <= {TARGET_WARM_S:g} s | {st['warm_s']:.2f} s | | {_ok(st['warm_s'] <= TARGET_WARM_S)} |")
    if steps:
        big = steps[-1][1]
        lines.append(f"| 5,000-sphere multi-layer bed runs | {big['us_per_step']:.0f} us/step = "
                     f"{1e3 * big['us_per_step'] / big['particles']:.1f} ns per particle-step | | met |")
        lines += ["", "### Step cost", "", "Velocity Verlet at dt = 1 us, kernel only (no recording), best of the repeats, "
                  "after the bed is set in motion.", "",
                  "| system | us/step | ns per particle-step | search | pairs listed / touching | wall contacts |",
                  "|---|---|---|---|---|---|"]
        for label, r in steps:
            lines.append(f"| {label} | {r['us_per_step']:.3f} | {1e3 * r['us_per_step'] / r['particles']:.1f} | {r['search']} | "
                         f"{r['pairs_listed']} / {r['pairs_touching']} | {r['walls_touching']} |")
    if cross:
        lines += ["", "### Cross-validation with LIGGGHTS", "",
                  "The 36-sphere cuboid at three strokes, same cycles (first 2 dropped), same seeded initial positions "
                  "for seed 0; pdamper with its default integrator, seeds 0-2 (mean and range), with its default "
                  "damping (`calibrated` Hertz-Gonthier) and with LIGGGHTS' own (`tsuji`, as its `model hertz`). "
                  "Friction differs in either case (pdamper's tanh law, LIGGGHTS' tangential spring with a Coulomb "
                  "limit).", "",
                  "| X [mm] | cycles | damping | pdamper eta* (mean, range) | pdamper s/run | LIGGGHTS eta* (seed 0) | "
                  "LIGGGHTS - pdamper mean | LIGGGHTS us/step | LIGGGHTS s/run |",
                  "|---|---|---|---|---|---|---|---|---|"]
        for c in cross:
            lg = c["liggghts"]
            for law, r in c["pdamper"].items():
                e = r["eta"]
                lg_cols = (f"{lg['eta_star']:.3f} | {lg['eta_star'] - statistics.mean(e):+.3f} | {lg['us_per_step']:.2f} | "
                           f"{lg['wall_time_s']:.0f}" if lg else "not run | | | ")
                lines.append(f"| {c['stroke'] * 1e3:g} | {c['cycles']} | {law} | {statistics.mean(e):.3f} "
                             f"({min(e):.3f}-{max(e):.3f}) | {r['wall_s']:.1f} | {lg_cols} |")
    if sw:
        lines += ["", "### Sweep", "", f"`run_study('fig4', ...)` from an empty store, {sw['cases']} cases, one seed, "
                  f"20 cycles, embedded local Dask cluster ({sw['workers']} workers): {sw['wall_s']:.1f} s. Peaks: "
                  + "; ".join(f"{k}: eta* = {v[0]:.3f} at {v[1] * 1e3:.3g} mm" for k, v in sw["peaks"].items()) + "."]
    if pp:
        lines += _paper_lines(pp, sw or {})
    return "\n".join(lines) + "\n"


def _paper_lines(pp, sw):
    """The paper-curves section: per-curve cost of the sample and the check of the estimator."""
    every = pp["every"]
    strokes = ", ".join(f"{x * 1e3:.3g}" for x in pp["strokes"])
    lines = ["", "### Every DEM curve of the paper", "",
             f"{pp['curves']} distinct curves (the settings of every `pdamper study`, a setting that repeats "
             f"another's physics counted once), one seed, {pp['cycles']} cycles, at every {every}th of the paper's 40 "
             f"strokes ({strokes} mm): {pp['cases']} cases in {pp['wall_s']:.0f} s wall on {pp['workers']} cores. "
             f"Estimate for all 40 strokes: {every} x {pp['wall_s']:.0f} s = **{pp['estimate_min']:.0f} min**"
             + (" (measured, not estimated: every stroke was run)." if every == 1 else
                " (extrapolated from the sample, not measured)."), ""]
    cpu = sw.get("case_cpu_s")
    if cpu and every > 1 and len(cpu[0]) == 40:
        full = sum(sum(row) for row in cpu)
        samp = sum(sum(row[every // 2::every]) for row in cpu)
        lines += [f"Check of the estimator on fig4, whose 40 strokes were all run above: {every} x the CPU time of "
                  f"its sampled strokes = {every * samp:.0f} s against {full:.0f} s measured "
                  f"({every * samp / full:.2f}x).", ""]
    lines += ["| curve | CPU s of the sample | slowest case [s] | Gear steps [M] | failed |", "|---|---|---|---|---|"]
    for c in sorted(pp["per_curve"], key=lambda c: -c["cpu_s"]):
        lines.append(f"| {c['label']} | {c['cpu_s']:.0f} | {c['slowest_s']:.0f} | {c['steps'] / 1e6:.1f} | {c['failed']} |")
    return lines


START, END = "<!-- benchmarks/run.py: start -->", "<!-- benchmarks/run.py: end -->"


def write_section(path, text):
    """Put ``text`` between the START/END markers of ``path`` (appended when they are missing),
    leaving the hand-written rest of the page as it is."""
    old = path.read_text() if path.exists() else ""
    block = f"{START}\n{text}{END}"
    if START in old and END in old:
        head, rest = old.split(START, 1)
        new = head + block + rest.split(END, 1)[1]
    else:
        new = old.rstrip("\n") + "\n\n" + block + "\n"
    path.write_text(new)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="shorter runs (a few minutes)")
    ap.add_argument("--no-liggghts", action="store_true", help="skip the LIGGGHTS rows")
    ap.add_argument("--report", help="Markdown file for the results (default: print only)")
    ap.add_argument("--json", help="also write the raw results as JSON here")
    ap.add_argument("--until-steady", type=float, default=0.02, metavar="TOL",
                    help="the tolerance of the fig4 run with --until-steady (part 'steady'; default 0.02)")
    ap.add_argument("--only", nargs="+", choices=("start", "steps", "cross", "sweep", "steady", "paper"),
                    help="run only these parts (the report then has only their rows)")
    ap.add_argument("--paper-every", type=int, default=8, metavar="K",
                    help="time every K-th stroke of every DEM curve of the paper (default 8; 1: all, hours; "
                         "0: skip)")
    ap.add_argument("--from-json", metavar="FILE", help="render the report of an earlier run's --json (nothing is run)")
    args = ap.parse_args()
    if args.from_json:
        res = json.loads(Path(args.from_json).read_text())
        text = report(res, args.quick, res.get("command", "python benchmarks/run.py"))
        print(text)
        if args.report:
            write_section(Path(args.report), text)
        return
    use_lig = not args.no_liggghts and liggghts.available() is not None
    if not args.no_liggghts and not use_lig:
        print(f"LIGGGHTS not found: its rows are skipped; {liggghts.INSTALL_HINT}")
    t0 = time.perf_counter()
    res = {"machine": f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}",
           "date": time.strftime("%Y-%m-%d")}
    parts = set(args.only or ("start", "steps", "cross", "sweep", "steady", "paper"))
    if args.paper_every <= 0:
        parts.discard("paper")
    with tempfile.TemporaryDirectory(prefix="pdamper-bench-") as work:
        if "start" in parts:
            print("compile and warm start", flush=True)
            res["start"] = start_times()
        if "steps" in parts:
            print("step cost", flush=True)
            res["steps"] = step_costs(args.quick)
        if "cross" in parts:
            print("cross-validation" + (" with LIGGGHTS" if use_lig else ""), flush=True)
            res["cross"] = cross_validation(args.quick, work, use_lig)
        if "sweep" in parts:
            print("sweep", flush=True)
            res["sweep"] = sweep_time(args.quick, work)
        if "steady" in parts and not args.quick:
            print("fig4 until steady", flush=True)
            full = res["sweep"]["dataset"] if "sweep" in res and len(res["sweep"]["case_cpu_s"][0]) == 40 else None
            res["steady"] = steady_time(work, args.until_steady, full)
        if "sweep" in res:
            res["sweep"].pop("dataset")
        if "paper" in parts:
            print("every DEM curve of the paper", flush=True)
            res["paper"] = paper_sample(args.quick, 20 if args.quick else args.paper_every)
    res["seconds"] = time.perf_counter() - t0
    cmd = ("python benchmarks/run.py" + (" --quick" if args.quick else "") + (" --no-liggghts" if args.no_liggghts else "")
           + (f" --only {' '.join(args.only)}" if args.only else "")
           + (f" --paper-every {args.paper_every}" if args.paper_every != 8 else "")
           + (f" --until-steady {args.until_steady:g}" if args.until_steady != 0.02 else ""))
    res["command"] = cmd
    text = report(res, args.quick, cmd)
    print()
    print(text)
    if args.report:
        write_section(Path(args.report), text)
    if args.json:
        Path(args.json).write_text(json.dumps(res, indent=1, default=str))


if __name__ == "__main__":
    main()
