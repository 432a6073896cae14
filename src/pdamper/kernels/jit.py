"""The one place where numba is configured for pdamper.

Every kernel is compiled with :data:`JIT` options: ``cache=True`` so the machine
code is written to ``__pycache__`` beside the sources (or ``NUMBA_CACHE_DIR``)
and later runs start without compiling; ``nogil=True`` so threads can run
kernels side by side; ``error_model='numpy'`` so a division by zero gives inf
instead of raising from inside numba.
"""

from __future__ import annotations

import numba

JIT = dict(cache=True, nogil=True, error_model="numpy", fastmath=False)


def njit(*args, **kwargs):
    """``numba.njit`` with pdamper's options (extra keyword arguments override)."""
    opts = {**JIT, **kwargs}
    if args and callable(args[0]):
        return numba.njit(**opts)(args[0])
    return numba.njit(*args, **opts)
