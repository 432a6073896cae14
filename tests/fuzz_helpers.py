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

from hypothesis import HealthCheck, settings

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
