"""The one place where numba is configured for pdamper (the ground floor: geometry, contact laws
and kernels all compile through :func:`njit`).

Every kernel is compiled with :data:`JIT` options: ``cache=True`` so the machine code is
written to disk and later runs start without compiling; ``nogil=True`` so threads can run
kernels side by side; ``error_model='numpy'`` so a division by zero gives inf instead of
raising from inside numba; ``fastmath={"contract"}`` lets LLVM fuse multiply-adds into FMA
instructions (shorter latency chains in the contact loops: a 36-sphere step takes 1.43 us with
it, 1.50 us without) and nothing else: no reassociation, no assumptions about NaN or infinities, so results
stay deterministic on a given machine.

**Cache directory.** numba checks only the source file of a cached function, not the files of
the functions it calls, so an edited contact law could be served stale from a caller's cache.
pdamper therefore keys the cache directory on a hash of all its compiled sources:
``$PDAMPER_CACHE_DIR`` (default ``~/.cache/pdamper``) ``/numba-<hash>``. ``NUMBA_CACHE_DIR``,
when set, wins.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

import numba

JIT = dict(cache=True, nogil=True, error_model="numpy", fastmath={"contract"})

_PKG = Path(__file__).resolve().parent
#: Folders whose sources hold compiled code (their hash names the cache directory), and this file.
_COMPILED_SOURCES = ("kernels", "kernels/gpu", "contact", "geometry")


def _source_hash() -> str:
    h = hashlib.sha1(numba.__version__.encode())
    h.update(Path(__file__).read_bytes())
    for sub in _COMPILED_SOURCES:
        for f in sorted((_PKG / sub).glob("*.py")):
            h.update(f.name.encode())
            h.update(f.read_bytes())
    return h.hexdigest()[:16]


def cache_dir() -> Path:
    """Directory where pdamper's compiled kernels are cached."""
    base = os.environ.get("PDAMPER_CACHE_DIR") or os.path.join(os.path.expanduser("~"), ".cache", "pdamper")
    return Path(base) / f"numba-{_source_hash()}"


if not os.environ.get("NUMBA_CACHE_DIR"):
    try:
        d = cache_dir()
        d.mkdir(parents=True, exist_ok=True)
        numba.config.CACHE_DIR = str(d)
    except OSError:  # read-only home: fall back to numba's default (__pycache__ beside the sources)
        pass


def njit(*args, **kwargs):
    """``numba.njit`` with pdamper's options (extra keyword arguments override)."""
    opts = {**JIT, **kwargs}
    if args and callable(args[0]):
        return numba.njit(**opts)(args[0])
    return numba.njit(*args, **opts)
