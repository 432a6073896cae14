"""Fuzzing the readers: records (CSV, HDF5, MAT, TDMS), run directories and the netCDF files a sweep
writes, damaged as files get damaged.

The invariant (issue 24): a damaged file gives :class:`InputError` naming the file (and the line
where a text file has one), or a record of finite numbers; never another exception, never a hang.
Damage: truncated at any byte, binary bytes inserted or overwritten, ragged rows, numbers that
overflow, one huge line, numerals of any size; file names of any length or encoding. The readers
are registered with tests/fuzz_helpers.py (``PDAMPER_FUZZ=long`` for a long run).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, strategies as st

from fuzz_helpers import DAMAGE, FUZZ, Reader, clear_message, counted, no_hang, overflow, overwrite, ragged, reader_tests
from pdamper.analysis import analyze_record
from pdamper.errors import InputError
from pdamper.io.records import read_record

T = np.arange(2000) * 1e-3
W = 2 * np.pi * 2.0
X, F = 0.01 * np.sin(W * T), 3.0 * np.cos(W * T)


def _csv_text(delimiter=",") -> str:
    rows = [delimiter.join(f"{v:.9g}" for v in row) for row in zip(T, F, X)]
    return delimiter.join(["time [s]", "force [N]", "position [mm]" if delimiter == ";" else "position [m]"]) + "\n" \
        + "\n".join(rows) + "\n"


def _binary_files(tmp) -> dict:
    """A valid record of each binary format, as bytes."""
    import h5py
    import scipy.io
    from nptdms import ChannelObject, TdmsWriter

    with h5py.File(tmp / "r.h5", "w") as f:
        f["time"], f["force"], f["position"] = T, F, X
    scipy.io.savemat(tmp / "r.mat", {"time": T, "force": F, "position": X})
    with TdmsWriter(tmp / "r.tdms") as w:
        w.write_segment([ChannelObject("rig", "force", F, properties={"wf_increment": 1e-3}),
                         ChannelObject("rig", "position", X, properties={"wf_increment": 1e-3})])
    return {s: (tmp / f"r{s}").read_bytes() for s in (".h5", ".mat", ".tdms")}


def check_record(rec):
    """A record that was read: finite numbers, and an analysis that is finite or an InputError."""
    n = len(rec)
    for arr in (rec.time, rec.force, rec.motion):
        assert arr.shape == (n,) and np.isfinite(arr).all()
    try:
        res = analyze_record(rec.time, rec.force, **{rec.motion_kind: rec.motion}, frequency=2.0, drop_cycles=0)
    except InputError as exc:
        clear_message(str(exc), limit=2000)
        return
    assert math.isfinite(res.energy_per_cycle_J) and np.isfinite(res.complex_power_W)


def check_read(path):
    """The invariant: a record of finite numbers (and an analysis that is finite or an InputError),
    or an InputError naming the file (one line, no numpy repr, at most 60 characters of a bad cell)."""
    with warnings.catch_warnings(), counted("measured record (any file)", f"reading {path.name}"):
        warnings.simplefilter("ignore")
        try:
            rec = read_record(path)
        except InputError as exc:
            assert path.name in str(exc), f"the message does not name the file: {exc}"
            clear_message(str(exc), limit=2000)
            return None
        check_record(rec)
        return rec


def _csv_good(delimiter):
    return lambda folder: _csv_text(delimiter).encode()


def _binary_good(suffix):
    def good(folder):
        files = _BINARY.get("files") or _BINARY.setdefault("files", _binary_files(folder))
        return files[suffix]
    return good


RECORD_CSV = Reader(name="measured record (CSV)", suffix=".csv", good=_csv_good(","), read=read_record,
                    check=check_record)
RECORD_SEMICOLON = Reader(name="measured record (CSV, ';' and units row)", suffix=".txt", good=_csv_good(";"),
                          read=read_record, check=check_record)
RECORD_H5 = Reader(name="measured record (HDF5)", suffix=".h5", good=_binary_good(".h5"), read=read_record,
                   check=check_record, text=False)
RECORD_MAT = Reader(name="measured record (MATLAB .mat)", suffix=".mat", good=_binary_good(".mat"), read=read_record,
                    check=check_record, text=False)
RECORD_TDMS = Reader(name="measured record (NI TDMS)", suffix=".tdms", good=_binary_good(".tdms"), read=read_record,
                     check=check_record, text=False)
TestRecordCsv = reader_tests(RECORD_CSV)
TestRecordSemicolon = reader_tests(RECORD_SEMICOLON)
TestRecordHdf5 = reader_tests(RECORD_H5)
TestRecordMat = reader_tests(RECORD_MAT)
TestRecordTdms = reader_tests(RECORD_TDMS)
_BINARY: dict = {}


@FUZZ
@given(data=st.binary(max_size=4096), suffix=st.sampled_from([".csv", ".txt", ".h5", ".mat", ".tdms", ""]))
def test_random_bytes_under_any_name(tmp_path_factory, data, suffix):
    path = tmp_path_factory.mktemp("raw") / f"record{suffix}"
    path.write_bytes(data)
    check_read(path)


# ----------------------------------------------------------------------------- run directories

def _run_dir(path):
    from pdamper.io.runs import ENERGY_COLUMNS, SIGNAL_COLUMNS, write_run_files
    from pdamper.config import dumps_case, load_case
    from pathlib import Path

    case = load_case(Path(__file__).parents[2] / "examples" / "cuboid_36.toml")
    n = 50
    return write_run_files(path, config_text=dumps_case(case), signals=[T[:n], F[:n], X[:n], X[:n]][:len(SIGNAL_COLUMNS)],
                           energy=[T[:n]] + [np.zeros(n)] * (len(ENERGY_COLUMNS) - 1),
                           trajectory={"time": T[:3], "positions": np.zeros((3, 4, 3))}, meta={"summary": {}})


@FUZZ
@given(damage=DAMAGE, victim=st.sampled_from(["signals.csv", "energy.csv", "result.json", "config.toml",
                                              "trajectory.npz"]))
def test_a_damaged_run_directory(tmp_path_factory, damage, victim):
    from pdamper.rundir import read_run

    run = _run_dir(tmp_path_factory.mktemp("run") / "run")
    target = run / victim
    target.write_bytes(damage[1](target.read_bytes()))
    with warnings.catch_warnings(), counted("run directory", f"reading a run directory with a damaged {victim}"):
        warnings.simplefilter("ignore")
        try:
            stored = read_run(run)
        except InputError as exc:
            assert str(run) in str(exc) or victim in str(exc), f"the message names neither the run nor the file: {exc}"
            clear_message(str(exc), limit=2000)
            return
    assert np.isfinite(stored.signals.force).all() or victim == "signals.csv"
    if victim == "signals.csv":
        assert np.isfinite(stored.signals.time).all()
    check_read(run / "signals.csv")


# ----------------------------------------------------------------------------- the netCDF files a sweep writes

def _results_nc(folder):
    """A sweep's results.nc as pdamper writes it (two strokes, one seed), as bytes (made once)."""
    if "results" in _BINARY:
        return _BINARY["results"]
    import xarray as xr

    from pdamper.io.files import netcdf_bytes

    ds = xr.Dataset({"eta_star": (("stroke", "seed"), np.array([[0.4], [0.6]]))},
                    coords={"stroke": ("stroke", [0.01, 0.02], {"units": "m"}), "seed": [0]},
                    attrs={"varied_keys": "drive.stroke"})
    return _BINARY.setdefault("results", netcdf_bytes(ds))


def _open_results(path):
    from pdamper.studies.sweep import open_results

    ds = open_results(path)
    assert ds is not None
    return ds


def _fields_nc(folder):
    """A damper-fields file as ``pdamper fields --out`` writes it (2 x 2 points), as bytes (made once)."""
    if "fields" in _BINARY:
        return _BINARY["fields"]
    import xarray as xr

    from pdamper.analysis.fields import FORMAT
    from pdamper.io.files import netcdf_bytes

    dims = ("amplitude", "frequency")
    return _BINARY.setdefault("fields", netcdf_bytes(xr.Dataset(
        {"eta_star": (dims, np.array([[0.4, 0.5], [0.6, 0.7]])), "mode_family": (dims, np.array([["rolling", "cascade"]] * 2))},
        coords={"amplitude": [0.01, 0.02], "frequency": [2.0, 3.0]}, attrs={"format": FORMAT})))


def _load_fields(path):
    from pdamper.studies.fields import load_fields

    return load_fields(path)


RESULTS = Reader(name="sweep results (netCDF)", suffix=".nc", good=_results_nc, read=_open_results, text=False)
FIELDS = Reader(name="damper fields (netCDF)", suffix=".nc", good=_fields_nc, read=_load_fields, text=False)
TestSweepResults = reader_tests(RESULTS)
TestDamperFields = reader_tests(FIELDS)


# ----------------------------------------------------------------------------- named cases

@pytest.mark.parametrize("damage, words", [
    (lambda d: ragged(d, 0.5, 2), r"line \d+: 2 fields but the header has 3"),
    (lambda d: overflow(d, 0.5, b"1e400"), r"line \d+, column 'position \[m\]': '1e400' is not a finite number"),
    (lambda d: overflow(d, 0.5, b"\x00\xff7" * 50_000), r"line \d+, column 'position \[m\]': cannot read .*"
                                                           r"\(150000 characters\)"),
    (lambda d: overwrite(d, 0.5, b"\x00\xff\x00\xff"), r"line \d+"),
])
def test_text_damage_is_named_with_its_line(tmp_path, damage, words):
    path = tmp_path / "record.csv"
    path.write_bytes(damage(_csv_text().encode()))
    with pytest.raises(InputError, match=words) as info:
        read_record(path)
    assert "record.csv" in str(info.value)
