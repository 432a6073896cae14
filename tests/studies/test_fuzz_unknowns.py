"""Fuzzing the unknowns' reader (``--uncertain U.toml``, pdamper.studies.unknowns) as the config reader
is fuzzed (tests/test_fuzz_config.py): any value at any entry of a valid file, any key, damaged bytes.

The invariant (issue 42): a broken file gives one clear line, an :class:`InputError` naming the file and
the table's number (and its key where it has one), or unknowns whose samples make cases (or refuse a
sample with a line naming it); never another exception, never a hang. No DEM is run. The file's bytes
and names are broken by the suite's reader tests (:func:`fuzz_helpers.reader_tests`), its entries and
keys here. Size: tests/fuzz_helpers.py (``PDAMPER_FUZZ=long`` for a long run)."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, strategies as st

from fuzz_helpers import FUZZ, Reader, counted, reader_tests
from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies.unknowns import DISTRIBUTIONS, Unknowns, sample, sample_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
#: The unknowns of examples/unknowns/frame_quake.toml and a choice of the frame's records and fillings.
FILE = (EXAMPLES / "unknowns" / "frame_quake.toml").read_text() + f"""
[[unknown]]
key = "particles.count"
distribution = "choice"
values = [30, 36]

[[unknown]]
key = "load.file"
distribution = "choice"
values = ["{EXAMPLES}/quake_synthetic.csv", "{EXAMPLES}/quake_synthetic.AT2"]
"""
TABLES = tomllib.loads(FILE)["unknown"]
BASE = load_case(EXAMPLES / "frame_quake.toml")
ENTRIES = [(k, e) for k, t in enumerate(TABLES) for e in t] + [(k, e) for k in range(len(TABLES))
                                                              for e in ("mean", "std", "low", "high", "values")]

#: Any value TOML can hold (as tests/test_fuzz_config.py's), and units of every kind.
VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
              st.text(max_size=12), st.sampled_from(list(DISTRIBUTIONS) + ["contact.friction", "initial.seed"]),
              st.sampled_from([5000, -400, 19]).map(lambda d: 10 ** abs(d) * (1 if d > 0 else -1)),  # numerals of any size
              st.sampled_from([1e308, -1e-320, "1e400", "9" * 5000]),
              st.builds(lambda x, u: f"{x:g}{u}", st.floats(allow_nan=True, allow_infinity=True),
                        st.sampled_from(["mm", "m", "Hz", "deg", "rad", "s", "kg", "N", "m/s^2", "%", "furlong", ""]))),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=6), inner, max_size=3)),
    max_leaves=6)


def _read_and_sample(tables, source="U.toml"):
    """Read, sample 3 and make their cases, as an ensemble does before it runs."""
    with counted("uncertainty file (U.toml): entries and keys", "the unknowns' reader"):
        unknowns = Unknowns.from_tables(tables, source=source, folder=EXAMPLES)
        for i, values in enumerate(sample(unknowns, 3, seed=1).points()):
            try:
                sample_case(BASE, values, label=f"sample {i}")
            except InputError as exc:
                assert str(exc).startswith(f"sample {i} (") and "\n" not in str(exc), str(exc)


def test_the_file_as_it_is_samples_cases():
    _read_and_sample(copy.deepcopy(TABLES))


@FUZZ
@given(target=st.sampled_from(ENTRIES), value=VALUES)
def test_any_value_at_any_entry_gives_a_clear_line_or_samples(target, value):
    k, entry = target
    tables = copy.deepcopy(TABLES)
    tables[k][entry] = value
    try:
        _read_and_sample(tables)
    except InputError as exc:
        msg = str(exc)
        assert "\n" not in msg and len(msg) < 1200 and "np.float" not in msg and "Traceback" not in msg, msg
        assert msg.startswith(("U.toml: ", "sample ")), msg
        if msg.startswith("U.toml: [[unknown]]"):
            assert f"#{k + 1}" in msg, msg
            key = tables[k].get("key")
            if entry != "key" and isinstance(key, str):
                assert repr(key.strip()) in msg, msg


@FUZZ
@given(key=st.text(alphabet="abcdefghijklmnopqrstuvwxyz_.[],0123456789 ", min_size=1, max_size=30))
def test_any_key_is_a_case_key_or_named_in_a_clear_line(key):
    tables = [{"key": key, "distribution": "uniform", "low": 0.5, "high": 0.6}]
    try:
        _read_and_sample(tables)
    except InputError as exc:
        msg = str(exc)
        assert "\n" not in msg and ("#1" in msg or msg.startswith("sample ")), msg


def _read_file(path):
    """What ``--uncertain`` does with the file: read it and draw its samples."""
    return sample(Unknowns.read(path), 3, seed=1)


def _finite(drawn):
    for key, column in drawn.columns.items():
        assert len(column) == 3 and all(isinstance(v, str) or np.isfinite(v) for v in column), key


#: The unknowns' file in the fuzz suite's reader tests (tests/fuzz_helpers.py): damaged bytes, random
#: bytes, every kind of file name.
UNKNOWNS_FILE = Reader(name="uncertainty file (U.toml)", suffix=".toml", good=lambda folder: FILE.encode(),
                       read=_read_file, check=_finite)
TestUnknownsFile = reader_tests(UNKNOWNS_FILE)


@pytest.mark.parametrize("n", [0, -1, 2.5, True])
def test_a_number_of_samples_that_is_no_count_is_one_line(n):
    with pytest.raises(InputError, match="--samples .*whole number >= 1"):
        sample(Unknowns.from_tables(copy.deepcopy(TABLES)), n)
