"""The GPU engine from the outside, without a GPU: ``--device cuda`` says in one line why it cannot
run (exit 2), and a case's config keeps ``numerics.device`` only when it is not the default."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from pdamper.config import case_from_dict, case_to_dict, dumps_case
from pdamper.errors import InputError
from pdamper.params import Case, ParticleSet
from pdamper.schema import replace

ROOT = Path(__file__).resolve().parents[2]


def _no_gpu_env():
    """The environment of a process without numba-cuda's simulator."""
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_ENABLE_CUDASIM"}
    env["PYTHONPATH"] = os.pathsep.join([str(ROOT / "src"), env.get("PYTHONPATH", "")])
    return env


def _gpu_here(env) -> bool:
    code = "from pdamper.engine.cuda import unavailable; print(unavailable() is None)"
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, timeout=120)
    return r.stdout.strip() == "True"


@pytest.mark.parametrize("command", [["run", str(ROOT / "examples" / "cuboid_36.toml")], ["study", "fig4"]])
def test_device_cuda_without_a_gpu_is_one_line(command, tmp_path):
    env = _no_gpu_env()
    if _gpu_here(env):
        pytest.skip("this machine has a GPU and numba-cuda: --device cuda would run")
    r = subprocess.run([sys.executable, "-m", "pdamper.cli", *command, "--device", "cuda", "--out",
                        str(tmp_path / "out")], env=env, capture_output=True, text=True, timeout=300, cwd=tmp_path)
    lines = [ln for ln in r.stderr.splitlines() if ln.strip() and not ln.startswith("warning:")]
    assert r.returncode == 2
    assert len(lines) == 1, r.stderr
    assert lines[0].startswith('Error: --device cuda needs an NVIDIA GPU and numba-cuda (pip install -e ".[gpu]"); '
                               "none found: ")
    assert not (tmp_path / "out").exists()  # nothing started


def test_device_is_written_only_when_not_the_default():
    case = Case(particles=(ParticleSet(count=4),))
    assert "device" not in dumps_case(case)  # a CPU case's text (a store's fingerprint) is as before
    gpu = replace(case, {"numerics.device": "cuda"})
    assert 'device = "cuda"' in dumps_case(gpu)
    assert case_from_dict(case_to_dict(gpu)) == gpu
    with pytest.raises(InputError, match="device = 'gpu'.*'cpu', 'cuda'"):
        replace(case, {"numerics.device": "gpu"})


def test_on_device_changes_where_not_what():
    from pdamper.run import on_device, on_gpu

    case = Case(particles=(ParticleSet(count=4),))
    gpu = on_device(case, "cuda")
    assert on_gpu(gpu) and not on_gpu(case)
    assert on_device(gpu, "cpu") == case
