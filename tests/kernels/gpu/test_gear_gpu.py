"""The GPU engine's Gear kernel in numba-cuda's simulator against the CPU engine's Gear.

Step by step the two agree to rounding: the same accepted and rejected steps, the positions,
velocities and accelerations of the Nordsieck vectors equal to rounding amplified by the step control
(the step itself 1.5e-12 apart after ten steps; the implicit friction pass included). Over hundreds of steps
rounding differences (the simulator's plain arithmetic against the compiled CPU kernel's fused
multiply-adds) move the step sizes (the error estimate is a difference of nearly equal numbers) and
now and then an accept or reject decision; the runs then agree to the integrator's tolerance, not to
rounding, which is what the second test holds.
"""

import dataclasses
import warnings

import numpy as np
import pytest

from gpu_helpers import on_both as _both
from gpu_helpers import pile_case as _pile
from gpu_helpers import tiny_case as _case


def _gear(case, mu=0.3):
    return dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator="gear"),
                               contact=dataclasses.replace(case.contact, friction=mu))


def _step_by_step(case, k, threads=2):
    """``k`` accepted steps of ``case`` (no settling) on both engines: the CPU's (status, steps, t,
    rejected, its stepper's state, its engine) and the GPU's batch."""
    from pdamper.engine.cuda import _Batch
    from pdamper.engine.steppers import GEAR_MIN_STEP
    from pdamper.kernels.bundles import GearSpan
    from pdamper.kernels.gear import run_gear
    from pdamper.simulation import Simulation

    case = dataclasses.replace(case, initial=dataclasses.replace(case.initial, settle_time=0.0))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = Simulation(case)
        gpu = Simulation(case)
    cpu.settle()
    st, e, num = cpu.stepper, cpu.engine, case.numerics
    span = GearSpan(t0=0.0, t_end=cpu.n_samples * cpu.interval, h_try=float(st.h_next), interval=float(cpu.interval),
                    record=True, prime=True, tolerance=float(num.gear_tolerance), h_min=GEAR_MIN_STEP,
                    h_max=float(num.gear_max_step), max_steps=k)
    status, steps, _, t, _, rejected = run_gear(span, e.bodies, st.state, e.pairs, e.walls, e.search, e.table, e.drive,
                                               cpu.samples)
    batch = _Batch([gpu._gpu_job()[0]], threads)
    while batch.snapshot(0).steps < k:
        batch.launch(1)
    return status, steps, t, rejected, st, e, batch


def _same_nordsieck(st, batch, t, rel_t=1e-12):
    """The same clock (within ``rel_t``: the steps are rounding apart, amplified by the step control)
    and the same Nordsieck vector to rounding."""
    snap = batch.snapshot(0)
    assert abs(snap.time - t) <= rel_t * t
    # the derivatives the Nordsieck vectors stand for (r_q = h^q / q! x^(q)): each engine's own step
    # has moved by rounding through the step control, the derivatives hardly
    hs_gpu, hs_cpu = snap.step, float(st.state.step[0])
    assert abs(hs_gpu - hs_cpu) <= 1e-9 * hs_cpu
    ours, ref = snap.nordsieck, st.state.nordsieck
    for q, fact in ((0, 1.0), (1, 1.0), (2, 2.0)):
        a = fact * ours[q] / hs_gpu ** q
        b = fact * ref[q] / hs_cpu ** q
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(b)), q


def test_gear_step_by_step_as_the_cpu():
    """Ten accepted steps (one rejected among them) of a violently driven 4-sphere bed: the same
    steps, the same Nordsieck vector to rounding."""
    k = 10
    status, steps, t, rejected, st, e, batch = _step_by_step(
        _gear(_case("cuboid", n=4, direction=(1.0, 0.3, 0.2), coated=True, cycles=0.004)), k)
    assert status == 0 and steps == k and batch.snapshot(0).rejected == rejected >= 1
    _same_nordsieck(st, batch, t)


def test_gear_implicit_pair_rows_in_the_cpus_order():
    """A resting pile (13 spheres, two layers) set moving: many touching pairs with friction, whose
    rows the implicit pass corrects one after another (Gauss-Seidel). After ten accepted steps the
    GPU's touching friction rows are the CPU's friction record's pair rows: the same pairs in the
    same order, the same normal, slip, secant coefficient and limit to rounding; and the Nordsieck
    vectors agree to rounding (a row missed or walked out of order would move the increments of its
    spheres by far more)."""
    k = 10
    status, steps, t, rejected, st, e, batch = _step_by_step(_gear(_pile()), k)
    snap = batch.snapshot(0)
    assert status == 0 and steps == k and snap.rejected == rejected
    rec = st.state.friction
    m = int(rec.ends[0])
    assert m >= 12  # many touching pairs
    assert np.array_equal(snap.pairs, rec.bodies[:m])
    ours, ref = snap.pair_rows, rec.rows[:m, :8]
    for col in range(8):
        assert np.max(np.abs(ours[:, col] - ref[:, col])) <= 1e-9 * np.max(np.abs(ref[:, col])), col
    _same_nordsieck(st, batch, t, 1e-10)  # (the step control amplifies rounding: 1.6e-11 here)


@pytest.mark.slow
def test_gear_bits_do_not_depend_on_the_threads_of_a_block():
    """The 13-sphere pile's ten steps on blocks of 1, 2, 4 and 34 threads (a lane takes 13, 7, 4 or
    one sphere, and the pairs a block's width apart; 34 threads are two warps, whose barriers are the
    block's and whose reductions go through shared memory): every sphere's sums, its increments and
    its rows of the walk in the same order, so the same Nordsieck vector and velocities to the bit
    (only the threads' running sums, a sum of sums, may part by rounding)."""
    runs = [_step_by_step(_gear(_pile()), 10, threads)[-1].snapshot(0) for threads in (1, 2, 4, 34)]
    for other in runs[1:]:
        assert other.steps == runs[0].steps == 10 and other.rejected == runs[0].rejected
        assert np.array_equal(other.nordsieck, runs[0].nordsieck)
        assert np.array_equal(other.velocity, runs[0].velocity)


def test_gear_step_by_step_with_the_tangential_spring():
    """The tangential spring under Gear (springs advanced by the prediction, restored with a
    rejected step; a tight tolerance makes some): the same accepted and rejected steps and Nordsieck
    vector, and the same stored spring forces at the walls."""
    case = _gear(_case("cuboid", n=4, direction=(1.0, 0.3, 0.2), coated=True, cycles=0.004))
    case = dataclasses.replace(case, contact=dataclasses.replace(case.contact, tangential="spring"),
                               numerics=dataclasses.replace(case.numerics, gear_tolerance=1e-10))
    k = 20
    status, steps, t, rejected, st, e, batch = _step_by_step(case, k)
    snap = batch.snapshot(0)
    assert status == 0 and steps == k and snap.rejected == rejected >= 1
    _same_nordsieck(st, batch, t, 1e-10)  # (twice the steps of the test above, two of them rejected)
    n, nw = e.walls.tangential.shape[:2]
    ours, ref = snap.wall_springs[:n, :nw], e.walls.tangential
    assert np.max(np.abs(ref[..., 3])) > 0.0  # springs are loaded
    assert np.max(np.abs(ours - ref)) <= 1e-9 * np.max(np.abs(ref))


@pytest.mark.slow
def test_gear_run_agrees_to_its_tolerance():
    """A whole short run (settling, drive, friction): positions within 100 x gear_tolerance, the same
    number of steps within 2 %, the wall force within 5 % of its peak."""
    cases = [_gear(_case("cuboid", n=4, direction=(1.0, 0.3, 0.2), coated=True, cycles=0.004))]
    cpu, gpu, outcomes = _both(cases, threads=2)
    c, g, o = cpu[0], gpu[0], outcomes[0]
    assert o.status == 0
    assert abs(o.steps - c.stepper.steps) <= 0.02 * c.stepper.steps
    assert np.max(np.abs(c.engine.bodies.position - g.engine.bodies.position)) <= 100 * case_tol(cases[0])
    peak = np.max(np.abs(c.samples.wall_force))
    assert peak > 1.0 and np.max(np.abs(c.samples.wall_force - g.samples.wall_force)) <= 0.05 * peak
    rec = g.finalize()
    assert rec.rejected_steps == o.rejected > 0


def test_an_overlap_in_a_rejected_step_is_forgotten_with_it():
    """A loose tolerance and a tight overlap limit (2.5 % of the radius): the first predictions into the
    coated floor are rejected, their overlaps beyond the limit, the retried steps within it. The CPU's
    Gear forgets a rejected step's status with the step and runs to the end; so must the GPU (its
    status once survived the rejection and stopped the case at the next accepted step, t = 26 us:
    the 'overlap beyond 5 %' failures of half the paper's cases on an H100)."""
    base = _gear(_case("cuboid", n=4, direction=(1.0, 0.3, 0.2), coated=True, cycles=0.004))
    case = dataclasses.replace(base, numerics=dataclasses.replace(base.numerics, gear_tolerance=1e-5,
                                                                  overlap_limit=0.025))
    cpu, gpu, outcomes = _both([case], threads=2)
    o = outcomes[0]
    assert o.status == 0
    assert o.steps == cpu[0].stepper.steps and o.rejected == cpu[0].finalize().rejected_steps >= 1


def case_tol(case):
    return case.numerics.gear_tolerance


@pytest.mark.slow
def test_gear_kernel_gives_the_same_bits_run_after_run():
    """A 4 x 3 pile (18 spheres, up to 23 touching pairs) on 3 threads, 100 steps in launches of 25,
    twice: the same bits. The simulator runs each GPU thread as a Python thread and switches between
    them at random, so a missing barrier (a thread reading what another has not written yet) can show
    as runs that differ. The race check (test_synchronisation_gpu.py) finds such a barrier for
    certain; this test holds the kernel deterministic. The walk's levels of the last step: a row's
    level is above that of every earlier row sharing a sphere with it (so the rows of one level share
    none), fewer levels than rows, the rule benchmarks/walk_levels.py counts by on the CPU engine."""
    from pdamper.engine.cuda import _Batch
    from pdamper.simulation import Simulation
    from script_loader import load_script

    case = _gear(_pile(4, 3))
    runs = []
    for _ in range(2):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sim = Simulation(case)
        batch = _Batch([sim._gpu_job()[0]], 3)
        for _ in range(4):
            batch.launch(25)
        runs.append(batch.snapshot(0))
    a, b = runs
    assert a.steps == b.steps >= 90
    assert len(a.pairs) >= 2
    assert np.array_equal(a.nordsieck, b.nordsieck)
    assert np.array_equal(a.partials, b.partials)
    ends, levels = a.pairs, a.levels
    for k in range(len(ends)):
        for q in range(k):
            if set(ends[q]) & set(ends[k]):
                assert levels[k] > levels[q]
    assert 1 <= levels.max() < len(ends)
    assert load_script("benchmarks/walk_levels.py").levels_of(ends.tolist()) == levels.tolist()
