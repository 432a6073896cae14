"""A scheduler for numba-cuda's simulator that waits instead of polling, for the GPU engine's
simulator tests (tests/kernels/gpu/conftest.py runs every one of them under :func:`quiet_scheduler`).

The simulator runs each thread of a block as a Python thread; a block's manager (its
``BlockManager.run``) releases a barrier once every live thread waits at it. numba-cuda 0.30's
manager finds that out by polling the threads in a loop that never sleeps, so it holds the
interpreter for a whole switch interval each time it gets it: about half of a launch's time went to
the poll (cProfile of the race check: 2.0 M ``Thread.is_alive`` calls in 12.5 s). Here the threads
tell the manager, under one condition variable, when they reach a barrier and when they end, and the
manager sleeps on it in between. What a thread does, and when the threads switch (the interpreter's
own choice, as before), is unchanged; a thread that raises stops the block (the others are aborted
at their next barrier) and its exception is raised from the launch, as the simulator's.

No library does this: it replaces two methods of the simulator (``BlockManager.run`` and
``BlockThread.syncthreads``: the barrier's own steps, as the simulator takes them, plus the
notification) while the context is on; :func:`gpu_race_check.tracking` wraps whichever barrier is
in place.
"""

from __future__ import annotations

import contextlib
import threading

import numpy as np

__all__ = ["quiet_scheduler"]


def _syncthreads(self):
    """The simulator's barrier, telling the block's manager that this thread waits at it."""
    if self.abort:
        raise RuntimeError("abort flag set on syncthreads call")
    with self.block_condition:
        self.syncthreads_blocked = True
        self.block_condition.notify()
    self.syncthreads_event.wait()
    self.syncthreads_event.clear()
    if self.abort:
        raise RuntimeError("abort flag set on syncthreads clear")


def _run_block(thread_cls):
    def run(self, grid_point, *args):
        """Run one block: start its threads, release each barrier once every live thread waits at
        it, sleep on the block's condition in between; raise the first exception a thread raised."""
        cond = threading.Condition()
        ended = []

        def target():
            me = threading.current_thread()
            try:
                self._f(*args)
            except BaseException:
                me.failed = True
                raise
            finally:
                with cond:
                    ended.append(me)
                    cond.notify()

        threads = []
        for block_point in np.ndindex(*self._block_dim):
            t = thread_cls(target, self, grid_point, block_point, self._debug)
            t.block_condition, t.failed = cond, False
            threads.append(t)
        for t in threads:
            t.start()
        with cond:
            while len(ended) < len(threads):
                if any(t.failed for t in ended):
                    for t in threads:
                        t.abort = True
                        t.syncthreads_blocked = False
                        t.syncthreads_event.set()
                    break
                live = [t for t in threads if t not in ended]
                if all(t.syncthreads_blocked for t in live):
                    for t in live:
                        t.syncthreads_blocked = False
                        t.syncthreads_event.set()
                cond.wait()
        for t in threads:
            t.join()
        # the first thread to fail (the others' aborts come after it), else any exception left
        for t in [t for t in ended if t.failed] + threads:
            if t.exception:
                raise t.exception[0].with_traceback(t.exception[1])

    return run


@contextlib.contextmanager
def quiet_scheduler():
    """Within it, the simulator's blocks run under the waiting manager (module docstring)."""
    from numba.cuda.simulator import kernel

    manager, thread = kernel.BlockManager, kernel.BlockThread
    real_run, real_sync = manager.run, thread.syncthreads
    manager.run, thread.syncthreads = _run_block(thread), _syncthreads
    try:
        yield
    finally:
        manager.run, thread.syncthreads = real_run, real_sync
