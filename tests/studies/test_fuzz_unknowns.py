"""Fuzzing the unknowns' reader (``--uncertain U.toml``, pdamper.studies.unknowns) as the config reader
is fuzzed (tests/test_fuzz_config.py): any value at any entry of a valid file, any key, damaged bytes.

The invariant (issue 42): a broken file gives one clear line, an :class:`InputError` naming the file and
the table's number (and its key where it has one), or unknowns whose samples make cases (or refuse a
sample with a line naming it); never another exception, never a hang. No DEM is run. Size:
tests/fuzz_helpers.py (``PDAMPER_FUZZ=long`` for a long run)."""

from __future__ import annotations

import copy
import tomllib
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from fuzz_helpers import DAMAGE, FUZZ, no_hang
from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies.unknowns import DISTRIBUTIONS, Unknowns, sample, sample_case

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FILE = f"""
[[unknown]]
key = "structure.stiffness_scale"
distribution = "normal"
mean = 1.0
std = 0.05

[[unknown]]
key = "container.tilt"
distribution = "uniform"
low = "0deg"
high = "0.2deg"

[[unknown]]
key = "contact.pair[steel,pvc].friction"
distribution = "lognormal"
mean = 0.1
std = 0.03

[[unknown]]
key = "load.scale"
distribution = "truncated"
mean = 4.0
std = 1.0
low = 2.8
high = 5.2

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
    with no_hang("the unknowns' reader"):
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


@FUZZ
@given(damage=DAMAGE)
def test_a_damaged_file_gives_a_clear_line_or_samples(tmp_path_factory, damage):
    how, fn = damage
    p = tmp_path_factory.mktemp("u") / "U.toml"
    p.write_bytes(fn(FILE.encode()))
    try:
        with no_hang(f"U.toml {how}"):
            unknowns = Unknowns.read(p)
            sample(unknowns, 2, seed=0)
    except InputError as exc:
        msg = str(exc)
        assert "\n" not in msg and "Traceback" not in msg, msg
        assert str(p) in msg or "--uncertain" in msg, msg


@pytest.mark.parametrize("n", [0, -1, 2.5, True])
def test_a_number_of_samples_that_is_no_count_is_one_line(n):
    with pytest.raises(InputError, match="--samples .*whole number >= 1"):
        sample(Unknowns.from_tables(copy.deepcopy(TABLES)), n)
