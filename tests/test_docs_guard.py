"""Every Python snippet of the docs, the README and the examples (scripts and notebooks) that runs a
sweep, a study or an ensemble calls it under ``if __name__ == "__main__":`` (issue 42): copied into a
script without it, the local Dask workers would import the script again and run the sweep once more
(pdamper refuses such a call: tests/studies/test_main_guard.py). The check is the one pdamper makes
on a running script (:func:`pdamper.studies.executor.in_main_guard`)."""

from __future__ import annotations

import ast
import json
import re
from pathlib import Path

from pdamper.studies.executor import in_main_guard

ROOT = Path(__file__).resolve().parents[1]
#: The calls that start worker processes (a sweep, a study, a calibration, an ensemble).
RUNS = {"run_sweep", "run_study", "calibrate", "run_ensemble", "run_validation"}
_BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def _snippets():
    for page in [ROOT / "README.md", ROOT / "examples" / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]:
        for k, m in enumerate(_BLOCK.finditer(page.read_text(encoding="utf-8"))):
            yield f"{page.relative_to(ROOT)} block {k + 1}", m.group(1)
    for nb in sorted((ROOT / "examples").glob("*.ipynb")):
        cells = [c for c in json.loads(nb.read_text(encoding="utf-8"))["cells"] if c["cell_type"] == "code"]
        for k, c in enumerate(cells):
            yield f"{nb.relative_to(ROOT)} cell {k + 1}", "".join(c["source"])
    for script in sorted((ROOT / "examples").rglob("*.py")):
        yield str(script.relative_to(ROOT)), script.read_text(encoding="utf-8")


def _calls(tree):
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            f = node.func
            name = f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else ""
            if name in RUNS:
                yield name, node.lineno


def _in_function(tree, line: int) -> bool:
    """A call inside a function body runs when the function is called (that call is checked)."""
    return any(isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef)) and n.lineno <= line <= n.end_lineno
               for n in ast.walk(tree))


def test_every_snippet_that_runs_a_sweep_has_the_main_guard():
    unguarded, seen = [], 0
    for where, code in _snippets():
        try:
            tree = ast.parse(code.replace("%matplotlib inline", ""))
        except SyntaxError:
            continue  # a fragment (an ellipsis, a shell line): no runnable sweep
        for name, line in _calls(tree):
            seen += 1
            if not in_main_guard(tree, line) and not _in_function(tree, line):
                unguarded.append(f"{where}, line {line}: {name}(...)")
    assert not unguarded, "snippets that run a sweep without 'if __name__ == \"__main__\":': " + "; ".join(unguarded)
    assert seen >= 2  # docs/sweeps.md and the sweep tutorial at least
