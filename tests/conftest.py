"""The whole suite's hooks: one warm-up of the kernel cache before pytest-xdist's workers start
(tests/kernel_warmup.py), and the fuzz suites' count of inputs, added up over the workers and
printed at the end of a run (``fuzz: N inputs over R readers, 0 tracebacks``; tests/fuzz_helpers.py)."""

import os

from fuzz_helpers import pytest_sessionfinish, pytest_terminal_summary, pytest_testnodedown  # noqa: F401


def _workers(config) -> int:
    """How many xdist workers this run starts (0: none, one process)."""
    n = getattr(config.option, "numprocesses", None)
    if n in (None, 0) or getattr(config.option, "dist", "no") == "no":
        return 0
    if isinstance(n, str):  # "auto" / "logical": the cores, capped by --maxprocesses
        n = os.cpu_count() or 1
    cap = getattr(config.option, "maxprocesses", None)
    return min(int(n), int(cap)) if cap else int(n)


def pytest_configure(config):
    if hasattr(config, "workerinput") or os.environ.get("PDAMPER_TEST_WARMUP", "1") == "0":
        return
    if _workers(config) < 2 or config.option.collectonly:
        return
    import kernel_warmup

    if kernel_warmup.needed():
        seconds = kernel_warmup.warm(parts=2)
        config._pdamper_warmup = seconds


def pytest_report_header(config):
    seconds = getattr(config, "_pdamper_warmup", None)
    if seconds is not None:
        return f"kernel cache warmed in {seconds:.0f} s (tests/kernel_warmup.py)"
