"""The GPU kernels' tests run in numba-cuda's simulator (``NUMBA_ENABLE_CUDASIM=1``, set here before
numba.cuda is first imported): no GPU needed. They need numba-cuda (the test extra installs it);
without it they are skipped, saying so."""

import os

import pytest

os.environ.setdefault("NUMBA_ENABLE_CUDASIM", "1")


@pytest.fixture(autouse=True)
def simulator():
    """numba-cuda's simulator (the engine shortens the interpreter's thread switch interval during a
    launch there: pdamper.engine.cuda.SIMULATOR_SWITCH_S), its shared arrays created under a lock,
    one per block (gpu_race_check.locked_shared: the simulator's own allocator can give two threads
    two arrays for one shared array)."""
    pytest.importorskip("numba_cuda", reason="numba-cuda is not installed (pip install -e '.[test]'): "
                        "the GPU engine's simulator tests are skipped")
    from numba import cuda

    if not cuda.jit.__module__.startswith("numba.cuda.simulator"):
        pytest.skip("numba.cuda was imported before NUMBA_ENABLE_CUDASIM=1 was set: run tests/kernels/gpu in a "
                    "process of its own to use the simulator")
    from gpu_race_check import locked_shared

    with locked_shared():
        yield
