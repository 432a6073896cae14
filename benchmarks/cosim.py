"""The coupling loop and the OpenSees co-simulation against pdamper's tight coupling, and the worked
example of docs/structure.md ("An OpenSees model: the engineer's own").

Usage::

    python benchmarks/cosim.py [--seeds 3] [--json OUT.json]

Part 1, the same linear frame three ways (examples/frame4_linear.py, one damper on the roof, the
synthetic record at 0.125 g, 10 s): the compiled tight coupling (the structure's modal step inside
the DEM step), the coupling loop on pdamper's exact linear modes, and the OpenSees co-simulation
(OpenSees' Newmark steps); every storey's peak and RMS per seed, their means and spreads, the
energy errors, the wall times and their ratios to the tight coupling's (the same machine, the same
run: timings are only comparable within it).

Part 2, the frame with storeys that yield (examples/frame4_yield.py), OpenSees co-simulated: bare,
one damper (examples/frame4_quake.toml), two dampers (examples/frame4_two_dampers.toml); peak and
residual displacement of every floor (relative to the ground) and every storey's peak and residual
drift ratio (pdamper.analysis.codes, storeys of 0.3 m).

Part 3, the coupling step: a locked bed (tests/dem_fixtures.py) on one mode under a pulse, the loop
at 2, 1, 0.5 and 0.25 ms against the exact structure carrying the bed.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
EX = ROOT / "examples"
sys.path.insert(0, str(ROOT / "tests"))


def _stats(x):
    return np.max(np.abs(x), axis=0), np.sqrt(np.mean(x * x, axis=0))


def part1(seeds):
    from pdamper.config import load_case
    from pdamper.cosim import run_coupled
    from pdamper.studies.structure_base import damped_run

    out = {}
    for how in ("tight", "loop", "opensees"):
        rows = []
        for seed in seeds:
            over = {"structure.opensees": "frame4_linear.py", "initial.seed": seed}
            if how == "opensees":
                over["structure.coupling"] = "opensees"
            case = load_case(EX / "frame4_quake.toml", over)
            t0 = time.perf_counter()
            if how == "loop":
                run = run_coupled(case)
                x, err = run.displacements, run.summary["interface_energy_error"]
            else:
                run = damped_run(case)
                x, err = run.dofs, (run.coupling or {}).get("interface_energy_error")
            wall = time.perf_counter() - t0
            peak, rms = _stats(x)
            rows.append({"seed": seed, "peak_m": peak.tolist(), "rms_m": rms.tolist(), "wall_s": wall,
                         "interface_energy_error": err})
            print(f"  {how:8s} seed {seed}: roof peak {1e3 * peak[-1]:.3f} mm, rms {1e3 * rms[-1]:.3f} mm, "
                  f"{wall:.1f} s" + (f", interface {err:.2g}" if err is not None else ""), flush=True)
        out[how] = rows
    return out


def part2(seeds):
    from pdamper.config import load_case
    from pdamper.studies.transient import run_transient

    out = {}
    for name in ("frame4_quake", "frame4_two_dampers"):
        rows = []
        for seed in seeds:
            t0 = time.perf_counter()
            s = run_transient(load_case(EX / f"{name}.toml", {"initial.seed": seed})).summary
            c = s["codes"]
            rows.append({"seed": seed, "peak_m": s["peak_m"], "residual_m": s["residual_m"], "rms_m": s["rms_m"],
                         "drift_peak": c["drift_ratio_peak"], "drift_residual": c["drift_ratio_residual"],
                         "wall_s": time.perf_counter() - t0,
                         "interface_energy_error": s["coupling"]["interface_energy_error"]})
            if "bare" not in out:
                out["bare"] = {"peak_m": s["peak_bare_m"], "residual_m": s["residual_bare_m"], "rms_m": s["rms_bare_m"],
                               "drift_peak": c["drift_ratio_peak_bare"], "drift_residual": c["drift_ratio_residual_bare"]}
                print(f"  bare: peak {np.round(1e3 * np.array(s['peak_bare_m']), 2)} mm, drift "
                      f"{np.round(100 * np.array(c['drift_ratio_peak_bare']), 3)} %, residual drift "
                      f"{np.round(100 * np.array(c['drift_ratio_residual_bare']), 3)} %", flush=True)
            print(f"  {name} seed {seed}: peak {np.round(1e3 * np.array(s['peak_m']), 2)} mm, drift "
                  f"{np.round(100 * np.array(c['drift_ratio_peak']), 3)} %, residual drift "
                  f"{np.round(100 * np.array(c['drift_ratio_residual']), 3)} %, {rows[-1]['wall_s']:.1f} s", flush=True)
        out[name] = rows
    return out


def part3():
    from dem_fixtures import locked_case
    from pdamper.cosim import run_coupled
    from pdamper.structure.linear import damper_motion

    case0 = locked_case('kind = "force_history"\ntime = [0, 0.01, 0.02, 0.0201]\nforce = [0, 2.0, 0, 0]\n'
                        'duration = 0.6')
    rows = []
    for h in (2e-3, 1e-3, 5e-4, 2.5e-4):
        case = dataclasses.replace(case0, drive=dataclasses.replace(case0.drive, coupling_step=h))
        run = run_coupled(case)
        xe = damper_motion(case.running_drive.carrying(case.bed_mass), run.time)[0]
        rows.append({"step_s": h, "displacement_error": float(np.max(np.abs(run.displacement - xe)) / np.max(np.abs(xe))),
                     "interface_energy_error": run.summary["interface_energy_error"],
                     "coupled_energy_balance_error": run.summary["coupled_energy_balance_error"]})
        print(f"  h = {1e3 * h:g} ms: displacement {rows[-1]['displacement_error']:.2g}, interface "
              f"{rows[-1]['interface_energy_error']:.2g}, coupled ledger {rows[-1]['coupled_energy_balance_error']:.2g}",
              flush=True)
    return rows


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--seeds", type=int, default=5)
    p.add_argument("--json")
    p.add_argument("--parts", default="123")
    a = p.parse_args(argv)
    seeds = list(range(a.seeds))
    out = {}
    if "1" in a.parts:
        print("part 1: the linear frame, tight coupling / loop / OpenSees co-simulation")
        out["linear"] = part1(seeds)
    if "2" in a.parts:
        print("part 2: the yielding frame, bare / one damper / two dampers")
        out["yielding"] = part2(seeds)
    if "3" in a.parts:
        print("part 3: the coupling step, a locked bed")
        out["step"] = part3()
    if a.json:
        Path(a.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
