"""Fuzzing the readers: records (CSV, HDF5, MAT, TDMS) and run directories, damaged as files get damaged.

The invariant (issue 24): a damaged file gives :class:`InputError` naming the file (and the line
where a text file has one), or a record of finite numbers; never another exception, never a hang.
Damage: truncated at any byte, binary bytes inserted or overwritten, ragged rows, numbers that
overflow, one huge line. Size: tests/fuzz_helpers.py (``PDAMPER_FUZZ=long`` for a long run).
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import given, strategies as st

from fuzz_helpers import DAMAGE, FUZZ, no_hang, overflow, overwrite, ragged
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


def check_read(path):
    """The invariant: a record of finite numbers (and an analysis that is finite or an InputError),
    or an InputError naming the file."""
    with warnings.catch_warnings(), no_hang(f"reading {path.name}"):
        warnings.simplefilter("ignore")
        try:
            rec = read_record(path)
        except InputError as exc:
            assert path.name in str(exc), f"the message does not name the file: {exc}"
            assert len(str(exc)) < 2000, "the message quotes too much of the file"
            return None
        n = len(rec)
        for arr in (rec.time, rec.force, rec.motion):
            assert arr.shape == (n,) and np.isfinite(arr).all()
        try:
            res = analyze_record(rec.time, rec.force, **{rec.motion_kind: rec.motion}, frequency=2.0, drop_cycles=0)
        except InputError:
            return rec
        assert math.isfinite(res.energy_per_cycle_J) and np.isfinite(res.complex_power_W)
        return rec


@FUZZ
@given(damage=DAMAGE, delimiter=st.sampled_from([",", ";"]))
def test_a_damaged_csv_record(tmp_path_factory, damage, delimiter):
    path = tmp_path_factory.mktemp("csv") / "record.csv"
    path.write_bytes(damage[1](_csv_text(delimiter).encode()))
    check_read(path)


@FUZZ
@given(damage=DAMAGE, suffix=st.sampled_from([".h5", ".mat", ".tdms"]))
def test_a_damaged_binary_record(tmp_path_factory, damage, suffix):
    tmp = tmp_path_factory.mktemp("bin")
    good = _BINARY.setdefault("files", None) or _BINARY.update(files=_binary_files(tmp)) or _BINARY["files"]
    path = tmp / f"record{suffix}"
    path.write_bytes(damage[1](good[suffix]))
    check_read(path)


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
    with warnings.catch_warnings(), no_hang(f"reading a run directory with a damaged {victim}"):
        warnings.simplefilter("ignore")
        try:
            stored = read_run(run)
        except InputError as exc:
            assert str(run) in str(exc) or victim in str(exc), f"the message names neither the run nor the file: {exc}"
            return
    assert np.isfinite(stored.signals.force).all() or victim == "signals.csv"
    if victim == "signals.csv":
        assert np.isfinite(stored.signals.time).all()
    check_read(run / "signals.csv")


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
