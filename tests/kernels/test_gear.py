"""Gear predictor-corrector (``numerics.integrator = "gear"``): Hertz contact time and restitution
as for Verlet, step adaptation, convergence as the tolerance tightens, a closed energy ledger."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from pdamper.config import load_case
from pdamper.contact.hertz_gonthier import contact_time, hertz_stiffness, peak_overlap
from pdamper.materials import PVC, STEEL_S235, effective_modulus
from pdamper.params import Recording
from pdamper.simulation import Simulation

from dem_fixtures import R, run, sphere_mass, still_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
M = sphere_mass()
ES = effective_modulus(STEEL_S235, PVC)


def _gear(case, **numerics):
    return dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator="gear", **numerics))


def _wall_impact(v, eps, duration=2e-3, **kw):
    x0 = -0.1 + R + 1e-6
    return run(_gear(still_case([[x0, 0.05, 0.0]], [[-v, 0.0, 0.0]], duration=duration, eps=eps, **kw)))


@pytest.mark.parametrize("v", [0.05, 0.5])
def test_undamped_wall_impact_lasts_hertz_time_and_reaches_hertz_overlap(v):
    tc = contact_time(M, R, ES, v)
    ts = tc / 400  # samples every tc/400: Gear's steps end on sample boundaries
    sim, res = _wall_impact(v, 1.0, duration=1.5 * tc, sample_rate=1.0 / ts)
    el = res.energy.elastic
    assert np.count_nonzero(el > 0) * ts == pytest.approx(tc, rel=0.02)
    k = hertz_stiffness(ES, R)
    assert (el.max() / (0.4 * k)) ** 0.4 == pytest.approx(peak_overlap(M, k, v), rel=0.01)
    assert sim.bodies.velocity[0, 0] == pytest.approx(v, rel=1e-3)


@pytest.mark.parametrize("eps", [0.5, 0.7, 0.8, 0.9, 0.95])
@pytest.mark.parametrize("v", [0.02, 0.3])
def test_wall_restitution_recovers_eps(eps, v):
    sim, _ = _wall_impact(v, eps)
    assert sim.bodies.velocity[0, 0] / v == pytest.approx(eps, rel=0.03)


@pytest.mark.parametrize("eps", [0.5, 0.7, 0.9, 0.95])
def test_pair_restitution_recovers_eps_and_conserves_momentum(eps):
    v = 0.2
    pos = [[-R - 1e-6, 0.05, 0.0], [R + 1e-6, 0.05, 0.0]]
    vel = [[v / 2, 0, 0], [-v / 2, 0, 0]]
    sim, _ = run(_gear(still_case(pos, vel, duration=1e-3, eps=eps)))
    assert (sim.bodies.velocity[1, 0] - sim.bodies.velocity[0, 0]) / v == pytest.approx(eps, rel=0.03)
    assert sim.bodies.velocity[:, 0].sum() == pytest.approx(0.0, abs=1e-12)


def test_step_grows_in_free_flight_and_shrinks_during_an_impact():
    T, v = 0.02, 0.3
    max_step = 5e-5  # Numerics.gear_max_step default

    def steps(x0):
        case = still_case([[x0, 0.05, 0.0]], [[-v, 0.0, 0.0]], duration=T, eps=0.9, sample_rate=1000)
        sim, res = run(_gear(case))
        return sim, res

    sim_free, free = steps(0.0)  # 6 mm flight in 20 ms: never reaches a wall
    sim_hit, hit = steps(-0.1 + R + 1e-3)  # hits the -x wall after ~3 ms
    assert sim_free.bodies.velocity[0, 0] == pytest.approx(-v, abs=1e-12) and sim_hit.bodies.velocity[0, 0] > 0
    # free flight: the longest step allowed (plus the start-up ramp)
    assert free.steps <= 1.05 * T / max_step + 20
    # the impact (Hertz time ~180 us at 0.3 m/s) costs many extra, much shorter steps
    tc = contact_time(M, R, ES, v)
    extra = hit.steps - free.steps
    assert extra >= 20
    assert tc / extra < max_step / 5
    assert hit.rejected_steps >= 0 and free.rejected_steps == 0


def _oscillation(tol):
    # a sphere pressed into the floor oscillates in its Hertz well without leaving it (smooth RHS)
    case = still_case([[0.0, R - 2e-7, 0.0]], [[0.0, -2e-4, 0.0]], duration=2e-3, eps=1.0, mu=0.0, gravity=9.81,
                      sample_rate=1e4)
    case = dataclasses.replace(_gear(case, gear_tolerance=tol, gear_max_step=1e-4),
                               recording=Recording(sample_rate=1e4, trajectory_fps=1e4))
    sim, res = run(case)
    return res.trajectory["position"][:, 0, 1], res.steps


def test_error_falls_as_the_tolerance_tightens():
    ref, _ = _oscillation(1e-17)
    # the reference agrees with a Verlet run at dt = 12.5 ns to ~1e-15 m (checked when writing this)
    tols = [1e-9, 1e-10, 1e-11, 1e-12]
    errs, steps = [], []
    for tol in tols:
        y, n = _oscillation(tol)
        errs.append(np.max(np.abs(y - ref)))
        steps.append(n)
    errs, steps = np.array(errs), np.array(steps)
    amplitude = np.ptp(ref)  # ~1.1e-7 m
    assert amplitude > 1e-7
    # the global error follows the local tolerance (measured 0.4 ... 2.8 x tol)
    assert np.all(errs < 5 * np.array(tols)), errs
    assert errs[-1] < errs[0] / 100
    assert np.all(np.diff(steps) > 0)
    # observed order in the step count: err ~ steps^-p, p ~ 8 here (>= 5 for a 5th-order method)
    p = -np.polyfit(np.log(steps), np.log(errs), 1)[0]
    assert p > 4, (p, errs, steps)


def test_energy_ledger_closes_in_a_short_damper_run():
    case = load_case(EXAMPLES / "cuboid_36.toml", {"run.cycles": 1, "run.drop_cycles": 0,
                                                   "numerics.integrator": "gear"})
    res = Simulation(case).run()
    assert res.case.numerics.integrator == "gear"
    assert res.energy.damping[-1] + res.energy.friction[-1] > 1e-3  # the bed dissipated energy
    assert res.energy.balance_error() < 0.01


@pytest.mark.parametrize("mu", [0.1, 1.0])
def test_oblique_floor_impact_ends_rolling_and_friction_does_not_set_the_step(mu):
    # a sphere strikes the floor at 0.5 m/s with 0.2 m/s along it, no spin: friction stops the
    # slip within the impact (mu > 2/7 v_t / ((1 + eps) v_n) = 0.06), so it leaves rolling, at
    # 5/7 of its tangential speed, and rebounds at eps x 0.5 m/s
    v_t = 0.2
    case = _gear(still_case([[0.0, R + 1e-6, 0.0]], [[v_t, -0.5, 0.0]], duration=2e-3, eps=0.9, mu=mu))
    sim, res = run(case)
    assert sim.bodies.velocity[0, 0] == pytest.approx(5 / 7 * v_t, rel=1e-5)
    assert abs(sim.bodies.velocity[0, 0] + R * sim.bodies.spin[0, 2]) < 1e-6  # no slip left
    assert sim.bodies.velocity[0, 1] == pytest.approx(0.45, rel=2e-4)  # 1.2e-4 at the default 1e-9 m
    assert res.energy.balance_error() < 1e-5
    # the friction is evaluated at the corrected slip, so Gear does not have to resolve the tanh
    # law's slope mu F_N tau (measured: 159 / 1507 steps at mu = 0.1 / 1; with the law evaluated
    # at the predicted slip 750 / 6323; without friction 85)
    assert res.steps < {0.1: 400, 1.0: 3000}[mu], res.steps
