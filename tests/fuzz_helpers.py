"""The fuzz suites' shared parts: the invariant, the damage, the readers and their count.

The invariant (issues 24, 42): bad input gives a clear :class:`pdamper.errors.InputError` (one line,
naming the config key or the file, the value as written: no numpy repr such as ``np.float64(0.0)``,
no 5,000-character quote), or a finite result; never another exception, never a hang.

**A new reader joins the suite in a few lines** (an uncertainty file, an OpenSees model script, a
damper list, a record suite ...): describe it with :class:`Reader` in the fuzz file of its room and
let :func:`reader_tests` make its tests::

    from fuzz_helpers import Reader, reader_tests

    UNCERTAIN = Reader(
        name="uncertainty file (U.toml)", suffix=".toml",
        good=lambda folder: b'[[unknown]]\\nkey = "contact.friction"\\ndistribution = "uniform"\\n'
                            b'low = 0.05\\nhigh = 0.2\\n',
        read=lambda path: read_uncertain(path))      # raises InputError or returns what it read
    TestUncertain = reader_tests(UNCERTAIN)          # pytest collects the class

``good(folder)`` returns the bytes of a valid input (and may write files it refers to into
``folder``); ``read(path)`` reads one; ``check(result)`` (optional) asserts what a read that worked
must satisfy (finite numbers ...); ``text=False`` for a binary format. The class breaks the input
every way :data:`DAMAGE` knows (truncated, junk overwritten or inserted, a ragged row, a number that
overflows, a huge line), gives it random bytes, and names the file in every way a file system allows
or refuses (:data:`NAMES`: 300 and 5,000 characters, a NUL, bytes of another encoding, a newline,
unicode, spaces and braces, a folder, a pipe, a missing file); each input counts once for the reader
(:func:`counted`), and the run prints the count (``fuzz: N inputs over R readers, 0 tracebacks``,
:func:`pytest_terminal_summary`, docs/reliability.md).

Size: ``PDAMPER_FUZZ=ci`` (the default) runs :data:`EXAMPLES` derandomized examples per generated
test (the same examples every run, so CI is stable); ``PDAMPER_FUZZ=long`` runs 2 000 random ones
(minutes), e.g. ``PDAMPER_FUZZ=long pytest tests/test_fuzz_config.py tests/io/test_fuzz_records.py``.
"""

from __future__ import annotations

import collections
import contextlib
import json
import os
import re
import signal
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

_PROFILES = {
    "ci": dict(max_examples=40, derandomize=True),
    "long": dict(max_examples=2_000, derandomize=False),
}
PROFILE = os.environ.get("PDAMPER_FUZZ", "ci")
if PROFILE not in _PROFILES:
    raise RuntimeError(f"PDAMPER_FUZZ={PROFILE!r}: choose one of {', '.join(_PROFILES)}")
#: Examples per generated test in this profile.
EXAMPLES = _PROFILES[PROFILE]["max_examples"]

#: The hypothesis settings of a fuzz test (a decorator); the deadline fails an example slower than 5 s.
FUZZ = settings(deadline=5000, suppress_health_check=[HealthCheck.too_slow, HealthCheck.function_scoped_fixture],
                **_PROFILES[PROFILE])

#: Longest one example may take before it counts as a hang [s].
HANG = 30.0


class Hang(Exception):
    """One input took longer than :data:`HANG`: the reader or loader hangs on it."""


@contextlib.contextmanager
def no_hang(what: str, seconds: float = HANG):
    """Fail with :class:`Hang` (naming ``what``) when the block runs longer than ``seconds``
    (a hypothesis deadline only reports a slow example after it has finished)."""
    def alarm(signum, frame):
        raise Hang(f"{what} did not finish in {seconds:g} s")

    old = signal.signal(signal.SIGALRM, alarm)
    signal.setitimer(signal.ITIMER_REAL, seconds)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)


# ----------------------------------------------------------------------------- the count

#: Inputs checked per reader, and the unexpected exceptions among them (this process's).
COUNTS: collections.Counter = collections.Counter()
TRACEBACKS: collections.Counter = collections.Counter()


@contextlib.contextmanager
def counted(reader: str, what: str | None = None):
    """Count one input of ``reader``; an exception other than InputError (or a failed assertion,
    or a hang) counts as a traceback of that reader and is raised on."""
    from pdamper.errors import InputError

    COUNTS[reader] += 1
    try:
        with no_hang(what or f"{reader}: one input"):
            yield
    except InputError:
        raise
    except BaseException:
        TRACEBACKS[reader] += 1
        raise


def pytest_sessionfinish(session):
    """(conftest hook) A worker of pytest-xdist hands its counts to the controller."""
    out = getattr(session.config, "workeroutput", None)
    if out is not None:
        out["pdamper_fuzz"] = json.dumps({"counts": COUNTS, "tracebacks": TRACEBACKS})


@pytest.hookimpl(optionalhook=True)
def pytest_testnodedown(node, error):
    """(conftest hook, pytest-xdist) The controller adds up the workers' counts."""
    got = json.loads(getattr(node, "workeroutput", {}).get("pdamper_fuzz", "{}") or "{}")
    COUNTS.update(got.get("counts", {}))
    TRACEBACKS.update(got.get("tracebacks", {}))


def pytest_terminal_summary(terminalreporter):
    """(conftest hook) ``fuzz: N inputs over R readers, T tracebacks`` and the count per reader."""
    if not COUNTS:
        return
    total = sum(COUNTS.values())
    tr = terminalreporter
    tr.write_sep("-", f"fuzz: {total:,} inputs over {len(COUNTS)} readers, {sum(TRACEBACKS.values())} tracebacks")
    for name, n in sorted(COUNTS.items(), key=lambda kv: -kv[1]):
        tr.write_line(f"  {n:>6,}  {name}" + (f"  ({TRACEBACKS[name]} tracebacks)" if TRACEBACKS[name] else ""))


# ----------------------------------------------------------------------------- the invariant on a message

#: A numpy scalar's or array's repr in a message (``np.float64(0.0)``, ``array([1.])``, ``dtype=``).
NUMPY_REPR = re.compile(r"\b(?:np|numpy)\.(?:float|int|uint|bool|str|complex|bytes|void|datetime|timedelta)\w*\("
                        r"|\barray\(|\bdtype=")


def clear_message(msg: str, *, limit: int = 1000) -> str:
    """Assert that ``msg`` is a clear error line: one line, under ``limit`` characters, no numpy
    repr; returns it."""
    assert "\n" not in msg, f"the message is more than one line: {msg!r}"
    assert len(msg) < limit, f"the message is {len(msg)} characters (quotes too much): {msg[:300]!r}..."
    assert not NUMPY_REPR.search(msg), f"the message prints a numpy repr: {msg}"
    return msg


def names_file(msg: str, path: Path) -> bool:
    """The message names the file: its name (or the start of it, for a name a message cuts), as
    :func:`pdamper.errors.shown_path` prints it."""
    from pdamper.errors import shown_path

    name = shown_path(path.name)
    return path.name in msg or name in msg or name[:30] in msg


# ----------------------------------------------------------------------------- damage
# How files get damaged.

def truncate(data: bytes, at: float) -> bytes:
    return data[:int(at * len(data))]


def overwrite(data: bytes, at: float, junk: bytes) -> bytes:
    k = int(at * len(data))
    return data[:k] + junk + data[k + len(junk):]


def insert(data: bytes, at: float, junk: bytes) -> bytes:
    k = int(at * len(data))
    return data[:k] + junk + data[k:]


def ragged(data: bytes, at: float, keep: int) -> bytes:
    lines = data.split(b"\n")
    k = 1 + int(at * (len(lines) - 2))
    lines[k] = b",".join(lines[k].split(b",")[:keep])
    return b"\n".join(lines)


def overflow(data: bytes, at: float, number: bytes) -> bytes:
    lines = data.split(b"\n")
    k = 1 + int(at * (len(lines) - 2))
    cells = lines[k].split(b",")
    cells[-1] = number
    lines[k] = b",".join(cells)
    return b"\n".join(lines)


def huge_line(data: bytes, at: float, size: int) -> bytes:
    lines = data.split(b"\n")
    k = int(at * (len(lines) - 1))
    lines[k] = lines[k] + b"," + b"\x00\xff7" * (size // 3)
    return b"\n".join(lines)


def numeral(data: bytes, at: float, number: bytes) -> bytes:
    """A number of the input (the first run of digits after ``at``) replaced by ``number``."""
    k = int(at * len(data))
    m = re.compile(rb"[0-9]+(?:\.[0-9]*)?(?:[eE][-+]?[0-9]+)?").search(data, k) or re.search(rb"[0-9]+", data)
    if m is None:
        return data + number
    return data[:m.start()] + number + data[m.end():]


AT = st.floats(0.0, 1.0)
JUNK = st.binary(min_size=1, max_size=64)
NUMBERS = st.sampled_from([b"1e400", b"-1e400", b"1e308", b"1e200", b"nan", b"inf", b"0x10", b"1,5", b"--1", b"1e",
                           b"", b" ", b"\xff\xfe", b'"1"', b'"', b"1e-400"])
#: Numerals of any size: 5,000 digits (Python's int() refuses more than 4,300), 400 digits (beyond a
#: float), an exponent of 5,000 digits, a 5,000-digit fraction.
BIG_NUMERALS = st.sampled_from([b"7" * 5000, b"-" + b"9" * 5000, b"1" * 400, b"1" * 400 + b".5", b"1e" + b"9" * 5000,
                                b"0." + b"0" * 5000 + b"1", b"1_000" * 1000, b"12345678901234567890123"])
DAMAGE = st.one_of(
    st.builds(lambda at: ("truncate", lambda d: truncate(d, at)), AT),
    st.builds(lambda at, j: ("overwrite", lambda d: overwrite(d, at, j)), AT, JUNK),
    st.builds(lambda at, j: ("insert", lambda d: insert(d, at, j)), AT, JUNK),
    st.builds(lambda at, n: ("ragged", lambda d: ragged(d, at, n)), AT, st.integers(0, 5)),
    st.builds(lambda at, n: ("overflow", lambda d: overflow(d, at, n)), AT, NUMBERS),
    st.builds(lambda at, n: ("huge line", lambda d: huge_line(d, at, n)), AT, st.sampled_from([200, 140_000])),
    st.builds(lambda at, n: ("numeral", lambda d: numeral(d, at, n)), AT, BIG_NUMERALS),
)


# ----------------------------------------------------------------------------- file names

def _pipe(folder: Path, name: str) -> Path:
    p = folder / name
    os.mkfifo(p)
    return p


def _folder(folder: Path, name: str) -> Path:
    p = folder / name
    p.mkdir()
    return p


def _loop(folder: Path, name: str) -> Path:
    p = folder / name
    os.symlink(p, p)
    return p


#: File names as users and file systems make them: ``(what, make)`` where ``make(folder, suffix,
#: data)`` returns the path to read (with the good data written under it where the name is a valid
#: one). The names a file system refuses (too long, a NUL) must give an InputError naming the file.
NAMES = {
    "300 characters": lambda d, s, b: d / ("n" * 300 + s),
    "5,000 characters": lambda d, s, b: Path(*(["x" * 200] * 25)) / ("y" + s),
    "5,000 characters, relative": lambda d, s, b: Path("z" * 5000 + s),
    "a NUL": lambda d, s, b: d / f"a\x00b{s}",
    "bytes of another encoding": lambda d, s, b: _written(d / f"caf\udce9{s}", b),
    "a newline": lambda d, s, b: _written(d / f"two\nlines{s}", b),
    "unicode": lambda d, s, b: _written(d / f"Mesure_é_µ_地震_🌊{s}", b),
    "spaces, quotes and braces": lambda d, s, b: _written(d / f" {{path}} 'a' \"b\" [c] %s{s}", b),
    "a folder": lambda d, s, b: _folder(d, f"folder{s}"),
    "a pipe": lambda d, s, b: _pipe(d, f"pipe{s}"),
    "a link to itself": lambda d, s, b: _loop(d, f"loop{s}"),
    "missing": lambda d, s, b: d / f"nowhere{s}",
    "empty name": lambda d, s, b: Path(""),
}


def _written(path: Path, data: bytes) -> Path:
    path.write_bytes(data)
    return path


# ----------------------------------------------------------------------------- readers

@dataclass(frozen=True)
class Reader:
    """A reader the fuzz suite breaks (module docstring).

    Attributes
    ----------
    name : str
        How the count and the docs name it, e.g. ``"accelerogram (PEER .AT2)"``.
    suffix : str
        The file name's ending its input has (``".AT2"``, ``".toml"``).
    good : callable
        ``good(folder) -> bytes``: a valid input (files it refers to written into ``folder``).
    read : callable
        ``read(path)``: what it read, or an :class:`~pdamper.errors.InputError`.
    check : callable, optional
        ``check(result)``: assertions on a read that worked.
    text : bool
        A text format (the line-wise damage applies too).
    names_the_file : bool
        Its messages name the file (False for a reader whose messages name a config key instead).
    """

    name: str
    suffix: str
    good: Callable[[Path], bytes]
    read: Callable[[Path], object]
    check: Callable[[object], None] = field(default=lambda result: None)
    text: bool = True
    names_the_file: bool = True


#: Every reader registered by :func:`reader_tests` (its name -> the reader).
READERS: dict[str, Reader] = {}


def read_one(reader: Reader, path: Path, how: str = ""):
    """Read ``path`` with ``reader`` under the invariant: the result, checked, or None after an
    InputError whose message is clear and names the file."""
    import warnings

    from pdamper.errors import InputError

    with counted(reader.name, f"{reader.name}: {how or path.name[:60]}"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            result = reader.read(path)
        except InputError as exc:
            msg = clear_message(str(exc), limit=2000)
            if reader.names_the_file:
                assert names_file(msg, path), f"{reader.name} ({how}): the message does not name the file: {msg}"
            return None
        reader.check(result)
        return result


def reader_tests(reader: Reader):
    """A test class for ``reader`` (assign it to a ``Test...`` name in a test module): the good input
    reads; damaged inputs, random bytes and every name of :data:`NAMES` give a clear error or a
    checked result. The reader is added to :data:`READERS`."""
    READERS[reader.name] = reader

    class ReaderFuzz:
        def test_the_good_input_reads(self, tmp_path):
            path = tmp_path / f"good{reader.suffix}"
            path.write_bytes(reader.good(tmp_path))
            assert read_one(reader, path, "as written") is not None, f"{reader.name}: the good input is refused"

        @FUZZ
        @given(damage=DAMAGE)
        def test_a_damaged_input(self, tmp_path_factory, damage):
            folder = tmp_path_factory.mktemp("damaged")
            how, hurt = damage
            if not reader.text and how in ("ragged", "overflow", "numeral"):
                how = "overwrite"
                hurt = lambda d: overwrite(d, 0.5, b"\xff\x00junk")  # noqa: E731
            path = folder / f"damaged{reader.suffix}"
            path.write_bytes(hurt(reader.good(folder)))
            read_one(reader, path, how)

        @FUZZ
        @given(data=st.binary(max_size=2048))
        def test_random_bytes(self, tmp_path_factory, data):
            folder = tmp_path_factory.mktemp("bytes")
            path = folder / f"random{reader.suffix}"
            path.write_bytes(data)
            read_one(reader, path, "random bytes")

        @pytest.mark.parametrize("how", list(NAMES))
        def test_any_file_name(self, tmp_path, how):
            path = NAMES[how](tmp_path, reader.suffix, reader.good(tmp_path))
            result = read_one(reader, path, how)
            if how in ("bytes of another encoding", "unicode", "spaces, quotes and braces", "a newline"):
                assert result is not None, f"{reader.name}: a valid file named with {how} is refused"

    ReaderFuzz.__name__ = ReaderFuzz.__qualname__ = "Test" + re.sub(r"\W+", "_", reader.name).strip("_").title()
    ReaderFuzz.__doc__ = f"The fuzz suite of the reader {reader.name!r} (tests/fuzz_helpers.py)."
    return ReaderFuzz


# ----------------------------------------------------------------------------- loads on a structure
# A small structure under each kind of load, the tables as a config has them and the files beside
# (tests/structure/test_fuzz_loads.py, and the [load] keys of tests/test_fuzz_config.py).

def _load_signal():
    import numpy as np

    t = np.arange(0.0, 2.0, 0.01)
    return t, 0.1 * np.sin(2 * np.pi * 2.0 * t) * np.sin(np.pi * t / 2.0)


LOAD_BASE = {"particles": {"count": 4},
             "structure": {"mass": "7kg", "natural_frequency": "2Hz", "damping_ratio": 0.01}}
LOAD_TABLES = {
    "force_history": {"kind": "force_history", "file": "force.csv", "duration": "3s", "scale": 1.0},
    "inline": {"kind": "force_history", "time": [0.0, 0.01, 0.02], "force": [0.0, 5.0, 0.0], "duration": "2s"},
    "ground_acceleration": {"kind": "ground_acceleration", "file": "quake.csv", "scale": 1.0, "baseline": "none"},
    "at2": {"kind": "ground_acceleration", "file": "quake.AT2", "participation": [1.0]},
    "random": {"kind": "random", "excitation": "ground", "spectrum": "kanai_tajimi", "level": 0.001,
               "ground_frequency": "2.5Hz", "ground_damping": 0.6, "duration": "5s", "seed": 2},
    "stepped_sine": {"kind": "stepped_sine", "amplitude": "0.2N", "frequencies": ["1.9Hz", "2Hz"], "cycles": 5},
    "harmonic": {"kind": "harmonic", "amplitude": "0.2N", "frequency": "2Hz"},
    "random_force": {"kind": "random", "excitation": "force", "spectrum": "white", "level": 0.01, "band": [1, 5],
                     "duration": "4s", "time_step": "5ms", "seed": 1},
    "column": {"kind": "force_history", "file": "force.csv", "column": "force"},
    "influence": {"kind": "ground_acceleration", "time": [0.0, 0.01, 0.02], "acceleration": [0.0, 1.0, 0.0],
                  "influence": [1.0]},
    # a suite of records, each scaled to a target (docs/structure.md, "Record suites")
    "suite_pga": {"kind": "ground_acceleration", "files": ["quake.csv", "quake.AT2"], "pga": "0.1g", "duration": "3s"},
    "suite_sa": {"kind": "ground_acceleration", "files": ["quake.AT2"], "sa": "0.2g", "sa_period": "0.5s",
                 "sa_damping": 0.05},
    "suite_force": {"kind": "force_history", "files": ["force.csv"], "scale": 0.5},
}


def at2_text(values, dt: float = 0.01, per_line: int = 5, width: int = 15) -> str:
    """A PEER NGA ``.AT2`` file of ``values`` [g] as the database writes it: four header lines, then
    ``per_line`` fields of ``width`` characters a line, in the E format without a leading zero
    (``  .1000000E-01``); a width of 13 makes a negative field touch the one before it, as in
    older PEER and COSMOS files (``.1000000E-01-.2000000E-01``)."""
    def field(v: float) -> str:
        m, e = f"{v:.6E}".split("E")  # d.dddddd E+xx -> .ddddddd E+(xx+1)
        mant = m.replace("-", "").replace(".", "")
        exp = int(e) + 1 if float(v) != 0.0 else 0
        return f"{'-' if v < 0 else ''}.{mant}E{exp:+03d}".rjust(width)

    body = "".join(field(v) + ("\n" if k % per_line == per_line - 1 else "") for k, v in enumerate(values))
    return ("PEER NGA STRONG MOTION DATABASE RECORD\nSYNTHETIC 2026, FUZZ, 90\nACCELERATION TIME SERIES IN UNITS OF G\n"
            f"NPTS=  {len(values)}, DT=   {dt:.4f} SEC\n" + body + ("" if body.endswith("\n") else "\n"))


def load_files(folder: Path) -> dict:
    """The good files of :data:`LOAD_TABLES`, as bytes, written into ``folder``."""
    t, a = _load_signal()
    out = {
        "force.csv": ("time [ms],force [N]\n" + "".join(f"{1e3 * x:.3f},{5 * y:.6g}\n" for x, y in zip(t, a))).encode(),
        "quake.csv": ("time [s];acceleration [g]\n" + "".join(f"{x:.3f};{y:.6g}\n" for x, y in zip(t, a))).encode(),
        "quake.AT2": at2_text(a).encode(),
    }
    for name, data in out.items():
        (folder / name).write_bytes(data)
    return out
