"""Where a GPU step's time goes: a clock for the probed Gear kernel
(:func:`pdamper.kernels.gpu.gear.gear_kernel` with ``probed=True``).

Hardware counters need ``ncu`` on the GPU machine and a profiler's permissions, which the machines
this project can use do not always give; a block reading its own multiprocessor's cycle counter
(PTX's ``%clock64``) at the end of each phase of a step needs neither. The probed kernel is the
same source as the production kernel with the probes switched on (:data:`PROBED` is a constant the
compiler folds away in the production kernel, so that kernel carries no probe); its thread 0 adds
each phase's cycles to :attr:`~.batch.GearClock.cycles`. Each phase ends at a barrier of the
block, so thread 0's cycles are the block's. A clock read is a few cycles and stops the compiler
moving work across it, so the probed kernel's step is a little slower than the production one:
its phases' shares are what it tells, the production kernel's time is measured on its own.

numba has no clock intrinsic for the CUDA target, so this module writes the one-instruction inline
PTX itself (as numba-cuda writes ``nanosleep``). In numba-cuda's simulator the clock is the host's
(nanoseconds), which only the tests of the bookkeeping use. The production kernels read it too, once
a step by thread 0, for a launch bounded by time (:func:`.verlet.out_of_time`).
"""

from __future__ import annotations

import time

from numba import cuda, types

from .targets import SIMULATOR

__all__ = ["clock", "lap", "PHASES", "PROBES", "P_ROWS", "P_REBUILDS"]

#: The phases of a step the probed kernel times, in the order of its columns of
#: :attr:`~.batch.GearClock.cycles`.
PHASES = ("span, drive start, priming", "displacement check", "neighbour rebuild",
          "rescale, predict, save history", "pair laws", "sphere forces, increments",
          "gather touching pairs", "implicit pair walk", "implicit walls", "error norm",
          "rejected step: restore", "accepted step: correct, ledger", "sample")
#: Columns after the phases: the implicit walk's rows, summed over the steps; the rebuilds.
P_ROWS = len(PHASES)
P_REBUILDS = P_ROWS + 1
#: Columns of :attr:`~.batch.GearClock.cycles`.
PROBES = P_REBUILDS + 1

if SIMULATOR:
    def _clock64():
        return time.perf_counter_ns()
else:
    from llvmlite import ir
    from numba.cuda.extending import intrinsic

    @intrinsic
    def _clock64(typingctx):
        """The multiprocessor's cycle counter (PTX ``mov.u64 %clock64``; a side effect, so the
        compiler keeps each read where it stands)."""
        sig = types.int64()

        def codegen(context, builder, signature, args):
            read = ir.InlineAsm(ir.FunctionType(ir.IntType(64), []), "mov.u64 $0, %clock64;", "=l",
                                side_effect=True)
            return builder.call(read, [])

        return sig, codegen


@cuda.jit(device=True)
def clock():
    """The cycle counter of the block's multiprocessor (the host's nanoseconds in the simulator)."""
    return _clock64()


@cuda.jit(device=True)
def lap(cycles, c, tid, k, tick):
    """Phase ``k`` of case ``c`` ends now: thread 0 adds the cycles since ``tick``; returns now."""
    now = clock()
    if tid == 0:
        cycles[c, k] += now - tick
    return now
