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


def test_structure_record_and_run_record_old_names_warn_and_give_the_same_values():
    import numpy as np

    from pdamper.recorders.structure import StructureRecord
    from pdamper.simulation import RunRecord

    z = np.zeros(2)
    rec = StructureRecord(time=z, displacement=z, velocity=z, external_work=z, damping_loss=z, mass_kg=2.0,
                          stiffness_N_m=800.0, x0_m=0.01, v0_m_s=-0.3)
    assert rec.initial_energy == pytest.approx(0.5 * 2.0 * 0.09 + 0.5 * 800.0 * 1e-4)
    for old, new in [("mass", "mass_kg"), ("stiffness", "stiffness_N_m"), ("x0", "x0_m"), ("v0", "v0_m_s")]:
        with pytest.warns(DeprecationWarning, match=f"StructureRecord.{new}"):
            assert getattr(rec, old) == getattr(rec, new)
    run = RunRecord(case=synthetic_result().case, time_step_s=3e-6)
    with pytest.warns(DeprecationWarning, match="RunRecord.time_step_s"):
        assert run.time_step == 3e-6


def test_the_analyse_spellings_warn_and_call_the_analyze_ones():
    from pdamper.plausible import check_case
    from pdamper.run import analyse_signals, analyze_signals

    res = synthetic_result()
    with pytest.warns(DeprecationWarning, match="analyze_signals"):
        assert analyse_signals(res.case, res.signals).eta_star == analyze_signals(res.case, res.signals).eta_star
    with pytest.warns(DeprecationWarning, match=r"check_case\(analyze=...\)"):
        check_case(res.case, analyse=True)
