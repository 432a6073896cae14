"""The energy balance of a mode with the damper at resonance (pdamper.theory.balance) and the
closed-form fields it uses (pdamper.theory.fields, rolling_mass_ratio): against hand calculations."""

import math

import pytest

from pdamper import theory as th
from pdamper.theory.balance import Mode, operating_points
from pdamper.theory.fields import closed_form_fields
from pdamper.theory.rolling import rolling_mass_ratio

from design_helpers import F0, F_N, K, M, SPHERE, ZETA

C = 2 * ZETA * math.sqrt(K * M)
#: the 25 kg / 3 Hz frame's one mode (shape 1 everywhere)
MODE = Mode(number=1, mass=M, stiffness=K, damping=C, frequency=F_N, damping_ratio=ZETA, phi_damper=1.0,
            phi_force=1.0, phi_response=1.0)


def test_rolling_bed_mass_is_two_sevenths_at_x_opt_and_the_whole_bed_far_above():
    # at X_opt the bed rolls the whole half cycle: a rolling sphere follows 2/7 of the floor's acceleration
    assert rolling_mass_ratio(1.0) == pytest.approx(2 / 7, abs=2e-4)
    # far above, the bed rides with the walls most of the cycle
    assert rolling_mass_ratio(1000.0) == pytest.approx(1.0, abs=0.02)
    eta, mu = closed_form_fields([0.5, 0.999, 1.0, 2.0, 4.0])
    assert eta[0] == pytest.approx(0.5 * th.X_OPT_OVER_H) and eta[1] == pytest.approx(0.999 * th.X_OPT_OVER_H)
    assert eta[2] == pytest.approx(th.ETA_MAX, rel=1e-9)  # the jump at X_opt kept
    assert eta[3] == pytest.approx(th.eta_rolling(2 * th.X_OPT_OVER_H, 1.0), rel=1e-4)
    assert eta[4] == pytest.approx(th.eta_rolling(4 * th.X_OPT_OVER_H, 1.0), rel=1e-4)


def test_energy_balance_against_a_hand_calculation_on_one_mode():
    md, c = MODE, C
    n, n_max, big_l = 36, 48, 0.120
    h = big_l * (1 - n / n_max)
    x_opt, m_bed = th.optimal_stroke(h), n * SPHERE
    pts = operating_points(md, F0, x_opt=x_opt, bed_mass=m_bed)
    stable = [p for p in pts if p.stable]
    assert len(stable) == 1 and stable[0].state == "rolling"
    x = stable[0].stroke_m
    # by hand: the force's work per cycle pi F X against the structure's pi c Omega X^2 and the damper's
    # E = pi eta* m_bed (X Omega)^2, at the resonance shifted by the rolling bed's effective mass
    eta = th.eta_rolling(x, h)
    m_eff = rolling_mass_ratio(x / x_opt) * m_bed
    omega = math.sqrt(K / (M + m_eff))
    work = math.pi * F0 * x
    loss = math.pi * c * omega * x**2 + math.pi * eta * m_bed * (x * omega) ** 2
    assert loss == pytest.approx(work, rel=1e-4)
    assert stable[0].frequency_hz == pytest.approx(omega / (2 * math.pi), rel=1e-6)


def test_a_force_inside_the_jump_holds_the_damper_at_x_opt():
    md = MODE
    h = 0.030
    x_opt, m_bed = th.optimal_stroke(h), 36 * SPHERE
    low = operating_points(md, 0.5, x_opt=x_opt, bed_mass=m_bed)
    # the force the scattered bed needs just below X_opt and the rolling bed at X_opt, by hand
    om_s = math.sqrt(K / (M + 2 / 7 * m_bed))
    f_low = x_opt * (md.damping * om_s + th.X_OPT_OVER_H * m_bed * om_s**2)
    f_high = x_opt * (md.damping * om_s + th.ETA_MAX * m_bed * om_s**2)
    f_mid = 0.5 * (f_low + f_high)
    pts = operating_points(md, f_mid, x_opt=x_opt, bed_mass=m_bed)
    assert [p.state for p in pts if p.stable] == ["held at X_opt"]
    assert [p.state for p in low if p.stable] == ["scattered"]  # a small force: below X_opt, scattered
    assert f_low < 1.5 and f_high < 1.5  # the 25 kg frame at 1.5 N: above the jump, on the rolling branch
