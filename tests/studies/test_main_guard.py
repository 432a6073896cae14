"""A script that runs a sweep without ``if __name__ == "__main__":`` (issue 42): local Dask workers are
spawned processes that import the script again, so each would run the sweep once more and die ("Nanny
failed to start", ~200 lines of traceback) and leave an empty store. pdamper finds the call outside
the guard before any process or store is made and says so in one line, with the fix. Each test runs a
real script in a subprocess; none starts a Dask worker."""

from __future__ import annotations

import subprocess
import sys
import textwrap
from pathlib import Path

from dem_fixtures import TINY_CONFIG

SRC = str(Path(__file__).resolve().parents[2] / "src")

SWEEP = """\
from pdamper.config import load_case
from pdamper.studies.sweep import SweepSpec, run_sweep

spec = SweepSpec(base=load_case("tiny.toml"), strokes=(0.004, 0.012), seeds=(0,))
"""


def _run(tmp_path, body: str):
    (tmp_path / "tiny.toml").write_text(TINY_CONFIG)
    (tmp_path / "script.py").write_text(body)
    return subprocess.run([sys.executable, "script.py"], cwd=tmp_path, capture_output=True, text=True, timeout=120,
                          env={"PYTHONPATH": SRC, "PATH": "/usr/bin:/bin", "HOME": str(Path.home())})


def test_an_unguarded_sweep_is_one_line_with_the_fix_and_leaves_no_store(tmp_path):
    r = _run(tmp_path, SWEEP + 'run_sweep(spec, "store", workers=2)\n')
    assert r.returncode == 1, r.stderr[-2000:]
    last = r.stderr.strip().splitlines()[-1]
    assert last.startswith("pdamper.errors.InputError: ") and "script.py, line 5: run_sweep runs its cases in worker" \
        in last and 'if __name__ == "__main__":' in last, r.stderr[-2000:]
    assert "Nanny" not in r.stderr and len(r.stderr.splitlines()) < 15, r.stderr[-3000:]
    assert not (tmp_path / "store").exists()  # nothing left behind


def test_the_guard_is_found_in_the_script(tmp_path):
    """The same check on scripts that have the guard, a function called from under it, and one
    that has not (the check alone: no sweep is run)."""
    probe = "from pdamper.studies.executor import unguarded_main_line\n"
    guarded = probe + textwrap.dedent("""\
        def main():
            print("inner", unguarded_main_line())

        if __name__ == "__main__":
            print("top", unguarded_main_line())
            main()
        """)
    r = _run(tmp_path, guarded)
    assert r.returncode == 0 and r.stdout.split("\n")[:2] == ["top None", "inner None"], r.stdout + r.stderr
    r = _run(tmp_path, probe + "x = unguarded_main_line()\nprint(x[1], x[0].rsplit('/', 1)[-1])\n")
    assert r.returncode == 0 and r.stdout.split() == ["2", "script.py"], r.stdout + r.stderr
    r = subprocess.run([sys.executable, "-c", probe + "print(unguarded_main_line())"], capture_output=True, text=True,
                       env={"PYTHONPATH": SRC, "PATH": "/usr/bin:/bin"}, timeout=60)
    assert r.stdout.strip() == "None", r.stdout + r.stderr  # python -c: no script to import again
