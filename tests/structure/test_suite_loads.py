"""A suite of records in ``[load]`` (``files = [...]`` or a folder) and the records' targets (``pga``,
``sa`` at the structure's first period): read, written back, refused in one line naming the key.

The fuzz suite breaks the suite's keys with every other load's: its tables are in
tests/fuzz_helpers.py (``LOAD_TABLES``: ``suite_pga``, ``suite_sa``, ``suite_force``).
"""

from __future__ import annotations

import copy
import warnings

import numpy as np
import pytest

from fuzz_helpers import no_hang
from pdamper.config import case_from_dict, dumps_case, loads_case
from pdamper.engine.build import build
from pdamper.errors import InputError
from pdamper.plausible import check_case
from pdamper.structure.loads import GroundAcceleration
from pdamper.structure.loads.base import Record

T = np.arange(0.0, 2.0, 0.01)
BASE = {"particles": {"count": 4}, "structure": {"mass": "7kg", "natural_frequency": "2Hz", "damping_ratio": 0.01}}
SUITE = {"kind": "ground_acceleration", "files": ["q1.csv", "q2.AT2"], "pga": "0.1g", "duration": "3s"}
SA = {"kind": "ground_acceleration", "files": "records", "sa": "0.2g", "sa_damping": 0.05}


def _write(folder):
    a1 = 0.1 * np.sin(2 * np.pi * 2.0 * T) * np.sin(np.pi * T / 2.0)
    a2 = 0.05 * np.sin(2 * np.pi * 3.0 * T) * np.sin(np.pi * T / 2.0)
    (folder / "q1.csv").write_text("time [s];acceleration [g]\n" + "".join(f"{t:.3f};{a:.6g}\n" for t, a in zip(T, a1)))
    (folder / "q2.AT2").write_text("SYNTHETIC\nsuite\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=  200, DT=   .0100 SEC\n"
                                   + "".join(f"{a:15.7E}" + ("\n" if k % 5 == 4 else "") for k, a in enumerate(a2)))
    (folder / "records").mkdir(exist_ok=True)
    for name in ("q1.csv", "q2.AT2"):
        (folder / "records" / name).write_bytes((folder / name).read_bytes())
    (folder / "records" / "notes.md").write_text("not a record")
    return a1, a2


def _case(table, folder):
    data = copy.deepcopy(BASE)
    data["load"] = copy.deepcopy(table)
    with warnings.catch_warnings(), no_hang("a suite case"):
        warnings.simplefilter("ignore")
        case = case_from_dict(data, base_dir=folder, source="suite.toml")
        check_case(case)
        build(case)
    return case


def test_a_suite_reads_its_records_scales_each_to_its_pga_and_writes_back(tmp_path):
    a1, a2 = _write(tmp_path)
    case = _case(SUITE, tmp_path)
    load = case.drive.load
    loads = load.records()
    assert [r.file.rsplit("/", 1)[-1] for r in loads] == ["q1.csv", "q2.AT2"]
    for rec, raw in zip(loads, (a1, a2)):
        assert rec.peak == pytest.approx(0.1 * 9.80665, rel=1e-12)
        assert rec.scale == pytest.approx(0.1 / np.max(np.abs(raw)), rel=1e-6)
        assert rec.duration == 3.0 and not rec.files
    # the suite itself runs as its first record outside pdamper transient, and says so
    assert load.kernel_table()[1].shape == loads[0].kernel_table()[1].shape
    assert "a suite of 2 records" in load.describe() and "each scaled to PGA 0.1 g" in load.describe()
    text = dumps_case(case)
    assert "files = [" in text and "pga = " in text and "\nscale" not in text.split("[load]")[1]
    assert loads_case(text, base_dir=tmp_path) == case


def test_a_folder_of_records_and_a_spectral_target_at_the_first_period(tmp_path):
    _write(tmp_path)
    case = _case(SA, tmp_path)
    load = case.drive.load
    assert len(load.records()) == 2 and load.sa_period == pytest.approx(0.5)   # the 2 Hz structure
    assert "Sa(0.5 s, 5 %) = 0.2 g" in load.records()[0].describe()
    assert loads_case(dumps_case(case), base_dir=tmp_path) == case


def test_a_python_caller_builds_a_suite_of_records():
    recs = tuple(Record(name=f"r{k}", time=tuple(T), values=tuple(np.sin(2 * np.pi * (1 + k) * T))) for k in range(3))
    load = GroundAcceleration(files=recs, pga=2.0)
    assert [r.peak for r in load.records()] == pytest.approx([2.0, 2.0, 2.0])
    with pytest.raises(InputError, match="sa_period"):
        GroundAcceleration(files=recs, sa=2.0).kernel_table()   # no structure told it the period
    assert GroundAcceleration(files=recs, sa=2.0, sa_period=1.0).records()[1].scale > 0


@pytest.mark.parametrize("change, words", [
    ({"files": "nowhere"}, r"\[load\] files = 'nowhere': not a folder"),
    ({"files": []}, r"\[load\] files = \[\]: give a list of record files"),
    ({"files": ["q1.csv", "missing.csv"]}, r"\[load\] files: .*file not found: .*missing.csv"),
    ({"file": "q1.csv"}, r"\[load\] give either files = \[...\] .* or file, not both"),
    ({"scale": 2.0}, r"\[load\] scale and pga both set the records' scale"),
    ({"sa": "0.1g"}, r"\[load\] pga and sa are both given"),
    ({"pga": "-1g"}, r"\[load\] pga = -9.80665 m/s\^2; must be > 0"),
    ({"pga": "0.1kg"}, r"\[load\] pga"),
    ({"sa_period": "1s"}, r"\[load\] sa_period and sa_damping belong to a target spectral acceleration"),
])
def test_a_broken_suite_key_is_named(tmp_path, change, words):
    _write(tmp_path)
    with pytest.raises(InputError, match=words):
        _case(dict(SUITE, **change), tmp_path)


def test_an_empty_folder_and_a_period_out_of_range_are_named(tmp_path):
    _write(tmp_path)
    (tmp_path / "empty").mkdir()
    with pytest.raises(InputError, match=r"files = 'empty': the folder holds no record file"):
        _case(dict(SA, files="empty"), tmp_path)
    with pytest.raises(InputError, match=r"\[load\] sa_period = 1000 s; give a period from 0.01 to 100 s"):
        _case(dict(SA, sa_period="1000s"), tmp_path)
