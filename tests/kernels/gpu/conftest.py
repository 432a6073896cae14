"""The GPU kernels' tests run in numba-cuda's simulator (``NUMBA_ENABLE_CUDASIM=1``, set here before
numba.cuda is first imported): no GPU needed. They need numba-cuda (the test extra installs it);
without it they are skipped, saying so."""

import os
import sys

import pytest

os.environ.setdefault("NUMBA_ENABLE_CUDASIM", "1")


@pytest.fixture(autouse=True)
def simulator():
    """numba-cuda's simulator, with a short thread switch interval: the simulator runs each GPU thread
    as a Python thread and polls them at every barrier, so the default 5 ms switch interval would make
    every barrier cost milliseconds."""
    pytest.importorskip("numba_cuda", reason="numba-cuda is not installed (pip install -e '.[test]'): "
                        "the GPU engine's simulator tests are skipped")
    from numba import cuda

    if not cuda.jit.__module__.startswith("numba.cuda.simulator"):
        pytest.skip("numba.cuda was imported before NUMBA_ENABLE_CUDASIM=1 was set: run tests/kernels/gpu in a "
                    "process of its own to use the simulator")
    old = sys.getswitchinterval()
    sys.setswitchinterval(1e-4)
    yield
    sys.setswitchinterval(old)
