"""A race check for the GPU kernels in numba-cuda's simulator.

On a GPU, a thread that reads what another thread of its block wrote (or writes over what another
read or wrote) sees it only if a barrier (``cuda.syncthreads``) lies between the two; without one
the result depends on the hardware's scheduling. numba-cuda's simulator runs each thread as a
Python thread and switches between them at random, so a missing barrier shows there only by chance
(one was found so: two runs of the same case parted at step 75). This check makes it certain: the
arrays a kernel shares (its shared memory, and the bundles of global memory it is given) become
:class:`Tracked` arrays that note, for every element, the thread that last wrote it and last read
it and at which of the block's barriers; every access compares against those notes:

- a read of an element another thread wrote since the last barrier,
- a write over an element another thread wrote or read since the last barrier,
- a read of a shared element that no thread wrote in this launch (shared memory starts with
  whatever was there on a GPU; the dynamic shared memory too),

each counted by where it happened. Each block gets shared arrays of its own (the simulator's
serve every block of a launch, one block after another); a launch orders everything before it
(:func:`new_launch`).

It patches two of the simulator's internals while it is on (:func:`tracking`): its shared-memory
allocator, ``FakeCUDAShared.array`` (with a lock: the simulator's own allocator is not thread-safe,
two threads can each get an array of their own for one shared array; :func:`locked_shared` is that
allocator alone, which every simulator test runs under), and its barrier,
``BlockThread.syncthreads``, which counts each thread's barriers (a warp's syncwarp is one in the
simulator, whose blocks in the tests are one warp; the barriers inside the simulator's stand-in for a
shuffle, pdamper.kernels.gpu.warp, are not counted: a shuffle orders no memory on a GPU). Reads inside the CPU-compiled
functions a kernel calls are not seen (those take their own sphere's values).
"""

from __future__ import annotations

import collections
import contextlib
import os
import sys
import threading
import traceback

import numpy as np

__all__ = ["Tracked", "tracking", "locked_shared", "track_bundle", "new_launch", "FINDINGS"]

#: (array, what, where) -> how many times
FINDINGS = collections.Counter()
_lock = threading.Lock()
_NEVER = -1


def _thread():
    t = threading.current_thread()
    return t.thread_id, getattr(t, "barriers", 0)


def _where():
    """The kernel lines that made the access (the simulator's own frames left out)."""
    stack = traceback.extract_stack(sys._getframe(2), limit=6)
    lines = [f"{os.path.basename(f.filename)}:{f.lineno}" for f in reversed(stack)
             if "simulator" not in f.filename and "race_check" not in f.filename and "threading" not in f.filename]
    return " <- ".join(lines[:3])


class Tracked(np.ndarray):
    """An array whose element accesses by the simulator's threads are checked (module docstring).
    A slice is tracked alike (it shares its notes with the array it is cut from)."""

    def _notes(self, idx):
        return np.asarray(self._flat[idx]).ravel()

    def __getitem__(self, idx):
        out = self.view(np.ndarray)[idx]
        if not hasattr(self, "_flat") or not hasattr(threading.current_thread(), "thread_id"):
            return out  # (the host's reads, between launches, are ordered by them)
        if isinstance(out, np.ndarray):  # a view: its element reads are checked when they come
            view = out.view(Tracked)
            view._flat = self._flat[idx]
            view._book = self._book
            return view
        tid, barrier = _thread()
        pos = self._notes(idx)
        writer, wrote, reader, read, name, shared = self._book
        with _lock:
            if shared and np.any(writer[pos] == _NEVER):
                FINDINGS[(name, "read of what no thread wrote in this launch", _where())] += 1
            if np.any((writer[pos] >= 0) & (writer[pos] != tid) & (wrote[pos] == barrier)):
                FINDINGS[(name, "read of another thread's write with no barrier between", _where())] += 1
            again = (read[pos] == barrier) & (reader[pos] != tid)
            reader[pos] = np.where(again, -2, tid)  # -2: read by several threads since the barrier
            read[pos] = barrier
        return out

    def reshape(self, *shape):
        """A view of another shape, tracked alike (the kernels see a flat buffer's region as a table)."""
        out = self.view(np.ndarray).reshape(*shape).view(Tracked)
        if hasattr(self, "_flat"):
            out._flat = self._flat.reshape(*shape)
            out._book = self._book
        return out

    def __setitem__(self, idx, value):
        if not hasattr(self, "_flat") or not hasattr(threading.current_thread(), "thread_id"):
            self.view(np.ndarray)[idx] = value
            return
        tid, barrier = _thread()
        pos = self._notes(idx)
        writer, wrote, reader, read, name, _ = self._book
        with _lock:
            if np.any((writer[pos] >= 0) & (writer[pos] != tid) & (wrote[pos] == barrier)):
                FINDINGS[(name, "write over another thread's write with no barrier between", _where())] += 1
            if np.any((read[pos] == barrier) & (reader[pos] != tid) & (reader[pos] != _NEVER)):
                FINDINGS[(name, "write over another thread's read with no barrier between", _where())] += 1
            writer[pos] = tid
            wrote[pos] = barrier
        self.view(np.ndarray)[idx] = value


def _track(a: np.ndarray, name: str, shared: bool) -> Tracked:
    t = a.view(Tracked)
    t._flat = np.arange(a.size).reshape(a.shape)
    # who last wrote / read each element, and after how many of the block's barriers
    t._book = (np.full(a.size, _NEVER if shared else -3, dtype=np.int64), np.full(a.size, -1, dtype=np.int64),
               np.full(a.size, _NEVER, dtype=np.int64), np.full(a.size, -1, dtype=np.int64), name, shared)
    return t


def track_bundle(bundle, name: str):
    """``bundle`` (a NamedTuple of arrays, a kernel's global memory) with each of its arrays tracked."""
    return type(bundle)(*[_track(a, f"{name}.{field}", False) if isinstance(a, np.ndarray) and a.size else a
                          for field, a in zip(bundle._fields, bundle)])


def new_launch(*bundles):
    """A launch starts: everything written or read before it is ordered before it."""
    for bundle in bundles:
        for a in bundle:
            if isinstance(a, Tracked) and hasattr(a, "_book"):
                a._book[1][:] = -1
                a._book[3][:] = -1


def _shared_allocator(track: bool):
    """A thread-safe stand-in for the simulator's ``FakeCUDAShared.array``: one array per call site
    and block (as on a GPU; the simulator's serves every block of a launch), created under a lock
    (the simulator's checks for the array and creates it with no lock, so two threads can each get
    one of their own); with ``track`` a :class:`Tracked` array filled with NaN (integers: the most negative),
    else an empty one as the simulator's."""
    from numba.cuda.np import numpy_support
    from numba.cuda.simulator import kernelapi

    real_array = kernelapi.FakeCUDAShared.array
    alloc = threading.Lock()

    def array(self, shape, dtype, alignment=None):
        if alignment is not None or shape == 0 and not track:  # as the simulator has them
            return real_array(self, shape, dtype, alignment)
        if not isinstance(dtype, (np.dtype, type)):
            dtype = numpy_support.as_dtype(dtype)
        if shape == 0:  # the dynamic shared memory, tracked: one array a block of the launch's size
            shape = self._dynshared_size // np.dtype(dtype).itemsize
        where = traceback.extract_stack(sys._getframe(1), limit=1)[0]
        key = (where.filename, where.lineno, threading.current_thread().blockIdx.x, np.shape(shape), str(dtype))
        with alloc:
            got = self._allocations.get(key)
            if got is None:
                if track:
                    fill = np.nan if np.dtype(dtype).kind == "f" else np.iinfo(dtype).min
                    got = _track(np.full(shape, fill, dtype=dtype), f"shared {os.path.basename(key[0])}:{key[1]}",
                                 True)
                else:
                    got = np.empty(shape, dtype)
                self._allocations[key] = got
        return got

    return array


@contextlib.contextmanager
def locked_shared():
    """Within it, the simulator's shared arrays come from :func:`_shared_allocator` (untracked): what
    the GPU engine's simulator tests run under (tests/kernels/gpu/conftest.py)."""
    from numba.cuda.simulator import kernelapi

    real = kernelapi.FakeCUDAShared.array
    kernelapi.FakeCUDAShared.array = _shared_allocator(False)
    try:
        yield
    finally:
        kernelapi.FakeCUDAShared.array = real


@contextlib.contextmanager
def tracking():
    """Within it, the simulator's shared arrays are tracked and its barriers counted (module
    docstring); FINDINGS starts empty."""
    from numba.cuda.simulator import kernel, kernelapi

    shared_cls, thread_cls = kernelapi.FakeCUDAShared, kernel.BlockThread
    real_array, real_sync = shared_cls.array, thread_cls.syncthreads

    def syncthreads(self):
        if not getattr(self, "exchanging", False):  # (a warp exchange's barrier orders no memory on a GPU)
            self.barriers = getattr(self, "barriers", 0) + 1
        return real_sync(self)

    FINDINGS.clear()
    shared_cls.array, thread_cls.syncthreads = _shared_allocator(True), syncthreads
    try:
        yield FINDINGS
    finally:
        shared_cls.array, thread_cls.syncthreads = real_array, real_sync


def findings_text() -> str:
    return "\n".join(f"{n} x {name}: {what} at {where}" for (name, what, where), n in FINDINGS.most_common())
