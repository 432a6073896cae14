"""The probed Gear kernel (:mod:`pdamper.kernels.gpu.probe`) in numba-cuda's simulator: the same
source as the production kernel with the phase clock switched on, so the same bits; its clock
counts every phase a step runs, and nothing in the production kernel."""

import dataclasses
import warnings

import numpy as np

from gpu_helpers import pile_case as _pile


def _batch(probe, k=6):
    """``k`` accepted steps of the 13-sphere resting pile (Gear, friction: the implicit pair walk runs
    every step) on one block of 4 threads."""
    from pdamper.engine.cuda import _Batch
    from pdamper.simulation import Simulation

    case = _pile()
    case = dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator="gear"),
                               contact=dataclasses.replace(case.contact, friction=0.3),
                               initial=dataclasses.replace(case.initial, settle_time=0.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(case)
    batch = _Batch([sim._gpu_job()[0]], 4, probe)
    while int(batch.ct.step[0]) < k:
        batch.launch(1)
    return batch


def test_the_probed_kernel_gives_the_production_kernels_bits_and_times_each_phase():
    from pdamper.kernels.gpu.probe import P_REBUILDS, P_ROWS, PHASES, PROBES

    plain, probed = _batch(False), _batch(True)
    assert int(plain.ct.step[0]) == int(probed.ct.step[0]) == 6
    assert np.array_equal(plain.gs.nordsieck, probed.gs.nordsieck)
    assert np.array_equal(plain.args[0].velocity, probed.args[0].velocity)
    assert not np.any(plain.gc.cycles)  # the production kernel carries no probe
    cycles = probed.gc.cycles[0]
    assert cycles.shape == (PROBES,)
    every_step = [PHASES.index(p) for p in ("displacement check", "rescale, predict, save history", "pair laws",
                                            "sphere forces, increments", "gather touching pairs",
                                            "implicit pair walk", "implicit walls", "error norm",
                                            "accepted step: correct, ledger")]
    assert np.all(cycles[every_step] > 0)
    # the pile's 32 touching pairs with friction are walked at each of the attempted steps
    attempted = int(probed.ct.step[0]) + int(probed.gc.rejected[0])
    assert 12 * attempted <= cycles[P_ROWS] <= int(probed.gs.pair_rows.shape[1]) * attempted
    assert 0 <= cycles[P_REBUILDS] <= attempted
