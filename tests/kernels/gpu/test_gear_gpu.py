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

from gpu_helpers import on_both as _both
from gpu_helpers import tiny_case as _case


def _gear(case, mu=0.3):
    return dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator="gear"),
                               contact=dataclasses.replace(case.contact, friction=mu))


def test_gear_step_by_step_as_the_cpu():
    """Ten accepted steps (one rejected among them) of a violently driven 4-sphere bed: the same
    steps, the same Nordsieck vector to rounding."""
    from pdamper.engine.cuda import _Batch
    from pdamper.engine.steppers import GEAR_MIN_STEP
    from pdamper.kernels.bundles import GearSpan
    from pdamper.kernels.gear import run_gear
    from pdamper.simulation import Simulation

    case = _gear(_case("cuboid", n=4, direction=(1.0, 0.3, 0.2), coated=True, cycles=0.004))
    case = dataclasses.replace(case, initial=dataclasses.replace(case.initial, settle_time=0.0))
    k = 10
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
    batch = _Batch([gpu._gpu_job()[0]], 2)
    while int(batch.args[6].step[0]) < k:
        batch.launch(1)
    clock = batch.args[11]
    assert status == 0 and steps == k and int(clock.rejected[0]) == rejected >= 1
    assert abs(float(clock.t[0]) - t) <= 1e-12 * t
    # the derivatives the Nordsieck vectors stand for (r_q = h^q / q! x^(q)): each engine's own step
    # has moved by rounding through the step control, the derivatives hardly
    hs_gpu, hs_cpu = float(clock.hs[0]), float(st.state.step[0])
    assert abs(hs_gpu - hs_cpu) <= 1e-9 * hs_cpu
    ours, ref = batch.args[10].nordsieck[0], st.state.nordsieck
    for q, fact in ((0, 1.0), (1, 1.0), (2, 2.0)):
        a = fact * ours[q] / hs_gpu ** q
        b = fact * ref[q] / hs_cpu ** q
        assert np.max(np.abs(a - b)) <= 1e-9 * np.max(np.abs(b)), q


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


def case_tol(case):
    return case.numerics.gear_tolerance
