"""The tangential spring on its own (:mod:`pdamper.contact.tangential_spring`): Mindlin's stiffness,
LIGGGHTS' damping ratio, a sticking spring that returns what it stored, an unloading that creates
no energy, the Coulomb cap, and the rotation with the contact."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pdamper.contact import TANGENTIAL_CHOICES, TANGENTIAL_LAWS
from pdamper.contact.tangential_spring import (damping_ratio, spring_damping, spring_energy, spring_force,
                                               spring_stiffness)
from pdamper.materials import PVC, STEEL_S235, effective_modulus, effective_shear_modulus

KT = 2.0e5  # N/m, a steel-PVC contact near its static overlap
Z = (0.0, 0.0, 0.0)
N = (0.0, 1.0, 0.0)  # the floor's normal


def _step(state, kt, lim, slip, dt, gt=0.0, normal=N):
    """Advance ``state = (F_s, kt_old)`` by one step of ``dt`` at the slip ``slip`` (the contact
    point moving by slip dt); returns (force, new state, loss)."""
    (sx, sy, sz), kt_old = state
    ds = np.array(slip) * dt
    fx, fy, fz, sx, sy, sz, loss = spring_force(kt, gt, lim, (sx, sy, sz), kt_old, tuple(normal), tuple(ds),
                                                tuple(slip), dt)
    return np.array([fx, fy, fz]), ((sx, sy, sz), kt), loss


def test_the_registry_names_both_laws_with_the_papers_first():
    assert TANGENTIAL_CHOICES == ("tanh", "spring")
    assert not TANGENTIAL_LAWS["tanh"].history and TANGENTIAL_LAWS["spring"].history


def test_an_unregistered_tangential_marker_is_refused_when_the_kernels_compile():
    from typing import NamedTuple

    from numba import typeof

    from pdamper.kernels.contact import _tangential_law_of

    class NotALaw(NamedTuple):
        pass

    with pytest.raises(TypeError, match="no tangential law is registered.*TANGENTIAL_LAWS"):
        _tangential_law_of(typeof(NotALaw()))
    assert _tangential_law_of(typeof(TANGENTIAL_LAWS["spring"].marker())) is TANGENTIAL_LAWS["spring"]


def test_mindlins_stiffness_is_two_one_minus_nu_over_two_minus_nu_of_the_normal_one():
    # for like materials k_t / (dF_N/d delta) = 8 G* / (2 E*) = 2 (1 - nu) / (2 - nu)
    nu = STEEL_S235.poisson_ratio
    r_star, delta = 0.0025, 1e-6
    kt = spring_stiffness(effective_shear_modulus(STEEL_S235, STEEL_S235), r_star, delta)
    kn = 2.0 * effective_modulus(STEEL_S235, STEEL_S235) * math.sqrt(r_star * delta)
    assert kt / kn == pytest.approx(2 * (1 - nu) / (2 - nu), rel=1e-12)
    # G* of unlike materials: 1/G* = (2 - nu1)/G1 + (2 - nu2)/G2, G = E / (2 (1 + nu))
    g = [m.youngs_modulus / (2 * (1 + m.poisson_ratio)) for m in (STEEL_S235, PVC)]
    expect = 1 / ((2 - STEEL_S235.poisson_ratio) / g[0] + (2 - PVC.poisson_ratio) / g[1])
    assert effective_shear_modulus(STEEL_S235, PVC) == pytest.approx(expect, rel=1e-12)


def test_the_damping_ratio_is_liggghts_gamma_t():
    # LIGGGHTS: gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*), beta = ln e / sqrt(ln^2 e + pi^2), S_t = k_t
    for e in (0.5, 0.9, 0.99):
        beta = math.log(e) / math.sqrt(math.log(e) ** 2 + math.pi**2)
        m = 4.1e-3
        gamma_t = -2 * math.sqrt(5 / 6) * beta * math.sqrt(KT * m)
        assert spring_damping(float(damping_ratio(e)), KT, m) == pytest.approx(gamma_t, rel=1e-12)
    assert damping_ratio(1.0) == 0.0


def test_a_sticking_spring_returns_what_it_stored_to_round_off():
    # load along x, then along z, then back along the same path, below the cap, at constant stiffness
    lim, dt = 1.0, 1e-6
    path = [(2e-3, 0.0, 0.0)] * 200 + [(0.0, 0.0, -1e-3)] * 100
    path = path + [tuple(-v for v in s) for s in reversed(path)]
    state, work, loss, peak, off = (Z, 0.0), 0.0, 0.0, 0.0, 0.0
    for slip in path:
        f_old = np.array(state[0])
        f, state, q = _step(state, KT, lim, slip, dt)
        # the work the bodies do on the spring: the step's mean spring force over its displacement
        work -= 0.5 * (f_old + f) @ (np.array(slip) * dt)
        loss += q
        stored = spring_energy(*f, KT)
        peak = max(peak, stored)
        off = max(off, abs(work - stored))
    assert peak > 1e-8 and loss == 0.0
    # at every step the spring holds the work done on it, and at the end it has given it all back
    assert off < 1e-12 * peak
    assert np.linalg.norm(state[0]) < 1e-12 * math.sqrt(2 * KT * peak) and abs(work) < 1e-12 * peak


def test_unloading_scales_the_force_down_and_creates_no_energy():
    lim, dt = 10.0, 1e-6
    state = (Z, 0.0)
    for _ in range(100):
        _, state, _ = _step(state, KT, lim, (1e-3, 0.0, 0.0), dt)  # load to 0.02 N
    held = state[0][0]
    e0 = spring_energy(*state[0], KT)
    # the overlap falls (k_t halves) with no slip: the force follows k_t, the energy falls by half
    f, state2, q = _step(state, KT / 2, lim, Z, 0.0)  # (no step: the state changes alone)
    assert f[0] == pytest.approx(held / 2, rel=1e-12)
    e1 = spring_energy(*state2[0], KT / 2)
    assert e1 == pytest.approx(e0 / 2, rel=1e-12) and q == pytest.approx(e0 - e1, rel=1e-12)
    # loaded again (k_t back up) at no slip: the force is kept, the energy falls again, none is made
    f, state3, q = _step(state2, KT, lim, Z, 0.0)
    assert f[0] == pytest.approx(held / 2, rel=1e-12)
    assert spring_energy(*state3[0], KT) + q == pytest.approx(e1, rel=1e-12)
    assert spring_energy(*state3[0], KT) < e1


def test_gross_slip_holds_the_cap_and_dissipates_mu_fn_times_the_slip():
    lim, dt, v = 0.05, 1e-6, 0.1
    state, loss = (Z, 0.0), 0.0
    for k in range(2000):
        f, state, q = _step(state, KT, lim, (v, 0.0, 0.0), dt)
        if k >= 100:  # sliding on the cap since k_t v dt k > lim
            loss += q
            assert f[0] == pytest.approx(-lim, rel=1e-12)
    assert loss == pytest.approx(lim * v * dt * 1900, rel=1e-9)


def test_a_falling_normal_force_lets_the_spring_slip_back_onto_the_cap():
    dt = 1e-6
    state = (Z, 0.0)
    for _ in range(100):
        _, state, _ = _step(state, KT, 1.0, (1e-3, 0.0, 0.0), dt)
    e0 = spring_energy(*state[0], KT)
    f, state, q = _step(state, KT, 0.005, Z, 0.0)  # the cap drops below the held 0.02 N
    assert np.linalg.norm(f) == pytest.approx(0.005, rel=1e-12)
    assert spring_energy(*state[0], KT) + q == pytest.approx(e0, rel=1e-12)
    # no push at all: nothing held, everything dissipated
    f, state, q2 = _step(state, KT, 0.0, Z, 0.0)
    assert tuple(f) == (0.0, 0.0, 0.0) and q2 == pytest.approx(spring_energy(0.005, 0, 0, KT), rel=1e-12)


def test_the_stored_force_turns_with_the_contact_and_keeps_its_magnitude():
    dt = 1e-6
    state = (Z, 0.0)
    for _ in range(100):
        _, state, _ = _step(state, KT, 1.0, (1e-3, 0.0, 0.0), dt)
    held = np.array(state[0])
    a = math.radians(10)
    normal = (math.sin(a), math.cos(a), 0.0)  # the contact turned by 10 degrees about z
    f, state, q = _step(state, KT, 1.0, Z, 0.0, normal=normal)
    assert np.linalg.norm(f) == pytest.approx(np.linalg.norm(held), rel=1e-12)
    assert abs(f @ np.array(normal)) < 1e-15 and q == pytest.approx(0.0, abs=1e-20)


def test_damping_acts_on_the_slip_and_never_lifts_the_total_over_the_cap():
    dt, m = 1e-6, 4.1e-3
    gt = spring_damping(float(damping_ratio(0.5)), KT, m)
    # below the cap: spring plus -gt v, the damping power gt v^2 dissipated
    f, state, q = _step((Z, 0.0), KT, 1.0, (1e-2, 0.0, 0.0), dt, gt=gt)
    assert f[0] == pytest.approx(-KT * 1e-2 * dt - gt * 1e-2, rel=1e-12)
    assert q == pytest.approx(gt * 1e-4 * dt, rel=1e-12)
    # near the cap the damping gives way: |F| = lim exactly
    f, state, q = _step((Z, 0.0), KT, 0.01, (0.1, 0.0, 0.0), dt, gt=gt)
    assert np.linalg.norm(f) == pytest.approx(0.01, rel=1e-12)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.floats(-1.0, 1.0).map(lambda v: v if abs(v) > 1e-100 else 0.0), min_size=16, max_size=16),
       st.just(0.0) | st.floats(1e-6, 1.0),
       st.just(0.0) | st.floats(1e-6, 5.0))
def test_the_force_never_exceeds_the_cap_and_the_energy_balance_is_exact(x, lim, gt):
    """Any stored state, displacement, slip and stiffness change: |F| <= lim and the stored force
    <= lim; undamped, the spring's balance over the step is exact with the mean of its forces at the
    step's ends (U_new - U_old + loss = -(F_old + F_new)/2 . ds_t); without a displacement the
    loss (the change of stiffness or cap alone) is >= 0: nothing is created."""
    normal = np.array(x[0:3]) + np.array([0.0, 2.0, 0.0])
    normal /= np.linalg.norm(normal)
    slip = np.array(x[3:6]) * 0.5
    slip -= (slip @ normal) * normal
    stored = np.array(x[6:9]) * lim
    kt_old = KT * (1.5 + x[9])
    kt = KT * (1.5 + x[10])
    ds = np.array(x[11:14]) * 1e-6
    dt = 1e-6 * (1.0 + x[14])
    fx, fy, fz, sx, sy, sz, loss = spring_force(kt, gt, lim, tuple(stored), kt_old, tuple(normal), tuple(ds),
                                                tuple(slip), dt)
    assert math.hypot(fx, fy, fz) <= lim * (1 + 1e-12) + 1e-300
    assert math.hypot(sx, sy, sz) <= lim * (1 + 1e-12) + 1e-300
    u_old, u_new = spring_energy(*stored, kt_old), spring_energy(sx, sy, sz, kt)
    scale = u_old + lim * lim / kt + lim * np.linalg.norm(ds) + 1e-300
    if gt == 0.0:
        ds_t = ds - (ds @ normal) * normal
        work = -0.5 * (stored + np.array([sx, sy, sz])) @ ds_t
        assert u_new - u_old + loss == pytest.approx(work, abs=1e-12 * scale)
    _, _, _, _, _, _, loss0 = spring_force(kt, gt, lim, tuple(stored), kt_old, tuple(normal), Z, tuple(slip), dt)
    assert loss0 >= -1e-12 * scale
