"""Refresh the pinned test environment, ``constraints/test.txt``, from the newest releases.

README's test command and ``.ci/run`` install the test extra *under these constraints*, so a new
release of a dependency (pytest 9.2 refused nested ``pytest.approx`` and broke a fresh install
while CI stayed green) cannot break a fresh install without a line of ours changing. Before each
release, and whenever a dependency should move, run::

    python tools/refresh_constraints.py          # fresh venv, newest releases, write the file
    python tools/refresh_constraints.py --test   # ... and run the whole suite in that venv first

It makes a fresh virtual environment in a temporary folder, installs ``.[test]`` there *without*
the current constraints (what the package registry serves today), optionally runs the test suite
in it (the file is written only if the suite passes), and writes ``pip freeze`` of that
environment (pdamper itself left out) to ``constraints/test.txt`` with a header saying when and
from which Python it was made. Review the diff and commit it with the code that needs it.

pip-tools or uv would resolve a lock without installing; this script installs instead because the
lock must be the environment the suite actually passed in, and pip with venv is all a fresh machine
has.
"""

from __future__ import annotations

import argparse
import datetime
import platform
import subprocess
import sys
import tempfile
import venv
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
TARGET = ROOT / "constraints" / "test.txt"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--test", action="store_true", help="run the test suite in the fresh venv before writing")
    ap.add_argument("--out", type=Path, default=TARGET, help=f"where to write (default {TARGET.relative_to(ROOT)})")
    args = ap.parse_args(argv)
    with tempfile.TemporaryDirectory(prefix="pdamper-constraints-") as tmp:
        env = Path(tmp) / "venv"
        venv.create(env, with_pip=True)
        py = str(env / "bin" / "python")
        subprocess.run([py, "-m", "pip", "install", "-q", "-e", f"{ROOT}[test]"], check=True)
        if args.test:
            rc = subprocess.run([py, "-m", "pytest", "-q"], cwd=ROOT).returncode
            if rc not in (0, 5):
                print(f"the suite failed in the fresh environment (exit {rc}); {args.out} left as it was",
                      file=sys.stderr)
                return rc
        frozen = subprocess.run([py, "-m", "pip", "freeze", "--exclude", "pdamper"], check=True,
                                capture_output=True, text=True).stdout
    pins = sorted((ln for ln in frozen.splitlines() if ln and not ln.startswith(("-e", "#"))), key=str.lower)
    head = [f"# The test environment pdamper's suite passes in: pip freeze of a fresh venv with '.[test]',",
            f"# made by tools/refresh_constraints.py on {datetime.date.today()} with Python "
            f"{platform.python_version()} on {platform.system()} {platform.machine()}.",
            "# Used by README's test command and .ci/run: pip install -e \".[test]\" -c constraints/test.txt"]
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text("\n".join(head + pins) + "\n")
    print(f"wrote {len(pins)} pins to {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
