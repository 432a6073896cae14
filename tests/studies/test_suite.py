"""A suite of records (pdamper.studies.suite): one coupled transient a record and the statistics
engineers report over them.

**A locked bed** (tests/studies/test_transient.py) is a pure added mass: record by record the
coupled DEM must be the structure carrying the bed's mass, solved exactly, and the suite's mean
and 84th percentile are those of these exact peaks. Three synthetic ground pulses (half sines of
0.10, 0.15 and 0.22 s, unequal in size and sign) are each scaled to a PGA of 1 m/s^2, so the
scaling is checked too. The records' spectra are the spectrum module's of each scaled record.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from dem_fixtures import locked_case
from pdamper.config import load_case
from pdamper.structure.linear import damper_motion
from pdamper.structure.spectrum import spectral_acceleration
from pdamper.studies.suite import is_suite, run_suite, suite_statistics

PULSES = (0.10, 0.15, 0.22)


def _records(folder):
    names = []
    for k, width in enumerate(PULSES):
        t = np.arange(0.0, 0.4001, 0.005)
        a = (k + 1) * (-1) ** k * np.where(t < width, np.sin(np.pi * t / width), 0.0)
        name = f"pulse_{k}.csv"
        (folder / name).write_text("time [s],acceleration [m/s^2]\n" + "".join(f"{x:.4f},{y:.10g}\n" for x, y in zip(t, a)))
        names.append(name)
    return names


def _suite(folder, target='pga = 1.0'):
    names = _records(folder)
    load = f'kind = "ground_acceleration"\nfiles = {names!r}\n{target}\nduration = "0.6s"'
    (folder / "case.toml").write_text(locked_case(load, text=True))
    return load_case(folder / "case.toml")


def test_a_suite_on_a_locked_bed_is_the_carried_mass_record_by_record(tmp_path):
    case = _suite(tmp_path)
    assert is_suite(case)
    res = run_suite(case)
    s = res.summary
    assert s["records"] == 3 and s["record_names"] == [f"pulse_{k}.csv" for k in range(3)]
    peaks, bare_peaks = [], []
    for run, load in zip(res.runs, case.drive.load.records()):
        assert load.peak == pytest.approx(1.0, rel=1e-12)                 # each record at the PGA
        st = run.case.running_drive
        rec_t = run.time
        locked, _, _ = damper_motion(st.carrying(case.bed_mass), rec_t)
        bare, _, _ = damper_motion(st, rec_t)
        assert np.max(np.abs(run.damper - locked)) < 1e-4 * np.max(np.abs(locked))
        peaks.append(float(np.max(np.abs(run.damper))))
        bare_peaks.append(float(np.max(np.abs(bare))))
    assert len(set(np.round(peaks, 6))) == 3                              # three different records
    stats = s["statistics"]
    assert stats["damper_peak_m"]["mean"] == pytest.approx(np.mean(peaks), rel=1e-12)
    ln = np.log(peaks)
    assert stats["damper_peak_m"]["p84"] == pytest.approx(math.exp(ln.mean() + ln.std(ddof=1)), rel=1e-12)
    assert stats["damper_peak_bare_m"]["mean"] == pytest.approx(np.mean(bare_peaks), rel=1e-9)
    assert s["damper_peak_ratio"] == pytest.approx(np.mean(peaks) / np.mean(bare_peaks), rel=1e-9)
    # the spectra: each record as scaled, at the structure's first period
    sp = s["spectra"]
    t1 = 1.0 / float(np.min(case.running_drive.mode_frequencies))
    assert sp["first_period_s"] == pytest.approx(t1)
    for psa, load in zip(sp["psa_at_first_period_m_s2"], case.drive.load.records()):
        t = np.asarray(load.time)
        assert psa == pytest.approx(spectral_acceleration(t, load.values(t), t1), rel=1e-6)


def test_records_scaled_to_a_spectral_acceleration_have_it_at_the_first_period(tmp_path):
    case = _suite(tmp_path, target='sa = "0.05g"')
    s = case.drive
    t1 = 1.0 / float(np.min(s.mode_frequencies))
    loads = s.load.records()
    assert s.load.sa_period == t1 and len(loads) == 3
    for load in loads:
        t = np.asarray(load.time)
        assert spectral_acceleration(t, load.values(t), t1) == pytest.approx(0.05 * 9.80665, rel=1e-12)
    # the structure with the empty container carried keeps the period the records were scaled at
    assert case.running_drive.load.records()[0].scale == loads[0].scale


def test_the_statistics_over_records():
    x = np.array([[1.0, 2.0], [2.0, 2.0], [4.0, 2.0]])
    s = suite_statistics(x)
    assert s["mean"] == pytest.approx([7.0 / 3.0, 2.0]) and s["median"] == [2.0, 2.0]
    beta = np.log([1.0, 2.0, 4.0]).std(ddof=1)
    assert s["beta"] == pytest.approx([beta, 0.0]) and s["p84"] == pytest.approx([2.0 * math.exp(beta), 2.0])
    one = suite_statistics([[3.0]])
    assert one["mean"] == [3.0] and one["p84"] is None
