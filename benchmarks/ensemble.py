"""An ensemble's wall time against its samples run one after another, measured in the same run.

    python benchmarks/ensemble.py [--samples 64] [--workers 2] [--serial 4] [--duration 20] [--out DIR]

The case (issue 39's): a 36-sphere damper (the paper's cuboid, 149 g of steel) on the top floor of a
3-storey shear frame (FE matrices written as Matrix Market files: 5 kg floors, storeys of 8987 N/m,
f_1 = 3.0 Hz, 0.4 % Rayleigh damping at modes 1 and 3) under a ground acceleration of ``--duration``
seconds (examples/make_loads.py's synthetic record, its strong motion 1.5-4.5 s, scaled so that the
top floor swings 15 mm without the damper). The unknowns: the frame's stiffness (normal, 5 %), the
friction (uniform 0.05-0.2), the record's scale (truncated normal, 15 %), the mounting tilt (uniform
0-0.2 deg) and the seed.

It runs ``--serial`` of the ensemble's samples one after another in this process
(:func:`pdamper.studies.transient.run_transient`, after a short warm-up run so that no compilation is
timed), then the whole ensemble of ``--samples`` on ``--workers`` local processes
(:func:`pdamper.studies.ensemble.run_ensemble`, a fresh store), and prints the ensemble's wall time
against ``--samples`` x the mean serial transient, and the CPU time the samples took in the workers
against the serial ones' (the same samples run in both), the load average, the summary and the JSON
(``--json FILE``). A timing on a machine shared with other work is a timing of that machine: the
CPU times say what the ensemble itself costs.
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import os
import shutil
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]

def unknowns(scale: float):
    """The unknowns (the tables a U.toml file holds), the record's ``scale`` the middle of its own."""
    from pdamper.studies.unknowns import Unknowns

    return Unknowns.from_tables([
        {"key": "structure.stiffness_scale", "distribution": "normal", "mean": 1.0, "std": 0.05},
        {"key": "contact.friction", "distribution": "uniform", "low": 0.05, "high": 0.2},
        {"key": "load.scale", "distribution": "truncated", "mean": scale, "std": 0.15 * scale, "low": 0.7 * scale,
         "high": 1.3 * scale},
        {"key": "container.tilt", "distribution": "uniform", "low": "0deg", "high": "0.2deg"},
        {"key": "initial.seed", "distribution": "uniform", "low": 0, "high": 999}], source="benchmarks/ensemble.py")


CASE = """# benchmarks/ensemble.py: 36 spheres on the top floor of a 3-storey frame under a ground acceleration
[container]
shape = "cuboid"
length = "120mm"
width = "40.4mm"
height = "40mm"
material = "pvc"
tilt = "0.1deg"

[particles]
count = 36
radius = "5mm"
material = "steel"

[structure]
matrices = {{M = "frame_M.mtx", K = "frame_K.mtx"}}
damper_dof = 2
rayleigh_modes = [1, 3]
rayleigh_ratios = [0.004, 0.004]

[load]
kind = "ground_acceleration"
file = "record.csv"
scale = {scale!r}
duration = "{duration}s"
"""

#: The frame: floor masses [kg] and storey stiffnesses [N/m] (f_1 = 3.0 Hz).
FLOORS, STOREY = (5.0, 5.0, 5.0), 8987.0
#: The top floor's peak without the damper the record is scaled to [m].
BARE_PEAK = 0.015


def write_case(folder: Path, duration: float) -> Path:
    """The frame's matrices, the record and the case file in ``folder``; returns the case file."""
    import scipy.io

    spec = importlib.util.spec_from_file_location("make_loads", ROOT / "examples" / "make_loads.py")
    loads = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(loads)
    t, a = loads.quake(duration=duration)
    (folder / "record.csv").write_text("time [s],acceleration [g]\n" + "".join(f"{x:.2f},{y:.6f}\n" for x, y in zip(t, a)))
    n = len(FLOORS)
    K = np.zeros((n, n))
    for i in range(n):  # storey i joins floor i to the one below it (the ground below floor 0)
        K[i, i] += STOREY
        if i + 1 < n:
            K[i, i] += STOREY
            K[i, i + 1] = K[i + 1, i] = -STOREY
    scipy.io.mmwrite(str(folder / "frame_M.mtx"), np.diag(FLOORS))
    scipy.io.mmwrite(str(folder / "frame_K.mtx"), K)
    path = folder / "frame_36.toml"
    path.write_text(CASE.format(scale=1.0, duration=duration))
    from pdamper.config import load_case
    from pdamper.structure.linear import dof_response

    s = load_case(path).running_drive
    tt = np.linspace(0.0, duration, int(200 * duration) + 1)
    peak = float(np.max(np.abs(dof_response(s, tt)[1][:, 2])))
    path.write_text(CASE.format(scale=round(BARE_PEAK / peak, 4), duration=duration))
    return path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--samples", type=int, default=64)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--serial", type=int, default=4, help="samples run one after another for the baseline")
    ap.add_argument("--duration", type=float, default=20.0, help="the record's length [s]")
    ap.add_argument("--out", type=Path, help="folder for the case, the store and the figures (default: a temporary one)")
    ap.add_argument("--json", type=Path, help="write the numbers here")
    args = ap.parse_args(argv)

    from pdamper.config import load_case
    from pdamper.studies.ensemble import EnsembleSpec, run_ensemble, summarize, summary_lines
    from pdamper.studies.transient import run_transient

    folder = args.out or Path(tempfile.mkdtemp(prefix="pdamper-ensemble-bench-"))
    folder.mkdir(parents=True, exist_ok=True)
    path = write_case(folder, args.duration)
    base = load_case(path)
    scale = base.drive.load.scale
    u = unknowns(scale)
    spec = EnsembleSpec(base=base, unknowns=u, samples=args.samples, study="transient")
    run_transient(load_case(path, {"load.duration": "0.2s"}))  # compile (or load the cache) untimed

    serial, serial_cpu = [], []
    for i in range(min(args.serial, args.samples)):
        t0, c0 = time.perf_counter(), time.process_time()
        run_transient(spec.case(i))
        serial.append(time.perf_counter() - t0)
        serial_cpu.append(time.process_time() - c0)
    one, one_cpu = float(np.mean(serial)), float(np.mean(serial_cpu))
    load_before = os.getloadavg()[0]

    store = folder / "store"
    shutil.rmtree(store, ignore_errors=True)
    t0 = time.perf_counter()
    ds = run_ensemble(base, u, args.samples, store, study="transient", workers=args.workers,
                      progress=False)
    wall = time.perf_counter() - t0
    load_after = os.getloadavg()[0]
    s = summarize(ds, target_peak_ratio=0.9, target_rms_ratio=0.8)
    in_workers = float(np.nansum(ds.wall_time.values))
    cpu_workers = float(np.nansum(ds.cpu_time.values))
    same = ds.isel(sample=slice(0, len(serial)))  # the serial samples, run again in the workers
    out = {
        "samples": args.samples, "workers": args.workers, "duration_s": args.duration, "particles": base.n_particles,
        "dofs": ds.dof.values.tolist(), "load_scale": scale, "serial_samples": len(serial), "serial_s": serial,
        "one_transient_s": one, "serial_estimate_s": args.samples * one, "ensemble_wall_s": wall,
        "ensemble_vs_serial": wall / (args.samples * one), "speedup": args.samples * one / wall,
        "sample_dem_time_sum_s": in_workers, "sample_dem_time_mean_s": in_workers / args.samples,
        "serial_cpu_s": serial_cpu, "one_transient_cpu_s": one_cpu, "sample_cpu_time_sum_s": cpu_workers,
        "same_samples_in_workers_wall_s": same.wall_time.values.tolist(),
        "same_samples_in_workers_cpu_s": same.cpu_time.values.tolist(),
        "steps_mean": float(np.mean(ds.steps.values)), "serial_steps_mean": float(np.mean(same.steps.values)),
        "load_average_before": load_before, "load_average_after": load_after, "cores": os.cpu_count(),
        "summary": s, "folder": str(folder),
    }
    print(f"{args.samples} samples of a {args.duration:g} s transient, {base.n_particles} spheres on a 3-storey frame, "
          f"{args.workers} workers")
    print(f"  one transient (mean of {len(serial)} run one after another here)   {one:8.1f} s "
          f"({', '.join(f'{x:.1f}' for x in serial)})")
    print(f"  {args.samples} x one transient                              {args.samples * one:8.1f} s")
    print(f"  the ensemble (run_ensemble, {args.workers} workers)              {wall:8.1f} s   "
          f"= {wall / (args.samples * one):.3f} x serial, speed-up {args.samples * one / wall:.2f}")
    print(f"  the samples' own wall time (in the workers)         {in_workers:8.1f} s   "
          f"(mean {in_workers / args.samples:.1f} s a sample)")
    print(f"  CPU: one transient here {one_cpu:.1f} s, the samples in the workers {cpu_workers:.1f} s "
          f"(mean {cpu_workers / args.samples:.1f} s; {args.samples} x one: {args.samples * one_cpu:.1f} s)")
    print(f"  the serial samples again in the workers: wall {', '.join(f'{x:.1f}' for x in same.wall_time.values)} s,"
          f" CPU {', '.join(f'{x:.1f}' for x in same.cpu_time.values)} s")
    print(f"  steps: the {args.samples} samples {np.mean(ds.steps.values):,.0f} a sample on average, the "
          f"{len(serial)} serial ones {np.mean(same.steps.values):,.0f}")
    print(f"  load average {load_before:.1f} before the ensemble, {load_after:.1f} after ({os.cpu_count()} cores)")
    print("\n".join(summary_lines(s)))
    if args.json:
        args.json.write_text(json.dumps(out, indent=2, default=lambda v: None if isinstance(v, float) and
                                        not math.isfinite(v) else str(v)))
    return out


if __name__ == "__main__":
    main()
