"""The tutorial notebooks in examples/ are stored executed and still run from top to bottom."""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat", reason="the notebook tools: pip install -e '.[test]'")
nbclient = pytest.importorskip("nbclient", reason="the notebook tools: pip install -e '.[test]'")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
NOTEBOOKS = ["tutorial_theory_and_run.ipynb", "tutorial_sweep.ipynb"]


def _text(nb) -> str:
    """All text the notebook's cells printed or showed (stdout, stderr, text/plain)."""
    parts = []
    for cell in nb.cells:
        for out in cell.get("outputs", []):
            if out.output_type == "stream":
                parts.append(out.text)
            elif "data" in out:
                parts.append(out.data.get("text/plain", ""))
    return "\n".join(parts)


def _execute(name: str, where: Path):
    for toml in EXAMPLES.glob("*.toml"):
        shutil.copy(toml, where)
    nb = nbformat.read(EXAMPLES / name, as_version=4)
    nbclient.NotebookClient(nb, timeout=240, kernel_name="python3", record_timing=False,
                            resources={"metadata": {"path": str(where)}}).execute()
    return nb


@pytest.mark.parametrize("name", NOTEBOOKS)
def test_stored_with_outputs(name):
    nb = nbformat.read(EXAMPLES / name, as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and all(c.execution_count for c in code), f"{name}: store it executed (every cell run)"
    assert not [o for c in code for o in c.outputs if o.output_type == "error"], f"{name} was stored with an error"
    assert any("image/png" in o.get("data", {}) for c in code for o in c.outputs), f"{name} has no figure"
    assert f"({name})" in (EXAMPLES / "README.md").read_text(encoding="utf-8"), f"{name} not in examples/README.md"


@pytest.mark.slow
def test_theory_and_run_notebook(tmp_path):
    text = _text(_execute("tutorial_theory_and_run.ipynb", tmp_path))
    assert re.search(r"X_opt\s+12\.23 mm", text)
    eta, mode = re.search(r"eta\* DEM\s+([0-9.]+)\s+motion mode: ([a-z-]+)", text).groups()
    assert 0.3 < float(eta) < 1.2 and mode == "rolling-collect-and-collide"


@pytest.mark.slow
def test_sweep_notebook(tmp_path):
    nb = _execute("tutorial_sweep.ipynb", tmp_path)
    text = _text(nb)
    assert "sweep: 100%" in text and "6/6" in text  # the progress bar shows in Jupyter
    assert "X_opt = 40.75 mm for 8 spheres" in text
    series = re.search(r"stroke\n0\.010\s+([0-9.]+)\n0\.025\s+([0-9.]+)\n0\.050\s+([0-9.]+)", text)
    assert series and all(0.0 < float(v) < 1.2 for v in series.groups())
    assert (tmp_path / "tutorial_sweep" / "results.nc").is_file()
