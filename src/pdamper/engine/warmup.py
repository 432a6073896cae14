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
who compiled what; a helper still running when the run's interpreter exits is ended.

Not started when this process may use one core only, inside a Dask worker (a study already keeps
every core busy), in a frozen application, when the cache directory is not known, when the
kernel is cached already (any copy of it for this Python: a first coupled or link-cell run after
plain ones compiles alone), or with ``PDAMPER_WARMUP=0``. No library does this (numba's own
parallel compilation is for ``parallel=True`` loops, not for the call graph of one kernel); it is
~100 lines.
"""

from __future__ import annotations

import atexit
import os
import pickle
import subprocess
import sys
import threading
from pathlib import Path

import numba
import numpy as np
from numba import typeof, types

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
    # numba's index file: <module>.<function>-<line>.py<major><minor>.nbi
    name = f"*.{kernel.py_func.__name__}-*.py{sys.version_info.major}{sys.version_info.minor}.nbi"
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


def _cores() -> int:
    """The processors this process may run on (a container's or ``taskset``'s limit included)."""
    try:
        return len(os.sched_getaffinity(0))
    except (AttributeError, OSError):
        return os.cpu_count() or 1


def start(case, stepper):
    """Launch the helper for ``case`` when it can help (module docstring); returns the process or
    None. It only saves time: whatever goes wrong with it (a case that cannot be pickled, a helper
    that cannot start or fails) leaves the run to compile alone, as without it, so no error of its
    own reaches the run. The process is ended, if it still runs, when this interpreter exits."""
    if os.environ.get("PDAMPER_WARMUP", "1") == "0" or _cores() < 2 or getattr(sys, "frozen", False) \
            or not sys.executable:
        return None
    try:
        if _in_dask_worker():
            return None
        kernel, _ = stepper.warm_jobs(empty_samples(stepper.engine.n))[0]
        if not cold(kernel):
            return None
        data = pickle.dumps(case)
        proc = subprocess.Popen([sys.executable, "-m", "pdamper.engine.warmup"], stdin=subprocess.PIPE,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env={**os.environ, "PDAMPER_WARMUP": "0"})
    except Exception:  # an optimisation only: never the reason a run fails
        return None
    # the case goes in and the helper is reaped by a thread of its own (a large case would block a
    # write until the helper reads; a finished helper must not linger as a zombie)
    threading.Thread(target=_feed, args=(proc, data), daemon=True).start()
    atexit.register(_end, proc)
    return proc


def _feed(proc, data: bytes) -> None:
    try:
        proc.stdin.write(data)
        proc.stdin.close()
    except OSError:  # the helper ended early: nothing to do
        pass
    proc.wait()


def _end(proc) -> None:
    if proc.poll() is None:
        proc.terminate()
        try:
            proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            proc.kill()


def compile_jobs(jobs) -> None:
    """Compile each ``(dispatcher, arguments)`` for the numba types of its arguments (loaded from
    the cache when it is there); an argument may be given as its numba type (a view whose layout
    numba types differently inside a kernel than from Python)."""
    for kernel, args in jobs:
        kernel.compile(tuple(a if isinstance(a, types.Type) else typeof(a) for a in args))


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
