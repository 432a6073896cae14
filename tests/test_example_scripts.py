"""The example scripts in examples/ run, do what they say, and are listed in examples/README.md."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


def test_every_script_is_listed_in_the_examples_readme():
    listed = (EXAMPLES / "README.md").read_text(encoding="utf-8")
    for script in EXAMPLES.glob("*.py"):
        assert f"({script.name})" in listed, script.name


def test_analyze_record_example(tmp_path):
    out = tmp_path / "rec.csv"
    proc = subprocess.run([sys.executable, str(EXAMPLES / "analyze_record.py"), str(out)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert out.read_text().splitlines()[0] == "time [ms],force [N],position [mm]"
    measured = float(re.search(r"energy per cycle\s+([0-9.]+) mJ", proc.stdout).group(1))
    exact = math.pi * 4.0 * (2 * math.pi * 2.0) * 0.012**2 * 1e3   # pi c Omega X^2 [mJ]
    assert measured == pytest.approx(exact, rel=1e-3)
    assert "cycles used          18" in proc.stdout


@pytest.mark.slow
def test_kinetic_energy_recorder_example():
    proc = subprocess.run([sys.executable, str(EXAMPLES / "kinetic_energy_recorder.py")], capture_output=True,
                          text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    m = re.search(r"eta\* = ([0-9.]+); bed kinetic energy over the last cycle: mean ([0-9.]+) mJ, max ([0-9.]+) mJ "
                  r"\((\d+) samples at 100 per second\)", proc.stdout)
    assert m, proc.stdout
    eta, mean, peak, n = float(m.group(1)), float(m.group(2)), float(m.group(3)), int(m.group(4))
    assert 0.3 < eta < 1.2 and 0 < mean < peak and n == 200
    # the bed moves with the container to first order: 1/2 m_bed (X Omega)^2 / 2 on average ~ 1.4 mJ
    assert mean == pytest.approx(1e3 * 0.5 * 0.1489 * (0.014 * 4 * math.pi) ** 2 / 2, rel=0.5)


def test_make_loads_writes_the_examples_load_files(tmp_path):
    """examples/make_loads.py writes the committed hammer.csv, quake_synthetic.csv and .AT2, byte for
    byte (the accelerogram is synthetic, seeded)."""
    proc = subprocess.run([sys.executable, str(EXAMPLES / "make_loads.py"), str(tmp_path)], capture_output=True,
                          text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    for name in ("hammer.csv", "quake_synthetic.csv", "quake_synthetic.AT2"):
        assert (tmp_path / name).read_bytes() == (EXAMPLES / name).read_bytes(), name

