"""The forced response from the damper's fields, the start on an orbit, the default grid and the
steadiness of each point (pdamper.studies.structure; issue 22, items 4 and 7)."""

import math
from pathlib import Path

import numpy as np
import pytest

import fields_helpers as fh
from pdamper.analysis.fields import DamperFields
from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies.structure import (default_frequencies, grid_warnings, run_response, run_response_fields,
                                       start_phasors, steadiness)

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "structure_36.toml"
MAST = ROOT / "examples" / "mast_modal.toml"
FREQS = [1.5, 1.8, 2.0, 2.2, 2.5]


def step_fields():
    strokes = np.array([0.001, 0.003, 0.005, 0.007, 0.009, 0.015, 0.018, 0.025, 0.04, 0.06])
    w = 2 * np.pi * np.asarray(FREQS)
    c = np.where(strokes[:, None] <= 0.009, 0.3, 0.6)
    modes = np.where(strokes <= 0.009, fh.OTHER, fh.COLLIDE)
    ds = fh.results(strokes, FREQS, c / (fh.M_BED * w[None, :]), modes=modes, m_eff=0.05)
    ds.attrs["bed_mass_kg"] = load_case(EXAMPLE).bed_mass
    return DamperFields.from_results(ds)


def test_response_from_fields_reports_branches_jumps_and_the_reference_curves():
    case = load_case(EXAMPLE)
    res = run_response_fields(case, np.linspace(1.9, 2.1, 21), step_fields(), force_amplitude=0.2)
    s = res.summary
    assert s["method"] == "fields"
    several = [v for v in s["damper_amplitude_m"] if isinstance(v, list)]
    assert several and all(len(v) == 2 for v in several)
    assert len(s["jump_frequencies_hz"]) == 2 and 1.9 < s["jump_frequencies_hz"][0] < s["jump_frequencies_hz"][1] < 2.1
    np.testing.assert_allclose(s["amplitude_bare_m"], case.drive.steady_amplitude(res.frequencies, 0.2), rtol=1e-12)
    assert s["peak_damped_m"] < s["peak_bare_m"]
    assert max(s["solve_time_per_frequency_s"]) < 5.0  # a solve is milliseconds; generous for a loaded CI machine


def test_fields_of_another_bed_and_a_box_too_small_are_refused():
    case = load_case(EXAMPLE, {"particles.count": 12})
    with pytest.raises(InputError, match="fields were built for a bed of"):
        run_response_fields(case, [2.0], step_fields(), force_amplitude=0.2)
    with pytest.raises(InputError, match=r"at f = 2 Hz and F0 = 5 N the damper amplitude lies above X = 60 mm"):
        run_response_fields(load_case(EXAMPLE), [2.0], step_fields(), force_amplitude=5.0)


def test_default_grid_is_centred_on_the_mode_and_a_grid_that_misses_it_warns():
    assert default_frequencies(load_case(EXAMPLE)).tolist() == np.linspace(1.8, 2.2, 9).tolist()  # today's grid
    mast = load_case(MAST)
    assert default_frequencies(mast)[[0, -1]].tolist() == [1.81, 2.22]
    assert default_frequencies(mast, 2)[[0, -1]].tolist() == [11.4, 13.9]
    assert grid_warnings(mast, [1.9, 2.1]) == []
    (w,) = grid_warnings(mast, [2.5, 3.0])
    assert "lie above the resonance of mode 1" in w and "and 2.0146 Hz, without the bed" in w
    # a grid inside the band between the bed as a solid mass and no bed has the damped peak: no warning
    s = mast.running_drive
    m = s.mass
    f_solid = s.natural_frequency * math.sqrt(m / (m + mast.bed_mass))
    assert grid_warnings(mast, [f_solid + 0.002, s.natural_frequency - 0.001]) == []
    (below,) = grid_warnings(mast, [1.90, f_solid - 1e-4])
    assert "lie below the resonance" in below
    with pytest.raises(InputError, match="--mode 3; the structure has 2 modes"):
        default_frequencies(mast, 3)


def test_steadiness_compares_the_last_two_periods():
    t = (np.arange(4000) + 0.5) * 1e-3
    steady = np.sin(2 * np.pi * 2 * t)
    growing = (1 - np.exp(-t / 2.0)) * steady  # ~5 % from the period 3-3.5 s to 3.5-4 s
    assert steadiness(t, steady, 2.0) == {"steady": True, "last_period_change": pytest.approx(0.0, abs=1e-9),
                                          "window_change": pytest.approx(0.0, abs=1e-9)}
    g = steadiness(t, growing, 2.0)
    expected = (1 - math.exp(-3.75 / 2)) / (1 - math.exp(-3.25 / 2)) - 1  # the envelopes at the periods' middles
    assert not g["steady"] and g["last_period_change"] == pytest.approx(expected, rel=0.05)
    # a slow beat (a free motion at 2.02 Hz, 20 % of the forced one) passes the last two periods, not the window
    t = (np.arange(10000) + 0.5) * 1e-3
    beat = np.sin(2 * np.pi * 2 * t) + 0.2 * np.sin(2 * np.pi * 2.02 * t)
    b = steadiness(t, beat, 2.0, measure_cycles=8)
    assert b["last_period_change"] < 0.02 < b["window_change"] and not b["steady"]


@pytest.mark.slow
def test_start_on_the_bare_orbit_is_steady_from_the_first_period():
    case = load_case(EXAMPLE, {"particles.count": 4, "run.cycles": 4})
    (z,) = start_phasors(case, [2.0], 0.4, "bare")
    assert abs(z) == pytest.approx(case.drive.steady_amplitude([2.0], 0.4)[0], rel=1e-12)
    res = run_response(case, [2.0], force_amplitude=0.4, measure_cycles=2, start="bare", progress=False)
    assert res.summary["bare_run_steady"] == [True] and res.summary["start"] == "bare"
    assert res.bare_run[0] == pytest.approx(res.bare[0], rel=2e-3)
    rest = run_response(case, [2.0], force_amplitude=0.4, measure_cycles=2, progress=False)
    assert rest.summary["bare_run_steady"] == [False]  # from rest, 4 cycles at 0.5 % damping: a transient
    with pytest.raises(InputError, match="--start fields needs the damper's fields"):
        start_phasors(case, [2.0], 0.4, "fields")


def test_a_response_from_the_fields_reports_what_codes_ask_for_and_its_tmd():
    """Every dof's acceleration amplitude is (2 pi f)^2 times the largest stable branch's amplitude,
    the bare one the steady phasor's; the TMD numbers at the peak are the peak solution's fields."""
    from pdamper.analysis.codes import Limits

    case = load_case(EXAMPLE, {"structure.storey_height": "2.5m"})
    f = np.linspace(1.9, 2.1, 21)
    res = run_response_fields(case, f, step_fields(), force_amplitude=0.2, limits=Limits(drift=0.004))
    s, c = res.summary, res.summary["codes"]
    top = np.array([max(v) if isinstance(v, list) else v for v in s["damper_amplitude_m"]])
    w2 = (2 * np.pi * f) ** 2
    assert c["by_frequency"]["acceleration_peak_m_s2"][0] == pytest.approx(w2 * top, rel=1e-9)
    bare = np.abs(case.running_drive.dof_phasors(f, 0.2)[:, 0])
    assert c["by_frequency_bare"]["acceleration_peak_m_s2"][0] == pytest.approx(w2 * bare, rel=1e-12)
    assert c["drift_ratio_peak"] == [pytest.approx(np.max(top) / 2.5, rel=1e-9)]
    assert c["acceleration_rms_m_s2"][0] == pytest.approx(c["acceleration_peak_m_s2"][0] / math.sqrt(2), rel=1e-12)
    d = c["limits"]["drift"]
    assert d["value"] == c["drift_ratio_peak"] and d["verdict"] == ["pass" if c["drift_ratio_peak"][0] <= 0.004
                                                                   else "exceed"]
    k = int(np.argmin(np.abs(f - s["peak_damped_frequency_hz"])))
    peak = max((x for x in res.solution.solutions[k] if x.stable), key=lambda x: x.damper_amplitude_m)
    tm = s["tmd_equivalent"][0]
    assert tm["equivalent_mass_kg"] == peak.effective_mass_kg
    assert tm["equivalent_damping_N_s_per_m"] == peak.equivalent_damping_N_s_per_m
    m, kk, cc, pd = (np.asarray(a) for a in case.running_drive.modal_arrays()[:4])
    assert tm["added_damping_ratio"][0] == pytest.approx(
        pd[0]**2 * peak.equivalent_damping_N_s_per_m / (2 * np.sqrt(kk[0] * (m[0] + pd[0]**2 * peak.effective_mass_kg))))
