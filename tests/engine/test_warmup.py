"""The second-core compile of a first run (pdamper.engine.warmup)."""

from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
from pathlib import Path

import pytest
from pdamper.engine import warmup
from pdamper.engine.build import build
from pdamper.engine.steppers import stepper_for
from pdamper.params import Case, HarmonicDrive, ParticleSet
from pdamper.schema import replace

CASE = Case(particles=(ParticleSet(count=4),), drive=HarmonicDrive(stroke=0.01, frequency=2.0), cycles=1, drop_cycles=0)


def _stepper(case):
    return stepper_for(build(case), 1.0 / case.recording.sample_rate)


_MAIN_RUN = r"""
import json, pickle, sys
from pdamper.run import run_case
from pdamper.kernels import forces, gear, neighbours, record
run_case(pickle.loads(sys.stdin.buffer.read()))
stats = {f.py_func.__name__: (f.stats.cache_hits, f.stats.cache_misses)
         for f in (record.record_sample, gear._implicit_friction, gear._predict, forces.compute_forces,
                   neighbours.rebuild_lists, gear.run_gear)}
print(json.dumps({k: (sum(h.values()), sum(m.values())) for k, (h, m) in stats.items()}))
"""


@pytest.mark.slow
def test_the_helper_fills_a_fresh_cache_with_the_callees_a_run_then_loads(tmp_path):
    """The helper compiles the callees, not the kernel, with the kernel's argument types: the main
    run finds each one in the cache and compiles only the kernel."""
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "PDAMPER_WARMUP": "0"}
    one = replace(CASE, {"particles": (ParticleSet(count=1),)})  # one sphere: its views are typed 'C' from Python
    p = subprocess.run([sys.executable, "-m", "pdamper.engine.warmup"], input=pickle.dumps(one), env=env,
                       capture_output=True, timeout=600)
    assert p.returncode == 0, p.stderr.decode()
    cached = {f.name.split("-")[0] for f in Path(tmp_path).rglob("*.nbi")}
    for name in ("record.record_sample", "gear._implicit_friction", "gear._predict", "forces.compute_forces",
                 "neighbours.rebuild_lists"):
        assert name in cached
    assert "gear.run_gear" not in cached
    p = subprocess.run([sys.executable, "-c", _MAIN_RUN], input=pickle.dumps(one), env=env, capture_output=True,
                       timeout=600)
    assert p.returncode == 0, p.stderr.decode()
    stats = json.loads(p.stdout.decode().strip().splitlines()[-1])
    for name in ("record_sample", "_implicit_friction", "_predict", "compute_forces", "rebuild_lists"):
        assert stats[name] == [1, 0], (name, stats[name])  # loaded from the cache, not compiled
    assert stats["run_gear"] == [0, 1]  # the kernel itself is compiled by the run


def test_jobs_start_with_the_kernel_and_name_each_callee_once():
    for integrator in ("gear", "verlet"):
        case = replace(CASE, {"numerics.integrator": integrator})
        jobs = _stepper(case).warm_jobs(warmup.empty_samples(4))
        names = [k.py_func.__name__ for k, _ in jobs]
        assert names[0] == ("run_gear" if integrator == "gear" else "run_verlet")
        assert len(set(names)) == len(names)
        assert "record_sample" in names and "compute_forces" in names


def test_not_started_when_switched_off_or_the_kernel_is_compiled(monkeypatch):
    stepper = _stepper(CASE)
    monkeypatch.setenv("PDAMPER_WARMUP", "0")
    assert warmup.start(CASE, stepper) is None
    monkeypatch.delenv("PDAMPER_WARMUP")
    from pdamper.run import run_case

    run_case(CASE)  # compiles (or loads) run_gear in this process
    kernel, _ = stepper.warm_jobs(warmup.empty_samples(4))[0]
    assert not warmup.cold(kernel)
    assert warmup.start(CASE, stepper) is None
