"""The record check of an accelerogram and its baseline correction (pdamper.structure.loads.record_check),
against closed forms: a known polynomial baseline added to a clean record is taken off again, a
zero-mean sine passes, a one-sided record (issue 39's: mean 0.14 g, never crossing zero) is warned of."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from pdamper.structure.loads.ground import GroundAcceleration
from pdamper.structure.loads.record_check import RecordWarning, baseline_correct, check_record

G = 9.80665
T = np.arange(0.0, 20.0, 0.005)
#: A clean record: a 2 Hz and a 3.3 Hz shake under a smooth envelope, ending at rest.
CLEAN = 0.1 * G * np.sin(np.pi * T / 20.0) ** 2 * (np.sin(2 * np.pi * 2.0 * T) + 0.5 * np.sin(2 * np.pi * 3.3 * T))


@pytest.mark.parametrize("order, baseline", [
    (0, 0.02 * G + 0 * T),
    (1, 0.03 * G - 0.004 * G * T),
    (2, -0.01 * G + 0.002 * G * T - 1.5e-4 * G * T**2),
    (3, 0.01 * G * (1 - 0.3 * T + 0.03 * T**2 - 8e-4 * T**3)),
])
def test_a_known_polynomial_baseline_is_taken_off_within_a_bound(order, baseline):
    """Closed form: the corrected record is the clean one, to within 1e-4 of its peak (what is left is the
    clean record's own projection on the polynomials: 7e-7 at order 3, measured); the baseline was 7 to 36 %
    of the peak."""
    dirty = CLEAN + baseline
    fixed = baseline_correct(T, dirty, order)
    peak = np.max(np.abs(CLEAN))
    assert np.max(np.abs(baseline)) > 0.07 * peak
    assert np.max(np.abs(fixed - CLEAN)) < 1e-4 * peak
    assert check_record(T, dirty).drifting and not check_record(T, fixed).drifting
    # correcting the corrected record changes it by no more than the trapezoids' error (the fit is a projection)
    assert np.max(np.abs(baseline_correct(T, fixed, order) - fixed)) < 1e-5 * peak


def test_a_lower_order_leaves_a_higher_baseline_in():
    """A quadratic baseline is not taken off by a constant one: the correction is the order asked for."""
    dirty = CLEAN + 2e-4 * G * (T - 10.0) ** 2
    assert np.max(np.abs(baseline_correct(T, dirty, 0) - CLEAN)) > 0.1 * np.max(np.abs(CLEAN))
    assert np.max(np.abs(baseline_correct(T, dirty, 2) - CLEAN)) < 1e-4 * np.max(np.abs(CLEAN))


def test_a_zero_mean_sine_passes_without_a_warning():
    a = 0.3 * G * np.sin(2 * np.pi * 2.0 * T)
    check = check_record(T, a)
    assert abs(check.mean) < 1e-12 * G and check.zero_crossings == 79 and not check.one_sided
    assert not check.drifting and check.warning() is None
    assert abs(check.velocity_trend) < 1e-3 * check.peak_velocity  # v = A/w (1 - cos wt): no trend
    with warnings.catch_warnings():
        warnings.simplefilter("error", RecordWarning)
        GroundAcceleration(time=tuple(T), acceleration=tuple(a))


def test_a_one_sided_record_is_warned_of_with_its_numbers():
    """Issue 39's record: mean 0.14 g, never crossing zero, hundreds of metres of travel when integrated."""
    a = 0.14 * G + 0.05 * G * np.sin(2 * np.pi * 1.3 * T)
    check = check_record(T, a)
    assert check.one_sided and check.drifting and check.zero_crossings == 0
    assert check.mean == pytest.approx(0.14 * G, rel=1e-3)
    # closed forms from rest: v(T) = 0.14 g T (+ the sine's small part), d(T) = 0.14 g T^2 / 2
    assert check.end_velocity == pytest.approx(0.14 * G * 20.0, rel=2e-3)
    assert check.end_displacement == pytest.approx(0.14 * G * 20.0**2 / 2, rel=5e-3)
    with pytest.warns(RecordWarning, match=r"quake\.csv is one-sided and drifting: mean 0\.14 g .* displacement 27\d "
                                           r"m at the end .*baseline = \"linear\""):
        load = GroundAcceleration(time=tuple(T), acceleration=tuple(a), file="quake.csv")
    assert load.record_check.one_sided
    with warnings.catch_warnings():  # corrected, it is a shake again: no warning
        warnings.simplefilter("error", RecordWarning)
        fixed = GroundAcceleration(time=tuple(T), acceleration=tuple(a), baseline="constant")
    assert abs(fixed.record_check.mean) < 0.01 * fixed.record_check.rms


def test_the_baseline_key_reads_and_writes_back(tmp_path):
    from pdamper.config import case_from_dict, case_to_dict

    a = CLEAN + 0.03 * G
    table = {"kind": "ground_acceleration", "time": T[::4].tolist(), "acceleration": (a[::4] / G).tolist(),
             "baseline": "constant"}
    data = {"particles": {"count": 4}, "structure": {"mass": "7kg", "natural_frequency": "2Hz",
                                                     "damping_ratio": 0.01}, "load": table}
    table["acceleration"] = a[::4].tolist()
    case = case_from_dict(data)
    load = case.drive.load
    assert load.baseline == "constant" and abs(load.record_check.mean) < 0.02 * load.record_check.rms
    again = case_from_dict(case_to_dict(case)).drive.load
    assert again.baseline == "constant" and np.allclose(again.acceleration, load.acceleration, rtol=0, atol=1e-12)
    plain = dict(data, load=dict(table, baseline="none"))
    with pytest.warns(RecordWarning, match="one-sided"):  # 0.03 g of offset left in
        written = case_to_dict(case_from_dict(plain))["load"]
    assert "baseline" not in written  # the default is not written
