"""The damping law's dispatch for the CUDA target.

:func:`pdamper.kernels.contact.law_touch` and :func:`~pdamper.kernels.contact.law_force` resolve,
when a kernel is compiled, to the ``touch`` and ``force`` of the law whose marker is in the contact
table. The CPU kernels register that resolution as generic-target overloads inlined at numba's IR
level (``inline="always"``); numba-cuda 0.30 cannot inline an overload registered that way (its
lowering sees the inlined arguments as omitted), so the CUDA target gets its own registration
here: the same resolution, the same law functions, a plain call (which NVVM inlines). A
target-specific overload takes precedence over the generic one for its target, so the CPU kernels
are untouched.

Importing this module registers the overloads (once); :mod:`pdamper.kernels.gpu.verlet` imports it.
In numba-cuda's simulator the kernels run as Python and call the CPU-compiled functions, so there
is nothing to register.
"""

from __future__ import annotations

from numba import cuda

from ..contact import _law_of, law_force, law_touch

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
    @_cuda_overload(law_touch)
    def _law_touch_cuda(law, coefficient, v_in, k, m_star):
        touch = _law_of(law).touch

        def impl(law, coefficient, v_in, k, m_star):
            return touch(coefficient, v_in, k, m_star)

        return impl

    @_cuda_overload(law_force)
    def _law_force_cuda(law, k, delta, delta_dot, d):
        force = _law_of(law).force

        def impl(law, k, delta, delta_dot, d):
            return force(k, delta, delta_dot, d)

        return impl
