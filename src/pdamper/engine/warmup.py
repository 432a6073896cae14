"""Compile on a second core while the first compiles: the first run on a cold kernel cache.

numba compiles a kernel and everything it calls in one thread under one lock, so a first run's
compiling (~15 CPU-s for Gear) takes one core while the other idles. Every function numba
compiles is cached on its own, and a kernel that needs a callee looks for it in the cache before
compiling it. So when the kernel cache holds no copy of the stepper's kernel yet, :func:`start`
launches ``python -m pdamper.engine.warmup`` with the case: it builds the same bundles and
compiles the kernel's larger callees in the order opposite to the one the kernel meets them
in (the stepper's :meth:`warm_jobs`); each one it finishes first is then loaded from the cache by
the main process instead of compiled again. Nothing is shared but the cache files, which numba
writes whole (to a temporary file, then renamed), so the outcome of a run does not depend on
who compiled what; the helper is ended when the run ends.

Not started when there is one core, inside a Dask worker (a study already keeps every core
busy), when the cache directory is not known, when the kernel is cached already, or with
``PDAMPER_WARMUP=0``. No library does this (numba's own parallel compilation is for
``parallel=True`` loops, not for the call graph of one kernel); it is ~100 lines.
"""

from __future__ import annotations

import atexit
import os
import pickle
import subprocess
import sys
from pathlib import Path

import numba
import numpy as np
from numba import typeof

__all__ = ["start", "cold", "empty_samples"]


def empty_samples(n: int):
    """A :class:`~pdamper.kernels.bundles.Samples` with no rows: the same numba type as a run's."""
    from ..kernels.bundles import ENERGY_COLUMNS, FRAME_COLUMNS, STRUCTURE_COLUMNS, Samples

    return Samples(interval=1.0, wall_force=np.zeros(0), energy=np.zeros((0, len(ENERGY_COLUMNS))),
                   frames=np.zeros((0, n, FRAME_COLUMNS)), frame_every=0,
                   structure=np.zeros((0, len(STRUCTURE_COLUMNS))), sums=np.zeros(4))


def cold(kernel) -> bool:
    """True when numba's cache directory is known and holds no copy of ``kernel`` (a dispatcher)
    and this process has not compiled it either."""
    if not hasattr(kernel, "py_func") or kernel.signatures:  # not a numba dispatcher, or compiled here
        return False
    root = numba.config.CACHE_DIR
    if not root or not os.path.isdir(root):
        return False
    name = f"*.{kernel.py_func.__name__}-*.nbi"  # numba's index file: <module>.<function>-<line>.<python>.nbi
    return not any(Path(root).glob(name)) and not any(Path(root).glob("*/" + name))


def _in_dask_worker() -> bool:
    if "distributed" not in sys.modules:
        return False
    from distributed import get_worker

    try:
        get_worker()
    except ValueError:
        return False
    return True


def start(case, stepper):
    """Launch the helper for ``case`` when it can help (module docstring); returns the process or
    None. The process is ended at the latest when this interpreter exits. It only saves time:
    whatever goes wrong with it (a case that cannot be pickled, a helper that fails) leaves the run
    to compile alone, as without it."""
    if os.environ.get("PDAMPER_WARMUP", "1") == "0" or (os.cpu_count() or 1) < 2:
        return None
    kernel, _ = stepper.warm_jobs(empty_samples(stepper.engine.n))[0]
    if not cold(kernel) or _in_dask_worker():
        return None
    try:
        data = pickle.dumps(case)
    except (pickle.PicklingError, TypeError, AttributeError):  # e.g. a drive or shape defined in a script
        return None
    try:
        proc = subprocess.Popen([sys.executable, "-m", "pdamper.engine.warmup"], stdin=subprocess.PIPE,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env={**os.environ, "PDAMPER_WARMUP": "0"})
        proc.stdin.write(data)
        proc.stdin.close()
    except OSError:  # no process could be started, or it ended at once: the run compiles alone
        return None
    atexit.register(_end, proc)
    return proc


def _end(proc) -> None:
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()


def compile_jobs(jobs) -> None:
    """Compile each ``(dispatcher, arguments)`` for the numba types of its arguments (loaded from
    the cache when it is there)."""
    for kernel, args in jobs:
        kernel.compile(tuple(typeof(a) for a in args))


def main() -> None:
    """The helper: read a pickled case on stdin, build its bundles and compile the callees of its
    stepper's kernel (the kernel itself is left to the main process)."""
    from .build import build
    from .steppers import stepper_for

    case = pickle.loads(sys.stdin.buffer.read())
    engine = build(case)
    stepper = stepper_for(engine, 1.0 / case.recording.sample_rate)
    compile_jobs(stepper.warm_jobs(empty_samples(engine.n))[1:])


if __name__ == "__main__":
    main()
