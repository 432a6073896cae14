"""Helpers shared by the sweep-store tests."""

from __future__ import annotations


def kill_after(cmd, store, cases: int = 2, timeout: float = 120.0) -> dict:
    """Start ``cmd`` (a sweep into ``store``), kill -9 its whole process group once ``cases`` case
    files exist, and return the case files then on disk (name -> bytes)."""
    import os
    import signal
    import subprocess
    import time

    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        deadline = time.time() + timeout
        while time.time() < deadline and len(list((store / "cases").glob("*.json"))) < cases:
            time.sleep(0.1)
    finally:
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
    return {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
