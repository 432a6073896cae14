"""Cross-code check: pdamper against LIGGGHTS on multi-layer, vertical, baffled and coated beds.

Usage::

    python benchmarks/crosscheck.py --results /work/crosscheck_results --jobs 2
    python benchmarks/crosscheck.py --cases vertical96 --strokes 9.55,12 --seeds 3 --tilt both
    python benchmarks/crosscheck.py --results DIR --table-only      # the table of what is stored

One command runs a matrix of cases in both codes: LIGGGHTS (``benchmarks/liggghts.py``: the same
container, drive, tilt, materials and seeded initial positions, Hertz with a Mindlin tangential
spring) and pdamper with each tangential law asked for (``--laws tanh,spring``; a law pdamper does
not know yet -- no ``contact.tangential`` key, or not that value -- is skipped with a line saying
so). Every run is stored as one JSON file (its full pdamper config, the code, law, stroke, seed,
tilt, the result and its cost) under ``RESULTS/runs/``; a run whose file exists is not run again,
so the command resumes where it stopped and adds only what is new. The table (per case, stroke and
tilt: mean, standard deviation and range over the seeds of each code and law, and LIGGGHTS minus
each pdamper law with the standard error of the difference) is printed and written to
``RESULTS/table.md`` and ``RESULTS/table.csv``.

Runs go to ``--jobs`` worker processes, all under ``nice -n --nice`` (the driver renices itself;
LIGGGHTS and the workers inherit it), the longest first. The cases (``CASES``):

- ``vertical96``: ``examples/vertical_96.toml`` (96 spheres in two layers, vertical drive 15 Hz);
- ``vertical96_dropped``: the same, its upper 48 spheres dropped from random places instead of
  stacked sphere on sphere (:func:`starting`): without tilt, pdamper's stacked start keeps every
  sphere in one of the floor's 12 slots along x until round-off breaks the symmetry
  (docs/crosscheck.md), the dropped one starts without that order;
- ``baffled``: the paper's 36-sphere cuboid (``examples/cuboid_36.toml``) with two full-height
  baffles at x = -20 and 20 mm (docs/robust.md);
- ``coated``: the same cuboid with TPU-coated end walls (``x_min``, ``x_max``; E = 26 MPa),
  ``numerics.overlap_limit = 0.25`` as in docs/robust.md (pdamper's overlap guard only).

``--tilt paper`` runs each case with its own tilt (the paper's 0.1 deg about x, y, z), ``none``
with zero tilt, ``both`` both. ``--friction 0`` adds the frictionless variant (mu = 0 everywhere).
"""

from __future__ import annotations

import argparse
import csv
import hashlib
import json
import math
import os
import platform
import subprocess
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if not os.environ.get("PYTHONPATH"):  # this tree's pdamper, unless PYTHONPATH names one
    sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import liggghts  # noqa: E402

#: name -> (config file, overrides of it, default strokes [mm], start: :func:`starting`).
CASES = {
    "vertical96": ("examples/vertical_96.toml", {}, (5, 7, 9.55, 12, 20, 30)),
    "vertical96_dropped": ("examples/vertical_96.toml", {}, (5, 7, 9.55, 12, 20, 30), "dropped"),
    "baffled": ("examples/cuboid_36.toml",
                {"container.baffles": [{"position": "-20mm"}, {"position": "20mm"}]}, (3.28, 5.38, 11.3)),
    "coated": ("examples/cuboid_36.toml",
               {"container.wall_materials": {"x_min": "tpu", "x_max": "tpu"}, "numerics.overlap_limit": 0.25},
               (14.5, 23.8, 39.0)),
}
NO_TILT = ["0deg", "0deg", "0deg"]
#: LIGGGHTS variants (``--liggghts``): law name -> keywords appended to its contact model.
LIGGGHTS_LAWS = {"liggghts": "", "liggghts_tdoff": "tangential_damping off"}


def build_case(name: str, stroke_mm: float, seed: int, tilt: str, friction: str, settle_step: float = 0.0):
    """The pdamper Case of one cell of the matrix (the law is set apart: :func:`with_law`);
    ``settle_step`` [s] lengthens the settling of seed k by (k - 1) settle_step."""
    from pdamper.config import load_case
    from pdamper.schema import replace

    path, changes, _, *start = CASES[name]
    changes = {**changes, "drive.stroke": f"{stroke_mm}mm", "initial.seed": seed}
    if settle_step:
        base = load_case(ROOT / path).initial.settle_time
        changes["initial.settle_time"] = base + (seed - 1) * settle_step
    if tilt == "none":
        changes["container.tilt"] = NO_TILT
    if friction != "case":
        changes["contact.friction"] = float(friction)
    return starting(replace(load_case(ROOT / path), changes), start[0] if start else "layers")


def starting(case, start: str):
    """``case`` as it starts: ``"layers"`` (pdamper's own ``initial.layers = "auto"``: the upper
    layer stacked on the lower, sphere on sphere) or ``"dropped"`` (the lower layer as pdamper
    lays it, the upper 48 spheres at random, seeded, non-overlapping places in the room above it,
    settling 0.3 s: a bed without columns)."""
    from pdamper.initial import initial_positions
    from pdamper.schema import replace

    if start == "layers":
        return case
    rng = np.random.default_rng(case.initial.seed + 1000)
    pos = initial_positions(case, np.random.default_rng(case.initial.seed))
    r = case.particles[0].radius
    g = case.container.geometry
    n = pos.shape[0] // 2
    upper = []
    while len(upper) < pos.shape[0] - n:
        p = np.array([rng.uniform(-g.length / 2 + r, g.length / 2 - r), rng.uniform(4 * r, g.height - r),
                      rng.uniform(-g.width / 2 + r, g.width / 2 - r)])
        if all(np.linalg.norm(p - q) > 2 * r + 1e-4 for q in list(pos[:n]) + upper):
            upper.append(p)
    return replace(case, {"initial.positions": np.vstack([pos[:n], upper]), "initial.settle_time": 0.3})


#: pdamper's laws (``--laws``): name -> the config keys that choose it (a name not listed here
#: is taken as a value of ``contact.tangential``).
PDAMPER_LAWS = {"tanh": {"contact.tangential": "tanh"}, "spring": {"contact.tangential": "spring"},
                "spring_tdoff": {"contact.tangential": "spring", "contact.tangential_damping": False},
                "spring_tsuji": {"contact.tangential": "spring", "contact.damping": "tsuji"}}


def with_law(case, law: str):
    """``case`` with the tangential law ``law`` (:data:`PDAMPER_LAWS`); None when this pdamper
    has no such law. The paper's law "tanh" is the only one of a pdamper without the key: the
    case as it is."""
    from pdamper.errors import InputError
    from pdamper.schema import replace

    try:
        return replace(case, PDAMPER_LAWS.get(law, {"contact.tangential": law}))
    except InputError:
        return case if law == "tanh" and not hasattr(case.contact, "tangential") else None


def spec_tag(spec: dict) -> str:
    fr = "" if spec["friction"] == "case" else f"_mu{spec['friction']}"
    st = f"_settle+{spec['settle_step'] * 1e3:g}ms" if spec.get("settle_step") else ""
    return f"{spec['case']}_X{spec['stroke_mm']:g}mm_s{spec['seed']}{st}_tilt-{spec['tilt']}_{spec['law']}{fr}"


def _git_head() -> str:
    try:
        return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def prepare(spec: dict, dt: float):
    """(case, config dict, file key) of a spec, or (None, reason, None) when it cannot run."""
    from pdamper.config import case_to_dict

    case = build_case(spec["case"], spec["stroke_mm"], spec["seed"], spec["tilt"], spec["friction"],
                      spec.get("settle_step", 0.0))
    if spec["code"] == "pdamper":
        case = with_law(case, spec["law"])
        if case is None:
            return None, f"pdamper has no tangential law {spec['law']!r} here (not merged yet?): skipped", None
    config = case_to_dict(case)
    keyed = json.loads(json.dumps(config, default=str))
    if keyed.get("contact", {}).get("tangential") == "tanh":
        # the paper's law, the default: a run stored before the key existed is the same run (and
        # the spring's own options do not touch it)
        del keyed["contact"]["tangential"]
        keyed["contact"].pop("tangential_damping", None)
    extra = {"dt_s": dt, "model": f"{liggghts.MODEL} {LIGGGHTS_LAWS[spec['law']]}".strip()} \
        if spec["code"] == "liggghts" else {}
    digest = hashlib.sha1(json.dumps([spec, keyed, extra], sort_keys=True, default=str).encode()).hexdigest()[:10]
    return case, {"config": config, **extra}, f"{spec['code']}/{spec_tag(spec)}_{digest}.json"


def start_key(spec: dict, case, config: dict) -> str:
    """What a run depends on besides its seed: its config without the seed, and the initial
    positions the seed gives (equal for every seed where the bed leaves no room for the jitter)."""
    from pdamper.initial import initial_positions

    pos = initial_positions(case, np.random.default_rng(case.initial.seed))
    cfg = json.loads(json.dumps(config, default=str))
    cfg["config"].get("initial", {}).pop("seed", None)
    other = {k: v for k, v in spec.items() if k != "seed"}
    return hashlib.sha1(json.dumps([other, cfg], sort_keys=True).encode() + pos.tobytes()).hexdigest()


def run_one(spec: dict, dt: float, results: str) -> dict:
    """Run one spec in a worker; write and return its record."""
    case, config, key = prepare(spec, dt)
    out = Path(results) / "runs" / key
    t0 = time.perf_counter()
    if spec["code"] == "liggghts":
        work = Path(results) / "liggghts_work" / out.stem
        res = liggghts.run(case, work, dt=dt, model_options=LIGGGHTS_LAWS[spec["law"]])
    else:
        from pdamper.run import run_case

        c0 = time.process_time()
        r = run_case(case)
        s = r.summary()
        s["cpu_time_s"] = time.process_time() - c0
        res = {k: s[k] for k in ("eta_star", "energy_per_cycle_J", "energy_balance_error", "steps", "time_step_s",
                                 "wall_time_s", "cpu_time_s", "us_per_step", "integrator") if k in s}
        res["mode"] = r.mode
    record = {"spec": spec, **config, "result": res, "elapsed_s": time.perf_counter() - t0,
              "finished": time.strftime("%Y-%m-%d %H:%M:%S"), "git": _git_head(), "host": platform.node(),
              "python": platform.python_version()}
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp = out.with_suffix(".tmp")
    tmp.write_text(json.dumps(record, indent=1, default=float))
    tmp.replace(out)
    return record


def matrix(args) -> list[dict]:
    tilts = {"paper": ["paper"], "none": ["none"], "both": ["paper", "none"]}[args.tilt]
    out = []
    for name in args.cases:
        strokes = args.strokes or CASES[name][2]
        for x in strokes:
            for seed in args.seeds:
                for tilt in tilts:
                    for fr in args.friction:
                        base = {"case": name, "stroke_mm": float(x), "seed": seed, "tilt": tilt, "friction": fr}
                        if args.settle_step and seed > 1:  # seed 1 settles as the case says
                            base["settle_step"] = args.settle_step
                        if "liggghts" in args.codes:
                            out += [{"code": "liggghts", "law": law, **base} for law in args.liggghts]
                        if "pdamper" in args.codes:
                            out += [{"code": "pdamper", "law": law, **base} for law in args.laws]
    return out


def _order(cases):
    """The order of the runs: the cases as listed, then seed by seed (a batch cut short has every
    stroke of its first seeds), LIGGGHTS first (the longest)."""
    return lambda spec: (cases.index(spec["case"]), spec["seed"], spec["code"] != "liggghts")


def stored(results: Path) -> list[dict]:
    """The stored records, the newest of each cell and seed (an earlier config of it is kept on
    disk but not tabled)."""
    newest: dict = {}
    for p in sorted((results / "runs").rglob("*.json")):
        r = json.loads(p.read_text())
        key = (r["spec"]["code"], spec_tag(r["spec"]))
        if key not in newest or r["finished"] > newest[key]["finished"]:
            newest[key] = r
    return list(newest.values())


def _stats(v):
    v = np.asarray(v, dtype=float)
    sd = float(v.std(ddof=1)) if v.size > 1 else math.nan
    return float(v.mean()), sd, float(v.min()), float(v.max()), v.size


def table(records: list[dict]):
    """(markdown, csv rows) of the cross-code table."""
    cells: dict = {}
    for r in records:
        s = r["spec"]
        key = (s["case"], s["friction"], s["stroke_mm"], s["tilt"])
        cells.setdefault(key, {}).setdefault(s["law"], []).append((s["seed"], r["result"]["eta_star"]))
    laws = sorted({law for c in cells.values() for law in c}, key=lambda x: (not x.startswith("liggghts"), x))
    rows, md = [], []
    head = ["case", "friction", "X [mm]", "tilt"] + [f"{law} eta*" for law in laws] + \
        [f"liggghts - {law}" for law in laws if not law.startswith("liggghts")]
    md.append("| " + " | ".join(head) + " |")
    md.append("|" + "---|" * len(head))
    for key in sorted(cells, key=lambda k: (k[0], k[1], k[2], k[3] != "none")):
        c = cells[key]
        line = [key[0], "mu = 0" if key[1] != "case" else "case", f"{key[2]:g}", key[3]]
        st = {}
        for law in laws:
            if law not in c:
                line.append("-")
                continue
            m, sd, lo, hi, n = st[law] = _stats([e for _, e in sorted(c[law])])
            line.append(f"{m:.3f} ± {sd:.3f} ({lo:.3f}–{hi:.3f}, n={n})" if n > 1 else f"{m:.3f} (n=1)")
            rows.append({"case": key[0], "friction": key[1], "stroke_mm": key[2], "tilt": key[3], "law": law,
                         "eta_mean": m, "eta_sd": sd, "eta_min": lo, "eta_max": hi, "seeds": n,
                         "values": " ".join(f"s{sd_}:{e:.4f}" for sd_, e in sorted(c[law]))})
        for law in laws:
            if law.startswith("liggghts"):
                continue
            if "liggghts" in st and law in st:
                (ml, sl, *_, nl), (mp, sp, *_, np_) = st["liggghts"], st[law]
                se = math.sqrt((sl**2 / nl if nl > 1 else 0) + (sp**2 / np_ if np_ > 1 else 0))
                line.append(f"{ml - mp:+.3f} ± {se:.3f}")
            else:
                line.append("-")
        md.append("| " + " | ".join(line) + " |")
    return "\n".join(md), rows


def write_table(results: Path, cases=None) -> str:
    """Write ``table.md``, ``table.csv`` and ``cost.txt`` of every stored run into ``results``;
    return the table and the costs of ``cases`` (None: all) as text."""
    every = stored(results)
    text, rows = table(every)
    (results / "table.md").write_text(text + "\n")
    if rows:
        with open(results / "table.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    records = [r for r in every if cases is None or r["spec"]["case"] in cases]
    cost: dict = {}
    for r in records:
        s = r["spec"]
        cost.setdefault((s["case"], s["law"]), []).append((r["result"]["wall_time_s"],
                                                            r["result"].get("cpu_time_s", math.nan)))
    lines = []
    for (c, law), v in sorted(cost.items()):
        wall, cpu = np.array(v).T
        line = f"{c} {law}: wall {wall.mean():.1f} s a run (n={len(v)}, {wall.min():.1f}-{wall.max():.1f})"
        if np.isfinite(cpu).any():
            line += f", CPU {np.nanmean(cpu):.1f} s ({np.isfinite(cpu).sum()} runs timed)"
        lines.append(line)
    (results / "cost.txt").write_text("\n".join(lines) + "\n")
    return table(records)[0] + "\n\ncost per run (shared machine):\n" + "\n".join(lines)


def figure(results: Path, case: str, path: Path) -> None:
    """eta* against the stroke for ``case``: each code and law, with and without tilt, seed mean
    with the seeds' range as error bars."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    _, rows = table([r for r in stored(results) if r["spec"]["case"] == case and r["spec"]["friction"] == "case"])
    fig, ax = plt.subplots(figsize=(10, 4.4))
    colours = {"liggghts": "C0", "liggghts_tdoff": "C2", "tanh": "C3", "spring": "C1", "spring_tdoff": "C4",
               "spring_tsuji": "C5"}
    names = {"liggghts": "LIGGGHTS (tangential damping on, its default)",
             "liggghts_tdoff": "LIGGGHTS (tangential_damping off)", "tanh": "pdamper, tanh (default)",
             "spring": "pdamper, spring", "spring_tdoff": "pdamper, spring, tangential_damping off",
             "spring_tsuji": "pdamper, spring, Tsuji normal damping"}
    for (law, tilt), style in (((law, tilt), "-" if tilt == "paper" else "--")
                               for law in colours for tilt in ("paper", "none")):
        pts = sorted((r["stroke_mm"], r["eta_mean"], r["eta_min"], r["eta_max"]) for r in rows
                     if r["law"] == law and r["tilt"] == tilt)
        if not pts:
            continue
        x, m, lo, hi = map(np.array, zip(*pts))
        shift = 1.0 + (0.012 if tilt == "none" else -0.012) + 0.006 * list(colours).index(law)
        ax.errorbar(x * shift, m, yerr=[m - lo, hi - m], color=colours[law], ls=style, marker="o" if tilt == "paper" else "s",
                    ms=4, capsize=2, label=f"{names.get(law, law)}, {'0.1° tilt' if tilt == 'paper' else 'no tilt'}")
    ax.set_xscale("log")
    ticks = sorted({r["stroke_mm"] for r in rows})
    ax.set_xticks(ticks, [f"{t:g}" for t in ticks])
    ax.minorticks_off()
    ax.set_xlabel("stroke X [mm]")
    ax.set_ylabel("η* [-]")
    ax.set_title(f"{case}: seed mean, bars = range over seeds")
    ax.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))  # beside the axes: no data hidden
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def _list(text, kind=str):
    return [kind(t) for t in str(text).split(",") if t.strip()]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=_list, default=list(CASES), help=f"comma list of {', '.join(CASES)}")
    ap.add_argument("--strokes", type=lambda t: _list(t, float), default=None,
                    help="comma list of strokes [mm] for every case (default: each case's own)")
    ap.add_argument("--seeds", default="1,2,3", help="comma list of seeds, or a count N (seeds 1..N); default 1,2,3")
    ap.add_argument("--tilt", choices=("paper", "none", "both"), default="both")
    ap.add_argument("--codes", type=_list, default=["liggghts", "pdamper"], help="liggghts,pdamper")
    ap.add_argument("--liggghts", type=_list, default=["liggghts"],
                    help=f"LIGGGHTS variants: {', '.join(LIGGGHTS_LAWS)} (default liggghts: its default "
                         "model, tangential damping on)")
    ap.add_argument("--laws", type=_list, default=["tanh", "spring"],
                    help=f"pdamper's tangential laws: {', '.join(PDAMPER_LAWS)} or another value of "
                         "contact.tangential (default tanh,spring; one this pdamper lacks is skipped)")
    ap.add_argument("--friction", type=_list, default=["case"], help="'case' (the case's mu) and/or 0 (frictionless)")
    ap.add_argument("--settle-step", type=float, default=0.0,
                    help="seed k settles (k - 1) times this much longer [s] (default 0): a spread for a bed "
                         "whose seeds all start alike (the baffled one)")
    ap.add_argument("--dt", type=float, default=1e-6, help="LIGGGHTS' time step [s] (default 1e-6)")
    ap.add_argument("--jobs", type=int, default=2, help="worker processes (default 2)")
    ap.add_argument("--nice", type=int, default=10, help="niceness of the whole batch (default 10)")
    ap.add_argument("--results", type=Path, default=ROOT / "results" / "crosscheck",
                    help="results folder (default results/crosscheck, ignored by git)")
    ap.add_argument("--dry-run", action="store_true", help="list what would run, run nothing")
    ap.add_argument("--table-only", action="store_true", help="only print and write the table of stored runs")
    ap.add_argument("--figure", type=Path, default=None,
                    help="also draw eta* against the stroke of each case into this folder (crosscheck_<case>_eta.png)")
    args = ap.parse_args(argv)
    bad = [c for c in args.cases if c not in CASES]
    if bad:
        ap.error(f"--cases: unknown {', '.join(bad)}; known: {', '.join(CASES)}")
    bad = [c for c in args.liggghts if c not in LIGGGHTS_LAWS]
    if bad:
        ap.error(f"--liggghts: unknown {', '.join(bad)}; known: {', '.join(LIGGGHTS_LAWS)}")
    args.seeds = list(range(1, int(args.seeds) + 1)) if args.seeds.isdigit() and "," not in args.seeds \
        else _list(args.seeds, int)
    args.results.mkdir(parents=True, exist_ok=True)
    if args.table_only:
        print(write_table(args.results, args.cases))
        _figures(args)
        return 0
    if "liggghts" in args.codes and liggghts.available() is None:
        print(f"LIGGGHTS not found: its runs are skipped; {liggghts.INSTALL_HINT}")
        args.codes = [c for c in args.codes if c != "liggghts"]
    todo, skipped, done = [], [], 0
    starts: dict = {}
    for spec in matrix(args):
        case, config, key = prepare(spec, args.dt)
        if case is None:
            skipped.append(config)
            continue
        same = starts.setdefault(start_key(spec, case, config), spec_tag(spec))
        if same != spec_tag(spec):
            skipped.append(f"{spec['case']}: seed {spec['seed']} starts from the same positions as another seed "
                           "(no room for the jitter), so both codes would repeat that run: not run")
            continue
        if (args.results / "runs" / key).exists():
            done += 1
            continue
        todo.append(spec)
    for msg in sorted(set(skipped)):
        print(msg, f"({sum(m == msg for m in skipped)} runs)")
    todo.sort(key=_order(args.cases))
    print(f"{len(todo)} runs to do, {done} stored already, {len(skipped)} skipped; results in {args.results}")
    if args.dry_run:
        for s in todo:
            print("  ", s["code"], spec_tag(s))
        return 0
    os.nice(args.nice)
    failed = 0
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        futures = {pool.submit(run_one, s, args.dt, str(args.results)): s for s in todo}
        for k, fut in enumerate(as_completed(futures), 1):
            s = futures[fut]
            try:
                r = fut.result()
                print(f"[{k}/{len(todo)}] {s['code']:8s} {spec_tag(s)}: eta* = {r['result']['eta_star']:.4f} "
                      f"({r['result']['wall_time_s']:.0f} s)", flush=True)
            except Exception as exc:  # noqa: BLE001 - a failed run is reported, the batch goes on
                failed += 1
                print(f"[{k}/{len(todo)}] {s['code']:8s} {spec_tag(s)}: FAILED {type(exc).__name__}: "
                      f"{str(exc).splitlines()[0] if str(exc) else ''}", flush=True)
    print(write_table(args.results, args.cases))
    _figures(args)
    return 1 if failed else 0


def _figures(args):
    if args.figure is None:
        return
    args.figure.mkdir(parents=True, exist_ok=True)
    for case in args.cases:
        figure(args.results, case, args.figure / f"crosscheck_{case}_eta.png")


if __name__ == "__main__":
    sys.exit(main())
