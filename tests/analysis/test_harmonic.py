"""Harmonic balance of a modal structure with the damper's fields (pdamper.analysis.harmonic)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fields_helpers as fh
from pdamper.analysis.fields import DamperFields
from pdamper.analysis.harmonic import decay_envelope, receptances, solve_frequency, solve_response
from pdamper.errors import InputError
from pdamper.structure import CoupledStructure, ModalStructure

SDOF = CoupledStructure(mass=7.0, stiffness=1105.0, damping_ratio=0.005, displacement=0.01)
MAST = ModalStructure(modes=({"frequency": 2.0146, "damping_ratio": 0.005, "modal_mass": 7.984, "damper": 1.0,
                              "force": 1.0, "response": 0.3395},
                             {"frequency": 12.625, "damping_ratio": 0.005, "modal_mass": 7.984, "damper": 1.0,
                              "force": 1.0, "response": -0.7137}), displacement=0.01)
STROKES = np.geomspace(1e-4, 0.1, 12)
FREQS = [1.5, 1.8, 2.0, 2.2, 2.5]


def constant_fields(m_a, c_a, strokes=STROKES, freqs=FREQS):
    """Fields of a rigid mass m_a [kg] and a dashpot c_a [N s/m] (c_eq = eta* m_bed Omega)."""
    return fh.constant_fields(m_a, c_a, strokes, freqs)


def modal_closed_form(s, f, F0, m_a, c_a):
    """|x_d|, |x_r| from the coupled modal equations (diag(k - W^2 m + i W c) + Z phi_d phi_d^T) q = phi_f F0."""
    m, k, c, pd, pf, pr = s.modal_arrays()
    w = 2 * math.pi * f
    A = np.diag(k - w * w * m + 1j * w * c) + complex(-w * w * m_a, w * c_a) * np.outer(pd, pd)
    q = np.linalg.solve(A, pf * F0)
    return abs(pd @ q), abs(pr @ q)


@pytest.mark.parametrize("structure", [SDOF, MAST], ids=["one mode", "two modes"])
def test_constant_mass_and_dashpot_give_the_closed_form(structure):
    m_a, c_a, F0 = 0.1, 0.8, 0.4
    F = constant_fields(m_a, c_a)
    fr = np.linspace(1.8, 2.2, 9)
    res = solve_response(structure.modal_arrays(), F, fr, F0)
    for f, sols in zip(fr, res.solutions):
        assert len(sols) == 1 and sols[0].stable
        xd, xr = modal_closed_form(structure, f, F0, m_a, c_a)
        assert sols[0].damper_amplitude_m == pytest.approx(xd, rel=1e-9)
        assert sols[0].response_amplitude_m == pytest.approx(xr, rel=1e-9)
    assert res.jumps == []


def test_rigid_mass_is_the_structures_own_solid_mass_curve():
    F = constant_fields(0.149, 0.0)
    fr = np.array([1.9, 2.0, 2.1])
    res = solve_response(SDOF.modal_arrays(), F, fr, 0.4)
    got = [s[0].damper_amplitude_m for s in res.solutions]
    np.testing.assert_allclose(got, SDOF.steady_amplitude(fr, 0.4, added_mass=0.149), rtol=1e-9)


def step_fields(c_low=0.3, c_high=0.6, lo=0.009, hi=0.015):
    """A bed with little damping (family 'other') up to ``lo`` and much ('collide') from ``hi`` [m]."""
    strokes = np.array([0.001, 0.003, 0.005, 0.007, lo, hi, 0.018, 0.025, 0.04, 0.06])
    w = 2 * np.pi * np.asarray(FREQS)
    c = np.where(strokes[:, None] <= lo, c_low, c_high)
    modes = np.where(strokes <= lo, fh.OTHER, fh.COLLIDE)
    return DamperFields.from_results(fh.results(strokes, FREQS, c / (fh.M_BED * w[None, :]), modes=modes,
                                                m_eff=0.05))


def test_a_step_in_the_fields_gives_two_stable_branches_and_the_jumps():
    F = step_fields()
    F0 = 0.2  # at resonance: ~10.7 mm on the collide branch, ~13.5 mm on the other (both in the jump interval)
    fr = np.linspace(1.9, 2.1, 21)
    res = solve_response(SDOF.modal_arrays(), F, fr, F0)
    n = [len(s) for s in res.solutions]
    assert max(n) == 2 and min(n) == 1
    two = [sols for sols in res.solutions if len(sols) == 2]
    for lower, upper in two:
        assert lower.stable and upper.stable  # each segment flat: dG/dX = 0 < 1
        assert {lower.branch, upper.branch} <= {"below", "above", ""}
        assert lower.equivalent_damping_N_s_per_m > upper.equivalent_damping_N_s_per_m  # lower amplitude: collide
    # every solution solves X = |x_d(X)| on its own branch, and each jump separates 1 from 2 solutions
    for f, sols in zip(fr, res.solutions):
        for s in sols:
            w = 2 * math.pi * f
            Hdd, Hdf, _, _ = receptances(SDOF.modal_arrays(), f)
            Z = complex(-w * w * s.effective_mass_kg, w * s.equivalent_damping_N_s_per_m)
            assert abs(Hdf * F0 / (1 + Hdd * Z)) == pytest.approx(s.damper_amplitude_m, rel=1e-9)
    assert len(res.jumps) == 2
    for j in res.jumps:
        f = j["frequency_hz"]
        below = solve_frequency(SDOF.modal_arrays(), F, f * (1 - 1e-3), F0)
        above = solve_frequency(SDOF.modal_arrays(), F, f * (1 + 1e-3), F0)
        assert {sum(s.stable for s in below), sum(s.stable for s in above)} == {1, 2}


def test_a_growing_branch_is_unstable_by_the_slope_criterion():
    # damping that falls steeply with amplitude: G grows faster than X somewhere -> three fixed points,
    # the middle one unstable (dG/dX > 1)
    strokes = np.geomspace(1e-3, 0.1, 40)
    w = 2 * np.pi * np.asarray(FREQS)
    c = 0.02 + 4.0 / (1.0 + (strokes / 0.01) ** 4)
    F = DamperFields.from_results(fh.results(strokes, FREQS, c[:, None] / (fh.M_BED * w[None, :]), m_eff=0.0))
    sols = solve_frequency(SDOF.modal_arrays(), F, SDOF.natural_frequency, 0.3)  # ~5, ~12, ~27 mm
    assert [s.stable for s in sols] == [True, False, True]


def test_refuses_outside_the_box_unless_extrapolating():
    F = constant_fields(0.1, 0.8, strokes=np.geomspace(1e-3, 5e-3, 5))
    with pytest.raises(InputError, match=r"above X = 5 mm.*f = 2 Hz|f = 2 Hz.*above X = 5 mm"):
        solve_frequency(SDOF.modal_arrays(), F, 2.0, 0.4)
    with pytest.raises(InputError, match=r"below X = 1 mm"):
        solve_frequency(SDOF.modal_arrays(), F, 2.0, 1e-4)
    with pytest.raises(InputError, match=r"f = 3 Hz is outside the frequencies"):
        solve_frequency(SDOF.modal_arrays(), F, 3.0, 0.4)
    sols = solve_frequency(SDOF.modal_arrays(), F, 2.0, 0.4, extrapolate=True)
    xd, _ = modal_closed_form(SDOF, 2.0, 0.4, 0.1, 0.8)
    assert len(sols) == 1 and sols[0].extrapolated
    assert sols[0].damper_amplitude_m == pytest.approx(xd, rel=1e-9)


def test_decay_envelope_of_a_dashpot_is_the_exponential():
    m_a, c_a = 0.1, 0.8
    F = constant_fields(m_a, c_a)
    t, A, f = decay_envelope(F, mass=SDOF.mass, stiffness=SDOF.stiffness, damping=SDOF.damping, amplitude=0.02,
                             duration=10.0)
    rate = (SDOF.damping + c_a) / (2 * (SDOF.mass + m_a))
    np.testing.assert_allclose(A, 0.02 * np.exp(-rate * t), rtol=1e-5)
    np.testing.assert_allclose(f, math.sqrt(SDOF.stiffness / (SDOF.mass + m_a)) / (2 * math.pi), rtol=1e-12)


def test_where_neither_mode_holds_the_solution_sits_at_the_jump():
    # low segment: G ~ 21 mm > the top of the interval (15 mm); collide segment: G ~ 6 mm < its bottom (9 mm):
    # the bed switches between its modes, the amplitude held at the interval's geometric midpoint
    F = step_fields(c_low=0.05, c_high=3.0)
    (s,) = solve_frequency(SDOF.modal_arrays(), F, 2.0, 0.3)
    assert s.branch == "jump" and s.stable and s.family == "other/collide"
    assert s.damper_amplitude_m == pytest.approx(math.sqrt(0.009 * 0.015), rel=1e-6)
    assert 0.05 < s.equivalent_damping_N_s_per_m < 3.0
    w = 4 * math.pi
    Hdd, Hdf, _, _ = receptances(SDOF.modal_arrays(), 2.0)
    Z = complex(-w * w * s.effective_mass_kg, w * s.equivalent_damping_N_s_per_m)
    assert abs(Hdf * 0.3 / (1 + Hdd * Z)) == pytest.approx(s.damper_amplitude_m, rel=1e-9)
