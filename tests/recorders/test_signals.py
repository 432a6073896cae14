"""Recorded signals are interval means: a constant force gives exactly that force, the container
velocity is (x(t1) - x(t0)) / dt, and an impact's impulse lands in the samples it falls in."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.excitation import HarmonicDrive, SampledDrive
from pdamper.params import Case, Container, ParticleSet
from pdamper.recorders.signals import Signals

from dem_fixtures import R, run, sphere_mass, still_case

M = sphere_mass()


def _case(drive, mass=0.0):
    return Case(particles=(ParticleSet(count=1),), container=Container(mass=mass), drive=drive, cycles=3,
                drop_cycles=1)


def test_a_constant_wall_force_is_recorded_as_exactly_that_force():
    case = _case(HarmonicDrive(stroke=0.012, frequency=2.0))
    s = Signals.from_run(case, 1e-3, np.full(1500, 0.25))
    np.testing.assert_array_equal(s.force, 0.25)


def test_container_velocity_is_the_interval_mean_and_time_stamps_the_centre():
    drive = HarmonicDrive(stroke=0.012, frequency=2.0)
    dt = 1e-3
    s = Signals.from_run(_case(drive), dt, np.zeros(1500))
    edges = np.arange(1501) * dt
    x, _, _ = drive.motion(edges)
    np.testing.assert_allclose(s.velocity, (x[1:] - x[:-1]) / dt, rtol=0, atol=1e-15)
    np.testing.assert_allclose(s.time, edges[:-1] + dt / 2, rtol=0, atol=1e-15)
    np.testing.assert_allclose(s.time_end, edges[1:], rtol=0, atol=1e-15)
    np.testing.assert_allclose(s.position, drive.motion(s.time)[0], atol=1e-16)
    # the interval mean of V cos(Omega t) is V cos(Omega t_c) sinc(Omega dt / 2): not a point sample
    w = drive.omega
    mean = drive.velocity_amplitude * np.cos(w * s.time) * math.sin(w * dt / 2) / (w * dt / 2)
    np.testing.assert_allclose(s.velocity, mean, atol=1e-14)


def test_container_mass_adds_its_mean_inertial_force():
    drive = HarmonicDrive(stroke=0.012, frequency=2.0)
    dt = 1e-3
    mc = 0.7
    s = Signals.from_run(_case(drive, mass=mc), dt, np.full(1500, 0.1))
    _, v, _ = drive.motion(np.arange(1501) * dt)
    np.testing.assert_allclose(s.force, 0.1 + mc * np.diff(v) / dt, rtol=1e-12, atol=1e-14)


def test_as_dict_names_units():
    s = Signals.from_run(_case(HarmonicDrive(stroke=0.01)), 1e-3, np.zeros(10))
    assert list(s.as_dict()) == ["time [s]", "force [N]", "velocity [m/s]", "position [m]"]


def test_constant_container_acceleration_is_recorded_as_m_a():
    # a sphere resting on the floor against the -x wall; the container accelerates at a constant a:
    # once the start transient has died out the wall pushes the sphere with exactly m a
    a, T = 2.0, 0.2
    t = np.linspace(0, T, 11)
    drive = SampledDrive(time=tuple(t), position=tuple(0.5 * a * t**2))  # a cubic spline reproduces it
    case = still_case([[-0.1 + R, R, 0.0]], [[0, 0, 0]], duration=T, mu=0.1, gravity=9.81, drive=drive,
                      sample_rate=1000)
    sim, res = run(case)
    f = res.signals.force
    np.testing.assert_allclose(f[50:], M * a, rtol=1e-6)
    # container velocity: interval means of a t
    np.testing.assert_allclose(res.signals.velocity, a * res.signals.time, rtol=1e-9)
    # the sphere moves with the container: lab velocity a T
    assert sim.bodies.velocity[0, 0] + a * T == pytest.approx(a * T, rel=1e-6)


@pytest.mark.parametrize("eps", [1.0, 0.8])
def test_an_impact_impulse_is_recorded_in_full_however_short(eps):
    # an impact of ~180 us inside 1 ms samples: a point sample would almost always miss it, the
    # interval mean keeps its impulse m (1 + eps) v
    v = 0.3
    case = still_case([[-0.1 + R + 2.5e-3, 0.05, 0.0]], [[-v, 0.0, 0.0]], duration=0.02, eps=eps,
                      sample_rate=1000)
    sim, res = run(case)
    f = res.signals.force
    dt = res.signals.time_end[0]
    assert np.count_nonzero(f) <= 2  # the impact falls in one or two samples
    assert np.sum(f) * dt == pytest.approx(M * (sim.bodies.velocity[0, 0] + v), rel=1e-9)
    assert sim.bodies.velocity[0, 0] == pytest.approx(eps * v, rel=0.03)
