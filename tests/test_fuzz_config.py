"""Fuzzing the config reader: every key of every example config, broken in every way a user breaks it.

The invariant (issue 24): loading a broken config and building its engine either works (a Case whose
kernel bundles build) or raises :class:`InputError` whose message names the key that was broken
(section and key); never another exception, never a hang. No DEM is run. Size: tests/fuzz_helpers.py
(``PDAMPER_FUZZ=long`` for a long run).
"""

from __future__ import annotations

import copy
import math
import tomllib
import warnings
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from fuzz_helpers import FUZZ, no_hang
from pdamper.config import SECTIONS, case_from_dict
from pdamper.engine.build import build
from pdamper.errors import InputError
from pdamper.plausible import check_case

EXAMPLES = Path(__file__).parents[1] / "examples"
CONFIGS = {p.name: tomllib.loads(p.read_text(encoding="utf-8")) for p in sorted(EXAMPLES.glob("*.toml"))}


def _keys(data):
    """(section, key) of every key of a parsed config."""
    for section, table in data.items():
        for t in table if isinstance(table, list) else [table]:
            for key in t:
                yield section, key


KEYS = [(name, section, key) for name, data in CONFIGS.items() for section, key in _keys(data)]

#: The ways a user breaks a value, by name: wrong type, wrong unit, a bare number where a unit is meant,
#: non-finite, negative, zero, huge, tiny, empty.
MUTATIONS = {
    "a list": [1, 2], "a table": {"a": 1}, "a boolean": True, "text": "abc", "a mass": "3kg", "a frequency": "2Hz",
    "an unknown unit": "5furlong", "a speed": "12 mm/s", "bare 13": 13, "bare '13'": "13", "bare 120.0": 120.0,
    "nan": math.nan, "inf": math.inf, "-inf": -math.inf, "'nan'": "nan", "'inf'": "inf", "-1": -1, "'-5mm'": "-5mm",
    "0": 0, "0.0": 0.0, "'0mm'": "0mm", "1e300": 1e300, "2**63": 2**63, "'1e300m'": "1e300m", "1e-300": 1e-300,
    "''": "", "[]": [], "{}": {}, "' '": " ", "'auto'": "auto", "'12mm' twice": ["12mm", "12mm"],
}


def names_key(message: str, section: str, key: str) -> bool:
    """The message names the key: ``[section] key``, ``section.key``, or the section and the key in its words."""
    return section in message and key in message


def load_and_build(name: str, data: dict):
    """What `pdamper run` does before the first step: read, check plausibility, build the kernel bundles."""
    with warnings.catch_warnings(), no_hang(f"{name} with a broken key"):
        warnings.simplefilter("ignore")
        case = case_from_dict(data, source=name, base_dir=EXAMPLES)
        check_case(case, analyse=True)
        engine = build(case)
    assert engine.n == case.n_particles and math.isfinite(engine.dt) and engine.dt > 0
    return case


def _set(data: dict, section: str, key: str, value) -> dict:
    data = copy.deepcopy(data)
    table = data[section]
    (table[0] if isinstance(table, list) else table)[key] = copy.deepcopy(value)
    return data


def _check(name, data, section, key):
    try:
        load_and_build(name, data)
    except InputError as exc:
        msg = str(exc)
        assert names_key(msg, section, key), f"{section}.{key}: the message does not name the key: {msg}"
        assert msg.startswith(f"{name}: ") or "[" not in msg.split(" ")[0], msg
        assert "\n" not in msg and len(msg) < 1000, msg


def test_every_example_loads_and_builds_as_it_is():
    for name, data in CONFIGS.items():
        assert load_and_build(name, data).n_particles > 0


@pytest.mark.parametrize("name, section, key", KEYS, ids=[f"{n}:{s}.{k}" for n, s, k in KEYS])
def test_every_key_broken_every_way_gives_a_clear_error_or_a_case(name, section, key):
    """The deterministic part: all keys x all mutations (about 2 500 loads, a few seconds)."""
    refused = 0
    for how, value in MUTATIONS.items():
        data = _set(CONFIGS[name], section, key, value)
        try:
            load_and_build(name, data)
        except InputError as exc:
            refused += 1
            assert names_key(str(exc), section, key), f"{section}.{key} = {how}: the message does not name it: {exc}"
    assert refused >= 5, f"{section}.{key}: only {refused} of {len(MUTATIONS)} broken values refused"


#: Any value TOML can hold (and some it cannot: a Python object a caller may pass in a dict).
VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
              st.text(max_size=12),
              st.builds(lambda x, u: f"{x:g}{u}", st.floats(allow_nan=True, allow_infinity=True),
                        st.sampled_from(["mm", "m", "Hz", "kHz", "deg", "rad", "s", "ms", "kg", "GPa", "N", "m/s",
                                         "m/s^2", "%", "furlong", " mm", "MM", ""]))),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=6), inner, max_size=3)),
    max_leaves=6)


@FUZZ
@given(target=st.sampled_from(KEYS), value=VALUES)
def test_any_value_at_any_key_gives_a_clear_error_or_a_case(target, value):
    name, section, key = target
    _check(name, _set(CONFIGS[name], section, key, value), section, key)


@FUZZ
@given(name=st.sampled_from(sorted(CONFIGS)), section=st.sampled_from(sorted(SECTIONS)),
       key=st.text(alphabet="abcdefghijklmnopqrstuvwxyz_", min_size=1, max_size=14), value=VALUES)
def test_an_unknown_key_is_named_with_its_section(name, section, key, value):
    data = copy.deepcopy(CONFIGS[name])
    table = data.setdefault(section, {})
    table = table[0] if isinstance(table, list) else table
    if key in table or key in SECTIONS[section]:
        return  # a known key: the other tests break those
    table[key] = value
    with pytest.raises(InputError) as info:
        load_and_build(name, data)
    msg = str(info.value)
    assert (f"unknown key {key!r} in [{section}]" in msg
            or (section == "structure" and "[structure]" in msg) or (section == "drive" and "[drive]" in msg)), msg


@FUZZ
@given(name=st.sampled_from(sorted(CONFIGS)), drop=st.sets(st.sampled_from(sorted(SECTIONS)), min_size=1),
       extra=st.sampled_from(["", "contianer", "partcles", "drives", "Run"]))
def test_missing_or_misspelt_sections(name, drop, extra):
    data = copy.deepcopy(CONFIGS[name])
    for s in drop:
        data.pop(s, None)
    if extra:
        data[extra] = {"count": 3}
    try:
        load_and_build(name, data)
    except InputError as exc:
        msg = str(exc)
        if extra:
            assert f"unknown section [{extra}]" in msg, msg
        else:
            assert "particles" in drop and "missing section [particles]" in msg, msg
    else:
        assert not extra and "particles" not in drop
