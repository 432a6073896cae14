"""Tsuji's viscoelastic Hertz damping as LIGGGHTS evaluates it: the coefficient, its restitution
(speed-free, equal to eps unclipped), and friction only while the contact pushes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from pdamper.contact.friction_tanh import TanhFriction
from pdamper.contact.hertz_tsuji import HertzTsuji, damping_ratio, normal_force, touch
from pdamper.contact.tangential_spring import SpringFriction
from pdamper.kernels.bundles import ContactConstants, ContactGeometry, ContactTable
from pdamper.kernels.contact import contact


def _restitution(alpha, clip):
    """Dimensionless impact u'' = -u^1.5 - alpha u^0.25 u' (u(0) = 0, u'(0) = 1), solved by scipy."""
    def rhs(_t, y):
        u, du = max(y[0], 0.0), y[1]
        f = -u**1.5 - alpha * u**0.25 * du
        return [du, min(f, 0.0) if clip else f]

    def leave(_t, y):
        return y[0]

    leave.terminal, leave.direction = True, -1
    sol = solve_ivp(rhs, [0.0, 100.0], [0.0, 1.0], events=leave, rtol=1e-11, atol=1e-13, method="DOP853",
                    first_step=1e-6)
    return -sol.y_events[0][0][1]


def test_the_coefficient_is_liggghts_gamma_n():
    # LIGGGHTS: gamma_n = -2 sqrt(5/6) beta sqrt(S_n m*), S_n = 2 E* sqrt(R* delta)
    e_star, r_star, m_star, delta, eps = 2.9e9, 0.005, 4.1e-3, 3e-6, 0.7
    beta = math.log(eps) / math.sqrt(math.log(eps) ** 2 + math.pi ** 2)
    gamma_n = -2 * math.sqrt(5 / 6) * beta * math.sqrt(2 * e_star * math.sqrt(r_star * delta) * m_star)
    k = 4 / 3 * e_star * math.sqrt(r_star)
    c = touch(float(damping_ratio(eps)), 0.1, k, m_star)
    fn, fdamp = normal_force(k, delta, 0.2, c)
    assert fdamp == pytest.approx(gamma_n * 0.2, rel=1e-12)
    assert fn == pytest.approx(k * delta**1.5 + gamma_n * 0.2, rel=1e-12)
    assert damping_ratio(1.0) == 0.0


@pytest.mark.parametrize("eps", [0.5, 0.6, 0.7, 0.8, 0.9, 0.95])
def test_unclipped_the_law_rebounds_at_eps_and_clipped_it_would_not(eps):
    alpha = float(damping_ratio(eps))
    assert _restitution(alpha, clip=False) == pytest.approx(eps, abs=1e-3)
    # the values the module docstring quotes for a force clipped at zero
    clipped = {0.5: 0.550, 0.6: 0.632, 0.7: 0.718, 0.8: 0.808, 0.9: 0.902, 0.95: 0.9505}[eps]
    assert _restitution(alpha, clip=True) == pytest.approx(clipped, abs=1e-3)


@pytest.mark.parametrize("tangential", [TanhFriction(), SpringFriction()], ids=["tanh", "spring"])
def test_friction_follows_only_the_pushing_part_of_the_force(tangential):
    table = ContactTable(law=HertzTsuji(), tangential=tangential, n_materials=1, modulus=np.array([2.9e9]),
                         shear_modulus=np.array([1.1e9]), friction=np.array([0.5]),
                         coefficient=np.full((1, 4), float(damping_ratio(0.5))), tangential_damping=np.zeros((1, 4)),
                         yield_pressure=np.zeros(1), log_speed0=0.0, dlog_speed=1.0, tau=1000.0, v_floor=1e-3,
                         overlap_limit=0.05)
    k, m = 4 / 3 * 2.9e9 * math.sqrt(0.005), 4.1e-3
    c = touch(float(damping_ratio(0.5)), 0.3, k, m)
    # a spring that holds a force along x from the steps before (the tanh law ignores it)
    hist = np.zeros((1, 5))
    hist[0, :4] = (-0.01, 0.0, 0.0, 1e5)
    # separating fast at a tiny overlap: the damping pulls, F_N < 0, and there is no friction
    constants = ContactConstants(0, 0.5, k, 0.005, m, 1.0)
    fn, ftx, fty, ftz, ff, lim, v_in, d, p_n, p_f, e_f = contact(
        table, hist, 0, constants, ContactGeometry(1e-9, -0.3, 0.0, 1.0, 0.0, 0.01, 0.0, 0.0, 0.01, 1e-8, 0.0, 0.0),
        0.3, c, 1e-6, 1e-6)
    assert fn < 0 and ff == 0.0 and p_f == 0.0 and (ftx, fty, ftz) == (0.0, 0.0, 0.0)
    assert p_n > 0  # the pulling damping still dissipates: F_damp delta_dot > 0
    # approaching: it pushes, and friction acts against the slip
    hist[0, :4] = (-0.01, 0.0, 0.0, 1e5)
    fn, ftx, *_ = contact(table, hist, 0, constants,
                          ContactGeometry(1e-9, 0.3, 0.0, 1.0, 0.0, 0.01, 0.0, 0.0, 0.01, 1e-8, 0.0, 0.0), 0.3, c, 1e-6,
                          1e-6)
    assert fn > 0 and ftx < 0
