"""Fuzzing the config readers: every key of every section, broken in every way a user breaks it;
the config file's text, ``--set``, and the other TOML and CSV inputs a case is made from.

The invariant (issues 24, 42): loading a broken config and building its engine either works (a Case
whose kernel bundles build) or raises :class:`InputError` whose message names the key that was broken
(section and key), on one line, with no numpy repr; never another exception, never a hang. No DEM is
run. Size and the reader registry: tests/fuzz_helpers.py (``PDAMPER_FUZZ=long`` for a long run).
"""

from __future__ import annotations

import copy
import math
import re
import tomllib
import warnings
from pathlib import Path

import pytest
from hypothesis import given, strategies as st

from fuzz_helpers import FUZZ, LOAD_TABLES, Reader, clear_message, counted, load_files, reader_tests
from pdamper.config import SECTIONS, case_from_dict, load_case
from pdamper.design import load_structure
from pdamper.engine.build import build
from pdamper.errors import InputError
from pdamper.plausible import check_case
from pdamper.studies.campaign import read_manifest
from pdamper.studies.named import load_study

EXAMPLES = Path(__file__).parents[1] / "examples"


def _readable(data: dict) -> bool:
    """An example this machine can read: one on an OpenSees model needs openseespy."""
    if "opensees" not in data.get("structure", {}):
        return True
    from pdamper.structure.opensees import available

    return available() is None


CONFIGS = {p.name: d for p in sorted(EXAMPLES.glob("*.toml"))
           for d in (tomllib.loads(p.read_text(encoding="utf-8")),) if _readable(d)}
CONFIG = "case config (keys and values)"


def _keys(data):
    """(section, key) of every key of a parsed config."""
    for section, table in data.items():
        for t in table if isinstance(table, list) else [table]:
            for key in t:
                yield section, key


def _family(data: dict) -> tuple:
    """What reads an example's keys: the rig or the structure model, the load kind, a suite, damper tables."""
    s = data.get("structure")
    if s is None:
        return ("rig",)
    model = next((m for m in ("opensees", "matrices", "modes") if m in s), "one mode")
    load = data.get("load") if isinstance(data.get("load"), dict) else {}
    return model, load.get("kind"), "files" in load, "damper" in data


def _every_key_once_a_family():
    """(example, section, key): every key of every example, broken in the first example of each family
    (:func:`_family`) that has it; the same key in another example of the family is read by the same
    code in the same context."""
    seen, out = set(), []
    for name, data in CONFIGS.items():
        for section, key in _keys(data):
            if (_family(data), section, key) not in seen:
                seen.add((_family(data), section, key))
                out.append((name, section, key))
    return out


KEYS = _every_key_once_a_family()

#: The ways a user breaks a value, by name: wrong type, wrong unit, a bare number where a unit is meant,
#: non-finite, negative, zero, huge, tiny, empty, numerals of any size.
MUTATIONS = {
    "a list": [1, 2], "a table": {"a": 1}, "a boolean": True, "text": "abc", "a mass": "3kg", "a frequency": "2Hz",
    "an unknown unit": "5furlong", "a speed": "12 mm/s", "bare 13": 13, "bare '13'": "13", "bare 120.0": 120.0,
    "nan": math.nan, "inf": math.inf, "-inf": -math.inf, "'nan'": "nan", "'inf'": "inf", "-1": -1, "'-5mm'": "-5mm",
    "0": 0, "0.0": 0.0, "'0mm'": "0mm", "1e300": 1e300, "2**63": 2**63, "'1e300m'": "1e300m", "1e-300": 1e-300,
    "''": "", "[]": [], "{}": {}, "' '": " ", "'auto'": "auto", "'12mm' twice": ["12mm", "12mm"],
    "10**400": 10**400, "'5,000 digits'": "7" * 5000, "'400 digits mm'": "1" * 400 + "mm",
    "'5,000 characters'": "a" * 5000,
}


def names_key(message: str, section: str, key: str) -> bool:
    """The message names the key: ``[section] key``, ``section.key``, or the section and the key in its words."""
    return section in message and key in message


def load_and_build(name: str, data: dict, base_dir=EXAMPLES):
    """What `pdamper run` does before the first step: read, check plausibility, build the kernel bundles."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        case = case_from_dict(data, source=name, base_dir=base_dir)
        check_case(case, analyse=True)
        engine = build(case)
    assert engine.n == case.n_particles and math.isfinite(engine.dt) and engine.dt > 0
    return case


def _set(data: dict, section: str, key: str, value) -> dict:
    data = copy.deepcopy(data)
    table = data.setdefault(section, {})
    (table[0] if isinstance(table, list) else table)[key] = copy.deepcopy(value)
    return data


def _check(name, data, section, key, base_dir=EXAMPLES, *, names_the_file=False, also=None):
    """The invariant for one broken key: a case, or an InputError naming it (True when refused); a
    reader's error names the file too (``names_the_file``: the plausibility checks after it name the key);
    ``also``: another (section, key) the message may name instead (the key it stands for)."""
    with counted(CONFIG, f"{name} with {section}.{key} broken"):
        try:
            load_and_build(name, data, base_dir)
        except InputError as exc:
            msg = clear_message(str(exc))
            assert names_key(msg, section, key) or (also and names_key(msg, *also)), \
                f"{section}.{key}: the message does not name the key: {msg}"
            if names_the_file:
                assert msg.startswith(f"{name}: ") or "[" not in msg.split(" ")[0], msg
            return True
    return False


def test_every_example_loads_and_builds_as_it_is():
    for name, data in CONFIGS.items():
        assert load_and_build(name, data).n_particles > 0


@pytest.mark.slow
@pytest.mark.parametrize("name, section, key", KEYS, ids=[f"{n}:{s}.{k}" for n, s, k in KEYS])
def test_every_key_broken_every_way_gives_a_clear_error_or_a_case(name, section, key):
    """The deterministic part: all keys of the examples x all mutations (about 3 500 loads, seconds)."""
    refused = sum(_check(name, _set(CONFIGS[name], section, key, value), section, key) for value in MUTATIONS.values())
    assert refused >= 5, f"{section}.{key}: only {refused} of {len(MUTATIONS)} broken values refused"


# ----------------------------------------------------------------------------- every key of the schema

#: The example a section's keys are broken in where no example has the key (a [load] key: the kinds'
#: own tables, LOAD_TABLES, beside the structure of fuzz_helpers.LOAD_BASE; a [drive] key: a drive of
#: the kind that has it).
_SECTION_BASE = {"structure": "frame_3hz.toml", "load": None}
_DRIVES = {"sampled": {"time": [0.0, 0.125, 0.25, 0.375, 0.5], "position": [0.0, 0.012, 0.0, -0.012, 0.0]},
           "still": {"kind": "still", "duration": "1s"}}


def _base(section: str, key: str) -> dict:
    """The config a key no example has is broken in: its section's example, a [drive] of its kind."""
    data = CONFIGS[_SECTION_BASE.get(section, "cuboid_36.toml")]
    if section == "drive":
        for table in _DRIVES.values():
            if key in table or (key in ("velocity", "acceleration", "samples") and "time" in table):
                return dict(copy.deepcopy(data), drive=copy.deepcopy(table))
    return data
_IN_EXAMPLES = {(s, k) for _, s, k in KEYS}
#: The mutations of a key no example has (fewer: the key's reading, not the example, is what is tested).
_FEW = ("a list", "a table", "a boolean", "text", "an unknown unit", "nan", "-1", "0", "1e300", "''",
        "10**400", "'5,000 characters'")


def _schema_keys():
    for section in SECTIONS:
        for key in SECTIONS[section]:
            if (section, key) in _IN_EXAMPLES or section == "load":
                continue
            yield section, key


SCHEMA_KEYS = list(_schema_keys())


@pytest.mark.parametrize("section, key", SCHEMA_KEYS, ids=[f"{s}.{k}" for s, k in SCHEMA_KEYS])
def test_every_key_of_the_schema_broken_gives_a_clear_error_or_a_case(section, key):
    """The keys of every section that no example config has ([recording], [initial] positions,
    [numerics] skin ...), each broken in a dozen ways, in an example of its section."""
    name = _SECTION_BASE.get(section, "cuboid_36.toml")
    refused = sum(_check(name, _set(_base(section, key), section, key, MUTATIONS[how]), section, key) for how in _FEW)
    assert refused >= 3, f"{section}.{key}: only {refused} of {len(_FEW)} broken values refused"


@pytest.mark.parametrize("kind, key", [(k, key) for k, t in LOAD_TABLES.items() for key in t])
def test_every_load_key_broken_gives_a_clear_error_or_a_case(tmp_path, kind, key):
    """Every key of every load kind's [load] table (fuzz_helpers.LOAD_TABLES), broken the same ways."""
    from fuzz_helpers import LOAD_BASE

    load_files(tmp_path)
    base = dict(LOAD_BASE, load=LOAD_TABLES[kind])
    # the harmonic force is the structure's own force (its structure_keys): a message may name that key
    also = ("structure", f"force_{key}") if kind == "harmonic" else None
    refused = sum(_check("load.toml", _set(base, "load", key, MUTATIONS[how]), "load", key, tmp_path, also=also)
                  for how in _FEW)
    assert refused >= 3, f"[load] {key} ({kind}): only {refused} of {len(_FEW)} broken values refused"


def test_every_section_of_the_schema_is_broken_somewhere():
    """The suites above break every key of every section (a key added to the schema joins them)."""
    broken = _IN_EXAMPLES | set(SCHEMA_KEYS) | {("load", k) for t in LOAD_TABLES.values() for k in t}
    missing = [f"[{s}] {k}" for s in SECTIONS for k in SECTIONS[s] if (s, k) not in broken]
    assert not missing, f"keys no fuzz test breaks: {', '.join(missing)}"


#: Any value TOML can hold (and some it cannot: a Python object a caller may pass in a dict).
VALUES = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
              st.text(max_size=12),
              st.builds(lambda x, u: f"{x:g}{u}", st.floats(allow_nan=True, allow_infinity=True),
                        st.sampled_from(["mm", "m", "Hz", "kHz", "deg", "rad", "s", "ms", "kg", "GPa", "N", "m/s",
                                         "m/s^2", "%", "furlong", " mm", "MM", ""])),
              st.sampled_from([10**400, -10**4000, "9" * 5000, "1" * 400 + "mm", "x" * 5000])),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=6), inner, max_size=3)),
    max_leaves=6)


@FUZZ
@given(target=st.sampled_from(KEYS), value=VALUES)
def test_any_value_at_any_key_gives_a_clear_error_or_a_case(target, value):
    name, section, key = target
    _check(name, _set(CONFIGS[name], section, key, value), section, key, names_the_file=True)


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
    with counted(CONFIG, f"{name}: unknown key {key} in [{section}]"), pytest.raises(InputError) as info:
        load_and_build(name, data)
    msg = clear_message(str(info.value))
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
    with counted(CONFIG, f"{name} without {', '.join(sorted(drop))}"):
        try:
            load_and_build(name, data)
        except InputError as exc:
            msg = clear_message(str(exc))
            if extra:
                assert f"unknown section [{extra}]" in msg, msg
            elif "particles" in drop:
                assert "missing section [particles]" in msg, msg
            else:  # a [load] without its [structure], a [structure] without its [load]: named
                assert any(f"[{s}]" in msg or f"{s}:" in msg for s in drop), msg
        else:
            assert not extra and "particles" not in drop


# ----------------------------------------------------------------------------- the text of a config, and --set

# the file as it is read (its plausibility is the keys' tests above: those messages name a key, not the file)
CASE_FILE = Reader(name="case config file (TOML text)", suffix=".toml",
                   good=lambda folder: (EXAMPLES / "cuboid_36.toml").read_bytes(), read=load_case)
TestCaseFile = reader_tests(CASE_FILE)

#: ``--set`` items as users type them, and as they break them.
SET_VALUES = st.one_of(
    st.text(max_size=20), st.sampled_from(["7" * 5000, "-" + "9" * 5000, "1" * 400 + "mm", "1e" + "9" * 5000,
                                           "[1, 2", "{a = 1}", '"x"', "true", "nan", "inf", "0x10", "1_000",
                                           "12mm", "x" * 5000, "'a\x00b'", "2Hz"]))
SET_KEYS = st.one_of(st.sampled_from([f"{s}.{k}" for _, s, k in KEYS]),
                     st.text(alphabet="abcdefghijklmnopqrstuvwxyz_.", max_size=16))


@FUZZ
@given(key=SET_KEYS, value=SET_VALUES, config=st.sampled_from(["mast_hammer.toml", "cuboid_36.toml"]))
def test_any_set_gives_a_clear_error_or_a_case(key, value, config):
    """``pdamper run CONFIG --set KEY=VALUE``: parsed as the CLI parses it, then the case read."""
    from pdamper.cli.common import parse_set

    with counted("--set overrides", f"--set {key[:30]}={value[:30]}"):
        try:
            overrides = parse_set([f"{key}={value}"])
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                check_case(load_case(EXAMPLES / config, overrides))
        except InputError as exc:
            msg = clear_message(str(exc))
            section, _, name = key.partition(".")
            # it names the override, the key, or its section (a [load] set alone lacks its kind)
            assert ("--set" in msg or "override" in msg or names_key(msg, section.strip(), name.strip())
                    or f"[{section.strip()}]" in msg), msg


def test_set_load_file_to_5000_digits_is_one_line():
    """Issue 42: ``pdamper run examples/mast_hammer.toml --set load.file=<5,000 digits>`` was a ValueError
    (int() refuses 4,300 digits) from the --set parser; now the digits are the file's name, which is too long."""
    from click.testing import CliRunner

    from pdamper.cli import main

    r = CliRunner().invoke(main, ["run", str(EXAMPLES / "mast_hammer.toml"), "--set", f"load.file={'7' * 5000}"])
    assert r.exit_code == 2 and r.output.startswith("Error: ") and r.output.count("\n") == 1, r.output[:300]
    assert len(r.output) < 400 and "[load] file: cannot read the force file" in r.output, r.output
    assert re.search(r"7{20}\.\.\.7{20}7* \(\d+ characters\): the file name is too long", r.output), r.output


@pytest.mark.parametrize("key", ["load.file", "structure.matrices"])
def test_a_file_name_with_a_nul_in_a_config_is_one_line(key):
    """A NUL character in the name of a file a config reads (a load's record, the FE matrices) is
    refused in one line naming the key, not a ValueError from os.path.realpath."""
    with pytest.raises(InputError, match=r"(\[load\] file|\[structure\] matrices).*(NUL|cannot read|\.npz)"):
        load_case(EXAMPLES / "mast_hammer.toml", {key: "a\x00b"})

def test_a_5000_character_file_name_in_a_config_is_one_line(tmp_path):
    """Issue 42: ``[load] file = "<5,000 characters>"`` was an OSError (File name too long) from deep inside."""
    from click.testing import CliRunner

    from pdamper.cli import main

    text = (EXAMPLES / "mast_hammer.toml").read_text().replace('file = "hammer.csv"', f'file = "{"a" * 5000}"')
    (tmp_path / "mast_hammer.toml").write_text(text)
    (tmp_path / "mast.npz").write_bytes((EXAMPLES / "mast.npz").read_bytes())
    r = CliRunner().invoke(main, ["transient", str(tmp_path / "mast_hammer.toml")])
    assert r.exit_code == 2 and r.output.count("\n") == 1 and len(r.output) < 400, r.output[:300]
    assert "mast_hammer.toml: [load] file: cannot read the force file" in r.output, r.output
    assert "the file name is too long for the file system" in r.output, r.output


def test_a_5000_digit_number_in_a_config_file_names_its_line(tmp_path):
    path = tmp_path / "big.toml"
    path.write_text((EXAMPLES / "cuboid_36.toml").read_text().replace("count = 36", "count = " + "7" * 5000))
    with pytest.raises(InputError, match=r"big\.toml, line \d+: a whole number of 5000 digits") as info:
        load_case(path)
    clear_message(str(info.value))


# ----------------------------------------------------------------------------- the other files a case is made from

def _drive_samples(path):
    from pdamper.excitation import read_motion_csv

    out = read_motion_csv(path)
    assert all(math.isfinite(v) for col in out.values() for v in col)
    return out


MOTION = Reader(name="drive samples (CSV)", suffix=".csv",
                good=lambda folder: ("time [s],position [mm]\n" + "".join(
                    f"{k / 100:.2f},{12 * math.sin(2 * math.pi * 2 * k / 100):.6f}\n" for k in range(100))).encode(),
                read=_drive_samples)
TestDriveSamples = reader_tests(MOTION)


STUDY = Reader(name="study file (TOML)", suffix=".toml",
               good=lambda folder: b'title = "mu"\nvary = ["drive.stroke=2mm:40mm:3"]\n\n[[setting]]\nlabel = "a"\n'
                                   b'base = "cuboid_36"\nset = { "contact.friction" = 0.05 }\n',
               read=load_study)
TestStudyFile = reader_tests(STUDY)


MANIFEST = Reader(name="campaign manifest (TOML)", suffix=".toml",
                  good=lambda folder: b'bed_mass = "149g"\nfrequency = "2Hz"\ndrop_cycles = 2\n\n[[record]]\n'
                                      b'file = "x12.csv"\nstroke = "12mm"\ncolumns = { force = "F_x" }\n',
                  read=read_manifest)
TestCampaignManifest = reader_tests(MANIFEST)


STRUCTURE_FILE = Reader(name="structure file of design (TOML)", suffix=".toml",
                        good=lambda folder: b'[structure]\nmass = "25kg"\nnatural_frequency = "3Hz"\n'
                                            b'damping_ratio = 0.003\n',
                        read=load_structure)
TestStructureFile = reader_tests(STRUCTURE_FILE)
