"""Shared settings of the fuzz suites (tests/test_fuzz_config.py, tests/io/test_fuzz_records.py).

The invariant they check: bad input gives a clear :class:`pdamper.errors.InputError` that names the
config key (or the file), or a finite result; never another exception, never a hang.

Size: ``PDAMPER_FUZZ=ci`` (the default) runs 50 derandomized examples per fuzz test (350 in all, seconds)
(the same examples every run, so CI is stable); ``PDAMPER_FUZZ=long`` runs 2 000 random examples per
test (minutes), e.g. ``PDAMPER_FUZZ=long pytest tests/test_fuzz_config.py tests/io/test_fuzz_records.py``.
"""

from __future__ import annotations

import contextlib
import os
import signal

from hypothesis import HealthCheck, settings, strategies as st

_PROFILES = {
    "ci": dict(max_examples=50, derandomize=True),
    "long": dict(max_examples=2_000, derandomize=False),
}
PROFILE = os.environ.get("PDAMPER_FUZZ", "ci")
if PROFILE not in _PROFILES:
    raise RuntimeError(f"PDAMPER_FUZZ={PROFILE!r}: choose one of {', '.join(_PROFILES)}")

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


# ----------------------------------------------------------------------------- damage
# How files get damaged (the readers' fuzz suites: tests/io/test_fuzz_records.py, tests/structure/test_fuzz_loads.py).

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


AT = st.floats(0.0, 1.0)
JUNK = st.binary(min_size=1, max_size=64)
NUMBERS = st.sampled_from([b"1e400", b"-1e400", b"1e308", b"1e200", b"nan", b"inf", b"0x10", b"1,5", b"--1", b"1e",
                           b"", b" ", b"\xff\xfe", b'"1"', b'"', b"1e-400"])
DAMAGE = st.one_of(
    st.builds(lambda at: ("truncate", lambda d: truncate(d, at)), AT),
    st.builds(lambda at, j: ("overwrite", lambda d: overwrite(d, at, j)), AT, JUNK),
    st.builds(lambda at, j: ("insert", lambda d: insert(d, at, j)), AT, JUNK),
    st.builds(lambda at, n: ("ragged", lambda d: ragged(d, at, n)), AT, st.integers(0, 5)),
    st.builds(lambda at, n: ("overflow", lambda d: overflow(d, at, n)), AT, NUMBERS),
    st.builds(lambda at, n: ("huge line", lambda d: huge_line(d, at, n)), AT, st.sampled_from([200, 140_000])),
)
