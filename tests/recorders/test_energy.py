"""The energy ledger: columns, residual and balance error, dissipation per cycle, and runs whose
ledger must close (a still container: no work; a container that pushes a sphere: work = kinetic)."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.excitation import HarmonicDrive, SampledDrive, Still
from pdamper.params import Case, ParticleSet
from pdamper.recorders.energy import COLUMNS, EnergyLedger

from dem_fixtures import R, run, sphere_mass, still_case

M = sphere_mass()


def _ledger(t, **cols):
    eng = np.zeros((t.size, 7))
    for k, c in enumerate(COLUMNS):
        if c in cols:
            eng[:, k] = cols[c]
    return EnergyLedger.from_array(t, eng)


def test_columns_and_mechanical_energy():
    assert COLUMNS == ("kinetic", "rotational", "potential", "elastic", "work", "damping", "friction")
    t = np.arange(1, 4) * 0.1
    e = _ledger(t, kinetic=[1.0, 2.0, 3.0], rotational=[0.5, 0.5, 0.5], potential=[-1.0, -1.0, -2.0],
                elastic=[0.1, 0.0, 0.0])
    np.testing.assert_allclose(e.mechanical, [0.6, 1.5, 1.5])


def test_residual_is_zero_for_a_closed_balance_and_measures_a_leak():
    t = np.arange(1, 11) * 0.01
    work = np.linspace(0, 1.0, 10)
    damping = 0.6 * work
    friction = 0.1 * work
    kinetic = 2.0 + work - damping - friction
    e = _ledger(t, kinetic=kinetic, work=work, damping=damping, friction=friction)
    np.testing.assert_allclose(e.residual, 0.0, atol=1e-15)
    assert e.balance_error() < 1e-15
    leaky = _ledger(t, kinetic=kinetic + 0.02 * work, work=work, damping=damping, friction=friction)
    assert leaky.balance_error() == pytest.approx(0.02)


def test_dissipated_per_cycle_uses_whole_cycles_after_the_dropped_ones():
    f = 2.0
    case = Case(particles=(ParticleSet(count=1),), drive=HarmonicDrive(stroke=0.01, frequency=f), cycles=5,
                drop_cycles=2)
    t = np.arange(1, 2501) * 1e-3  # 2.5 s = 5 cycles
    # dissipation grows at 3 J per cycle after a start-up burst of 10 J in the first cycle
    damping = 3.0 * f * t + 10.0 * np.minimum(t / 0.5, 1.0)
    e = _ledger(t, damping=damping)
    assert e.dissipated_per_cycle(case) == pytest.approx(3.0, rel=1e-9)
    still = Case(particles=(ParticleSet(count=1),), cycles=1, drop_cycles=0,
                 drive=Still(duration_s=1.0))
    assert np.isnan(e.dissipated_per_cycle(still))


def test_ledger_residual_is_nil_for_spheres_bouncing_in_a_still_container():
    rng = np.random.default_rng(4)
    pos = [[x, 0.02 + 0.015 * (k % 3), z] for k, (x, z) in
           enumerate([(x, z) for x in (-0.06, -0.02, 0.02, 0.06) for z in (-0.02, 0.02)])]
    vel = rng.normal(0.0, 0.3, (len(pos), 3))
    sim, res = run(still_case(pos, vel, duration=0.3, eps=0.8, mu=0.1, gravity=9.81))
    e = res.energy
    assert np.all(e.work == 0.0)  # a still container does no work
    assert e.damping[-1] > 0.05 * e.mechanical[0] and e.friction[-1] > 0  # much was dissipated
    assert np.max(np.abs(e.residual)) < 1e-3 * (e.damping[-1] + e.friction[-1])
    assert np.all(np.diff(e.damping) >= 0) and np.all(np.diff(e.friction) >= 0)


def test_ledger_of_a_sphere_at_rest_stays_at_rest():
    sim, res = run(still_case([[0.0, R - 2.7e-7, 0.0]], [[0, 0, 0]], duration=0.05, eps=0.9, mu=0.1,
                              gravity=9.81))
    e = res.energy
    assert np.max(np.abs(e.residual)) < 1e-12
    assert e.kinetic[-1] < 1e-12


def test_kinetic_energy_is_counted_in_the_lab_frame():
    # frictionless sphere on the floor of a moving container: it stays at rest in the lab
    drive = HarmonicDrive(stroke=0.01, frequency=2.0)
    case = still_case([[0.0, R - 2.7e-7, 0.0]], [[0, 0, 0]], duration=0.5, mu=0.0, gravity=9.81, drive=drive,
                      sample_rate=1000)
    sim, res = run(case)
    e = res.energy
    container_ke = 0.5 * M * drive.velocity_amplitude**2  # what a container-frame ledger would show
    assert np.max(e.kinetic) < 1e-6 * container_ke  # only the settling of the Hertz well (~1e-11 J)
    assert np.max(np.abs(e.work)) < 1e-14
    # in the container frame it moves backwards with the container's velocity
    t_end = res.signals.time_end[-1]  # one whole cycle (still_case runs cycles = 1)
    assert sim.bodies.velocity[0, 0] == pytest.approx(-drive.motion(t_end)[1], rel=1e-9)


def test_work_done_by_a_pushing_container_becomes_kinetic_energy():
    a, T = 2.0, 0.2
    t = np.linspace(0, T, 11)
    drive = SampledDrive(time=tuple(t), position=tuple(0.5 * a * t**2))
    case = still_case([[-0.1 + R, R, 0.0]], [[0, 0, 0]], duration=T, mu=0.1, gravity=9.81, drive=drive,
                      sample_rate=1000)
    sim, res = run(case)
    e = res.energy
    assert e.kinetic[-1] == pytest.approx(0.5 * M * (a * T) ** 2, rel=1e-6)
    assert e.work[-1] == pytest.approx(e.kinetic[-1] + e.damping[-1] + e.friction[-1], rel=1e-4)
    assert e.balance_error() < 1e-4
