"""The whole suite's hooks: the fuzz suites' count of inputs, added up over pytest-xdist's workers and
printed at the end of a run (``fuzz: N inputs over R readers, 0 tracebacks``; tests/fuzz_helpers.py)."""

from fuzz_helpers import pytest_sessionfinish, pytest_terminal_summary, pytest_testnodedown  # noqa: F401
