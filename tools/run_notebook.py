"""Execute a tutorial notebook of examples/ and store it with its outputs.

    python tools/run_notebook.py examples/tutorial_sweep.ipynb [...]

Runs each notebook in a temporary copy of examples/ (so the sweep's store is not left behind),
as tests/test_notebooks.py does, and writes the executed notebook back in place.
"""

from __future__ import annotations

import shutil
import sys
import tempfile
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run(path: Path) -> float:
    with tempfile.TemporaryDirectory() as tmp:
        for toml in EXAMPLES.glob("*.toml"):
            shutil.copy(toml, tmp)
        nb = nbformat.read(path, as_version=4)
        t0 = time.perf_counter()
        NotebookClient(nb, timeout=300, kernel_name="python3", record_timing=False,
                       resources={"metadata": {"path": tmp}}).execute()
        seconds = time.perf_counter() - t0
    nbformat.write(nb, path)
    return seconds


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for arg in sys.argv[1:]:
        print(f"{arg}: executed in {run(Path(arg)):.1f} s")
