"""The kernels' barriers: every access one thread makes to what another thread of its block wrote or
read is ordered by a barrier, and no thread reads shared memory no thread wrote
(:mod:`gpu_race_check`, which makes a missing barrier certain to show in the simulator instead of by
chance)."""

import dataclasses
import warnings

import numpy as np
from numba import float64

import gpu_race_check as race_check
from pdamper.kernels.gpu.batch import I_STATUS
from gpu_helpers import pile_case, tiny_case


def _racy(out):
    """Thread 0 writes what thread 1 reads, with no barrier between; then with one (``cuda``: a
    global of its compiled copy, the test's)."""
    s = cuda.shared.array(2, float64)
    t = cuda.threadIdx.x
    if t == 0:
        s[0] = 1.0
    if t == 1:
        out[0] = s[0]
    cuda.syncthreads()
    if t == 1:
        out[1] = s[0]


def test_the_check_finds_a_missing_barrier():
    """A kernel whose thread 1 reads what thread 0 writes with no barrier between is found (the
    read after the barrier is not). (numba.cuda is imported here, not when the module is: imported
    at collection it would come before the conftest's NUMBA_ENABLE_CUDASIM=1 took hold, and every
    simulator test would skip.)"""
    import types

    from numba import cuda

    racy = types.FunctionType(_racy.__code__, dict(_racy.__globals__, cuda=cuda), "_racy")
    with race_check.tracking() as found:
        cuda.jit(racy)[1, 2](np.zeros(2))
    kinds = {what for (_, what, _) in found}
    assert any("another thread's write with no barrier between" in k or "no thread wrote" in k for k in kinds), \
        race_check.findings_text()
    assert all(":" in where for (_, _, where) in found)


def _run_tracked(case, threads, launches, steps, cycles=0):
    from pdamper.engine.cuda import _Batch
    from pdamper.simulation import Simulation

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(case)
    batch = _Batch([sim._gpu_job()[0]], threads)
    batch.bt = race_check.track_bundle(batch.bt, "bt")
    batch.args = (batch.bt,) + batch.args[1:]
    for _ in range(launches):
        race_check.new_launch(batch.bt)
        batch.launch(steps, cycles)
    return batch.snapshot(0), int(batch.bt.ci[0, I_STATUS])


def _gear(case, tangential="tanh"):
    """Gear on ``case``, every step with a rebuild of the neighbour rows (a skin of 1 nm) and the
    first steps rejected (a tolerance of 1e-12 m)."""
    num = dataclasses.replace(case.numerics, integrator="gear", gear_tolerance=1e-12, skin=1e-9)
    return dataclasses.replace(case, numerics=num,
                               contact=dataclasses.replace(case.contact, friction=0.3, tangential=tangential))


def test_every_kernel_orders_its_threads_by_barriers():
    """Gear with the tanh law (the rows listed by a scan, the walk by levels: an 8-sphere pile on 3
    threads, so a thread takes several spheres and pairs and the scans several rounds), Gear with the
    spring (its history double-buffered), both rebuilding their lists every step and rejecting steps,
    and Verlet (a violent 4-sphere bed on 3 threads), each in two launches; then Verlet and Gear in
    launches bounded by time (thread 0's clock told to the block by its vote: one nanosecond, so every
    launch ends after its first step): no finding in shared memory (the dynamic shared memory, the
    spheres' hot state and Gear's increments, included) or in the batch's buffers."""
    with race_check.tracking() as found:
        runs = [_run_tracked(_gear(pile_case(3, 2)), 3, 2, 2), _run_tracked(_gear(pile_case(3, 2), "spring"), 3, 2, 2),
                _run_tracked(tiny_case("cuboid", n=4, direction=(1.0, 0.3, 0.2)), 3, 2, 5)]
        timed = [_run_tracked(tiny_case("cuboid", n=4, direction=(1.0, 0.3, 0.2)), 3, 3, 5, cycles=1),
                 _run_tracked(_gear(pile_case(3, 2)), 3, 3, 5, cycles=1)]
    assert not found, race_check.findings_text()
    for snap, status in runs:
        assert status == 0 and snap.steps >= 2
    assert all(snap.rejected > 0 for snap, _ in runs[:2])
    assert timed[0][0].steps == 3 and timed[1][0].steps + timed[1][0].rejected == 3
