"""The waiting scheduler every simulator test runs under (tests/gpu_simulator.py): barriers order
the threads as the simulator's own do, a thread that ends early does not hold the others at their
barriers, and a thread's exception stops the launch with its message instead of hanging it.
(numba.cuda is imported inside the tests: see conftest.py.)"""

import threading
import types

import numpy as np
from numba import float64


def _compiled(fn):
    """``fn`` compiled in the simulator (``cuda`` as a global of its copy, the test's)."""
    from numba import cuda

    return cuda.jit(types.FunctionType(fn.__code__, dict(fn.__globals__, cuda=cuda), fn.__name__))


def _rounds(out):
    """Each of 4 rounds: every thread adds its id + 1 to a shared sum, barrier, thread 0 records it,
    barrier, every thread clears its share. Right only if each barrier waits for every thread."""
    s = cuda.shared.array(8, float64)
    t = cuda.threadIdx.x
    for r in range(4):
        s[t] = t + 1.0 + r
        cuda.syncthreads()
        if t == 0:
            total = 0.0
            for k in range(cuda.blockDim.x):
                total += s[k]
            out[cuda.blockIdx.x, r] = total
        cuda.syncthreads()


def _early_exit(out):
    """Thread 3 ends before the others' barriers; they still pass them."""
    t = cuda.threadIdx.x
    if t == 3:
        return
    for r in range(3):
        cuda.syncthreads()
        out[t] += 1.0


def _raises(out):
    """Thread 1 fails after the first barrier; the others wait at the second."""
    t = cuda.threadIdx.x
    cuda.syncthreads()
    if t == 1:
        raise ValueError("thread 1 failed on purpose")
    cuda.syncthreads()
    out[t] = 1.0


def test_barriers_order_every_thread_of_every_block():
    out = np.zeros((3, 4))
    _compiled(_rounds)[3, 8](out)
    # 8 threads: sum of (t + 1 + r) for t = 0..7 is 36 + 8 r
    assert np.array_equal(out, np.tile(36.0 + 8.0 * np.arange(4), (3, 1)))


def test_a_thread_that_ends_early_does_not_hold_the_others():
    out = np.zeros(4)
    _compiled(_early_exit)[1, 4](out)
    assert out.tolist() == [3.0, 3.0, 3.0, 0.0]


def test_a_threads_exception_stops_the_launch_with_its_message():
    kernel = _compiled(_raises)
    out = np.zeros(4)
    caught = []

    def launch():
        try:
            kernel[1, 4](out)
        except Exception as exc:  # noqa: BLE001  (what the test looks at)
            caught.append(exc)

    runner = threading.Thread(target=launch, daemon=True)
    runner.start()
    runner.join(timeout=60.0)
    assert not runner.is_alive(), "the launch hung after a thread raised"
    assert len(caught) == 1 and isinstance(caught[0], ValueError)
    assert "thread 1 failed on purpose" in str(caught[0]) and "tid=[1, 0, 0]" in str(caught[0])
    assert out.tolist() == [0.0, 0.0, 0.0, 0.0]


def test_the_scheduler_is_the_one_in_place():
    """The conftest's fixture put the waiting manager in place (else this file tests the simulator's)."""
    from numba.cuda.simulator import kernel

    from gpu_simulator import _syncthreads

    assert kernel.BlockThread.syncthreads is _syncthreads
    assert kernel.BlockManager.run.__module__ == "gpu_simulator"
