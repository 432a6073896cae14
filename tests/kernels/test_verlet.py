"""Velocity Verlet: energy conservation with elastic frictionless collisions, second-order convergence."""

from __future__ import annotations

import numpy as np
import pytest

from dem_fixtures import R, run, still_case


def _gas(n=12, seed=1):
    rng = np.random.default_rng(seed)
    xs = np.linspace(-0.08, 0.08, 4)
    zs = np.linspace(-0.035, 0.035, 3)
    pos = [[x, R + 0.01 + 0.02 * (k % 2), z] for k, (x, z) in enumerate((x, z) for x in xs for z in zs)][:n]
    vel = rng.normal(0.0, 0.3, (n, 3))
    return pos, vel


def test_total_energy_is_conserved_with_elastic_frictionless_collisions():
    # 30 steps per contact: the error of one Hertz impact scales with dt^2 (15 steps: 3e-4)
    pos, vel = _gas()
    sim, res = run(still_case(pos, vel, duration=0.5, eps=1.0, mu=0.0, gravity=9.81, steps_per_contact=30))
    e = res.energy
    total = e.kinetic + e.rotational + e.potential + e.elastic
    # many collisions happened (each sphere hit the floor and others several times)
    assert e.damping[-1] == 0.0 and e.friction[-1] == 0.0
    drift = np.max(np.abs(total - total[0])) / total[0]
    assert drift < 1e-4


def test_second_order_convergence_on_a_smooth_contact_oscillation():
    # a sphere pressed into the floor oscillates in its Hertz well without leaving it (smooth RHS)
    def final_height(dt):
        case = still_case([[0.0, R - 2e-7, 0.0]], [[0.0, -2e-4, 0.0]], duration=2e-3, eps=1.0, mu=0.0,
                          gravity=9.81, dt=dt, sample_rate=1e4)
        sim, _ = run(case)
        return sim.bodies.position[0, 1]

    ref = final_height(1e-7 / 8)
    errs = [abs(final_height(dt) - ref) for dt in (4e-6, 2e-6, 1e-6)]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(orders > 1.8) and np.all(orders < 2.3), orders
