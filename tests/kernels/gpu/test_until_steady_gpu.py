"""``until_steady`` on the GPU engine (numba-cuda's simulator): a case stops at the cycle at which the
CPU engine's run of it stops, judged between the GPU's launches (pdamper.run.SteadyJudge), and the
cases of its batch that are not steady yet run on.

The cases: two soft spheres driven at 20 Hz, 12 cycles (1 dropped), judged at a tolerance of 0.5:
at 0.5 mm the record is steady after the fewest cycles the rule allows (7), at 1 mm never (its
first and second halves differ), so it runs all 12 (measured on the CPU engine, both integrators).
"""

import warnings

import numpy as np
import pytest

from pdamper.excitation import HarmonicDrive
from pdamper.materials import Material
from pdamper.params import Case, InitialState, Numerics, ParticleSet, Recording

SOFT = Material(name="soft", youngs_modulus=2e4, poisson_ratio=0.3, density=7800.0)
TOL = 0.5
STEADY, DRIFTING = 0.0005, 0.001


def _case(stroke, device, integrator="verlet"):
    extra = {"time_step": 1e-3} if integrator == "verlet" else {"gear_max_step": 1e-3}
    return Case(particles=(ParticleSet(count=2, material=SOFT),), drive=HarmonicDrive(stroke=stroke, frequency=20.0),
                cycles=12, drop_cycles=1, recording=Recording(sample_rate=200.0),
                numerics=Numerics(integrator=integrator, overlap_limit=0.4, device=device, **extra),
                initial=InitialState(settle_time=0.01, seed=0))


def _same(a, b, rel=1e-12):
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and float(np.max(np.abs(a - b))) <= rel * max(float(np.max(np.abs(a))), 1e-300)


def test_each_case_of_a_batch_stops_where_the_cpu_engine_stops():
    """``run_cases(until_steady=)``, one batch of a steady and a drifting case (Verlet): the steady
    one stops after 7 cycles, its record, eta* and error those of the CPU engine's early stop to
    rounding; the drifting one runs all 12, as on the CPU."""
    from pdamper.run import run_case, run_cases

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = [run_case(_case(x, "cpu"), until_steady=TOL) for x in (STEADY, DRIFTING)]
        gpu = run_cases([_case(x, "cuda") for x in (STEADY, DRIFTING)], until_steady=TOL)
    assert [r.extras["cycles_run"] for r in cpu] == [7.0, 12.0]
    for c, g in zip(cpu, gpu):
        assert g.extras["cycles_run"] == c.extras["cycles_run"]
        assert g.signals.time.size == c.signals.time.size == int(c.extras["cycles_run"] * 10)
        assert _same(g.signals.force, c.signals.force, 1e-9)
        assert g.eta_star == pytest.approx(c.eta_star, rel=1e-9)
        assert g.extras["eta_star_error"] == pytest.approx(c.extras["eta_star_error"], rel=1e-7)
        assert g.extras["steady"] == c.extras["steady"]


@pytest.mark.slow
@pytest.mark.parametrize("integrator, strokes, force_rel", [("verlet", (STEADY, DRIFTING), 1e-9),
                                                             ("gear", (STEADY,), 1e-3)])
def test_a_running_case_is_stopped_between_launches_and_the_others_run_on(integrator, strokes, force_rel):
    """Launches of 40 steps: the steady case is judged as its record grows, stopped at the launch
    after its 7th cycle (its steps short of the whole run's), its record kept up to there and the
    same as the CPU engine's (Verlet's to rounding, Gear's to its tolerance: rounding moves its
    steps, tests/kernels/gpu/test_gear_gpu.py; here a sample's force by up to 2.3e-4 of the
    largest); the drifting case (Verlet's) runs to its end. Gear's clock gives the record's
    length."""
    from pdamper.engine.cuda import run_jobs
    from pdamper.run import SteadyJudge, run_case
    from pdamper.simulation import Simulation

    cases = [_case(x, "cuda", integrator) for x in strokes]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cpu = run_case(_case(STEADY, "cpu", integrator), until_steady=TOL)
        whole = run_case(_case(STEADY, "cpu", integrator))
        sims = [Simulation(c) for c in cases]
        alone = Simulation(_case(STEADY, "cpu", integrator))
        alone.run()
    class Watched(SteadyJudge):
        """A judge that keeps a copy of every record it is shown."""

        shown = []

        def __call__(self, wall_force):
            self.shown.append(np.array(wall_force))
            return super().__call__(wall_force)

    judges = [Watched(cases[0], TOL, sims[0].interval, sims[0].n_samples)] + \
        [SteadyJudge(c, TOL, s.interval, s.n_samples) for c, s in zip(cases[1:], sims[1:])]
    seen = []
    outcomes = run_jobs([s._gpu_job()[0] for s in sims], max_launch_steps=40, steady=judges,
                        progress=lambda done, total: seen.append((done, total)))
    steady = outcomes[0]
    assert steady.status == 0 and steady.kept == 70 and judges[0].cycles == 7
    assert 70 <= steady.reached < sims[0].n_samples  # stopped before the end of its run
    assert 0.9 * cpu.steps <= steady.steps < 0.9 * whole.steps
    for drifting, judge in zip(outcomes[1:], judges[1:]):
        assert drifting.status == 0 and drifting.kept == -1 and judge.kept is None
    done = [d for d, _ in seen]
    assert done == sorted(done) and all(d <= t for d, t in seen)
    for s, o in zip(sims, outcomes):
        s._gpu_done(o)
    rec = sims[0].finalize()
    assert sims[0].sample == 70 and rec.steps == steady.steps
    # the judge was shown whole samples only, as the CPU engine records them, the last as far as the case had gone
    assert Watched.shown and Watched.shown[-1].size == steady.reached
    assert all(_same(w, alone.samples.wall_force[: w.size], force_rel) for w in Watched.shown)
    signals = rec.outputs["signals"]
    assert signals.time.size == 70 and _same(signals.force, cpu.signals.force, force_rel)
    # the mean step is the steps over the time they took, the time past the kept record included
    assert rec.time_step_s == pytest.approx(sims[0].stepper.mean_step((sims[0].settle_samples + steady.reached)
                                                                      * sims[0].interval))
