"""The contact laws' dispatch for the CUDA target.

:func:`pdamper.kernels.contact.law_touch` and :func:`~pdamper.kernels.contact.law_force` resolve,
when a kernel is compiled, to the ``touch`` and ``force`` of the damping law whose marker is in the
contact table; :func:`~pdamper.kernels.contact.friction` and
:func:`~pdamper.kernels.contact.keeps_history` to the tangential law of its ``tangential`` marker
(the tanh law or the spring). The CPU kernels register that resolution as generic-target overloads
inlined at numba's IR level (``inline="always"``); numba-cuda 0.30 cannot inline an overload
registered that way (its lowering sees the inlined arguments as omitted), so the CUDA target gets
its own registration of the very same resolution functions (``kernels/contact.py``'s), as a plain
call (which NVVM inlines). A target-specific overload takes precedence over the generic one for its
target, so the CPU kernels are untouched.

Importing this module registers the overloads (once); :mod:`pdamper.kernels.gpu.verlet` imports it.
In numba-cuda's simulator the kernels run as Python and call the CPU-compiled functions, so there
is nothing to register.
"""

from __future__ import annotations

from numba import cuda

from .. import contact as _contact

__all__ = ["SIMULATOR"]

#: True when numba-cuda's simulator runs the kernels (``NUMBA_ENABLE_CUDASIM=1`` when numba.cuda
#: was first imported): its ``cuda.jit`` is the simulator's.
SIMULATOR = cuda.jit.__module__.startswith("numba.cuda.simulator")


def _cuda_overload(func):
    """numba-cuda's overload for its own target (numba-cuda >= 0.21), else numba's with
    ``target="cuda"`` (older numba-cuda)."""
    try:
        from numba.cuda.extending import overload
    except ImportError:
        from numba.extending import overload as _generic

        return _generic(func, target="cuda")
    return overload(func)


if not SIMULATOR:
    # the CPU's resolution functions (numba's @overload hands the decorated function back)
    for _stub, _resolve in ((_contact.law_touch, _contact._law_touch), (_contact.law_force, _contact._law_force),
                            (_contact.friction, _contact._friction),
                            (_contact.keeps_history, _contact._keeps_history)):
        _cuda_overload(_stub)(_resolve)
