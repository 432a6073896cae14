"""The GPU engine's benchmark: one command on one NVIDIA GPU (issue 29's targets).

    PYTHONUNBUFFERED=1 python benchmarks/gpu.py --out gpu.json [--budget-s 450] [--only PART ...]

What it runs, the bounded parts first (a part that overruns the device call's limit then loses only
what follows it), writing ``--out`` (JSON) after every part and a markdown summary at the end (also
``--out`` with ``.md``):

1. ``env``: the GPU, numba and numba-cuda, the commit, the profilers on PATH (``ncu``, ``nsys``).
2. ``compile``: the first GPU launch of the kernel (numba-cuda typing, NVVM, the driver's PTX JIT;
   a launch with no steps) and the compiled kernel's registers per thread, shared and local memory
   per block, the blocks an SM can hold.
3. ``agree``: the GPU's kernels against the CPU engine on the GPU itself (the test suite holds them
   together only in numba-cuda's simulator, which runs the CPU-compiled functions): two fig4 cases,
   the settling and half a cycle, under Gear and Verlet with the tanh law, Verlet with the spring,
   and Gear with the spring (refused on a GPU: run here to see its fault), each variant in a process
   of its own (``--agree-variants`` picks them): the steps, the first sample at which the wall force
   parts from the CPU's, the final positions; for Gear first the shapes of its arrays as a kernel
   with its arguments sees them (kept if the run then faults).
   ``profile``: where Gear's step spends its time, phase by phase: fig4's cases as one batch
   (``--profile-cases``: some of them, e.g. the longest alone) for ``--profile-seconds`` (10) under
   the probed kernel (``pdamper.kernels.gpu.probe``: the block's cycle counter read at the end of
   each phase): cycles per attempted step of each phase and its share, the implicit walk's rows per
   step and cycles per row, the rebuilds; each case's own.
   ``fig4_steady`` (only when named): the ``fig4`` part with ``--until-steady 0.02`` (each case stops
   once its record is steady, at the CPU engine's cycle): wall time, the longest case's steps, and
   per stroke the cycles run and eta* against the CPU engine's same command
   (``benchmarks/data/fig4_cpu_until_steady.csv``, ``--make-steady-reference``).
   ``fault`` (only when named: ``--only fault``): Gear with the tangential spring, which faults on a
   GPU, on four fig4 cases in synchronised launches of 200 steps for ``--fault-seconds`` (10), as the
   production kernel and compiled twice more with other numba-cuda options (NVVM unoptimised; at most
   128 registers), each in a process of its own: whether and when each faults (a fault that goes
   with the options is the compilers'), and the production kernel's PTX and SASS as this machine
   compiles them, into ``--artifacts`` (default ``fault/`` beside ``--out``). The ``env`` part says
   the CUDA driver, runtime and libNVVM versions.
   ``steps``: what changes a step's cost: fig4's cases as one batch for ``--steps-seconds`` (10)
   under Gear with the tanh law (the default), Verlet with the tanh law and with the tangential
   spring, the default's longest case alone, and the default with 32 threads a block: microseconds
   per step per block of each (a variant the engine refuses says so).
4. ``bed``: the 5,000-sphere multi-layer bed of ``benchmarks/run.py`` (one case, one block of 256
   threads) for ``--bed-seconds`` (20): microseconds per step and per particle-step.
5. ``fig4``: ``run_study("fig4", device="cuda")`` as ``pdamper study fig4 --device cuda`` runs it
   (40 strokes x 20 cycles, 36 and 44 spheres, one seed, from an empty store): wall time, the
   longest case's steps and the per-step cost of a block, and eta* of every stroke against the CPU
   engine's seeds 0-2 (``benchmarks/data/fig4_cpu_reference.csv``). It runs to its end (no budget).
6. ``paper``: every distinct DEM curve of the paper (``benchmarks/run.py``'s ``paper_curves``) at
   the paper's 40 strokes, 20 cycles, one seed, as one GPU batch: wall time, cases finished and
   failed. Stopped at the budget (``--budget-s``, counted from the start): then what was done is
   said (steps done of all steps), never extrapolated into a figure.

``--tiny`` runs the same parts on tiny cases (a few soft spheres, a few hundred steps) in
numba-cuda's simulator (``NUMBA_ENABLE_CUDASIM=1``): the test suite's check that this script works
(tests/kernels/gpu/test_benchmark_gpu.py). ``--ptx`` needs no GPU: it compiles the kernel to PTX for
sm_90 with the local CUDA toolkit's NVVM and reads ``ptxas -v`` (registers, spills, shared memory);
``--ptx-tangential spring`` compiles the kernels for the tangential spring instead of the tanh law.

**On the project's GPU machines** (numba, numba-cuda, numpy, scipy, xarray, pandas, matplotlib, h5py
there; no package registry), the rest of pdamper's dependencies travel as wheels in the git-ignored
folder ``.whl/`` of the repository, fetched here by ``bash benchmarks/gpu_wheels.sh``; the device
call then runs::

    pip install -q --no-index --no-deps --target /tmp/site .whl/*.whl && \\
    export PYTHONPATH=/tmp/site:$PWD/src && \\
    PYTHONUNBUFFERED=1 python benchmarks/gpu.py --out $OUT/gpu.json

(``carry`` names ``.whl``). The figures go into docs/performance.md with the GPU's name.
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
PARTS = ("env", "compile", "agree", "profile", "steps", "bed", "fig4", "paper")
#: Parts run only when named (--only): ``fault``, the spring kernel's fault under other compiles;
#: ``fig4_steady``, fig4 with ``--until-steady`` (:data:`STEADY_TOL`).
EXTRA_PARTS = ("fault", "fig4_steady")
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
    """Registers per thread, shared and local memory of the compiled kernel, and the blocks of
    ``threads`` an SM holds by each limit (H100: 65,536 registers, 228 KiB shared memory, 2,048
    threads, 32 blocks per SM)."""
    from pdamper.engine.cuda import threads_for
    from pdamper.kernels.gpu.gear import gear_kernel
    from pdamper.kernels.gpu.verlet import verlet_kernel

    out = {"kernel": "gear" if sim.stepper.rejected is not None else "verlet"}
    try:
        k = gear_kernel() if out["kernel"] == "gear" else verlet_kernel()
        regs = k.get_regs_per_thread()
        smem = k.get_shared_mem_per_block()
        local = k.get_local_mem_per_thread()
        regs = list(regs.values())[0] if isinstance(regs, dict) else regs
        smem = list(smem.values())[0] if isinstance(smem, dict) else smem
        local = list(local.values())[0] if isinstance(local, dict) else local
        out.update(registers_per_thread=int(regs), shared_bytes_per_block=int(smem), local_bytes_per_thread=int(local))
        for n, label in ((36, "36 spheres"), (44, "44 spheres"), (176, "176 spheres"), (5000, "5,000 spheres")):
            t = threads_for(n)
            by_regs = 65536 // max(1, int(regs) * t)
            by_smem = (228 * 1024) // max(1, int(smem) + 1024)
            out[f"blocks_per_sm_{label.split()[0].replace(',', '')}"] = {
                "threads": t, "by_registers": by_regs, "by_shared": by_smem, "by_threads": 2048 // t,
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
    """The 5,000-sphere bed for about ``seconds``: the cost of a step."""
    from pdamper.run import on_device
    from pdamper.simulation import Simulation, run_on_gpu

    sys.path.insert(0, str(BENCH))
    from run import big_bed  # noqa: E402  (benchmarks/run.py's bed)

    case = big_bed(12 if tiny else 5000)
    case = dataclasses.replace(case, cycles=1.0, drop_cycles=0)
    if tiny:
        case = _soft(case)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(_integrator(on_device(case, "cuda")))
    t0 = time.perf_counter()
    seen = {}

    def stop(done, total):
        seen.update(done=done, total=total, t=time.perf_counter() - t0)
        return time.perf_counter() - t0 < seconds

    rec = run_on_gpu([sim], progress=stop)[0]
    wall = time.perf_counter() - t0
    steps = sim.stepper.steps
    out = {"particles": sim.n, "steps": steps, "wall_s": wall, "finished": not isinstance(rec, Exception),
           "us_per_step": 1e6 * wall / max(steps, 1), "ns_per_particle_step": 1e9 * wall / max(steps, 1) / sim.n}
    print(f"bed: {sim.n} spheres, {steps} steps in {wall:.1f} s = {out['us_per_step']:.1f} us/step "
          f"({out['ns_per_particle_step']:.1f} ns per particle-step)", flush=True)
    return out


#: The variants of :func:`part_steps`: (name, integrator, tangential law, cases, threads a block:
#: None, one a sphere).
STEP_VARIANTS = (("gear, tanh (the default)", "gear", "tanh", "all", None),
                 ("verlet, tanh (no error control, no pass)", "verlet", "tanh", "all", None),
                 ("verlet, spring", "verlet", "spring", "all", None),
                 ("gear, tanh, one case alone", "gear", "tanh", "one", None),
                 ("gear, tanh, 32 threads a block", "gear", "tanh", "all", 32))


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


#: The variants of :func:`part_agree`: (name, integrator, tangential law). Gear with the spring is
#: refused on a GPU (it faults there); this part runs it all the same, in its own process, to see.
AGREE_VARIANTS = (("gear, tanh", "gear", "tanh"), ("verlet, tanh", "verlet", "tanh"),
                  ("verlet, spring", "verlet", "spring"), ("gear, spring (refused on a GPU)", "gear", "spring"))


#: The arrays whose shapes :func:`kernel_view` reads inside a kernel: (bundle, field), in the
#: order of the Gear kernel's arguments.
VIEWED = (("sp", "position"), ("li", "partner"), ("li", "tangential"), ("wl", "tangential"), ("gs", "nordsieck"),
          ("gs", "saved_pair"), ("gs", "saved_wall"), ("gs", "pair_rows"), ("gc", "cycles"))


def _echo(sp, li, wl, tb, law, tlaw, mo, ct, rec, nmat, row0, gs, gc, max_steps, max_cycles, out):
    """Gear's kernel's arguments, and one more: the shapes of :data:`VIEWED` as a kernel sees them
    (``cuda`` and ``put``, :func:`_put` for the device, globals of the compiled copy,
    :func:`kernel_view`)."""
    if cuda.threadIdx.x == 0 and cuda.blockIdx.x == 0:
        k = put(out, 0, sp.position.shape)
        k = put(out, k, li.partner.shape)
        k = put(out, k, li.tangential.shape)
        k = put(out, k, wl.tangential.shape)
        k = put(out, k, gs.nordsieck.shape)
        k = put(out, k, gs.saved_pair.shape)
        k = put(out, k, gs.saved_wall.shape)
        k = put(out, k, gs.pair_rows.shape)
        put(out, k, gc.cycles.shape)


def _put(out, k, shape):
    """``shape`` into ``out`` from ``k`` on; returns the next free index."""
    for d in range(len(shape)):
        out[k + d] = shape[d]
    return k + len(shape)


def kernel_view(jobs):
    """The shapes of a Gear batch's arrays as a kernel with the Gear kernel's arguments sees them,
    against the host's: ``{name: [host shape, kernel shape]}`` and whether all agree. (The spring
    kernel's fault on the H200 wrote where a wrong sphere count would put it: this says whether the
    kernel receives its arguments right.)"""
    import types

    import numpy as np
    from numba import cuda

    from pdamper.engine.cuda import _Batch, threads_for
    from pdamper.kernels.gpu.targets import SIMULATOR

    b = _Batch(jobs, threads_for(max(j.engine.n for j in jobs)))
    bundles = dict(zip(("sp", "li", "wl"), b.args[:3]), gs=b.gs, gc=b.gc)
    host = [tuple(int(x) for x in getattr(bundles[bundle], name).shape) for bundle, name in VIEWED]
    out = np.full(64, -1, dtype=np.int64)
    dev = out if SIMULATOR else cuda.to_device(out)
    put = cuda.jit(device=True)(_put)
    echo = types.FunctionType(_echo.__code__, dict(_echo.__globals__, cuda=cuda, put=put), "_echo")
    cuda.jit(echo)[1, 32](*b.args, 0, 0, dev)
    seen = out if SIMULATOR else dev.copy_to_host()
    view, k = {}, 0
    for (bundle, name), shape in zip(VIEWED, host):
        view[f"{bundle}.{name}"] = [list(shape), [int(x) for x in seen[k:k + len(shape)]]]
        k += len(shape)
    return {"shapes": view, "agree": all(h == s for h, s in view.values())}


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
        view = None
        if integrator == "gear":  # the kernel's view of its arguments first (kept if the run then faults)
            with _unrefused():  # (on beds of their own: a job starts its simulation's recorders)
                view = kernel_view([Simulation(c)._gpu_job()[0] for c in on_gpu])
            if report is not None:
                report.put("agree_one", {"variant": name, "kernel_view": view})
            print(f"agree: {name}: the kernel sees its arrays' shapes as the host made them: {view['agree']}",
                  flush=True)
        with _unrefused():
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
    return {"variant": name, "cases": rows, "kernel_view": view}


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
        if v.get("kernel_view") and not v["kernel_view"]["agree"]:
            print(f"agree: {name}: the kernel sees other shapes than the host made: {v['kernel_view']['shapes']}",
                  flush=True)
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


#: The spring kernel's fault (Gear with the tangential spring faults on a GPU; docs/performance.md):
#: the production compile, and two that change only what the compilers do with the same source:
#: numba-cuda's ``cuda.jit`` options, each in a process of its own. A fault that goes with the
#: compile options is the compilers' (NVVM, or the driver's PTX compiler); one that stays is the
#: kernel's or its arguments'.
FAULT_VARIANTS = (("production", {}), ("NVVM unoptimised", {"opt": False}), ("128 registers", {"max_registers": 128}))
#: Attempted steps per launch of the fault part (each launch synchronised, so a fault is placed).
FAULT_CHUNK = 200


def fault_one(tiny, k, seconds, artifacts=None, report=None, chunk=FAULT_CHUNK):
    """Variant ``k`` of :data:`FAULT_VARIANTS`: four fig4 cases (seed 0; with ``tiny`` the soft
    stand-ins) with Gear and the tangential spring as one batch, in launches of ``chunk`` attempted
    steps, each synchronised, for ``seconds`` or to the end: the compile, the launches that
    ran clean and the fault, if one came. With ``artifacts`` (a folder) the kernel's PTX as this
    machine's NVVM wrote it, and its SASS where ``nvdisasm`` is on PATH, go there (the production
    compile only). What is known before the run (the compile) is reported first, so a fault that
    takes the process keeps it."""
    import numpy as np

    from pdamper.engine.cuda import _Batch, _host, _sync, numpy_aliases_for_numba_cuda, threads_for
    from pdamper.run import on_device
    from pdamper.simulation import Simulation

    numpy_aliases_for_numba_cuda()
    from numba import cuda

    from pdamper.kernels.gpu.gear import batch_gear
    from pdamper.kernels.gpu.targets import SIMULATOR

    name, options = FAULT_VARIANTS[k]
    cases = [c for _, _, c in fig4_cases(tiny)]
    if len(cases) > 4:
        cases = [cases[i] for i in np.linspace(0, len(cases) - 1, 4).astype(int)]
    jobs = []
    with warnings.catch_warnings(), _unrefused():
        warnings.simplefilter("ignore")
        for case in cases:
            c = dataclasses.replace(case, contact=dataclasses.replace(case.contact, tangential="spring"),
                                    numerics=dataclasses.replace(case.numerics, integrator="gear"))
            jobs.append(Simulation(on_device(c, "cuda"))._gpu_job()[0])
        b = _Batch(jobs, threads_for(max(j.engine.n for j in jobs)))
    if options and not SIMULATOR:  # (the simulator compiles nothing: its variants are the same kernel)
        b.kernel = cuda.jit(**options)(batch_gear)
    out = {"variant": name, "options": options, "cases": len(jobs), "chunk": chunk}
    t = time.perf_counter()
    b.launch(0)
    _sync()
    out["compile_s"] = time.perf_counter() - t
    if artifacts and not options and not SIMULATOR:
        out["artifacts"] = _kernel_artifacts(b.kernel, Path(artifacts))
    if report is not None:
        report.put("fault_one", out)
    print(f"fault: {name}: compiled in {out['compile_s']:.1f} s", flush=True)
    clean, t0 = 0, time.perf_counter()
    out["fault"] = None
    try:
        while time.perf_counter() - t0 < seconds:
            b.launch(chunk)
            _sync()
            clean += 1
            b.poll()
            if b.finished:
                break
    except Exception as exc:  # noqa: BLE001  (the fault is the finding)
        out["fault"] = f"{type(exc).__name__}: {' '.join(str(exc).split())[:300]}"
    out["launches_clean"] = clean
    out["run_s"] = time.perf_counter() - t0
    if out["fault"] is None:  # (after a fault the context is gone: nothing more comes back)
        out["steps"] = [int(x) for x in _host(b.ct.step)]
        out["statuses"] = sorted({int(x) for x in _host(b.ct.status)})
    return out


def _kernel_artifacts(kernel, folder):
    """The compiled kernel's PTX (and SASS, where nvdisasm is on PATH) into ``folder``: their file names
    and sizes, or why not."""
    import shutil

    folder.mkdir(parents=True, exist_ok=True)
    out = {}
    for kind, what in (("ptx", "inspect_asm"), ("sass", "inspect_sass")):
        if kind == "sass" and shutil.which("nvdisasm") is None:
            out[kind] = "nvdisasm is not on PATH"
            continue
        try:
            text = "\n".join(getattr(kernel, what)().values())
            path = folder / f"gear_spring.{kind}"
            path.write_text(text)
            out[kind] = {"file": path.name, "bytes": len(text)}
        except Exception as exc:  # noqa: BLE001
            out[kind] = f"? ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})"
    return out


def part_fault(tiny, seconds, artifacts=None, variants=None, chunk=FAULT_CHUNK):
    """Gear with the tangential spring on the GPU under each of :data:`FAULT_VARIANTS` (``variants``:
    their numbers; default all), each in a process of its own (:func:`fault_one`; a fault takes its
    process's CUDA context): whether and when it faults."""
    out = {}
    for k, (name, _) in enumerate(FAULT_VARIANTS):
        if variants is not None and k not in variants:
            continue
        extra = ["--fault-seconds", str(seconds), "--fault-chunk", str(chunk)]
        v = _in_own_process("fault_one", k, name, tiny, extra + (["--artifacts", str(artifacts)] if artifacts else []))
        out[name] = v
        print(f"fault: {_fault_line(name, v)}", flush=True)
    return out


def _fault_line(name, v):
    """One variant of the fault part, in words (the log and the markdown summary)."""
    compiled = f"compiled in {v['compile_s']:.1f} s" if "compile_s" in v else "not compiled"
    ran = f"{v.get('launches_clean', 0)} launches of {v.get('chunk', '?')} steps ran clean"
    return f"{name}: {compiled}; {ran}; " + (f"FAULT: {v['fault']}" if v.get("fault") else "no fault")


def part_profile(tiny, seconds, cases=None):
    """Where Gear's step spends its time: fig4's cases (seed 0, one batch, Gear with the tanh law;
    ``cases``: only these, by index into :func:`fig4_cases`, e.g. the longest alone, whose late
    steps a batch's first seconds do not reach) for ``seconds`` under the probed kernel
    (:mod:`pdamper.kernels.gpu.probe`), which reads the block's cycle counter at the end of each
    phase of a step. Per phase: cycles per attempted step (all cases' cycles over all their
    attempted steps) and share of the step; the implicit walk's rows per attempted step and cycles
    per row; rebuilds per step; each case's own. The probed step is a little
    slower than the production one (a clock read holds the compiler's scheduling at it): the
    shares are what this tells; the production kernel's time is the steps part's."""
    import numpy as np

    from pdamper.engine.cuda import run_jobs
    from pdamper.kernels.gpu.probe import P_REBUILDS, P_ROWS, PHASES
    from pdamper.run import on_device
    from pdamper.simulation import Simulation

    every = fig4_cases(tiny)
    picked = range(len(every)) if cases is None else cases
    wrong = beyond_fig4(picked, len(every))
    if wrong:
        raise SystemExit(f"--profile-cases {wrong}")
    cases = []
    for k in picked:
        case = every[k][2]
        c = dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator="gear"))
        cases.append(on_device(c, "cuda"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.perf_counter()
        run_jobs([Simulation(cases[0])._gpu_job()[0]], compile_only=True, probe=True)
        compile_s = time.perf_counter() - t
        jobs = [Simulation(c)._gpu_job()[0] for c in cases]
        t0 = time.perf_counter()
        # (tiny: launches of 20 steps, so that the simulator stops soon after its window)
        outcomes = run_jobs(jobs, probe=True, progress=lambda done, total: time.perf_counter() - t0 < seconds,
                            max_launch_steps=20 if tiny else 10**9)
        wall = time.perf_counter() - t0
    cyc = np.array([o.cycles for o in outcomes], dtype=float)
    attempted = np.array([o.steps + o.rejected for o in outcomes], dtype=float)
    tried = max(float(attempted.sum()), 1.0)
    per_step = cyc[:, :len(PHASES)].sum(axis=0) / tried
    total = float(per_step.sum())
    clock_khz = None
    if not tiny:
        try:
            from numba import cuda

            clock_khz = float(cuda.get_current_device().CLOCK_RATE)
        except Exception:  # noqa: BLE001  (the clock rate is a convenience: cycles are the figure)
            clock_khz = None
    walk = PHASES.index("implicit pair walk")
    rows = float(cyc[:, P_ROWS].sum()) / tried
    out = {"seconds": seconds, "cases": len(jobs), "picked": list(picked), "compile_s": compile_s, "wall_s": wall,
           "attempted_steps": int(tried), "most_steps": int(max(o.steps for o in outcomes)),
           "rejected_share": float(sum(o.rejected for o in outcomes)) / tried,
           "us_per_step_per_block_probed": 1e6 * wall / max(max(o.steps for o in outcomes), 1),
           "cycles_per_attempted_step": total, "sm_clock_khz": clock_khz,
           "us_per_attempted_step_from_cycles": 1e3 * total / clock_khz if clock_khz else None,
           "walk_rows_per_attempted_step": rows,
           "walk_cycles_per_row": float(per_step[walk]) / rows if rows > 0 else None,
           "rebuilds_per_attempted_step": float(cyc[:, P_REBUILDS].sum()) / tried,
           "phases": {name: {"cycles_per_attempted_step": float(v), "share": float(v) / total if total else 0.0}
                      for name, v in zip(PHASES, per_step)}}
    # each case's own step, cycles and walk rows (a launch of equal step counts lasts as long as its
    # slowest block; one bounded by time lets each case take its own)
    own = cyc[:, :len(PHASES)].sum(axis=1) / np.maximum(attempted, 1.0)
    out["per_case"] = [{"case": picked[k], "spheres": int(j.engine.n), "cycles_per_attempted_step": float(own[k]),
                        "walk_rows_per_attempted_step": float(cyc[k, P_ROWS] / max(attempted[k], 1.0)),
                        "walk_cycles_per_attempted_step": float(cyc[k, walk] / max(attempted[k], 1.0)),
                        "rebuilds_per_attempted_step": float(cyc[k, P_REBUILDS] / max(attempted[k], 1.0)),
                        "attempted_steps": int(attempted[k])} for k, j in enumerate(jobs)]
    out["slowest_case_cycles_per_attempted_step"] = float(own.max())
    print(f"profile: {len(jobs)} cases, {int(tried)} attempted steps in {wall:.1f} s (probed kernel, compile "
          f"{compile_s:.1f} s): {total:.0f} cycles per attempted step (slowest case {own.max():.0f}); walk "
          f"{rows:.1f} rows a step", flush=True)
    for name, v in out["phases"].items():
        print(f"profile:   {name:34s} {v['cycles_per_attempted_step']:10.0f} cycles  {100 * v['share']:5.1f} %",
              flush=True)
    return out


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


class _unrefused:
    """Within it, the GPU engine refuses nothing (``pdamper.engine.cuda.refusal`` says None): for
    compiling a refused kernel to PTX, which runs nothing."""

    def __enter__(self):
        import pdamper.engine.cuda as engine

        self.engine, self.refusal = engine, engine.refusal
        engine.refusal = lambda *args, **kwargs: None

    def __exit__(self, *exc):
        self.engine.refusal = self.refusal
        return False


def part_ptx(kernels=("gear", "verlet"), tangential="tanh"):
    """The kernels (Gear's, the default, and Verlet's) compiled to PTX for sm_90 without a GPU (the
    local CUDA toolkit's NVVM), and ``ptxas -v``'s registers, spills and shared memory (when ptxas
    is on PATH); ``tangential``: the tangential law they are compiled for (``contact.tangential``)."""
    import dataclasses as dc
    import re
    import shutil

    import numba
    import numpy as np
    from numba import types

    import numba.cuda.dispatcher as dispatcher

    class _Hopper:  # device functions compile for the current device's cc: say it is sm_90
        compute_capability = (9, 0)

    dispatcher.get_current_device = lambda: _Hopper()
    from numba import cuda

    from pdamper.engine.cuda import kernel_arguments
    from pdamper.kernels.gpu.gear import batch_gear, gear_kernel
    from pdamper.kernels.gpu.verlet import batch_verlet
    from pdamper.run import on_device
    from pdamper.simulation import Simulation

    _, _, case = fig4_cases(False)[0]
    out = {}
    probed = gear_kernel(probed=True).py_func
    for name, kernel, integrator in (("gear", batch_gear, "gear"), ("verlet", batch_verlet, "verlet"),
                                     ("gear_probed", probed, "gear")):
        if name not in kernels:
            continue
        c = dc.replace(case, numerics=dc.replace(case.numerics, integrator=integrator),
                       contact=dc.replace(case.contact, tangential=tangential))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sim = Simulation(on_device(c, "cuda"))
        # (the GPU engine refuses Gear with the spring on a GPU, for a fault not yet found; its kernel is
        # compiled here all the same: reading it is how that fault is studied)
        with _unrefused():
            job, _ = sim._gpu_job()
        args, _ = kernel_arguments([job])
        # the output arrays as the GPU has them (C-contiguous; off the simulator the packing leaves only their shapes)
        args[8] = args[8]._replace(wall_force=np.zeros((1, 1)), energy=np.zeros((1, 1, 7)),
                                   frames=np.zeros((1, 1, 1, 9)))
        sig = tuple(numba.typeof(a) for a in args) + (types.int64, types.int64)
        t = time.perf_counter()
        try:
            ptx, _ = cuda.compile_ptx(kernel, sig, cc=(9, 0))
        except Exception as exc:  # noqa: BLE001  (no NVVM / NVRTC here)
            if "NVVM" in str(exc) or "nvrtc" in str(exc).lower() or "DynamicLibNotFound" in type(exc).__name__:
                out = {"skipped": f"no CUDA toolkit's NVVM here ({type(exc).__name__}: {' '.join(str(exc).split())[:200]})"}
                print("ptx:", json.dumps(out), flush=True)
                return out
            raise
        k = {"ptx_compile_s": time.perf_counter() - t, "ptx_bytes": len(ptx), "entry": ".entry" in ptx}
        if shutil.which("ptxas"):
            with tempfile.TemporaryDirectory() as d:
                p = Path(d) / "k.ptx"
                p.write_text(ptx)
                r = subprocess.run(["ptxas", "--gpu-name", "sm_90", "-v", str(p), "-o", str(Path(d) / "k.cubin")],
                                   capture_output=True, text=True, timeout=600)
            text = r.stdout + r.stderr
            m = re.findall(r"Used (\d+) registers.*?(\d+) bytes smem", text)
            sp_ = re.findall(r"(\d+) bytes stack frame, (\d+) bytes spill stores, (\d+) bytes spill loads", text)
            if m:
                k.update(registers_per_thread=int(m[-1][0]), shared_bytes_per_block=int(m[-1][1]))
            if sp_:
                k.update(stack_bytes=max(int(x[0]) for x in sp_), spill_store_bytes=max(int(x[1]) for x in sp_),
                         spill_load_bytes=max(int(x[2]) for x in sp_))
            k["ptxas_ok"] = r.returncode == 0
        k["tangential"] = tangential
        out[name] = k
        print(f"ptx ({name}, {tangential}):", json.dumps(k), flush=True)
    return out


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
    if "fault" in p:
        for name, v in p["fault"].items():
            lines.append("- fault, Gear with the spring, " + _fault_line(name, v))
    if "profile" in p:
        q = p["profile"]
        lines.append(f"- profile (probed Gear kernel, {q['cases']} cases): {q['cycles_per_attempted_step']:.0f} cycles per "
                     f"attempted step; walk {q['walk_rows_per_attempted_step']:.1f} rows a step, "
                     f"{q['walk_cycles_per_row'] or 0:.0f} cycles a row; "
                     + ", ".join(f"{k} {100 * v['share']:.1f} %" for k, v in q["phases"].items() if v["share"] >= 0.01))
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
                     f"({b['ns_per_particle_step']:.1f} ns per particle-step)")
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
    ap.add_argument("--ptx", action="store_true", help="compile to PTX for sm_90 without a GPU; ptxas -v")
    ap.add_argument("--ptx-kernels", default="gear,verlet",
                    help="the kernels --ptx compiles (gear, verlet, gear_probed: Gear's with the phase clock)")
    ap.add_argument("--ptx-tangential", default="tanh", choices=("tanh", "spring"),
                    help="the tangential law --ptx compiles the kernels for (contact.tangential)")
    ap.add_argument("--steps-seconds", type=float, default=10.0,
                    help="how long each variant of the steps part runs")
    ap.add_argument("--agree-one", type=int, metavar="K", help=argparse.SUPPRESS)
    ap.add_argument("--agree-variants", default=None,
                    help="the agree part's variants, by number (0: gear tanh, 1: verlet tanh, 2: verlet spring, "
                         "3: gear spring), comma-separated; default all")
    ap.add_argument("--fault-one", type=int, metavar="K", help=argparse.SUPPRESS)
    ap.add_argument("--fault-seconds", type=float, default=10.0,
                    help="how long each variant of the fault part runs (if it does not fault first)")
    ap.add_argument("--fault-chunk", type=int, default=FAULT_CHUNK, help="attempted steps per launch of the fault part")
    ap.add_argument("--artifacts", default=None,
                    help="where the fault part writes the spring kernel's PTX and SASS (default: 'fault' beside --out)")
    ap.add_argument("--profile-seconds", type=float, default=10.0, help="how long the profile part's batch runs")
    ap.add_argument("--profile-cases", type=int, nargs="+", default=None,
                    help="the profile part's fig4 cases, by index (36 spheres 0-39, 44 spheres 40-79, strokes "
                         "ascending); default all 80")
    ap.add_argument("--bed-seconds", type=float, default=20.0, help="how long the 5,000-sphere bed runs")
    ap.add_argument("--make-paper-reference", action="store_true",
                    help="write benchmarks/data/paper_cpu_reference.csv: every paper case, seed 0, on the CPU engine")
    ap.add_argument("--make-steady-reference", metavar="STUDY_DIR",
                    help="write benchmarks/data/fig4_cpu_until_steady.csv from "
                         "'pdamper study fig4 --until-steady 0.02 --out STUDY_DIR'")
    ap.add_argument("--make-reference", metavar="STUDY_DIR",
                    help="write benchmarks/data/fig4_cpu_reference.csv from 'pdamper study fig4 --seeds 3 --out STUDY_DIR'")
    args = ap.parse_args(argv)
    if args.profile_cases:  # (said before any part runs: a GPU's time is short)
        wrong = beyond_fig4(args.profile_cases, len(fig4_cases(args.tiny)))
        if wrong:
            ap.error(f"--profile-cases {wrong}")
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
    report = Report(args.out)
    if args.ptx:
        report.put("ptx", part_ptx(tuple(args.ptx_kernels.split(",")), args.ptx_tangential))
        return 0
    if args.agree_one is not None:  # (one variant of the agree part, in its own process)
        report.put("agree_one", agree_one(args.tiny, args.agree_one, report))
        return 0
    if args.fault_one is not None:  # (one variant of the fault part, in its own process)
        report.put("fault_one", fault_one(args.tiny, args.fault_one, args.fault_seconds, args.artifacts, report,
                                          args.fault_chunk))
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
                elif part == "fault":
                    artifacts = args.artifacts or (Path(args.out).parent / "fault" if args.out else None)
                    report.put(part, part_fault(args.tiny, args.fault_seconds, artifacts, chunk=args.fault_chunk))
                elif part == "profile":
                    report.put(part, part_profile(args.tiny, min(args.profile_seconds, left), args.profile_cases))
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
