"""The GPU kernels' tests run in numba-cuda's simulator (``NUMBA_ENABLE_CUDASIM=1``, set here before
numba.cuda is first imported): no GPU needed. They need numba-cuda (the test extra installs it);
without it they are skipped, saying so. A test module here imports numba.cuda inside its tests,
never at its top: collected with the whole suite, a module-level import can come before this
setting takes hold, and every simulator test then skips."""

import os

import pytest

os.environ.setdefault("NUMBA_ENABLE_CUDASIM", "1")
# numba reads its environment when it is first imported (the modules collected before this one
# import it) and again only when it compiles; on a warm kernel cache nothing may compile before the
# first simulator test, so read it again now, or numba.cuda would come up without the simulator
import numba.core.config  # noqa: E402

numba.core.config.reload_config()


@pytest.fixture(autouse=True)
def simulator():
    """numba-cuda's simulator (the engine shortens the interpreter's thread switch interval during a
    launch there: pdamper.engine.cuda.SIMULATOR_SWITCH_S), its shared arrays created under a lock,
    one per block (gpu_race_check.locked_shared: the simulator's own allocator can give two threads
    two arrays for one shared array), its blocks under a manager that waits for its threads instead
    of polling them (gpu_simulator.quiet_scheduler: the same threads, two to four times faster)."""
    pytest.importorskip("numba_cuda", reason="numba-cuda is not installed (pip install -e '.[test]'): "
                        "the GPU engine's simulator tests are skipped")
    from numba import cuda

    if not cuda.jit.__module__.startswith("numba.cuda.simulator"):  # a failure, not a skip: it loses them all
        pytest.fail("numba.cuda was imported before NUMBA_ENABLE_CUDASIM=1 was set (a test module importing "
                    "numba.cuda at its top?), so the simulator tests cannot run in this process")
    from gpu_race_check import locked_shared
    from gpu_simulator import quiet_scheduler

    with locked_shared(), quiet_scheduler():
        yield
