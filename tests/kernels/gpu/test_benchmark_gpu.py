"""benchmarks/gpu.py runs: its --tiny mode in numba-cuda's simulator (the same ``run_study(...,
device="cuda")`` path as on a GPU, on tiny cases), and its --ptx mode, which compiles the real kernel
to PTX for sm_90 with the local CUDA toolkit's NVVM (skipped without one)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from script_loader import load_script

ROOT = Path(__file__).resolve().parents[3]
SCRIPT = ROOT / "benchmarks" / "gpu.py"


def _module():
    return load_script("benchmarks/gpu.py")


@pytest.mark.slow
def test_tiny_study_runs_in_the_simulator(tmp_path, monkeypatch):
    """The fig4 part on tiny cases: a study through the GPU engine, its JSON and markdown written,
    eta* compared with a CPU reference (seeds 0-2) and with further CPU runs of the same stroke: a
    reference spanning (0, 1) holds every GPU value, one above every CPU run none."""
    mod = _module()
    labels = [label for label, _, _ in mod.fig4_cases(True)]
    ref = tmp_path / "ref.csv"
    ref.write_text("setting,stroke_m,eta_mean,eta_min,eta_max,seeds,eta_seed0,eta_seed1,eta_seed2\n"
                   f"{labels[0]},0.002,0.5,0.01,0.99,3,0.01,0.5,0.99\n"
                   f"{labels[1]},0.002,1.5,1.4,1.6,3,1.4,1.5,1.6\n")
    spread = tmp_path / "spread.csv"
    spread.write_text("setting,stroke_m,kind,k,eta_star,steps,failed\n"
                      f"{labels[1]},0.002,nudge,1,1.7,1,\n")
    monkeypatch.setattr(mod, "REFERENCE", ref)
    monkeypatch.setattr(mod, "SPREAD", spread)
    out = tmp_path / "gpu.json"
    assert mod.main(["--tiny", "--only", "fig4", "--out", str(out)]) == 0
    data = json.loads(out.read_text())
    fig4 = data["parts"]["fig4"]
    assert fig4["cases"] == 2 and fig4["longest_case_steps"] > 100
    assert all(0.0 < s["eta_gpu"] < 1.0 for s in fig4["strokes"])
    assert fig4["compared_with_cpu"] == 2 and fig4["cpu_runs_per_stroke"] == [3, 4]
    assert fig4["within_cpu_seed_range"] == 1 and fig4["within_every_cpu_run"] == 1
    assert "study fig4: 2 cases" in out.with_suffix(".md").read_text()


def test_fig4_steady_part_runs_in_the_simulator(tmp_path, monkeypatch):
    """The fig4_steady part on tiny cases (two cycles: too few to stop early, so each runs them all):
    a study with --until-steady through the GPU engine, its cycles and eta* against a CPU reference
    of the same command (one stroke there with the same cycles, one with others)."""
    mod = _module()
    labels = [label for label, _, _ in mod.fig4_cases(True)]
    ref = tmp_path / "steady.csv"
    ref.write_text("setting,stroke_m,until_steady,cycles_run,steps,eta_star\n"
                   f"{labels[0]},0.002,0.02,2,200,0.0\n{labels[1]},0.002,0.02,3,300,0.0\n")
    monkeypatch.setattr(mod, "STEADY_REFERENCE", ref)
    out = tmp_path / "gpu.json"
    assert mod.main(["--tiny", "--only", "fig4_steady", "--out", str(out)]) == 0
    part = json.loads(out.read_text())["parts"]["fig4_steady"]
    assert part["cases"] == 2 and part["until_steady"] == 0.02 and part["cycles_run"] == [2.0, 2.0]
    assert part["compared_with_cpu"] == 2 and part["same_cycles_as_cpu"] == 1
    etas = [s["eta_gpu"] for s in part["strokes"]]
    assert part["mean_abs_eta_dev_vs_cpu"] == pytest.approx(sum(abs(e) for e in etas) / 2)
    assert "study fig4 --until-steady 0.02: 2 cases" in out.with_suffix(".md").read_text()


def _ptx_report(tmp_path, kernels):
    """``benchmarks/gpu.py --ptx --ptx-kernels KERNELS --json FILE`` in a process without the
    simulator: its JSON's ``ptx`` part (skipped, with the one-line reason, where NVVM or ptxas is
    absent)."""
    pytest.importorskip("numba_cuda", reason="numba-cuda is not installed")
    from importlib import metadata

    try:  # the gpu extra's toolkit wheels (NVVM's PTX needs their ptxas); without them nothing to compile
        metadata.version("nvidia-cuda-nvcc")
    except metadata.PackageNotFoundError:
        pytest.skip("the PTX compile needs the gpu extra (pip install -e '.[gpu]': the CUDA toolkit's wheels)")
    out = tmp_path / "ptx.json"
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")])
    r = subprocess.run([sys.executable, str(SCRIPT), "--ptx", "--ptx-kernels", kernels, "--json", str(out)], env=env,
                       capture_output=True, text=True, timeout=1800)
    if r.returncode:
        pytest.fail(r.stderr[-2000:])
    part = json.loads(out.read_text())["parts"]["ptx"]
    if "skipped" in part:
        pytest.skip(part["skipped"])
    return part


@pytest.mark.slow
def test_production_kernels_keep_to_128_registers_without_spills(tmp_path):
    """The largest and the smallest production kernel (Gear with the spring, Verlet with the tanh law;
    ``benchmarks/gpu.py --ptx`` gives all four) through numba-cuda, the gpu extra's NVVM and ptxas for
    sm_90 (no GPU needed; about two minutes of compiling): each assembles, with at most 128 registers
    a thread and no spill stores or loads (issue 38's target; docs/performance.md has all four)."""
    part = _ptx_report(tmp_path, "gear-spring,verlet-tanh")
    assert set(part) == {"gear, spring", "verlet, tanh"}
    for name, k in part.items():
        assert k["ptxas_ok"] and k["ptx_bytes"] > 10_000, name
        assert k["registers"] <= 128 and k["spill_store_bytes"] == 0 and k["spill_load_bytes"] == 0, (name, k)


def test_step_cost_part_runs_in_the_simulator():
    """The steps part on a tiny case, one variant (Verlet, one case: the cheapest in the simulator):
    it compiles, runs for its window and reports the steps and the cost of one."""
    mod = _module()
    out = mod.part_steps(True, 0.5, variants=(("verlet alone", "verlet", "tanh", "one", None),))
    v = out["variants"]["verlet alone"]
    assert v["cases"] == 1 and v["steps"] > 0
    assert v["us_per_step_per_block"] == pytest.approx(1e6 * v["wall_s"] / v["steps"])
    assert v["us_per_step_least_advanced"] == pytest.approx(1e6 * v["wall_s"] / v["steps_least"])


def test_paper_part_compares_with_the_cpu_reference(tmp_path, monkeypatch):
    """The paper part on tiny cases (two curves, one stroke) against a CPU reference file: each
    finished case compared, the deviation the GPU's eta* minus the file's."""
    import time

    mod = _module()
    cases = mod.paper_cases(True)
    ref = tmp_path / "paper.csv"
    ref.write_text("curve,stroke_m,eta_star,steps,wall_time_s,failed\n"
                   + "".join(f"{label},{x!r},0.5,1,0.1,\n" for label, x, _ in cases))
    monkeypatch.setattr(mod, "PAPER_REFERENCE", ref)
    out = mod.part_paper(True, time.perf_counter() + 600)
    assert out["finished"] == len(cases) == 2 and out["compared_with_cpu"] == 2
    for d in out["per_curve"].values():
        assert d["compared"] == 1 and -0.5 < d["mean_dev_vs_cpu"] < 0.5
        assert d["rms_dev_vs_cpu"] == pytest.approx(abs(d["mean_dev_vs_cpu"]))


@pytest.mark.slow
def test_agree_part_runs_in_the_simulator():
    """The agree part on the tiny cases, Gear with the spring, in its own process: in the simulator
    the kernels call the CPU's compiled functions, so the two engines agree to rounding at every
    sample and end at the same positions."""
    mod = _module()
    out = mod.part_agree(True, {3})
    assert list(out) == ["gear, spring"]
    for name in ("gear, spring",):
        rows = out[name]["cases"]
        assert len(rows) == 2 and all(r["failed"] is None for r in rows), name
        assert [r["setting"] for r in rows] == ["N_p = 36", "N_p = 44"]  # (each line says its case)
        assert "N_p = 44, 4 spheres" in mod._agree_line(name, rows[1])
        for r in rows:
            assert r["steps_cpu"] == r["steps_gpu"] > 0 and r["samples"] >= 2
            assert r["first_sample_apart"] is None and r["max_wall_force_diff_over_peak"] <= 1e-12
            assert r["max_position_diff_over_radius"] <= 1e-12


def test_step_cost_part_says_a_refused_variant_and_goes_on(monkeypatch):
    """A variant the GPU engine refuses (here a coupled structure's stand-in: every refusal) is
    recorded as refused with the engine's message, and the next variant still runs."""
    mod = _module()
    import pdamper.engine.cuda as engine

    real = engine.refusal
    calls = []

    def refuse_first(*args, **kwargs):
        calls.append(1)
        return "refused for the test" if len(calls) == 1 else real(*args, **kwargs)

    monkeypatch.setattr(engine, "refusal", refuse_first)
    out = mod.part_steps(True, 0.5, variants=(("refused", "verlet", "tanh", "one", None),
                                              ("verlet alone", "verlet", "tanh", "one", None)))
    assert "refused for the test" in out["variants"]["refused"]["refused"]
    assert out["variants"]["verlet alone"]["steps"] > 0


