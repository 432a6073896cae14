"""DamperFields on synthetic results: mean and spread over seeds, interpolation through the nodes,
monotone between monotone nodes, no smoothing across a mode change, refusal outside the box."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from pdamper.analysis.fields import DamperFields, mode_family
from pdamper.errors import InputError

from fields_helpers import COLLIDE, FREQS, M_BED, OTHER, STROKES, results


def test_mean_and_spread_over_seeds_leave_nan_seeds_out():
    eta = np.zeros((2, 1, 3))
    eta[0, 0] = [0.2, 0.4, np.nan]
    eta[1, 0] = [0.5, 0.5, 0.8]
    f = DamperFields.from_results(results([0.01, 0.02], [2.0], eta, seeds=3))
    ds = f.dataset
    np.testing.assert_allclose(ds.eta_star.values[:, 0], [0.3, 0.6])
    np.testing.assert_allclose(ds.eta_star_std.values[:, 0], [np.std([0.2, 0.4], ddof=1), np.std([0.5, 0.5, 0.8], ddof=1)])
    np.testing.assert_allclose(ds.eta_star_min.values[:, 0], [0.2, 0.5])
    np.testing.assert_allclose(ds.eta_star_max.values[:, 0], [0.4, 0.8])
    np.testing.assert_array_equal(ds.seeds.values[:, 0], [2, 3])
    # the NaN seed is left out of every field, not only eta*
    w = 2 * np.pi * 2.0
    assert ds.equivalent_damping.values[0, 0] == pytest.approx(0.3 * M_BED * w, rel=1e-12)
    assert ds.eta_star.attrs["units"] == "1" and ds.energy_per_cycle.attrs["units"] == "J"
    assert ds.amplitude.attrs["units"] == "m" and ds.frequency.attrs["units"] == "Hz"


def test_interpolation_passes_through_every_node_exactly():
    rng = np.random.default_rng(3)
    eta = rng.uniform(0.1, 0.9, (len(STROKES), len(FREQS)))
    m = rng.uniform(0.1, 1.0, (len(STROKES), len(FREQS))) * M_BED
    f = DamperFields.from_results(results(STROKES, FREQS, eta, m_eff=m))
    for i, X in enumerate(STROKES):
        for j, fr in enumerate(FREQS):
            v = f.at(X, fr)
            assert v.eta_star == pytest.approx(eta[i, j], rel=1e-12)
            assert v.effective_mass_kg == pytest.approx(m[i, j], rel=1e-12)
            assert v.equivalent_damping_N_s_per_m == pytest.approx(eta[i, j] * M_BED * 2 * np.pi * fr, rel=1e-12)
            assert v.energy_per_cycle_J == pytest.approx(np.pi * M_BED * (2 * np.pi * fr * X) ** 2 * eta[i, j], rel=1e-12)
            assert not v.extrapolated and v.branch == ""


def test_interpolation_is_monotone_between_monotone_nodes_where_a_cubic_spline_overshoots():
    # rising steeply, then flat: a cubic spline through these overshoots the plateau
    eta = np.array([0.10, 0.11, 0.80, 0.81, 0.82])[:, None] * np.array([1.0, 1.1, 1.2])[None, :]
    f = DamperFields.from_results(results(STROKES, FREQS, eta))
    xs = np.geomspace(STROKES[0], STROKES[-1], 400)
    spline = CubicSpline(np.log(STROKES), eta[:, 1])(np.log(xs))
    assert np.any(np.diff(spline) < -1e-6), "the data must be able to show an overshoot"
    for fr in (2.0, 2.4):
        ys = np.array([f.at(x, fr).eta_star for x in xs])
        assert np.all(np.diff(ys) >= -1e-12)
    # along the frequency at a node amplitude: eta* rises with f there, so does the interpolation
    fs = np.linspace(FREQS[0], FREQS[-1], 200)
    ys = np.array([f.at(STROKES[2], fr).eta_star for fr in fs])
    assert np.all(np.diff(ys) >= -1e-12)
    assert ys[0] == pytest.approx(eta[2, 0]) and ys[-1] == pytest.approx(eta[2, 2])


def test_it_refuses_to_extrapolate_and_names_the_box_and_the_point():
    f = DamperFields.from_results(results(STROKES, FREQS, 0.5))
    for X, fr in ((0.04, 2.0), (0.004, 2.0), (0.01, 1.0), (0.01, 3.5)):
        with pytest.raises(InputError) as err:
            f.at(X, fr)
        msg = str(err.value)
        assert "X 5-30 mm x f 1.5-3 Hz" in msg and f"X = {X * 1e3:.4g} mm, f = {fr:g} Hz" in msg
        assert "extrapolate=True" in msg
    # asked for: the end values continued, eta* and m_eff held, E ~ X^2 f^2, c_eq ~ f
    end = f.at(0.03, 3.0)
    v = f.at(0.06, 6.0, extrapolate=True)
    assert v.extrapolated and v.eta_star == pytest.approx(end.eta_star)
    assert v.effective_mass_kg == pytest.approx(end.effective_mass_kg)
    assert v.energy_per_cycle_J == pytest.approx(end.energy_per_cycle_J * 4 * 4, rel=1e-12)
    assert v.equivalent_damping_N_s_per_m == pytest.approx(end.equivalent_damping_N_s_per_m * 2, rel=1e-12)


def test_a_mode_change_is_a_jump_with_two_branches_never_smoothed():
    # eta* 0.2 below X_opt (scattered), 0.9 above (collide); the step lies between 10 and 20 mm
    eta = np.where(np.array(STROKES) < 0.012, 0.2, 0.9)[:, None].repeat(len(FREQS), 1)
    modes = np.where(np.array(STROKES) < 0.012, OTHER, COLLIDE)[:, None].repeat(len(FREQS), 1)
    f = DamperFields.from_results(results(STROKES, FREQS, eta, modes=modes))
    assert [(j["below_m"], j["above_m"], j["family_below"], j["family_above"]) for j in f.jumps(2.0)] == \
        [(0.010, 0.020, "other", "collide")]
    mid = math.sqrt(0.010 * 0.020)
    xs = np.geomspace(STROKES[0], STROKES[-1], 500)
    for fr in (2.0, 2.5):
        ys = np.array([f.at(x, fr).eta_star for x in xs])
        assert np.all(np.isclose(ys, 0.2) | np.isclose(ys, 0.9)), "no value between the branches"
        assert np.all(np.isclose(ys[xs < mid], 0.2)) and np.all(np.isclose(ys[xs >= mid], 0.9))
    inside = f.branches(0.012, 2.0)
    assert [b.branch for b in inside] == ["below", "above"]
    assert [b.eta_star for b in inside] == pytest.approx([0.2, 0.9])
    assert [b.family for b in inside] == ["other", "collide"]
    # each branch continued into the interval at its end node's eta*: E grows as X^2
    assert inside[0].energy_per_cycle_J == pytest.approx(f.at(0.010, 2.0).energy_per_cycle_J * 1.2**2, rel=1e-12)
    assert f.at(0.018, 2.0, branch="below").eta_star == pytest.approx(0.2)
    assert f.at(0.011, 2.0, branch="above").eta_star == pytest.approx(0.9)
    assert len(f.branches(0.025, 2.0)) == 1 and len(f.branches(0.008, 2.0)) == 1
    # without modes the same data are interpolated across the step: the modes are what keeps it
    plain = DamperFields.from_results(results(STROKES, FREQS, eta))
    assert 0.25 < plain.at(0.014, 2.0).eta_star < 0.85


def test_a_jump_that_moves_with_the_frequency_is_tracked_between_the_frequency_nodes():
    # the step lies between 10 and 20 mm at 1.5 and 2 Hz, between 20 and 30 mm at 3 Hz
    collide = np.array(STROKES)[:, None] > np.array([0.012, 0.012, 0.025])[None, :]
    eta = np.where(collide, 0.9, 0.2)
    f = DamperFields.from_results(results(STROKES, FREQS, eta, modes=np.where(collide, COLLIDE, OTHER)))
    # half-way from 2 to 3 Hz the interval's ends are half-way in log X: 14.14 and 24.49 mm
    lo, hi = math.sqrt(0.010 * 0.020), math.sqrt(0.020 * 0.030)
    xs = np.geomspace(STROKES[0], STROKES[-1], 500)
    ys = np.array([f.at(x, 2.5).eta_star for x in xs])
    assert np.all(np.isclose(ys, 0.2) | np.isclose(ys, 0.9)), "no value between the branches between the nodes"
    jump = math.sqrt(lo * hi)
    assert np.all(np.isclose(ys[xs < jump], 0.2)) and np.all(np.isclose(ys[xs >= jump], 0.9))
    assert [b.eta_star for b in f.branches(0.016, 2.5)] == pytest.approx([0.2, 0.9])
    assert [b.branch for b in f.branches(0.016, 2.5)] == ["below", "above"]
    assert len(f.branches(0.013, 2.5)) == 1 and len(f.branches(0.026, 2.5)) == 1
    # at a node the column's own interval holds: 15 mm at 3 Hz is below its jump (20-30 mm)
    assert f.at(0.015, 3.0).eta_star == pytest.approx(0.2) and f.at(0.015, 2.0).eta_star == pytest.approx(0.9)


def test_points_without_a_mode_or_with_a_tie_join_a_segment():
    modes = np.array([[OTHER, OTHER], [OTHER, COLLIDE], ["", ""], [COLLIDE, COLLIDE], ["unknown", "unknown"]],
                     dtype=object)[:, None, :]
    f = DamperFields.from_results(results(STROKES, [2.0], np.linspace(0.1, 0.9, 5), modes=modes, seeds=2))
    ds = f.dataset
    assert list(ds.mode_family.values[:, 0]) == ["other", "", "", "collide", ""]
    assert list(ds.mode_mixed.values[:, 0]) == [0, 1, 0, 0, 0]
    assert [(j["below_m"], j["above_m"]) for j in f.jumps()] == [(0.010, 0.020)]
    assert mode_family(COLLIDE) == "collide" and mode_family("lift-off") == "other" and mode_family("failed") == ""


def test_a_single_frequency_takes_the_attribute_and_asks_for_no_frequency():
    f = DamperFields.from_results(results(STROKES, [2.0], np.linspace(0.1, 0.5, 5), frequency_attr=2.0))
    assert list(f.frequencies) == [2.0]
    assert f.at(0.010).eta_star == pytest.approx(0.3) and f.at(0.010, 2.0).eta_star == pytest.approx(0.3)
    with pytest.raises(InputError, match="f = 2.1 Hz is outside the measured box"):
        f.at(0.010, 2.1)


def test_nan_only_points_are_no_nodes_and_empty_rows_and_columns_are_dropped():
    eta = np.full((len(STROKES), len(FREQS)), 0.5)
    eta[1, 0] = np.nan              # one point
    eta[4, :] = np.nan              # a whole amplitude
    eta[:, 2] = np.nan              # a whole frequency
    f = DamperFields.from_results(results(STROKES, FREQS, eta))
    assert list(f.amplitudes) == STROKES[:4] and list(f.frequencies) == FREQS[:2]
    assert f.at(STROKES[1], 2.0).eta_star == pytest.approx(0.5)
    assert f.at(STROKES[1], 1.5).eta_star == pytest.approx(0.5)  # between its neighbours, not NaN


@pytest.mark.parametrize("change, message", [
    (lambda ds: ds.isel(frequency=0, drop=True), "no frequency"),
    (lambda ds: ds.assign(eta_star=ds.eta_star * np.nan), "no finished point"),
    (lambda ds: ds.expand_dims(friction=[0.1]), "vary friction besides"),
    (lambda ds: ds.drop_vars("eta_star"), "no eta"),
])
def test_bad_results_are_clear_input_errors(change, message):
    with pytest.raises(InputError, match=message):
        DamperFields.from_results(change(results(STROKES, [2.0], 0.5)))


def test_a_bad_branch_amplitude_or_missing_frequency_is_an_input_error():
    f = DamperFields.from_results(results(STROKES, FREQS, 0.5))
    with pytest.raises(InputError, match="branch"):
        f.at(0.01, 2.0, branch="left")
    with pytest.raises(InputError, match="amplitude"):
        f.at(-0.01, 2.0)
    with pytest.raises(InputError, match="give the frequency"):
        f.at(0.01)


def test_docstring_examples_run():
    import doctest
    import importlib

    failures, tried = doctest.testmod(importlib.import_module("pdamper.analysis.fields"))
    assert tried >= 2 and failures == 0
