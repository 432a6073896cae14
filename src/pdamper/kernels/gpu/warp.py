"""A block's synchronisation and reductions, warp-level where the block is one warp.

A case's block is one warp (a bed of up to 64 spheres) or a few (:data:`~.batch.MAX_WARPS`). Within
a warp the lanes synchronise with ``__syncwarp`` and exchange values by shuffles; only a block of
several warps goes through a block barrier and a few words of shared memory (``red``, one word a
warp). Every function here is called by every thread of the block, in the same order: the block's
control flow is uniform wherever one is called.

- :func:`sync`: a barrier of the block (``syncwarp`` for one warp, ``syncthreads`` for several).
- :func:`block_max`, :func:`block_sum`, :func:`block_min_int`, :func:`block_or`: every thread gets the
  block's result (a tree of ``shfl_down`` in each warp, lane 0's result broadcast; then the warps' in
  warp order). ``block_max`` lets a NaN through, as the error control needs.
- :func:`block_scan`: the exclusive prefix sum of an integer over the threads, in thread order, and
  its total (``shfl_up`` in each warp, then the warps before): where each thread's rows go in a
  compact list in the CPU's order.

numba-cuda's simulator has no warp intrinsics. There (:data:`~.targets.SIMULATOR`) the same
functions are plain Python that exchange values through the block's barrier (the simulator runs a
block's threads as Python threads; a warp's exchange waits for the block, which is right for a block
of one warp, what the simulator tests run, and for the uniform calls of several). They mark the
thread while they exchange, so that the tests' race check does not count those barriers as the
kernel's own: a shuffle orders no memory on a GPU. The block's reductions and scan take one such
exchange there (the tree's shuffles, one exchange each, made the simulator tests several times
slower); the trees themselves run in the simulator in tests/kernels/gpu/test_warp_gpu.py, warp by
warp, on blocks of one and of two warps.
"""

from __future__ import annotations

import threading

from numba import cuda

from .batch import WARP
from .targets import SIMULATOR

__all__ = ["sync", "clock", "out_of_time", "block_max", "block_sum", "block_min_int", "block_or", "block_scan", "FULL"]

#: The mask of a whole warp.
FULL = 0xFFFFFFFF

if SIMULATOR:
    def _exchange(value):
        """Every thread's ``value`` of the block, by thread index (the simulator's stand-in for a shuffle)."""
        t = threading.current_thread()
        box = vars(t._manager).setdefault("exchange", {})  # (the simulator makes a manager a block)
        t.exchanging = True
        box[t.threadIdx.x] = value
        t.syncthreads()
        seen = dict(box)
        t.syncthreads()
        t.exchanging = False
        return seen

    def _lane_value(value, src):
        """``value`` of lane ``src`` of this thread's warp (own value when it has no such lane)."""
        t = threading.current_thread()
        seen = _exchange(value)
        tid = t.threadIdx.x
        k = (tid // WARP) * WARP + src
        return seen[k] if 0 <= src < WARP and k in seen else value

    def shfl_down(value, delta):
        t = threading.current_thread()
        return _lane_value(value, t.threadIdx.x % WARP + delta)

    def shfl_up(value, delta):
        t = threading.current_thread()
        return _lane_value(value, t.threadIdx.x % WARP - delta)

    def shfl_idx(value, src):
        return _lane_value(value, src)

    def syncwarp():
        threading.current_thread().syncthreads()
else:
    @cuda.jit(device=True)
    def shfl_down(value, delta):
        return cuda.shfl_down_sync(FULL, value, delta)

    @cuda.jit(device=True)
    def shfl_up(value, delta):
        return cuda.shfl_up_sync(FULL, value, delta)

    @cuda.jit(device=True)
    def shfl_idx(value, src):
        return cuda.shfl_sync(FULL, value, src)

    @cuda.jit(device=True)
    def syncwarp():
        cuda.syncwarp(FULL)


@cuda.jit(device=True)
def sync(bd):
    """A barrier of the block of ``bd`` threads (warp-level when it is one warp)."""
    if bd > WARP:
        cuda.syncthreads()
    else:
        syncwarp()


@cuda.jit(device=True)
def _lanes(tid, bd):
    """This thread's lane, warp, and the lanes of its warp."""
    w = tid // WARP
    return tid % WARP, w, min(WARP, bd - w * WARP)


@cuda.jit(device=True)
def _warp_max(v, lane, lanes):
    off = WARP // 2
    while off > 0:
        y = shfl_down(v, off)
        if lane + off < lanes and (y > v or y != y):
            v = y
        off //= 2
    return shfl_idx(v, 0)


@cuda.jit(device=True)
def _tree_max(v, tid, bd, red):
    """The largest ``v`` of the block's threads (a NaN wins); every thread gets it."""
    lane, w, lanes = _lanes(tid, bd)
    v = _warp_max(v, lane, lanes)
    if bd > WARP:
        if lane == 0:
            red[w] = v
        cuda.syncthreads()
        v = red[0]
        for k in range(1, (bd + WARP - 1) // WARP):
            y = red[k]
            if y > v or y != y:
                v = y
        cuda.syncthreads()
    return v


@cuda.jit(device=True)
def _tree_sum(v, tid, bd, red):
    """The sum of ``v`` over the block's threads (a tree in each warp, then the warps in order);
    every thread gets it."""
    lane, w, lanes = _lanes(tid, bd)
    off = WARP // 2
    while off > 0:
        y = shfl_down(v, off)
        if lane + off < lanes:
            v += y
        off //= 2
    v = shfl_idx(v, 0)
    if bd > WARP:
        if lane == 0:
            red[w] = v
        cuda.syncthreads()
        v = red[0]
        for k in range(1, (bd + WARP - 1) // WARP):
            v += red[k]
        cuda.syncthreads()
    return v


@cuda.jit(device=True)
def block_min_int(v, tid, bd, red):
    """The smallest integer ``v`` of the block's threads; every thread gets it."""
    return -int(block_max(float(-v), tid, bd, red))


@cuda.jit(device=True)
def _tree_or(v, tid, bd, red):
    """The bitwise or of the small non-negative integer ``v`` (a few flag bits) over the block's
    threads; every thread gets it."""
    lane, w, lanes = _lanes(tid, bd)
    off = WARP // 2
    while off > 0:
        y = shfl_down(v, off)
        if lane + off < lanes:
            v |= y
        off //= 2
    v = shfl_idx(v, 0)
    if bd > WARP:
        if lane == 0:
            red[w] = float(v)
        cuda.syncthreads()
        v = 0
        for k in range((bd + WARP - 1) // WARP):
            v |= int(red[k])
        cuda.syncthreads()
    return v


@cuda.jit(device=True)
def _tree_scan(m, tid, bd, red):
    """The exclusive prefix sum of the integer ``m`` over the block's threads in thread order, and
    its total: ``(before, total)``."""
    lane, w, lanes = _lanes(tid, bd)
    v = m
    off = 1
    while off < WARP:
        y = shfl_up(v, off)
        if lane >= off:
            v += y
        off *= 2
    total = shfl_idx(v, lanes - 1)
    before = v - m
    if bd > WARP:
        if lane == 0:
            red[w] = float(total)
        cuda.syncthreads()
        total = 0
        for k in range((bd + WARP - 1) // WARP):
            t = int(red[k])
            if k < w:
                before += t
            total += t
        cuda.syncthreads()
    return before, total


if SIMULATOR:
    def clock():
        """The host's nanoseconds (the simulator's stand-in for the multiprocessor's cycle counter)."""
        import time

        return time.perf_counter_ns()
else:
    from llvmlite import ir
    from numba import types
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
        """The cycle counter of the block's multiprocessor (numba has no clock intrinsic for the
        CUDA target: one instruction of inline PTX, as numba-cuda writes ``nanosleep``)."""
        return _clock64()


if SIMULATOR:
    def opaque(x):
        """``x`` (the simulator has no compiler to keep from hoisting)."""
        return x
else:
    @intrinsic
    def _opaque(typingctx, x):
        """``x`` (an integer) through one ``mov`` of inline PTX with a side effect: the compiler cannot
        hoist what is computed from the result out of the loop it is read in, nor merge two reads."""
        if not isinstance(x, types.Integer):
            return None
        bits = x.bitwidth
        sig = x(x)

        def codegen(context, builder, signature, args):
            mov = ir.InlineAsm(ir.FunctionType(ir.IntType(bits), [ir.IntType(bits)]), f"mov.b{bits} $0, $1;",
                               "=l,l" if bits == 64 else "=r,r", side_effect=True)
            return builder.call(mov, [args[0]])

        return sig, codegen

    @cuda.jit(device=True)
    def opaque(x):
        """``x``, computed afresh where it is read (:func:`_opaque`)."""
        return _opaque(x)


@cuda.jit(device=True)
def out_of_time(start, max_cycles):
    """Whether a launch bounded by time has used its ``max_cycles`` (> 0; 0: bounded by steps alone)
    since ``start`` by the block's clock (:func:`clock`), so that each case of a launch takes as many
    steps as its own step's cost allows. Read by thread 0, which tells the block."""
    return max_cycles > 0 and clock() - start >= max_cycles


if SIMULATOR:
    def _values(v):
        """Every thread's ``v`` of the block, in thread order (one exchange)."""
        seen = _exchange(v)
        return [seen[k] for k in sorted(seen)]

    def block_max(v, tid, bd, red):
        vals = _values(v)
        m = vals[0]
        for y in vals[1:]:
            if y > m or y != y:
                m = y
        return m

    def block_sum(v, tid, bd, red):
        vals = _values(v)
        total = vals[0]
        for y in vals[1:]:
            total += y
        return total

    def block_or(v, tid, bd, red):
        out = 0
        for y in _values(v):
            out |= y
        return out

    def block_scan(m, tid, bd, red):
        vals = _values(m)
        return sum(vals[:tid]), sum(vals)
else:
    block_max, block_sum, block_or, block_scan = _tree_max, _tree_sum, _tree_or, _tree_scan
