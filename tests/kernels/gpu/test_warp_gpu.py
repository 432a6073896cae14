"""The block's reductions and scan as a GPU runs them (the trees of shuffles of
pdamper.kernels.gpu.warp, warp by warp, then the warps in order), in numba-cuda's simulator with its
stand-in for the shuffles: on a block of one partial warp (the simulator's blocks), of one whole warp
and of two warps (the paper's larger beds), every thread gets the block's result. (numba.cuda is
imported inside the tests: see conftest.py.)"""

import types

import numpy as np
import pytest
from numba import float64


def _reduce(values, out, scans):
    """Each thread its value's block maximum, sum, or and prefix sum."""
    t = cuda.threadIdx.x
    bd = cuda.blockDim.x
    red = cuda.shared.array(4, float64)
    v = values[t]
    out[t, 0] = warp._tree_max(v, t, bd, red)
    out[t, 1] = warp._tree_sum(v, t, bd, red)
    out[t, 2] = warp._tree_or(int(v) % 8, t, bd, red)
    out[t, 3] = warp.block_min_int(int(v), t, bd, red)
    before, total = warp._tree_scan(int(v), t, bd, red)
    scans[t, 0] = before
    scans[t, 1] = total


@pytest.mark.parametrize("threads", [3, 32, 40])
def test_the_trees_give_every_thread_the_blocks_result(threads):
    from numba import cuda

    from pdamper.kernels.gpu import warp

    kernel = cuda.jit(types.FunctionType(_reduce.__code__, dict(_reduce.__globals__, cuda=cuda, warp=warp), "_reduce"))
    rng = np.random.default_rng(threads)
    values = rng.integers(0, 50, threads).astype(float)
    values[threads // 2] = 77.0
    out = np.zeros((threads, 4))
    scans = np.zeros((threads, 2), dtype=np.int64)
    kernel[1, threads](values, out, scans)
    ints = values.astype(int)
    assert np.all(out[:, 0] == 77.0) and np.all(out[:, 1] == values.sum())
    assert np.all(out[:, 2] == np.bitwise_or.reduce(ints % 8)) and np.all(out[:, 3] == ints.min())
    assert scans[:, 0].tolist() == (np.cumsum(ints) - ints).tolist() and np.all(scans[:, 1] == ints.sum())


def _nan(out):
    t = cuda.threadIdx.x
    red = cuda.shared.array(4, float64)
    out[t] = warp._tree_max(math.nan if t == 1 else float(t), t, cuda.blockDim.x, red)


def test_a_nan_wins_the_maximum():
    """The error control's maximum lets a NaN through (a non-finite increment stops the case)."""
    import math

    from numba import cuda

    from pdamper.kernels.gpu import warp

    kernel = cuda.jit(types.FunctionType(_nan.__code__, dict(_nan.__globals__, cuda=cuda, warp=warp, math=math), "_nan"))
    out = np.zeros(5)
    kernel[1, 5](out)
    assert np.all(np.isnan(out))
