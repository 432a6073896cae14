"""Rolling with tanh-regularised friction (SPEC Sect. 9): 2V/7 and 5/7 g sin(alpha)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.contact.friction_tanh import friction_factor
from pdamper.excitation import SampledDrive

from dem_fixtures import R, run, still_case

G = 9.81


def _moving_floor(V, tau):
    t = np.linspace(0.0, 1.0, 5)
    drive = SampledDrive(time=tuple(t), position=tuple(V * t))
    case = still_case([[0.0, R, 0.0]], [[0, 0, 0]], duration=0.3, mu=0.1, gravity=G, tau=tau, drive=drive)
    return run(case)


@pytest.mark.parametrize("tau", [1e2, 1e3, 1e4])
def test_sphere_on_floor_set_moving_ends_rolling_at_two_sevenths(tau):
    V = 0.1
    sim, _ = _moving_floor(V, tau)
    lab = sim.bodies.velocity[0, 0] + V
    assert lab == pytest.approx(2 * V / 7, rel=0.005)
    # rolls without slip: contact-point velocity relative to the floor vanishes
    slip = sim.bodies.velocity[0, 0] + R * sim.bodies.spin[0, 2]
    assert abs(slip) < 1e-3 * V


@pytest.mark.parametrize("axis", [0, 2])
def test_sphere_on_tilted_floor_accelerates_at_five_sevenths_g_sin_alpha(axis):
    alpha = math.radians(3.0)
    tilt = [0.0, 0.0, 0.0]
    tilt[axis] = alpha
    T = 0.15
    sim, _ = run(still_case([[0.0, R, 0.0]], [[0, 0, 0]], duration=T, mu=0.1, gravity=G, tilt=tuple(tilt)))
    speed = np.hypot(sim.bodies.velocity[0, 0], sim.bodies.velocity[0, 2])
    assert speed == pytest.approx(5 / 7 * G * math.sin(alpha) * T, rel=0.01)


def test_friction_factor_limits():
    # no slip: the factor stays finite (mu tau), so the friction force factor * v_t vanishes
    assert friction_factor(0.1, 1000.0, 0.0) == pytest.approx(0.1 * 1000.0, rel=1e-6)
    # saturates at mu / |v| for fast slip, linear (mu tau) for slow slip
    assert friction_factor(0.1, 1000.0, 1.0) == pytest.approx(0.1)
    assert friction_factor(0.1, 1000.0, 1e-7) == pytest.approx(0.1 * 1000.0, rel=1e-6)


def test_tanh_approximation_is_accurate_everywhere():
    import math

    from pdamper.contact.friction_tanh import tanh_pos

    xs = np.geomspace(1e-12, 50.0, 20001)
    err = max(abs(tanh_pos(x) - math.tanh(x)) / math.tanh(x) for x in xs)
    assert err < 3e-7
