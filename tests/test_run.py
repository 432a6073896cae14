"""RunResult names its numbers as its summary does (docs/names.md); the old names still work and warn."""

from __future__ import annotations

import pytest

from test_rundir import synthetic_result


def test_new_names_match_the_summary_keys():
    res = synthetic_result()
    s = res.summary()
    assert res.energy_per_cycle_J == s["energy_per_cycle_J"]
    assert res.time_step_s == s["time_step_s"] == 2e-6
    assert res.wall_time_s == s["wall_time_s"]


def test_old_names_warn_and_give_the_same_values():
    res = synthetic_result()
    with pytest.warns(DeprecationWarning, match="energy_per_cycle_J"):
        assert res.energy_per_cycle == res.energy_per_cycle_J
    with pytest.warns(DeprecationWarning, match="time_step_s"):
        assert res.time_step == res.time_step_s


def test_power_result_angular_frequency():
    res = synthetic_result()
    with pytest.warns(DeprecationWarning, match="angular_frequency_rad_s"):
        assert res.analysis.angular_frequency == res.analysis.angular_frequency_rad_s
