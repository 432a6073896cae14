"""eta*'s standard error over the cycles and the steady-state flag (pdamper.analysis.steady)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.analysis.steady import MIN_CYCLES, cycle_statistics


def _used(n, drop=2):
    return [False] * drop + [True] * n


def test_independent_cycles_give_the_standard_error_of_the_mean():
    rng = np.random.default_rng(1)
    e = 1.0 + 0.1 * rng.standard_normal(20000)
    st = cycle_statistics(np.r_[9.0, 9.0, e], _used(20000), 0.8)
    naive = 0.8 * np.std(e, ddof=1) / math.sqrt(20000) / np.mean(e)
    # no correlation: the long-run variance is the variance
    assert st.eta_star_error == pytest.approx(naive, rel=0.1)
    assert st.steady and st.cycles == 20000


def test_correlated_cycles_widen_the_error_to_the_long_run_variance():
    rng = np.random.default_rng(2)
    n, phi = 4000, 0.6
    x = np.zeros(n)
    for k in range(1, n):
        x[k] = phi * x[k - 1] + rng.standard_normal()
    e = 10.0 + x
    st = cycle_statistics(e, [True] * n, 1.0)
    naive = np.std(e, ddof=1) / math.sqrt(n) / np.mean(e)
    assert st.correlation == pytest.approx(phi, abs=0.05)
    # an AR(1) record's mean has sqrt((1 + phi)/(1 - phi)) = 2 times the iid error
    assert st.relative_error / naive == pytest.approx(math.sqrt((1 + phi) / (1 - phi)), rel=0.1)


def test_energy_stored_at_one_cycle_end_and_given_back_in_the_next_does_not_count_as_error():
    rng = np.random.default_rng(3)
    n = 2000
    stored = rng.standard_normal(n + 1)  # energy in the bed at each cycle boundary
    e = 5.0 + 0.05 * rng.standard_normal(n) + np.diff(stored)  # dissipated + change of the stored energy
    st = cycle_statistics(e, [True] * n, 1.0)
    naive = np.std(e, ddof=1) / math.sqrt(n) / np.mean(e)
    assert st.correlation == pytest.approx(-0.5, abs=0.05)
    assert st.relative_error < 0.5 * naive


def test_a_drifting_record_is_not_steady_and_a_flat_one_is():
    n = 12
    assert not cycle_statistics(np.linspace(1.0, 2.0, n) + 0.01 * np.sin(np.arange(n)), [True] * n, 0.5).steady
    assert cycle_statistics(1.5 + 0.05 * np.sin(2.1 * np.arange(n)), [True] * n, 0.5).steady


def test_too_few_cycles_are_never_steady_and_one_cycle_has_no_error():
    assert not cycle_statistics([1.0] * (MIN_CYCLES - 1), [True] * (MIN_CYCLES - 1), 0.5).steady
    one = cycle_statistics([3.0, 1.0], [False, True], 0.5)
    assert math.isnan(one.eta_star_error) and not one.steady and one.cycles == 1


def test_the_error_scales_with_eta_star_and_not_with_the_energy_unit():
    e = [1.0, 1.2, 0.9, 1.1, 1.0, 0.8]
    a = cycle_statistics(e, [True] * 6, 0.4)
    b = cycle_statistics(np.asarray(e) * 1e-3, [True] * 6, 0.8)
    assert b.eta_star_error == pytest.approx(2 * a.eta_star_error)
