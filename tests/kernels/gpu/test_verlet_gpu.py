"""The GPU engine's Verlet kernel in numba-cuda's simulator against the CPU engine's Verlet: the same
trajectory to rounding, the same recorded channels, per-case failures, refusals.

The simulator runs each GPU thread as a Python thread (the CPU-compiled physics functions do the
arithmetic, without the FMA contraction of compiled code in the kernel's own loops), so the two
agree to rounding, not bit for bit. The cases are tiny (a few spheres, a few hundred steps) and
start with the spheres in motion so that pairs, the floor and the other walls all touch.
"""

import dataclasses
import math

import numpy as np
import pytest

from gpu_helpers import close as _close
from gpu_helpers import on_both as _both
from gpu_helpers import tiny_case as _case
from pdamper.errors import InputError, SimulationError
from pdamper.excitation import CoupledStructure, HarmonicDrive
from pdamper.geometry.baffles import Baffle
from pdamper.materials import Material
from pdamper.params import Case, InitialState, Numerics, ParticleSet, Recording
from pdamper.simulation import Simulation, run_on_gpu

@pytest.mark.slow
def test_same_trajectory_as_the_cpu_engine_in_one_batch():
    """A tilted cuboid with a baffle and a coated floor, driven along a direction with a vertical part,
    and a cylinder of another size in the same batch (padding, per-case tables and walls): the same
    positions, velocities and spins after ~900 steps, the same wall force and ledger to rounding."""
    cases = [_case("cuboid", n=4, direction=(1.0, 0.3, 0.2), coated=True,
                   baffles=(Baffle(position=0.02, gap_below=0.004),)),
             _case("cylinder", n=3, seed=1)]
    cpu, gpu, outcomes = _both(cases, threads=2)
    for c, g, o in zip(cpu, gpu, outcomes):
        assert o.status == 0
        assert o.steps == c.stepper.steps > 800
        for name in ("position", "velocity", "spin"):
            assert _close(getattr(c.engine.bodies, name), getattr(g.engine.bodies, name)), name
        assert _close(c.samples.wall_force, g.samples.wall_force, 1e-9)
        assert np.max(np.abs(c.samples.wall_force)) > 1.0  # the walls were struck
        for col in range(7):
            assert _close(c.samples.energy[:, col], g.samples.energy[:, col], 1e-9), col
        assert g.finalize().steps == c.finalize().steps


def test_same_trajectory_with_tsuji_damping():
    """The other damping law (its own kernel): the same trajectory."""
    cpu, gpu, outcomes = _both([_case("cuboid", n=3, damping="tsuji", seed=2, cycles=0.01)], threads=3)
    assert outcomes[0].status == 0
    for name in ("position", "velocity", "spin"):
        assert _close(getattr(cpu[0].engine.bodies, name), getattr(gpu[0].engine.bodies, name)), name


def test_same_trajectory_with_the_tangential_spring():
    """The tangential spring (its history per contact slot: carried over by the rebuilds, dropped when
    a contact opens): the same trajectory, wall force and ledger as the CPU engine after ~900 steps of
    spheres flying between the walls, and the spring did the friction (its losses in the ledger)."""
    case = _case("cuboid", n=4, direction=(1.0, 0.3, 0.2), seed=4)
    case = dataclasses.replace(case, contact=dataclasses.replace(case.contact, tangential="spring"))
    cpu, gpu, outcomes = _both([case], threads=2)
    c, g = cpu[0], gpu[0]
    assert outcomes[0].status == 0 and outcomes[0].steps == c.stepper.steps > 800
    for name in ("position", "velocity", "spin"):
        assert _close(getattr(c.engine.bodies, name), getattr(g.engine.bodies, name)), name
    assert _close(c.samples.wall_force, g.samples.wall_force, 1e-9)
    for col in range(7):
        assert _close(c.samples.energy[:, col], g.samples.energy[:, col], 1e-9), col
    assert np.max(np.abs(c.samples.wall_force)) > 1.0 and c.samples.energy[-1, 6] > 0.0


def test_a_failed_case_stops_alone():
    """A step far too long makes one case overlap: that case fails with the CPU engine's message,
    the other of the batch finishes; the interpreter's thread switch interval, shortened during the
    simulator's launches, is the caller's again."""
    import sys
    import warnings

    cases = [_case("cuboid", n=3, time_step=2e-4), _case("cuboid", n=3, seed=3, cycles=0.006)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sims = [Simulation(c) for c in cases]
    before = sys.getswitchinterval()
    out = run_on_gpu(sims)
    assert sys.getswitchinterval() == before
    assert isinstance(out[0], SimulationError)
    assert "became unstable" in str(out[0]) and "numerics.time_step" in str(out[0])
    assert not isinstance(out[1], Exception)
    assert out[1].signals.force.size == sims[1].n_samples


def test_a_launch_takes_no_more_steps_than_its_cap():
    """``max_launch_steps`` caps every launch, the first too (it once took 200 steps whatever the cap);
    a progress call that returns False stops the batch, the case saying it was stopped."""
    import warnings

    from pdamper.engine.cuda import STATUS_STOPPED, run_jobs

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(_case("cuboid", n=2))
    seen = []

    def progress(done, total):
        seen.append((done, total))
        return len(seen) < 3

    (out,) = run_jobs([sim._gpu_job()[0]], max_launch_steps=7, progress=progress)
    assert [d for d, _ in seen] == [7, 14, 21] and seen[0][1] > 21
    assert out.steps == 21 and out.status == STATUS_STOPPED


def test_a_launch_bounded_by_time_stops_each_case_at_its_own_step():
    """A launch given a time on its blocks' clocks (``cycles``, nanoseconds in the simulator) stops
    each block at the first step that ends past it: with one nanosecond, every case takes exactly
    one step whatever the step cap; the steps a case takes do not depend on how launches cut them
    (the same bits as launches of three steps), for Verlet and for Gear (an attempted step each)."""
    import warnings

    from pdamper.engine.cuda import _Batch, launch_cycles

    assert launch_cycles(0.5) == 500_000_000  # (the simulator's clock: the host's nanoseconds)

    def batch(case):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            sims = [Simulation(case), Simulation(dataclasses.replace(case, initial=dataclasses.replace(case.initial,
                                                                                                       seed=3)))]
        return _Batch([s._gpu_job()[0] for s in sims], 3)

    for case in (_case("cuboid", n=4, direction=(1.0, 0.3, 0.2)),
                 dataclasses.replace(_case("cuboid", n=3), numerics=Numerics(integrator="gear"))):
        by_time, by_steps = batch(case), batch(case)
        for k in range(1, 7):
            by_time.launch(10**6, 1)
            assert [s.steps + s.rejected for s in map(by_time.snapshot, (0, 1))] == [k, k]
        for _ in range(2):
            by_steps.launch(3)
        for c in (0, 1):
            a, b = by_time.snapshot(c), by_steps.snapshot(c)
            assert a.steps == b.steps
            for name in ("position", "velocity", "partials", "nordsieck"):
                assert np.array_equal(getattr(a, name), getattr(b, name)), name


@pytest.mark.slow
def test_eta_star_of_a_short_ensemble():
    """Three seeds of a short run on both engines (soft spheres, so that 310 steps make three cycles):
    the GPU's eta* of every seed within a tenth of the CPU's seed spread of it; the mean inside the
    CPU's range of seeds."""
    import warnings

    from pdamper.run import run_case, run_cases

    soft = Material(name="soft", youngs_modulus=2e4, poisson_ratio=0.3, density=7800.0)

    def case(seed, device):
        return Case(particles=(ParticleSet(count=4, material=soft),), drive=HarmonicDrive(stroke=0.002, frequency=10.0),
                    cycles=3, drop_cycles=1, recording=Recording(sample_rate=100.0),
                    numerics=Numerics(integrator="verlet", time_step=1e-3, overlap_limit=0.4, device=device),
                    initial=InitialState(settle_time=0.01, seed=seed))

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = np.array([run_case(case(s, "cpu")).eta_star for s in range(3)])
        gpu = np.array([r.eta_star for r in run_cases([case(s, "cuda") for s in range(3)])])
    spread = cpu.max() - cpu.min()
    assert spread > 0.0 and np.all(np.isfinite(gpu))
    assert np.all(np.abs(gpu - cpu) <= 0.1 * spread)
    assert cpu.min() <= gpu.mean() <= cpu.max()


def test_refuses_what_the_gpu_does_not_run():
    """A coupled structure is refused before anything runs, saying how to run it."""
    import warnings

    structure = CoupledStructure(mass=7.0, stiffness=1105.0, displacement=0.012)
    case = Case(particles=(ParticleSet(count=3),), drive=structure, cycles=0.02, drop_cycles=0,
                numerics=Numerics(integrator="verlet"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(case)
    with pytest.raises(InputError, match="coupled structure.*CPU"):
        run_on_gpu([sim])


def test_row_capacity_holds_a_dense_shell():
    """Equal spheres: the rows hold the 12 touching neighbours and the skin's; unequal ones more."""
    from pdamper.engine.cuda import row_capacity

    assert 14 <= row_capacity(np.full(100, 0.005), 0.001) <= 40
    assert row_capacity(np.array([0.01] + [0.002] * 300), 0.0004) > row_capacity(np.full(301, 0.01), 0.002)
    assert row_capacity(np.full(3, 0.005), 0.001) == 2
    assert math.isfinite(row_capacity(np.full(2, 0.005), 0.0))


def test_gear_with_the_tangential_spring_is_not_refused(monkeypatch):
    """Gear's kernel with the tangential spring runs on a GPU as in the simulator (the kernel that
    faulted on an H200 is gone; the simulator tests hold this one to the CPU): no refusal, on the
    simulator or off it."""
    import dataclasses
    import warnings

    from pdamper.engine.cuda import refusal
    from pdamper.kernels.gpu import targets

    case = Case(particles=(ParticleSet(count=3),), cycles=0.02, drop_cycles=0, numerics=Numerics(integrator="gear"))
    case = dataclasses.replace(case, contact=dataclasses.replace(case.contact, tangential="spring"))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sim = Simulation(case)
    assert sim._gpu_job()[1] is None
    monkeypatch.setattr(targets, "SIMULATOR", False)
    assert refusal(sim.engine) is None


def test_progress_reaches_the_whole_run():
    """The GPU's progress (what a run's bar shows) ends at the whole: its last call says every step
    done, a failed case counted whole (it once stopped a round short, the bar never at 100 %)."""
    import warnings

    from pdamper.engine.cuda import run_jobs

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sims = [Simulation(_case("cuboid", n=2, cycles=0.005)), Simulation(_case("cuboid", n=3, time_step=2e-4))]
    seen = []
    out = run_jobs([s._gpu_job()[0] for s in sims], max_launch_steps=50, progress=lambda d, t: seen.append((d, t)))
    assert out[0].status == 0 and out[1].status != 0  # (the second case fails: a step far too long)
    done, total = seen[-1]
    assert done == total > 0 and len(seen) > 2
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)


def test_a_bed_beyond_the_gpus_runs_on_the_cpu_engine_and_says_so(monkeypatch):
    """A case whose bed is larger than a block takes (here the limit lowered to 3 spheres) runs on the
    CPU engine, with one warning that says so; the other case of the call runs on the GPU engine."""
    import warnings

    from pdamper.kernels.gpu import batch
    from pdamper.run import run_case, run_cases

    monkeypatch.setattr(batch, "MAX_SPHERES", 3)
    small, big = (dataclasses.replace(_case("cuboid", n=n, cycles=0.005),
                                      numerics=Numerics(integrator="verlet", device="cuda")) for n in (3, 4))
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = run_cases([small, big], analyze=False)
    said = [str(w.message) for w in caught if "CPU engine" in str(w.message)]
    assert said == ["1 case of 4 spheres run on the CPU engine: the GPU engine takes beds of up to 3 spheres "
                    "(docs/engine.md, 'The GPU engine')"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = run_case(dataclasses.replace(big, numerics=Numerics(integrator="verlet")), analyze=False)
    assert np.array_equal(out[1].signals.force, cpu.signals.force)  # the CPU engine's own run
