"""The GPU engine's benchmark: one command on one NVIDIA GPU (issue 38's targets).

    PYTHONUNBUFFERED=1 python benchmarks/gpu.py --out gpu.json [--budget-s 450] [--only PART ...]

What it runs, the bounded parts first (a part that overruns the device call's limit then loses only
what follows it), writing ``--out`` (JSON) after every part and a markdown summary at the end (also
``--out`` with ``.md``):

1. ``env``: the GPU, numba and numba-cuda, the commit, the CUDA driver, runtime and libNVVM versions.
2. ``compile``: the first GPU launch of the default kernel (numba-cuda typing, NVVM, the driver's
   PTX JIT; a launch with no steps) and the compiled kernel's registers per thread, shared and
   local memory, the blocks an SM can hold for beds of 36 to 256 spheres.
3. ``agree``: the GPU's kernels against the CPU engine on the GPU itself (the test suite holds them
   together only in numba-cuda's simulator, which runs the CPU-compiled functions): two fig4 cases,
   the settling and half a cycle, under Gear and Verlet with the tanh law and with the spring, each
   variant in a process of its own (a kernel that faults takes only its own; ``--agree-variants``
   picks them): the steps, the first sample at which the wall force parts from the CPU's, the final
   positions.
4. ``steps``: what a step costs: fig4's cases as one batch for ``--steps-seconds`` (10) under Gear with
   the tanh law (the default), the default's longest case alone, Verlet with the tanh law, Gear and
   Verlet with the spring: microseconds per step of the batch's most and least advanced case, and
   each kernel's compile.
5. ``bed``: the largest bed the GPU engine takes (256 spheres, the multi-layer bed of
   ``benchmarks/run.py``) for ``--bed-seconds`` (20): microseconds per step and per particle-step;
   the 5,000-sphere bed runs on the CPU engine (said, not run).
6. ``fig4``: ``run_study("fig4", device="cuda")`` as ``pdamper study fig4 --device cuda`` runs it
   (40 strokes x 20 cycles, 36 and 44 spheres, one seed, from an empty store): wall time, the
   longest case's steps and the per-step cost of a block, and eta* of every stroke against the CPU
   engine's seeds 0-2 (``benchmarks/data/fig4_cpu_reference.csv``) and every CPU run of
   ``fig4_cpu_spread.csv``. It runs to its end (no budget).
7. ``fig4_steady``: the same with ``--until-steady 0.02`` (each case stops once its record is steady,
   at the CPU engine's cycle): wall time, the longest case's steps, and per stroke the cycles run and
   eta* against the CPU engine's same command (``benchmarks/data/fig4_cpu_until_steady.csv``).
8. ``paper``: every distinct DEM curve of the paper (``benchmarks/run.py``'s ``paper_curves``) at
   the paper's 40 strokes, 20 cycles, one seed, as one GPU batch, to its end or to the budget
   (``--budget-s``, counted from the start): then what was done is said (steps done of all steps),
   never extrapolated into a figure.

``--tiny`` runs the same parts on tiny cases (a few soft spheres, a few hundred steps) in
numba-cuda's simulator (``NUMBA_ENABLE_CUDASIM=1``): the test suite's check that this script works
(tests/kernels/gpu/test_benchmark_gpu.py). ``--ptx --json FILE`` needs no GPU: it compiles the four
production kernels (Gear and Verlet, the tanh law and the spring) to PTX for sm_90 with the ``gpu``
extra's NVVM and reads ``ptxas -v`` (the ``nvidia-cuda-nvcc`` wheel's): per kernel its registers,
spill stores and loads, stack frame (local memory), static shared memory and parameter space [B],
and whether it keeps to 128 registers with no spills.

**On the project's GPU machines** (numba, numba-cuda, numpy, scipy, xarray, pandas, matplotlib, h5py
there; no package registry), the rest of pdamper's dependencies travel as wheels in the git-ignored
folder ``.whl/`` of the repository, fetched here by ``bash benchmarks/gpu_wheels.sh``; the device
call then runs ``bash benchmarks/gpu_device.sh`` (``carry`` names ``.whl``; docs/performance.md). The
figures go into docs/performance.md with the GPU's name.
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

BENCH = Path(__file__).resolve().parent
ROOT = BENCH.parent
REFERENCE = BENCH / "data" / "fig4_cpu_reference.csv"
PAPER_REFERENCE = BENCH / "data" / "paper_cpu_reference.csv"
SPREAD = BENCH / "data" / "fig4_cpu_spread.csv"
STEADY_REFERENCE = BENCH / "data" / "fig4_cpu_until_steady.csv"
PARTS = ("env", "compile", "agree", "steps", "fig4", "fig4_steady", "paper", "bed")
#: Parts run only when named (--only): none now (the spring kernel's fault part and the probed
#: kernel's profile went with the kernel they studied, docs/performance.md).
EXTRA_PARTS = ()
#: The tolerance of the ``fig4_steady`` part (``pdamper study fig4 --until-steady 0.02``).
STEADY_TOL = 0.02
#: The integrator the parts run with: None, each case's own (Gear, the paper's); "verlet" when Gear's
#: kernel failed to compile on this GPU (the compile part then tries Verlet's, so one device run
#: still measures something, and says so).
FALLBACK = {"integrator": None}
#: The issue's targets on one H100.
TARGET_FIG4_S = 10.0
TARGET_PAPER_S = 120.0
TARGET_COMPILE_S = 30.0


class Report:
    """The results so far, written to ``path`` (JSON) after every part."""

    def __init__(self, path):
        self.path = Path(path) if path else None
        self.data = {"started": time.strftime("%Y-%m-%d %H:%M:%S"), "parts": {}}

    def put(self, part, value):
        self.data["parts"][part] = value
        if self.path is not None:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self.path.write_text(json.dumps(self.data, indent=1, default=_plain))


def _plain(v):
    try:
        return float(v)
    except (TypeError, ValueError):
        return str(v)


def env_info():
    import numba
    import numpy

    out = {"python": platform.python_version(), "numpy": numpy.__version__, "numba": numba.__version__,
           "machine": platform.machine(), "cpus": os.cpu_count()}
    try:
        import importlib.metadata as md

        out["numba_cuda"] = md.version("numba-cuda")
    except Exception as exc:  # noqa: BLE001
        out["numba_cuda"] = f"not found ({exc})"
    try:
        out["commit"] = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True,
                                       text=True, timeout=10).stdout.strip()
    except Exception:  # noqa: BLE001
        out["commit"] = "?"
    from pdamper.engine.cuda import unavailable

    out["gpu_unavailable"] = unavailable()
    try:
        from numba import cuda

        if not cuda.jit.__module__.startswith("numba.cuda.simulator"):
            dev = cuda.get_current_device()
            out["gpu"] = dev.name.decode() if isinstance(dev.name, bytes) else str(dev.name)
            out["compute_capability"] = list(dev.compute_capability)
            out["multiprocessors"] = int(dev.MULTIPROCESSOR_COUNT)
        else:
            out["gpu"] = "numba-cuda simulator"
    except Exception as exc:  # noqa: BLE001
        out["gpu"] = f"? ({exc})"
    try:
        smi = subprocess.run(["nvidia-smi", "--query-gpu=name,driver_version,memory.total", "--format=csv,noheader"],
                             capture_output=True, text=True, timeout=20)
        out["nvidia_smi"] = smi.stdout.strip()
    except Exception:  # noqa: BLE001
        pass
    import shutil

    out["profilers"] = {p: shutil.which(p) for p in ("ncu", "nsys", "compute-sanitizer", "nvdisasm")}
    out["cuda"] = cuda_stack()
    print("env:", json.dumps(out), flush=True)
    return out


def cuda_stack():
    """The CUDA software the kernels go through, as far as it answers: the driver's CUDA version,
    the runtime's, libNVVM's (the compiler from numba's IR to PTX; the driver then compiles the PTX
    for the GPU) and where it was found, cuda-core and cuda-bindings (numba-cuda's launcher)."""
    import importlib.metadata as md

    out = {}
    for name in ("cuda-core", "cuda-bindings"):
        try:
            out[name] = md.version(name)
        except Exception:  # noqa: BLE001
            out[name] = None
    probes = {"driver": lambda: __import__("numba.cuda.cudadrv.driver", fromlist=["driver"]).driver.get_version(),
              "runtime": lambda: __import__("numba.cuda.cudadrv.runtime", fromlist=["runtime"]).runtime.get_version(),
              "nvvm": lambda: __import__("numba.cuda.cudadrv.nvvm", fromlist=["NVVM"]).NVVM().get_version(),
              "nvvm_path": lambda: str(__import__("numba.cuda.cuda_paths", fromlist=["get_cuda_paths"])
                                       .get_cuda_paths()["nvvm"])}
    for name, probe in probes.items():
        try:
            v = probe()
            out[name] = list(v) if isinstance(v, tuple) else v
        except Exception as exc:  # noqa: BLE001
            out[name] = f"? ({type(exc).__name__})"
    return out


# ---------------------------------------------------------------------------------------------- cases
def _soft(case):
    """A tiny stand-in of ``case`` for the simulator: at most 4 soft spheres (long contacts, a 1 ms
    step), a 2 mm stroke at 10 Hz, 2 cycles sampled at 200 Hz, with Verlet (the simulator's barriers
    are slow, and Gear's step has more of them): about 210 steps."""
    from pdamper.materials import Material
    from pdamper.schema import replace

    soft = Material(name="soft", youngs_modulus=3e4, poisson_ratio=0.3, density=7800.0)
    parts = tuple(dataclasses.replace(p, material=soft, count=min(p.count, 4)) for p in case.particles)
    case = dataclasses.replace(case, particles=parts, cycles=2, drop_cycles=1)
    return replace(case, {"drive.stroke": 0.002, "drive.frequency": 10.0, "recording.sample_rate": 200.0,
                          "numerics.time_step": 1e-3, "numerics.overlap_limit": 0.45, "initial.settle_time": 0.01,
                          "numerics.integrator": "verlet"})


def _integrator(case):
    """``case`` with the fallback integrator when there is one (:data:`FALLBACK`)."""
    if FALLBACK["integrator"] is None:
        return case
    return dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator=FALLBACK["integrator"]))


def fig4_cases(tiny):
    """fig4's ``(setting label, stroke, case)`` at seed 0."""
    from pdamper.schema import replace
    from pdamper.studies.named import load_study
    from pdamper.studies.sweep import STROKE, parse_axis

    study = load_study("fig4")
    strokes = next(a for a in map(parse_axis, study.vary) if a.key == STROKE).values
    if tiny:
        strokes = strokes[:1]
    out = []
    for label, case, _ in study.settings:
        for x in strokes:
            c = replace(case, {STROKE: float(x), "initial.seed": 0})
            out.append((label, float(x), _soft(c) if tiny else c))
    return out


def beyond_fig4(indices, n):
    """What is wrong with ``indices`` into fig4's ``n`` cases (:func:`fig4_cases`), or None: the
    message of every command line that picks fig4 cases by index."""
    bad = [k for k in indices if not 0 <= k < n]
    return f"{bad}: fig4 has cases 0-{n - 1} (36 spheres first, strokes ascending)" if bad else None


def make_reference(study_dir):
    """``benchmarks/data/fig4_cpu_reference.csv`` from the study directory of
    ``pdamper study fig4 --seeds 3 --out DIR`` (the CPU engine): per setting and stroke, eta* of each
    seed, their mean, min and max."""
    import numpy as np
    import xarray as xr

    ds = xr.load_dataset(Path(study_dir) / "study.nc", engine="h5netcdf")
    seeds = [int(s) for s in ds.seed.values]
    REFERENCE.parent.mkdir(parents=True, exist_ok=True)
    with REFERENCE.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["setting", "stroke_m", "eta_mean", "eta_min", "eta_max", "seeds"] + [f"eta_seed{s}" for s in seeds])
        for k, label in enumerate(ds.setting.values.tolist()):
            for j, x in enumerate(ds.stroke.values.tolist()):
                e = np.asarray(ds.eta_star.values[k, j, :], dtype=float)
                w.writerow([label, repr(float(x)), f"{np.nanmean(e):.6f}", f"{np.nanmin(e):.6f}", f"{np.nanmax(e):.6f}",
                            int(np.sum(np.isfinite(e)))] + [f"{v:.6f}" for v in e])
    print(f"wrote {REFERENCE} ({ds.sizes['setting']} settings x {ds.sizes['stroke']} strokes x {len(seeds)} seeds)")


def make_steady_reference(study_dir):
    """``benchmarks/data/fig4_cpu_until_steady.csv`` from the study directory of ``pdamper study fig4
    --until-steady 0.02 --out DIR`` (the CPU engine, seed 0): per setting and stroke, the cycles run,
    the steps and eta*."""
    import xarray as xr

    ds = xr.load_dataset(Path(study_dir) / "study.nc", engine="h5netcdf")
    with STEADY_REFERENCE.open("w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["setting", "stroke_m", "until_steady", "cycles_run", "steps", "eta_star"])
        for k, label in enumerate(ds.setting.values.tolist()):
            for j, x in enumerate(ds.stroke.values.tolist()):
                w.writerow([label, repr(float(x)), STEADY_TOL, f"{float(ds.cycles_run.values[k, j, 0]):g}",
                            int(ds.steps.values[k, j, 0]), f"{float(ds.eta_star.values[k, j, 0]):.6f}"])
    print(f"wrote {STEADY_REFERENCE} ({ds.sizes['setting']} settings x {ds.sizes['stroke']} strokes)")


def read_spread():
    """The CPU engine's further runs of fig4 strokes (``benchmarks/fig4_spread.py``: more seeds,
    round-off nudges of seed 0): ``{(setting, stroke rounded): [eta*, ...]}``."""
    if not SPREAD.exists():
        return {}
    out = {}
    with SPREAD.open() as f:
        for r in csv.DictReader(f):
            if math.isfinite(float(r["eta_star"])):
                out.setdefault((r["setting"], round(float(r["stroke_m"]), 9)), []).append(float(r["eta_star"]))
    return out


def read_reference():
    """The CPU engine's fig4: ``{(setting, stroke rounded): row}``."""
    if not REFERENCE.exists():
        return {}
    with REFERENCE.open() as f:
        rows = list(csv.DictReader(f))
    return {(r["setting"], round(float(r["stroke_m"]), 9)): r for r in rows}


# ---------------------------------------------------------------------------------------------- parts
def part_compile(tiny):
    """The first launch (compiling) and the compiled kernel's resources."""
    from pdamper.run import on_device
    from pdamper.simulation import Simulation, run_on_gpu

    label, x, case = fig4_cases(tiny)[0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(on_device(case, "cuda"))
    t = time.perf_counter()
    out = {}
    try:
        run_on_gpu([sim], compile_only=True)
    except Exception as exc:  # noqa: BLE001  (Gear's kernel did not compile here: measure Verlet's)
        import traceback

        traceback.print_exc()
        out["gear_failed"] = f"{type(exc).__name__}: {' '.join(str(exc).split())[:400]}"
        print(f"compile: Gear's kernel failed ({out['gear_failed']}); the parts run with Verlet", flush=True)
        FALLBACK["integrator"] = "verlet"
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sim = Simulation(_integrator(on_device(case, "cuda")))
        t = time.perf_counter()
        run_on_gpu([sim], compile_only=True)
    out.update(first_launch_s=time.perf_counter() - t, target_s=TARGET_COMPILE_S)
    out.update(kernel_resources(sim))
    print(f"compile: first launch {out['first_launch_s']:.1f} s; {json.dumps({k: v for k, v in out.items() if k != 'first_launch_s'})}",
          flush=True)
    return out


def kernel_resources(sim):
    """Registers per thread, shared and local memory of the compiled kernel, and the blocks of a
    bed's size an SM holds by each limit (H100: 65,536 registers, 228 KiB shared memory, 2,048
    threads, 32 blocks per SM; a block's shared memory is the kernel's static array plus the
    spheres' hot state, :data:`pdamper.kernels.gpu.batch.SHARED_FIELDS` doubles a sphere)."""
    from pdamper.engine.cuda import kernel_for, threads_for
    from pdamper.kernels.gpu.batch import SHARED_FIELDS

    out = {"kernel": "gear" if sim.stepper.rejected is not None else "verlet"}
    try:
        k = kernel_for(out["kernel"])
        regs = k.get_regs_per_thread()
        smem = k.get_shared_mem_per_block()
        local = k.get_local_mem_per_thread()
        regs = list(regs.values())[0] if isinstance(regs, dict) else regs
        smem = list(smem.values())[0] if isinstance(smem, dict) else smem
        local = list(local.values())[0] if isinstance(local, dict) else local
        out.update(registers_per_thread=int(regs), static_shared_bytes_per_block=int(smem),
                   local_bytes_per_thread=int(local))
        for n in (36, 44, 144, 176, 256):
            t = threads_for(n)
            shared = int(smem) + 8 * SHARED_FIELDS * n
            by_regs = 65536 // max(1, int(regs) * t)
            by_smem = (228 * 1024) // max(1, shared + 1024)
            out[f"blocks_per_sm_{n}"] = {"threads": t, "shared_bytes": shared, "by_registers": by_regs,
                                         "by_shared": by_smem, "by_threads": 2048 // t,
                                         "blocks": min(32, by_regs, by_smem, 2048 // t)}
    except Exception as exc:  # noqa: BLE001  (the simulator has no compiled kernel)
        out["resources"] = f"not available ({type(exc).__name__}: {exc})"
    return out


def _tiny_study(workdir):
    """fig4's study file with each setting's case made tiny (:func:`_soft`) and one stroke: the
    same ``run_study`` path, a few hundred steps a case."""
    from pdamper.config import dumps_case
    from pdamper.studies.named import load_study

    work = Path(workdir)
    study = load_study("fig4")
    rows = []
    for k, (label, case, panel) in enumerate(study.settings):
        (work / f"tiny{k}.toml").write_text(dumps_case(_soft(case)))
        rows.append(f'[[setting]]\nlabel = "{label}"\nconfig = "tiny{k}.toml"\npanel = "{panel}"\n')
    path = work / "fig4_tiny.toml"
    path.write_text('title = "fig4, tiny"\nfigure = "sweep"\nvary = ["drive.stroke=2mm"]\n\n' + "\n".join(rows))
    return path


def _fallback_study(workdir):
    """fig4's study file with every setting on the fallback integrator."""
    from pdamper.studies.named import load_study

    study = load_study("fig4")
    text = Path(study.source).read_text()
    text = text.replace('base = "cuboid_36"', f'base = "cuboid_36"\nset = {{ "numerics.integrator" = "{FALLBACK["integrator"]}" }}')
    text = text.replace('base = "cuboid_44"', f'base = "cuboid_44"\nset = {{ "numerics.integrator" = "{FALLBACK["integrator"]}" }}')
    path = Path(workdir) / "fig4_fallback.toml"
    path.write_text(text)
    return path


def _study_fig4(tiny, workdir, out, **kw):
    """``pdamper study fig4 --device cuda`` (seed 0; the tiny study, or the fallback integrator's, as
    the run asks) into ``workdir/out`` from an empty store, with ``kw`` of ``run_study``: its dataset
    and wall time [s]."""
    from pdamper.studies.named import run_study

    name = _tiny_study(workdir) if tiny else ("fig4" if FALLBACK["integrator"] is None else _fallback_study(workdir))
    t = time.perf_counter()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ds = run_study(name, Path(workdir) / out, seeds=(0,), device="cuda", progress=False, **kw)
    return ds, time.perf_counter() - t


def part_fig4(tiny, workdir):
    """``pdamper study fig4 --device cuda``, timed, and its eta* against the CPU reference."""
    import numpy as np

    ds, wall = _study_fig4(tiny, workdir, "fig4")
    etas = {}
    for k, label in enumerate(ds.setting.values.tolist()):
        for j, x in enumerate(ds.stroke.values.tolist()):
            etas[(str(label), round(float(x), 9))] = float(ds.eta_star.values[k, j, 0])
    steps = [int(v) for v in np.ravel(ds["steps"].values) if np.isfinite(v)] if "steps" in ds else []
    ref = read_reference()
    more = read_spread()
    within, devs, compared, within3, within_all, runs = 0, [], 0, 0, 0, []
    table = []
    for (label, x), eta in sorted(etas.items()):
        r = ref.get((label, x))
        if r is None:
            table.append({"setting": label, "stroke_m": x, "eta_gpu": eta})
            continue
        lo, hi, mean = float(r["eta_min"]), float(r["eta_max"]), float(r["eta_mean"])
        seeds = [float(v) for k, v in r.items() if k.startswith("eta_seed")]
        std = float(np.std(seeds, ddof=1)) if len(seeds) > 1 else math.nan
        compared += 1
        ok = lo <= eta <= hi
        within += ok
        # a fourth sample of the same spread falls inside three seeds' range only half the time: say
        # also how many strokes are within 3 standard deviations of the seeds' mean
        z = (eta - mean) / max(std, 1e-12)
        within3 += abs(z) <= 3.0
        devs.append(z)
        # every CPU run of this stroke: seeds 0-2 and what benchmarks/fig4_spread.py added
        every = seeds + more.get((label, x), [])
        in_all = min(every) <= eta <= max(every)
        within_all += in_all
        runs.append(len(every))
        table.append({"setting": label, "stroke_m": x, "eta_gpu": eta, "eta_cpu_mean": mean, "eta_cpu_min": lo,
                      "eta_cpu_max": hi, "eta_cpu_std": std, "within": ok, "z": z, "cpu_runs": len(every),
                      "eta_cpu_all_min": min(every), "eta_cpu_all_max": max(every), "within_all_runs": in_all})
    longest = max(steps) if steps else 0
    out = {"wall_s": wall, "cases": len(etas), "target_s": TARGET_FIG4_S, "longest_case_steps": longest,
           "us_per_step_per_block": 1e6 * wall / longest if longest else math.nan,
           "compared_with_cpu": compared, "within_cpu_seed_range": within, "within_3_std": within3,
           "within_every_cpu_run": within_all, "cpu_runs_per_stroke": [min(runs, default=0), max(runs, default=0)],
           "max_abs_z": max((abs(d) for d in devs), default=math.nan),
           "mean_z": float(np.mean(devs)) if devs else math.nan, "strokes": table}
    print(f"fig4: {len(etas)} cases in {wall:.1f} s (target {TARGET_FIG4_S:g} s); longest case {longest} steps "
          f"= {out['us_per_step_per_block']:.2f} us/step per block; eta* within the CPU's seeds 0-2 range at {within} "
          f"of {compared} strokes, within 3 std of their mean at {within3} (max |z| {out['max_abs_z']:.2f}, mean z "
          f"{out['mean_z']:+.2f}); within the range of every CPU run of the stroke ({min(runs, default=0)}-"
          f"{max(runs, default=0)} runs) at {within_all}", flush=True)
    return out


def part_fig4_steady(tiny, workdir):
    """``pdamper study fig4 --device cuda --until-steady 0.02``, timed: the longest case's steps, and
    per stroke the cycles run and eta* against the CPU engine's run of the same command."""
    import numpy as np

    ds, wall = _study_fig4(tiny, workdir, "fig4_steady", until_steady=STEADY_TOL)
    ref = {}
    if STEADY_REFERENCE.exists():
        with STEADY_REFERENCE.open() as f:
            ref = {(r["setting"], round(float(r["stroke_m"]), 9)): r for r in csv.DictReader(f)}
    table, same, devs = [], 0, []
    for k, label in enumerate(ds.setting.values.tolist()):
        for j, x in enumerate(ds.stroke.values.tolist()):
            row = {"setting": str(label), "stroke_m": float(x), "cycles_run": float(ds.cycles_run.values[k, j, 0]),
                   "steps": float(ds.steps.values[k, j, 0]), "eta_gpu": float(ds.eta_star.values[k, j, 0])}
            r = ref.get((str(label), round(float(x), 9)))
            if r is not None:
                row.update(cycles_cpu=float(r["cycles_run"]), steps_cpu=int(r["steps"]), eta_cpu=float(r["eta_star"]))
                same += row["cycles_run"] == row["cycles_cpu"]
                devs.append(row["eta_gpu"] - row["eta_cpu"])
            table.append(row)
    steps = [r["steps"] for r in table if math.isfinite(r["steps"])]
    longest = int(max(steps)) if steps else 0
    out = {"wall_s": wall, "cases": len(table), "until_steady": STEADY_TOL, "longest_case_steps": longest,
           "cycles_run": [min(r["cycles_run"] for r in table), max(r["cycles_run"] for r in table)],
           "compared_with_cpu": len(devs), "same_cycles_as_cpu": same,
           "mean_abs_eta_dev_vs_cpu": float(np.mean(np.abs(devs))) if devs else math.nan, "strokes": table}
    print(f"fig4 --until-steady {STEADY_TOL:g}: {len(table)} cases in {wall:.1f} s; longest case {longest} steps; "
          f"cycles run {out['cycles_run'][0]:g}-{out['cycles_run'][1]:g}; the CPU's cycles at {same} of {len(devs)} "
          f"strokes, eta* {out['mean_abs_eta_dev_vs_cpu']:.4f} from the CPU's on average", flush=True)
    return out


def part_bed(tiny, seconds):
    """The largest bed the GPU engine takes (:data:`pdamper.kernels.gpu.batch.MAX_SPHERES`, the
    multi-layer bed of ``benchmarks/run.py`` at that count, one case) for about ``seconds``: the cost
    of a step; and the 5,000-sphere bed, which the GPU engine leaves to the CPU engine: the line it
    says (not run)."""
    from pdamper.engine.cuda import takes
    from pdamper.kernels.gpu.batch import MAX_SPHERES
    from pdamper.run import on_device
    from pdamper.simulation import Simulation, run_on_gpu

    sys.path.insert(0, str(BENCH))
    from run import big_bed  # noqa: E402  (benchmarks/run.py's bed)

    case = big_bed(12 if tiny else MAX_SPHERES)
    case = dataclasses.replace(case, cycles=1.0, drop_cycles=0)
    if tiny:
        case = _soft(case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(_integrator(on_device(case, "cuda")))
    t0 = time.perf_counter()

    def stop(done, total):
        return time.perf_counter() - t0 < seconds

    rec = run_on_gpu([sim], progress=stop)[0]
    wall = time.perf_counter() - t0
    steps = sim.stepper.steps
    big = big_bed(5000)
    out = {"particles": sim.n, "steps": steps, "wall_s": wall, "finished": not isinstance(rec, Exception),
           "us_per_step": 1e6 * wall / max(steps, 1), "ns_per_particle_step": 1e9 * wall / max(steps, 1) / sim.n,
           "big_particles": big.n_particles,
           "big": "on the GPU" if takes(big) else "runs on the CPU engine (pdamper.engine.cuda.takes)"}
    print(f"bed: {sim.n} spheres, {steps} steps in {wall:.1f} s = {out['us_per_step']:.1f} us/step "
          f"({out['ns_per_particle_step']:.1f} ns per particle-step); {big.n_particles} spheres: {out['big']}",
          flush=True)
    return out


#: The variants of :func:`part_steps`: (name, integrator, tangential law, cases, threads a block:
#: None, one a sphere).
STEP_VARIANTS = (("gear, tanh (the default)", "gear", "tanh", "all", None),
                 ("gear, tanh, the longest case alone", "gear", "tanh", "one", None),
                 ("verlet, tanh (no error control, no pass)", "verlet", "tanh", "all", None),
                 ("gear, spring", "gear", "spring", "all", None),
                 ("verlet, spring", "verlet", "spring", "all", None))


def part_steps(tiny, seconds, variants=STEP_VARIANTS):
    """Where a step's time goes, by what changes it: fig4's cases (seed 0, as one batch) run for
    ``seconds`` under each of :data:`STEP_VARIANTS`: Gear with the tanh law (the default), Verlet
    (no error reduction, no pass, no rejected steps) with the tanh law and with the tangential spring
    (Gear's spring kernel is refused on a GPU; the profile part gives the implicit pass's share),
    the default's longest case alone on the GPU (the batch's step against one block's: what sharing
    the GPU costs), and the default with one warp a block (two spheres a thread: fewer idle threads and barrier
    levels, more serial work).
    Each variant's kernel compiles first (timed on its own); then microseconds per step of the
    batch's most advanced case and of its least advanced (a launch after the first is bounded by
    time, so each case takes the steps its own step's cost allows: the two differ by how much the
    cases' steps do). The window is each batch's first ``seconds`` (the settling and the
    drive's start), the same for every variant; the tangential laws' runs are other physics, so only
    their step cost is compared."""
    from pdamper.errors import InputError
    from pdamper.run import on_device
    from pdamper.simulation import Simulation, run_on_gpu

    base = fig4_cases(tiny)
    out = {"seconds": seconds, "variants": {}}
    for name, integrator, tangential, which, threads in variants:
        chosen = base if which == "all" else [max(base, key=lambda c: c[1])]
        cases = []
        for _, _, case in chosen:
            c = dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator=integrator),
                                    contact=dataclasses.replace(case.contact, tangential=tangential))
            cases.append(on_device(c, "cuda"))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            first = Simulation(cases[0])
            t = time.perf_counter()
            try:
                run_on_gpu([first], compile_only=True, threads=threads)
            except InputError as exc:  # a variant the GPU engine refuses says so; the others go on
                out["variants"][name] = {"refused": str(exc)}
                print(f"steps: {name}: refused: {exc}", flush=True)
                continue
            compile_s = time.perf_counter() - t
            sims = [Simulation(c) for c in cases]
            t0 = time.perf_counter()
            run_on_gpu(sims, progress=lambda done, total: time.perf_counter() - t0 < seconds, threads=threads)
            wall = time.perf_counter() - t0
        steps = max(sim.stepper.steps for sim in sims)
        least = min(sim.stepper.steps for sim in sims)
        v = {"cases": len(sims), "compile_s": compile_s, "wall_s": wall, "steps": steps, "steps_least": least,
             "us_per_step_per_block": 1e6 * wall / max(steps, 1),
             "us_per_step_least_advanced": 1e6 * wall / max(least, 1)}
        out["variants"][name] = v
        print(f"steps: {name}: {len(sims)} cases, {steps} steps in {wall:.1f} s = {v['us_per_step_per_block']:.2f} "
              f"us/step per block ({v['us_per_step_least_advanced']:.2f} for the least advanced case; compile "
              f"{compile_s:.1f} s)", flush=True)
    return out


#: The variants of :func:`part_agree`: (name, integrator, tangential law).
AGREE_VARIANTS = (("gear, tanh", "gear", "tanh"), ("verlet, tanh", "verlet", "tanh"),
                  ("verlet, spring", "verlet", "spring"), ("gear, spring", "gear", "spring"))


def agree_one(tiny, k, report=None):
    """Variant ``k`` of :data:`AGREE_VARIANTS` on both engines: two fig4 cases (36 and 44 spheres,
    seed 0, the settling and half a cycle of the drive; with ``tiny`` the soft stand-ins, no
    settling and a hundredth of a cycle), each on
    the CPU engine and both as one GPU batch; per case the steps, the wall force sample by sample
    and the final positions against the CPU's."""
    import numpy as np

    from pdamper.run import on_device
    from pdamper.schema import replace
    from pdamper.simulation import Simulation, run_on_gpu

    name, integrator, tangential = AGREE_VARIANTS[k]
    cases = fig4_cases(tiny)
    picked = [cases[0], cases[-1]] if tiny else [cases[20], cases[60]]
    built = []
    for _, _, case in picked:
        if tiny:  # (a few hundred steps in the simulator)
            case = dataclasses.replace(replace(case, {"recording.sample_rate": 5000.0, "initial.settle_time": 0.0}),
                                       cycles=0.01, drop_cycles=0)
        c = dataclasses.replace(case, cycles=min(case.cycles, 0.5), drop_cycles=0,
                                numerics=dataclasses.replace(case.numerics, integrator=integrator),
                                contact=dataclasses.replace(case.contact, tangential=tangential))
        built.append(c)
    on_gpu = [on_device(c, "cuda") for c in built]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = [Simulation(c) for c in built]
        for sim in cpu:
            sim.run()
        gpu = [Simulation(c) for c in on_gpu]
        if report is not None:  # (what it is, kept if the run then faults)
            report.put("agree_one", {"variant": name})
        out = run_on_gpu(gpu)
    rows = []
    for (label, _, _), a, b, rec in zip(picked, cpu, gpu, out):
        fa, fb = np.asarray(a.samples.wall_force), np.asarray(b.samples.wall_force)
        peak = max(float(np.max(np.abs(fa))), 1e-300)
        apart = np.nonzero(np.abs(fa - fb) > 1e-9 * peak)[0]
        pa, pb = a.engine.bodies.position, b.engine.bodies.position
        rows.append({"setting": label, "spheres": int(a.n),
                     "failed": None if not isinstance(rec, Exception) else str(rec)[:200],
                     "steps_cpu": int(a.stepper.steps), "steps_gpu": int(b.stepper.steps), "samples": int(fa.size),
                     "first_sample_apart": int(apart[0]) if apart.size else None,
                     "max_wall_force_diff_over_peak": float(np.max(np.abs(fa - fb))) / peak,
                     "max_position_diff_over_radius": float(np.max(np.abs(pa - pb)) / np.min(a.engine.bodies.radius))})
    return {"variant": name, "cases": rows}


def part_agree(tiny, variants=None):
    """Do the GPU's kernels compute what the CPU engine computes, on the GPU itself? (The test suite
    holds them together in numba-cuda's simulator, which runs the CPU-compiled functions.) Each of
    :data:`AGREE_VARIANTS` in a process of its own (a kernel that faults takes its CUDA context
    with it): :func:`agree_one`; a variant whose process fails says how."""
    out = {}
    for k, (name, _, _) in enumerate(AGREE_VARIANTS):
        if variants is not None and k not in variants:
            continue
        v = _in_own_process("agree_one", k, name, tiny)
        out[name] = v
        for row in v.get("cases", []):
            print("agree: " + _agree_line(name, row), flush=True)
        if "fault" in v:
            print(f"agree: {name}: {v['fault']}", flush=True)
    return out


def _in_own_process(part, k, name, tiny, extra=()):
    """Variant ``k`` (called ``name``) of ``part`` (``agree_one``, ``fault_one``: run by
    ``--agree-one K``, ``--fault-one K``) in a process of its own, since a kernel that faults takes
    its process's CUDA context with it: what that process reported, to its end or up to its fault
    (each writes what it knows before it runs), and ``fault`` when it did not end well (its own
    words, else its exit status and last lines)."""
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "one.json"
        cmd = [sys.executable, str(Path(__file__).resolve()), "--" + part.replace("_", "-"), str(k), "--out", str(path),
               *extra] + (["--tiny"] if tiny else [])
        r = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
        v = {"variant": name}
        if path.exists():
            v.update(json.loads(path.read_text())["parts"][part])
        if r.returncode != 0 or not path.exists():
            tail = [ln for ln in (r.stdout + r.stderr).splitlines() if ln.strip()][-3:]
            v["fault"] = v.get("fault") or f"exit {r.returncode}: " + " | ".join(tail)[:600]
    return v


def _agree_line(name, row):
    """One case of a variant of the agree part, in words (the log and the markdown summary)."""
    return (f"{name}, {row['setting']}, {row['spheres']} spheres: steps CPU {row['steps_cpu']} GPU "
            f"{row['steps_gpu']}; wall force apart from sample {row['first_sample_apart']} of {row['samples']} (max "
            f"{row['max_wall_force_diff_over_peak']:.1e} of its peak); positions "
            f"{row['max_position_diff_over_radius']:.1e} radii apart at the end")


def paper_cases(tiny, device="cuda"):
    """Every distinct DEM curve of the paper (``benchmarks/run.py``'s ``paper_curves``) at the
    paper's 40 strokes, seed 0, on ``device``: ``[(curve label, stroke, case)]``."""
    from pdamper.schema import replace
    from pdamper.studies.sweep import stroke_grid

    sys.path.insert(0, str(BENCH))
    from run import paper_curves  # noqa: E402

    curves = paper_curves()
    strokes = stroke_grid(0.5e-3, 50e-3, 40)
    if tiny:
        curves, strokes = curves[:2], strokes[:1]
    out = []
    for label, case in curves:
        for x in strokes:
            c = replace(case, {"drive.stroke": float(x), "initial.seed": 0, "numerics.device": device})
            out.append((label, float(x), _soft(c) if tiny else _integrator(c)))
    return out


def make_paper_reference(path=None):
    """``benchmarks/data/paper_cpu_reference.csv``: every case of :func:`paper_cases` on the CPU
    engine (all cores, as ``pdamper study``), a row written as each case finishes; a rerun skips the
    rows already there (an interrupted run keeps what finished)."""
    path = Path(path) if path else PAPER_REFERENCE
    done = set(read_paper_reference(path))
    items = [((label, x), x, 0, case) for label, x, case in paper_cases(False, device="cpu")
             if (label, round(x, 9)) not in done]
    t0 = time.perf_counter()
    append_runs(path, ["curve", "stroke_m", "eta_star", "steps", "wall_time_s", "failed"], items,
                lambda key, r: [key[0], repr(key[1]), f"{r['eta_star']:.6f}" if "eta_star" in r else "nan",
                                r.get("steps", ""), f"{r['wall_time_s']:.2f}" if "wall_time_s" in r else "",
                                " ".join(r.get("failed", "").split())])
    print(f"{path}: {len(items)} cases run in {time.perf_counter() - t0:.0f} s ({len(done)} were there)")


def append_runs(path, header, items, row):
    """Run the ``(key, point, seed, case)`` of ``items`` on the CPU engine (all cores, as ``pdamper
    study``: :func:`pdamper.studies.executor.execute`) and append ``row(key, result)`` to the CSV
    ``path`` as each finishes (``header`` first when the file is new): an interrupted run keeps
    what finished."""
    from pdamper.studies.executor import execute
    from pdamper.studies.sweep import run_one

    new = not Path(path).exists()
    Path(path).parent.mkdir(parents=True, exist_ok=True)
    with Path(path).open("a", newline="") as f:
        w = csv.writer(f)
        if new:
            w.writerow(header)
            f.flush()

        def store(key, x, seed, r):
            w.writerow(row(key, r))
            f.flush()

        if items:
            execute(items, lambda c: run_one(c, keep="none"), store)


def read_paper_reference(path=None):
    """The CPU engine's paper cases: ``{(curve, stroke rounded): row}``."""
    path = Path(path) if path else PAPER_REFERENCE
    if not path.exists():
        return {}
    with path.open() as f:
        return {(r["curve"], round(float(r["stroke_m"]), 9)): r for r in csv.DictReader(f)}


def part_paper(tiny, deadline):
    """Every distinct DEM curve of the paper at its 40 strokes, one batch, stopped at ``deadline``."""
    from pdamper.run import run_cases

    both = paper_cases(tiny)
    curves = sorted({label for label, _, _ in both})
    cases = [c for _, _, c in both]
    t0 = time.perf_counter()
    seen = {"done": 0, "total": 0}

    def stop(done, total):
        seen.update(done=done, total=total)
        return time.perf_counter() < deadline

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = run_cases(cases, progress=stop)
    wall = time.perf_counter() - t0
    failed = [str(r) for r in res if isinstance(r, Exception)]
    stopped = sum("was stopped" in f for f in failed)
    per_curve = {}
    ref = read_paper_reference()
    diffs = []
    for (label, x, _), r in zip(both, res):
        d = per_curve.setdefault(label, {"cases": 0, "finished": 0, "max_steps": 0, "compared": 0, "dev": []})
        d["cases"] += 1
        if not isinstance(r, Exception):
            d["finished"] += 1
            d["max_steps"] = max(d["max_steps"], r.steps)
            cpu = ref.get((label, round(x, 9)))
            if cpu is not None and math.isfinite(float(cpu["eta_star"])):
                dev = float(r.summary()["eta_star"]) - float(cpu["eta_star"])
                d["compared"] += 1
                d["dev"].append(dev)
                diffs.append(dev)
    for d in per_curve.values():
        # eta* of seed 0 on both engines: one sample each of a chaotic run, so the difference is
        # a seed-to-seed scatter unless it leans one way over a curve (its mean)
        dev = d.pop("dev")
        d["mean_dev_vs_cpu"] = sum(dev) / len(dev) if dev else math.nan
        d["rms_dev_vs_cpu"] = math.sqrt(sum(v * v for v in dev) / len(dev)) if dev else math.nan
    out = {"curves": len(curves), "cases": len(cases), "wall_s": wall, "target_s": TARGET_PAPER_S,
           "finished": len(cases) - len(failed), "failed": len(failed) - stopped, "stopped_by_budget": stopped,
           "steps_done_of_total": [seen["done"], seen["total"]], "compared_with_cpu": len(diffs),
           "mean_dev_vs_cpu": sum(diffs) / len(diffs) if diffs else math.nan,
           "rms_dev_vs_cpu": math.sqrt(sum(v * v for v in diffs) / len(diffs)) if diffs else math.nan,
           "per_curve": per_curve, "failures": [f for f in failed if "was stopped" not in f][:5]}
    print(f"paper: {out['finished']} of {len(cases)} cases ({len(curves)} curves) finished in {wall:.0f} s (target "
          f"{TARGET_PAPER_S:g} s); {out['failed']} failed; {stopped} stopped by the budget; eta* - the CPU's seed 0 "
          f"over {len(diffs)} cases: mean {out['mean_dev_vs_cpu']:+.3f}, rms {out['rms_dev_vs_cpu']:.3f}", flush=True)
    return out


#: The production kernels :func:`part_ptx` compiles: (name, integrator, tangential law).
PTX_KERNELS = (("gear, tanh", "gear", "tanh"), ("gear, spring", "gear", "spring"), ("verlet, tanh", "verlet", "tanh"),
               ("verlet, spring", "verlet", "spring"))
#: What a production kernel may use (issue 38): registers a thread at most, and no spills.
PTX_MAX_REGISTERS = 128


def ptxas_report(text):
    """``ptxas -v``'s report of one kernel: registers, stack frame, spill stores and loads, shared
    and constant memory [B] (None where it says nothing)."""
    import re

    out = {}
    m = re.findall(r"Used (\d+) registers", text)
    out["registers"] = int(m[-1]) if m else None
    m = re.findall(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads", text)
    if m:
        out.update(stack_frame_bytes=max(int(x[0]) for x in m), spill_store_bytes=max(int(x[1]) for x in m),
                   spill_load_bytes=max(int(x[2]) for x in m))
    m = re.findall(r"(\d+) bytes smem", text)
    out["static_shared_bytes"] = int(m[-1]) if m else 0
    m = re.findall(r"(\d+) bytes cmem\[0\]", text)
    out["parameter_bytes"] = int(m[-1]) if m else None
    return out


def part_ptx(kernels=None, sm="sm_90"):
    """The four production kernels (Gear and Verlet, each with the tanh law and with the tangential
    spring) compiled to PTX for ``sm`` without a GPU (the ``gpu`` extra's NVVM: numba-cuda compiles
    what a launch would) and assembled by ``ptxas -v`` (the ``nvidia-cuda-nvcc`` wheel's, or one on
    PATH): per kernel its registers a thread, stack frame (local memory), spill stores and loads,
    static shared memory and parameter space [B], the dynamic shared memory a block of fig4's
    44-sphere case asks, and whether it meets :data:`PTX_MAX_REGISTERS` with no spills.
    ``{"skipped": why}`` where NVVM or ptxas is absent. ``kernels``: names of :data:`PTX_KERNELS`."""
    import dataclasses as dc

    import numba
    import numpy as np
    from numba import types

    ptxas = ptxas_path()
    if ptxas is None:
        return {"skipped": "no ptxas (pip install -e '.[gpu]' brings the nvidia-cuda-nvcc wheel's)"}
    import numba.cuda.dispatcher as dispatcher

    class _Hopper:  # device functions compile for the current device's cc: say it is sm_90
        compute_capability = (9, 0)

    dispatcher.get_current_device = lambda: _Hopper()
    from numba import cuda

    from pdamper.engine.cuda import kernel_arguments
    from pdamper.kernels.gpu.gear import batch_gear
    from pdamper.kernels.gpu.verlet import batch_verlet
    from pdamper.run import on_device
    from pdamper.simulation import Simulation

    _, _, case = fig4_cases(False)[-1]  # (44 spheres)
    out = {}
    for name, integrator, tangential in PTX_KERNELS:
        if kernels is not None and name not in kernels:
            continue
        c = dc.replace(case, numerics=dc.replace(case.numerics, integrator=integrator),
                       contact=dc.replace(case.contact, tangential=tangential))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            job, _ = Simulation(on_device(c, "cuda"))._gpu_job()
        args, bd, shared = kernel_arguments([job])
        bt = args[0]
        args[0] = bt._replace(out=np.zeros((1, 1)))  # (C-contiguous, as the GPU's)
        sig = tuple(numba.typeof(a) for a in args) + (types.int64, types.int64)
        t = time.perf_counter()
        try:
            ptx, _ = cuda.compile_ptx(batch_gear if integrator == "gear" else batch_verlet, sig, cc=(9, 0))
        except Exception as exc:  # noqa: BLE001  (no NVVM / NVRTC here)
            if "NVVM" in str(exc) or "nvrtc" in str(exc).lower() or "DynamicLibNotFound" in type(exc).__name__:
                return {"skipped": f"no CUDA toolkit's NVVM here ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})"}
            raise
        k = {"ptx_compile_s": time.perf_counter() - t, "ptx_bytes": len(ptx), "threads": bd,
             "dynamic_shared_bytes_44_spheres": shared}
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "k.ptx"
            path.write_text(ptx)
            r = subprocess.run([ptxas, "--gpu-name", sm, "-v", str(path), "-o", str(Path(d) / "k.cubin")],
                               capture_output=True, text=True, timeout=900)
        k.update(ptxas_report(r.stdout + r.stderr), ptxas_ok=r.returncode == 0, sm=sm)
        k["parameter_bytes"] = parameter_bytes(ptx)
        if r.returncode != 0:
            k["ptxas_error"] = " ".join((r.stdout + r.stderr).split())[-600:]
        if os.environ.get("PDAMPER_PTX_DIR"):  # (to read the PTX: keep it)
            Path(os.environ["PDAMPER_PTX_DIR"], name.replace(", ", "-") + ".ptx").write_text(ptx)
        k["within_limits"] = bool(k["ptxas_ok"] and k["registers"] is not None and k["registers"] <= PTX_MAX_REGISTERS
                                  and k.get("spill_store_bytes", 1) == 0 and k.get("spill_load_bytes", 1) == 0)
        out[name] = k
        print(f"ptx ({name}):", json.dumps(k), flush=True)
    return out


def parameter_bytes(ptx):
    """The kernel's parameter space [B]: its ``.entry``'s parameters as the PTX declares them."""
    import re

    head = ptx[ptx.index(".entry"):]
    head = head[:head.index(")")]
    sizes = {"8": 1, "16": 2, "32": 4, "64": 8}
    return sum(sizes[w] for w in re.findall(r"\.param\s+\.[a-z](8|16|32|64)\s", head))


def ptxas_path():
    """``ptxas``: the ``nvidia-cuda-nvcc`` wheel's (the ``gpu`` extra; its version matches the
    extra's NVVM, whose PTX an older ptxas refuses), else one on PATH; None if neither."""
    import shutil
    from importlib import metadata

    try:
        for f in metadata.files("nvidia-cuda-nvcc") or []:
            if f.name == "ptxas":
                return str(f.locate())
    except metadata.PackageNotFoundError:
        pass
    return shutil.which("ptxas")


def markdown(data):
    p = {k: v for k, v in data["parts"].items() if isinstance(v, dict) and "error" not in v and "skipped" not in v}
    failed = {k: v for k, v in data["parts"].items() if isinstance(v, dict) and ("error" in v or "skipped" in v)}
    lines = [f"GPU benchmark ({data['started']}): {p.get('env', {}).get('gpu', '?')}", ""]
    if "compile" in p:
        c = p["compile"]
        lines.append(f"- first GPU launch (compile): {c['first_launch_s']:.1f} s (target {TARGET_COMPILE_S:g} s); "
                     f"{c.get('registers_per_thread', '?')} registers/thread, {c.get('shared_bytes_per_block', '?')} "
                     "B shared/block")
    if "fig4" in p:
        f = p["fig4"]
        lines.append(f"- study fig4: {f['cases']} cases in {f['wall_s']:.1f} s (target {TARGET_FIG4_S:g} s); longest "
                     f"case {f['longest_case_steps']} steps, {f['us_per_step_per_block']:.2f} us/step per block; eta* "
                     f"within the CPU's seed range at {f['within_cpu_seed_range']} of {f['compared_with_cpu']} strokes, "
                     f"within 3 std at {f['within_3_std']} (max |z| {f['max_abs_z']:.2f}, mean z {f['mean_z']:+.2f}), "
                     f"within every CPU run's range at {f.get('within_every_cpu_run', '?')}")
    if "fig4_steady" in p:
        f = p["fig4_steady"]
        lines.append(f"- study fig4 --until-steady {f['until_steady']:g}: {f['cases']} cases in {f['wall_s']:.1f} s; "
                     f"longest case {f['longest_case_steps']} steps; cycles run {f['cycles_run'][0]:g}-"
                     f"{f['cycles_run'][1]:g}; the CPU's cycles at {f['same_cycles_as_cpu']} of "
                     f"{f['compared_with_cpu']} strokes, eta* {f['mean_abs_eta_dev_vs_cpu']:.4f} from the CPU's on "
                     "average")
    if "agree" in p:
        for name, v in p["agree"].items():
            if "fault" in v:
                lines.append(f"- agree, {name}: {v['fault']}")
            for r in v.get("cases", []):
                lines.append("- agree, " + _agree_line(name, r))
    if "steps" in p:
        for name, v in p["steps"]["variants"].items():
            if "refused" in v:
                lines.append(f"- steps, {name}: refused ({v['refused']})")
                continue
            lines.append(f"- steps, {name}: {v['us_per_step_per_block']:.2f} us/step per block, "
                         f"{v['us_per_step_least_advanced']:.2f} for the least advanced case ({v['cases']} cases, "
                         f"{v['steps']} steps in {v['wall_s']:.1f} s; compile {v['compile_s']:.1f} s)")
    if "bed" in p:
        b = p["bed"]
        lines.append(f"- {b['particles']}-sphere bed: {b['us_per_step']:.1f} us/step "
                     f"({b['ns_per_particle_step']:.1f} ns per particle-step); the {b['big_particles']}-sphere bed: "
                     f"{b['big']}")
    if "paper" in p:
        q = p["paper"]
        lines.append(f"- the paper's {q['curves']} curves: {q['finished']} of {q['cases']} cases in {q['wall_s']:.0f} s "
                     f"(target {TARGET_PAPER_S:g} s); {q['failed']} failed, {q['stopped_by_budget']} stopped by the budget")
    for k, v in failed.items():
        lines.append(f"- {k}: {v.get('error') or v.get('skipped')}")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="gpu.json", help="JSON result (written after every part); .md beside it")
    ap.add_argument("--budget-s", type=float, default=450.0, help="stop the paper part at this many seconds")
    ap.add_argument("--only", nargs="+", choices=PARTS + EXTRA_PARTS,
                    help="run only these parts (the extra part 'fault' only when named)")
    ap.add_argument("--tiny", action="store_true", help="tiny cases (numba-cuda's simulator: the test suite)")
    ap.add_argument("--ptx", action="store_true",
                    help="compile the four production kernels to PTX for sm_90 without a GPU and read ptxas -v "
                         "(registers, spills, local and shared memory) into --json or --out")
    ap.add_argument("--ptx-kernels", default=None,
                    help="the kernels --ptx compiles, comma-separated ('gear, tanh', 'gear, spring', 'verlet, tanh', "
                         "'verlet, spring' without the spaces: gear-tanh, ...); default all four")
    ap.add_argument("--json", default=None, help="with --ptx: where its JSON goes (default --out)")
    ap.add_argument("--steps-seconds", type=float, default=10.0,
                    help="how long each variant of the steps part runs")
    ap.add_argument("--agree-one", type=int, metavar="K", help=argparse.SUPPRESS)
    ap.add_argument("--agree-variants", default=None,
                    help="the agree part's variants, by number (0: gear tanh, 1: verlet tanh, 2: verlet spring, "
                         "3: gear spring), comma-separated; default all")
    ap.add_argument("--bed-seconds", type=float, default=20.0,
                    help="how long the largest bed the GPU engine takes (256 spheres) runs")
    ap.add_argument("--make-paper-reference", action="store_true",
                    help="write benchmarks/data/paper_cpu_reference.csv: every paper case, seed 0, on the CPU engine")
    ap.add_argument("--make-steady-reference", metavar="STUDY_DIR",
                    help="write benchmarks/data/fig4_cpu_until_steady.csv from "
                         "'pdamper study fig4 --until-steady 0.02 --out STUDY_DIR'")
    ap.add_argument("--make-reference", metavar="STUDY_DIR",
                    help="write benchmarks/data/fig4_cpu_reference.csv from 'pdamper study fig4 --seeds 3 --out STUDY_DIR'")
    args = ap.parse_args(argv)
    if args.make_reference:
        make_reference(args.make_reference)
        return 0
    if args.make_steady_reference:
        make_steady_reference(args.make_steady_reference)
        return 0
    if args.make_paper_reference:
        make_paper_reference()
        return 0
    t0 = time.perf_counter()
    report = Report(args.json if args.ptx and args.json else args.out)
    if args.ptx:
        chosen = None if args.ptx_kernels is None else {k.replace("-", ", ") for k in args.ptx_kernels.split(",")}
        report.put("ptx", part_ptx(chosen))
        return 0
    if args.agree_one is not None:  # (one variant of the agree part, in its own process)
        report.put("agree_one", agree_one(args.tiny, args.agree_one, report))
        return 0
    parts = args.only or PARTS
    report.put("env", env_info())
    if report.data["parts"]["env"].get("gpu_unavailable"):
        print("no GPU: " + report.data["parts"]["env"]["gpu_unavailable"], flush=True)
        return 2
    with tempfile.TemporaryDirectory() as work:
        for part in parts:
            if part == "env":
                continue
            left = args.budget_s - (time.perf_counter() - t0)
            if left <= 0:
                report.put(part, {"skipped": "the budget was spent"})
                continue
            try:
                if part == "compile":
                    report.put(part, part_compile(args.tiny))
                elif part == "fig4":
                    report.put(part, part_fig4(args.tiny, work))
                elif part == "fig4_steady":
                    report.put(part, part_fig4_steady(args.tiny, work))
                elif part == "agree":
                    chosen = None if args.agree_variants is None else {int(k) for k in args.agree_variants.split(",")}
                    report.put(part, part_agree(args.tiny, chosen))
                elif part == "steps":
                    report.put(part, part_steps(args.tiny, min(args.steps_seconds, left)))
                elif part == "bed":
                    report.put(part, part_bed(args.tiny, min(args.bed_seconds, left)))
                elif part == "paper":
                    report.put(part, part_paper(args.tiny, t0 + args.budget_s))
            except Exception as exc:  # noqa: BLE001  (one part failing does not lose the others)
                import traceback

                traceback.print_exc()
                print(f"{part}: failed: {type(exc).__name__}: {exc}", flush=True)
                report.put(part, {"error": f"{type(exc).__name__}: {exc}"})
    report.data["integrator"] = FALLBACK["integrator"] or "each case's own (gear)"
    report.data["total_s"] = time.perf_counter() - t0
    report.put("done", True)
    text = markdown(report.data)
    if report.path is not None:
        report.path.with_suffix(".md").write_text(text + "\n")
    print(text, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
