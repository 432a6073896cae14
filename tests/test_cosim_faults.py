"""Faults of a co-simulation: kill -9 of pdamper during an OpenSees co-simulated run.

The unit of work of a co-simulation is one coupled run (a transient, a frequency of a response, a
decay): its state is in memory and in the OpenSees child, so a run killed part-way is run again
from its start, and nothing of it is written before it finishes (the figure by a temporary file
and a rename, the JSON printed at the end). The OpenSees child, in a session of its own, ends by
itself when its parent's pipe closes, and removes its log.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from pdamper.structure.opensees import available

ROOT = Path(__file__).resolve().parents[1]


def _workers():
    """{pid: argv} of the OpenSees children running now (Linux /proc)."""
    out = {}
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                argv = (d / "cmdline").read_bytes().split(b"\0")
            except OSError:
                continue
            if any(a.endswith(b"_opensees_worker.py") for a in argv):
                out[int(d.name)] = [a.decode() for a in argv if a]
    return out


@pytest.mark.slow
@pytest.mark.skipif(available() is not None or not Path("/proc").is_dir(),
                    reason=f"needs openseespy and Linux /proc: {available()}")
def test_kill_9_during_a_cosimulation_leaves_nothing_half_written_and_no_child(tmp_path):
    before = set(_workers())
    plot = tmp_path / "quake.png"
    env = dict(os.environ, PYTHONPATH=str(ROOT / "src"))
    proc = subprocess.Popen([sys.executable, "-m", "pdamper.cli", "transient", str(ROOT / "examples/frame4_quake.toml"),
                             "--plot", str(plot)], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env,
                            cwd=tmp_path)
    try:
        deadline = time.time() + 240
        mine = {}
        while time.time() < deadline and not mine:  # the co-simulation has started: its OpenSees child runs
            mine = {p: a for p, a in _workers().items() if p not in before}
            time.sleep(0.2)
        assert mine, "the co-simulation did not start"
        time.sleep(1.0)  # well into the run
        assert proc.poll() is None
    finally:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
    (pid, argv), = mine.items()
    log = Path(argv[-1])
    deadline = time.time() + 20
    while time.time() < deadline and pid in _workers():
        time.sleep(0.1)
    assert pid not in _workers(), "the OpenSees child outlived its parent"
    assert not log.exists(), "the child's log was left behind"
    assert list(tmp_path.iterdir()) == [], "something was written"
