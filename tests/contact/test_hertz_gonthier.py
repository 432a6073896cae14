"""Hertz contact time and overlap, Gonthier restitution, resting-contact guard (SPEC Sect. 9)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from pdamper.contact.hertz_gonthier import contact_time, damping_parameter, hertz_stiffness, peak_overlap
from pdamper.materials import PVC, STEEL_S235, effective_modulus

from dem_fixtures import R, run, sphere_mass, still_case

M = sphere_mass()


def _wall_impact(v, eps, dt=None, sample_rate=None, duration=2e-3):
    # sphere 1 um in front of the -x wall, moving towards it
    x0 = -0.1 + R + 1e-6
    case = still_case([[x0, 0.05, 0.0]], [[-v, 0.0, 0.0]], duration=duration, eps=eps, dt=dt, sample_rate=sample_rate)
    return run(case)


@pytest.mark.parametrize("v", [0.05, 0.5])
def test_undamped_wall_impact_lasts_hertz_time_and_reaches_hertz_overlap(v):
    es = effective_modulus(STEEL_S235, PVC)
    tc = contact_time(M, R, es, v)
    dt = tc / 400
    sim, res = _wall_impact(v, 1.0, dt=dt, sample_rate=1.0 / dt, duration=1.5 * tc)
    el = res.energy.elastic
    measured = np.count_nonzero(el > 0) * dt
    assert measured == pytest.approx(tc, rel=0.02)
    k = hertz_stiffness(es, R)
    dmax = (el.max() / (0.4 * k)) ** 0.4
    assert dmax == pytest.approx(peak_overlap(M, k, v), rel=0.01)
    # elastic: leaves with the speed it came with
    assert sim.bodies.velocity[0, 0] == pytest.approx(v, rel=1e-3)


@pytest.mark.parametrize("eps", [0.5, 0.6, 0.7, 0.8, 0.9, 0.95])
@pytest.mark.parametrize("v", [0.02, 0.3])
def test_wall_restitution_recovers_eps(eps, v):
    sim, _ = _wall_impact(v, eps)
    assert sim.bodies.velocity[0, 0] / v == pytest.approx(eps, rel=0.03)


@pytest.mark.parametrize("eps", [0.5, 0.7, 0.9, 0.95])
def test_pair_restitution_recovers_eps(eps):
    v = 0.2
    pos = [[-R - 1e-6, 0.05, 0.0], [R + 1e-6, 0.05, 0.0]]
    vel = [[v / 2, 0, 0], [-v / 2, 0, 0]]
    sim, _ = run(still_case(pos, vel, duration=1e-3, eps=eps))
    outgoing = sim.bodies.velocity[1, 0] - sim.bodies.velocity[0, 0]
    assert outgoing / v == pytest.approx(eps, rel=0.03)
    # momentum is conserved exactly by pair forces
    assert sim.bodies.velocity[:, 0].sum() == pytest.approx(0.0, abs=1e-12)


def test_paper_gonthier_formula_rebounds_lower_than_nominal_as_documented():
    # independent check of the law as written: d = (1 - eps^2)/(eps v_in), solved by scipy
    from pdamper.contact.hertz_gonthier import restitution_for_chi

    for eps, got in [(0.6, 0.5773), (0.7, 0.6696), (0.9, 0.8764)]:
        assert restitution_for_chi((1 - eps**2) / eps) == pytest.approx(got, abs=2e-4)


def test_gonthier_option_in_the_engine_matches_the_ode():
    from pdamper.contact.hertz_gonthier import restitution_for_chi

    v, eps = 0.3, 0.7
    x0 = -0.1 + R + 1e-6
    case = still_case([[x0, 0.05, 0.0]], [[-v, 0.0, 0.0]], duration=2e-3, eps=eps)
    case = dataclasses.replace(case, contact=dataclasses.replace(case.contact, damping="gonthier"))
    sim, _ = run(case)
    assert sim.bodies.velocity[0, 0] / v == pytest.approx(restitution_for_chi((1 - eps**2) / eps), rel=0.01)


def test_calibration_table_is_reproducible():
    from pdamper.contact.hertz_gonthier import _calibration, compute_calibration

    fresh = compute_calibration()
    np.testing.assert_allclose(_calibration(), fresh, rtol=1e-9, atol=1e-12)


def test_calibrated_chi_inverts_the_impact():
    from pdamper.contact.hertz_gonthier import chi_for_restitution, restitution_for_chi

    for eps in [0.3, 0.5, 0.75, 0.9, 0.99]:
        assert restitution_for_chi(chi_for_restitution(eps)) == pytest.approx(eps, abs=2e-4)
    assert chi_for_restitution(1.0) == 0.0


def test_damping_parameter_formula_and_floor():
    assert damping_parameter(0.9, 0.5) == pytest.approx((1 - 0.81) / (0.9 * 0.5))
    assert damping_parameter(0.9, 0.0) == damping_parameter(0.9, 1e-3)


def test_sphere_dropped_on_floor_settles_and_stays_at_rest():
    # dropped from 2 mm: bounces, then rests in its Hertz well without creeping or jittering
    pos = [[0.0, R + 2e-3, 0.0]]
    sim, res = run(still_case(pos, [[0, 0, 0]], duration=0.5, eps=0.9, mu=0.1, gravity=9.81))
    k = hertz_stiffness(effective_modulus(STEEL_S235, PVC), R)
    static = (M * 9.81 / k) ** (2 / 3)
    assert sim.bodies.position[0, 1] == pytest.approx(R - static, abs=0.01 * static)
    assert np.abs(sim.bodies.velocity).max() < 1e-6
    # the ledger balances through all the bounces
    assert res.energy.balance_error() < 1e-3
