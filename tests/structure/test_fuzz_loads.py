"""Fuzzing the loads' readers: accelerograms (CSV, PEER .AT2), force histories, structure matrices and
``[load]`` tables, damaged as files and configs get damaged.

The invariant (issue 30, as issue 24's for the other readers): a damaged file gives an
:class:`InputError` of one line naming the file (read alone) or ``[load] file`` (read by a config),
or a signal of finite, strictly increasing times and finite values; a broken ``[load]`` key gives
one naming ``[load]`` and the key, or a case whose kernel bundles build; never another exception,
never a hang; ``pdamper transient`` on such a file says ``Error: ...`` (exit 2) and writes nothing.
The readers are registered with tests/fuzz_helpers.py (damage, random bytes, file names); the
load tables are fuzz_helpers.LOAD_TABLES, whose keys tests/test_fuzz_config.py breaks too.
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

from fuzz_helpers import (DAMAGE, FUZZ, LOAD_BASE, LOAD_TABLES, Reader, at2_text, clear_message, counted, load_files,
                          reader_tests)
from pdamper.config import case_from_dict
from pdamper.engine.build import build
from pdamper.errors import InputError
from pdamper.io.records import read_signal
from pdamper.plausible import check_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
LOAD = "[load] table and its file"


def _case(table: dict, folder: Path):
    data = copy.deepcopy(LOAD_BASE)
    data["load"] = copy.deepcopy(table)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case = case_from_dict(data, base_dir=folder, source="fuzz.toml")
        check_case(case)
        build(case)
    return case


def finite_signal(sig):
    assert np.all(np.isfinite(sig.time)) and np.all(np.isfinite(sig.values)) and np.all(np.diff(sig.time) > 0)


def _good(name):
    return lambda folder: load_files(folder)[name]


FORCE_CSV = Reader(name="force history (CSV)", suffix=".csv", good=_good("force.csv"),
                   read=lambda p: read_signal(p, "force"), check=finite_signal)
QUAKE_CSV = Reader(name="accelerogram (CSV)", suffix=".csv", good=_good("quake.csv"),
                   read=lambda p: read_signal(p, "acceleration"), check=finite_signal)
QUAKE_AT2 = Reader(name="accelerogram (PEER .AT2)", suffix=".AT2", good=_good("quake.AT2"),
                   read=lambda p: read_signal(p, "acceleration"), check=finite_signal)
TestForceHistory = reader_tests(FORCE_CSV)
TestAccelerogramCsv = reader_tests(QUAKE_CSV)
TestAccelerogramAt2 = reader_tests(QUAKE_AT2)


def _npz(folder):
    import io

    buf = io.BytesIO()
    np.savez(buf, M=np.diag([2.0, 1.0]), K=np.array([[300.0, -100.0], [-100.0, 100.0]]))
    return buf.getvalue()


def _matrices(path):
    from pdamper.structure.matrices import check_matrices, read_structure_matrices

    mats = read_structure_matrices(path)
    try:
        check_matrices(mats)
    except InputError:
        pass
    return mats


def _mtx(folder):
    return b"%%MatrixMarket matrix coordinate real symmetric\n2 2 3\n1 1 300\n2 1 -100\n2 2 100\n"


def _matrix(path):
    from pdamper.structure.matrices import _load_matrix

    return _load_matrix(path, "K")


MATRICES = Reader(name="structure matrices (.npz)", suffix=".npz", good=_npz, read=_matrices, text=False)
MATRIX = Reader(name="structure matrix (Matrix Market .mtx)", suffix=".mtx", good=_mtx, read=_matrix)
TestStructureMatrices = reader_tests(MATRICES)
TestStructureMatrix = reader_tests(MATRIX)


def test_the_good_files_and_tables_read(tmp_path):
    load_files(tmp_path)
    for name, table in LOAD_TABLES.items():
        case = _case(table, tmp_path)
        load = case.drive.load  # the harmonic force is carried by the structure itself (force_amplitude)
        kind = load.config_table()["kind"] if load is not None else "harmonic" * (case.drive.force_amplitude > 0)
        assert kind == table["kind"] and case.duration > 0, name


@FUZZ
@given(damage=DAMAGE, name=st.sampled_from(["force.csv", "quake.csv", "quake.AT2"]))
def test_a_damaged_load_file_read_by_a_config_names_load_file(tmp_path_factory, damage, name):
    folder = tmp_path_factory.mktemp("load")
    good = load_files(folder)
    how, hurt = damage
    (folder / name).write_bytes(hurt(good[name]))
    role = "force" if name.startswith("force") else "acceleration"
    table = LOAD_TABLES["force_history" if role == "force" else ("at2" if name.endswith("AT2") else
                                                                  "ground_acceleration")]
    with counted(LOAD, f"[load] file = {name}, {how}"):
        try:
            _case(table, folder)
        except InputError as exc:
            msg = clear_message(str(exc), limit=2000)
            assert "[load]" in msg or "structure" in msg, (how, msg)


#: Any value TOML holds, and some a caller may pass.
VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
              st.text(max_size=10),
              st.builds(lambda x, u: f"{x:g}{u}", st.floats(allow_nan=True, allow_infinity=True),
                        st.sampled_from(["s", "ms", "Hz", "N", "g", "m/s^2", "kN", "mm", "furlong", ""])),
              st.sampled_from([10**400, "7" * 5000, "x" * 5000, "1" * 400 + "s"])),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=6), inner, max_size=3)),
    max_leaves=6)
KEYS = [(kind, key) for kind, table in LOAD_TABLES.items() for key in table]


@FUZZ
@given(target=st.sampled_from(KEYS), value=VALUES)
def test_any_value_at_any_load_key_gives_a_clear_error_or_a_case(tmp_path_factory, target, value):
    folder = tmp_path_factory.mktemp("key")
    load_files(folder)
    kind, key = target
    table = dict(LOAD_TABLES[kind], **{key: value})
    with counted(LOAD, f"[load] {key} of {kind}"):
        try:
            _case(table, folder)
        except InputError as exc:
            msg = clear_message(str(exc), limit=2000)
            assert "load" in msg and key in msg, f"[load] {key} = {value!r}: the message does not name it: {msg}"


@pytest.mark.parametrize("key, value", [("kind", "quake"), ("seed", -1), ("duration", "0s"), ("band", [5, 1]),
                                        ("frequencies", ["2Hz", "-1Hz"]), ("cycles", 0), ("level", "1N"),
                                        ("ground_damping", math.inf), ("baseline", "cubic spline")])
def test_a_broken_load_key_is_named(tmp_path, key, value):
    load_files(tmp_path)
    kind = next((k for k, t in LOAD_TABLES.items() if key in t), "random")
    with pytest.raises(InputError) as info:
        _case(dict(LOAD_TABLES[kind], **{key: value}), tmp_path)
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


def test_at2_helper_writes_what_read_at2_reads(tmp_path):
    """The fuzz suite's .AT2 writer (fuzz_helpers.at2_text) against the reader: the values back to 7 digits."""
    from pdamper.io.records import read_at2

    a = np.array([0.01, -0.02, 0.0, 1.5e-5, -0.3333333, 0.25])
    (tmp_path / "a.AT2").write_text(at2_text(a, dt=0.005, per_line=4))
    sig = read_at2(tmp_path / "a.AT2")
    assert np.allclose(sig.values, a * 9.80665, rtol=1e-6, atol=0) and np.allclose(sig.time, 0.005 * np.arange(6))
