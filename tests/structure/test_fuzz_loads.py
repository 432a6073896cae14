"""Fuzzing the loads' readers: accelerograms (CSV, PEER .AT2), force histories and ``[load]`` tables,
damaged as files and configs get damaged.

The invariant (issue 30, as issue 24's for the other readers): a damaged file gives an
:class:`InputError` of one line naming the file (read alone) or ``[load] file`` (read by a config),
or a signal of finite, strictly increasing times and finite values; a broken ``[load]`` key gives
one naming ``[load]`` and the key, or a case whose kernel bundles build; never another exception,
never a hang; ``pdamper transient`` on such a file says ``Error: ...`` (exit 2) and writes nothing.
The damage is the records' (tests/fuzz_helpers.py); the example configs' ``[load]`` keys are broken
by tests/test_fuzz_config.py with every other key. Size: tests/fuzz_helpers.py.
"""

from __future__ import annotations

import copy
import math
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from hypothesis import given, strategies as st

from fuzz_helpers import DAMAGE, FUZZ, no_hang
from pdamper.config import case_from_dict
from pdamper.engine.build import build
from pdamper.errors import InputError
from pdamper.io.records import read_signal
from pdamper.plausible import check_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
T = np.arange(0.0, 2.0, 0.01)
A = 0.1 * np.sin(2 * np.pi * 2.0 * T) * np.sin(np.pi * T / 2.0)

#: A small structure under each kind of load (tables as a config has them); the files beside.
BASE = {"particles": {"count": 4}, "structure": {"mass": "7kg", "natural_frequency": "2Hz", "damping_ratio": 0.01}}
TABLES = {
    "force_history": {"kind": "force_history", "file": "force.csv", "duration": "3s", "scale": 1.0},
    "inline": {"kind": "force_history", "time": [0.0, 0.01, 0.02], "force": [0.0, 5.0, 0.0], "duration": "2s"},
    "ground_acceleration": {"kind": "ground_acceleration", "file": "quake.csv", "scale": 1.0},
    "at2": {"kind": "ground_acceleration", "file": "quake.AT2", "participation": [1.0]},
    "random": {"kind": "random", "excitation": "ground", "spectrum": "kanai_tajimi", "level": 0.001,
               "ground_frequency": "2.5Hz", "ground_damping": 0.6, "duration": "5s", "seed": 2},
    "stepped_sine": {"kind": "stepped_sine", "amplitude": "0.2N", "frequencies": ["1.9Hz", "2Hz"], "cycles": 5},
}


def _files(folder: Path) -> dict:
    """The good files, as bytes, written into ``folder``."""
    out = {
        "force.csv": ("time [ms],force [N]\n" + "".join(f"{1e3 * t:.3f},{5 * a:.6g}\n" for t, a in zip(T, A))).encode(),
        "quake.csv": ("time [s];acceleration [g]\n" + "".join(f"{t:.3f};{a:.6g}\n" for t, a in zip(T, A))).encode(),
        "quake.AT2": ("SYNTHETIC\nfuzz\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=  200, DT=   .0100 SEC\n"
                      + "".join(f"{a:15.7E}" + ("\n" if k % 5 == 4 else "") for k, a in enumerate(A))).encode(),
    }
    for name, data in out.items():
        (folder / name).write_bytes(data)
    return out


def _case(table: dict, folder: Path):
    data = copy.deepcopy(BASE)
    data["load"] = copy.deepcopy(table)
    with warnings.catch_warnings(), no_hang("a [load] case"):
        warnings.simplefilter("ignore")
        case = case_from_dict(data, base_dir=folder, source="fuzz.toml")
        check_case(case)
        build(case)
    return case


def check_signal(path: Path, role: str):
    with no_hang(f"reading {path.name}"):
        try:
            sig = read_signal(path, role)
        except InputError as exc:
            msg = str(exc)
            assert path.name in msg and "\n" not in msg and len(msg) < 2000, msg
            return None
    assert np.all(np.isfinite(sig.time)) and np.all(np.isfinite(sig.values)) and np.all(np.diff(sig.time) > 0)
    return sig


def test_the_good_files_and_tables_read(tmp_path):
    _files(tmp_path)
    for name, table in TABLES.items():
        case = _case(table, tmp_path)
        assert case.drive.load.in_time and case.duration > 0, name


@FUZZ
@given(damage=DAMAGE, name=st.sampled_from(["force.csv", "quake.csv", "quake.AT2"]))
def test_a_damaged_load_file_gives_a_clear_error_or_a_finite_signal(tmp_path_factory, damage, name):
    folder = tmp_path_factory.mktemp("load")
    good = _files(folder)
    how, hurt = damage
    (folder / name).write_bytes(hurt(good[name]))
    role = "force" if name.startswith("force") else "acceleration"
    check_signal(folder / name, role)
    table = TABLES["force_history" if role == "force" else ("at2" if name.endswith("AT2") else "ground_acceleration")]
    try:
        _case(table, folder)
    except InputError as exc:
        msg = str(exc)
        assert "\n" not in msg and len(msg) < 2000 and ("[load]" in msg or "structure" in msg), (how, msg)


@FUZZ
@given(data=st.binary(max_size=2048), suffix=st.sampled_from([".csv", ".AT2", ".at2", ".txt", ".h5", ".mat"]))
def test_any_bytes_under_any_name(tmp_path_factory, data, suffix):
    path = tmp_path_factory.mktemp("bytes") / f"load{suffix}"
    path.write_bytes(data)
    for role in ("force", "acceleration"):
        check_signal(path, role)


#: Any value TOML holds, and some a caller may pass.
VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
              st.text(max_size=10),
              st.builds(lambda x, u: f"{x:g}{u}", st.floats(allow_nan=True, allow_infinity=True),
                        st.sampled_from(["s", "ms", "Hz", "N", "g", "m/s^2", "kN", "mm", "furlong", ""]))),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=6), inner, max_size=3)),
    max_leaves=6)
KEYS = [(kind, key) for kind, table in TABLES.items() for key in table]


@FUZZ
@given(target=st.sampled_from(KEYS), value=VALUES)
def test_any_value_at_any_load_key_gives_a_clear_error_or_a_case(tmp_path_factory, target, value):
    folder = tmp_path_factory.mktemp("key")
    _files(folder)
    kind, key = target
    table = dict(TABLES[kind], **{key: value})
    try:
        _case(table, folder)
    except InputError as exc:
        msg = str(exc)
        assert "\n" not in msg and len(msg) < 2000, msg
        assert "load" in msg and key in msg, f"[load] {key} = {value!r}: the message does not name it: {msg}"


@pytest.mark.parametrize("key, value", [("kind", "quake"), ("seed", -1), ("duration", "0s"), ("band", [5, 1]),
                                        ("frequencies", ["2Hz", "-1Hz"]), ("cycles", 0), ("level", "1N"),
                                        ("ground_damping", math.inf)])
def test_a_broken_load_key_is_named(tmp_path, key, value):
    _files(tmp_path)
    kind = next((k for k, t in TABLES.items() if key in t), "random")
    with pytest.raises(InputError) as info:
        _case(dict(TABLES[kind], **{key: value}), tmp_path)
    assert f"[load] {key}" in str(info.value)


@pytest.mark.parametrize("damage", [b"time [s],acceleration [g]\n0,0\n0.01,nan\n", b"", b"\x00\xff" * 40,
                                    b"time [s],acceleration [parsec]\n0,0\n1,1\n", b"time [s],force [N]\n0,0\n1,1\n"])
def test_pdamper_transient_on_a_damaged_accelerogram_says_one_line_and_writes_nothing(tmp_path, damage):
    from pdamper.cli import main

    text = (EXAMPLES / "frame_quake.toml").read_text().replace('file = "quake_synthetic.csv"', 'file = "bad.csv"')
    (tmp_path / "bad.csv").write_bytes(damage)
    (tmp_path / "quake.toml").write_text(text)
    before = sorted(tmp_path.iterdir())
    r = CliRunner().invoke(main, ["transient", str(tmp_path / "quake.toml"), "--plot", str(tmp_path / "q.png"),
                                  "--json"])
    assert r.exit_code == 2 and r.output.startswith("Error: ") and r.output.count("\n") == 1, r.output
    assert "[load] file" in r.output and "bad.csv" in r.output
    assert sorted(tmp_path.iterdir()) == before
    assert tomllib.loads(text)["load"]["kind"] == "ground_acceleration"
