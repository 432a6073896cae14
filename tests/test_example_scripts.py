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
