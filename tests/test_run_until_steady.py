"""run_case(..., until_steady=TOL): a run stops at the first steady cycle with eta*'s error below TOL."""

from __future__ import annotations

import dataclasses

import pytest

from dem_fixtures import TINY_CONFIG
from pdamper.config import loads_case
from pdamper.errors import InputError
from pdamper.run import MIN_STEADY_CYCLES, run_case


@pytest.fixture(scope="module")
def tiny():
    return dataclasses.replace(loads_case(TINY_CONFIG), cycles=12, drop_cycles=1)


def test_a_loose_tolerance_stops_after_the_fewest_cycles_with_the_answer_of_that_shorter_run(tiny):
    early = run_case(tiny, until_steady=10.0)
    k = tiny.drop_cycles + MIN_STEADY_CYCLES
    assert early.extras["cycles_run"] == k and early.extras["steady"]
    assert early.signals.time.size == k * 500
    short = run_case(dataclasses.replace(tiny, cycles=k))
    # stopping early is the shorter run, bit for bit
    assert early.eta_star == short.eta_star
    assert early.extras["eta_star_error"] == short.extras["eta_star_error"]
    assert early.steps == short.steps


def test_a_tight_tolerance_runs_every_configured_cycle(tiny):
    full = run_case(tiny, until_steady=1e-12)
    assert full.extras["cycles_run"] == tiny.cycles
    assert full.eta_star == run_case(tiny).eta_star
    assert full.extras["eta_star_error"] > 1e-12


def test_every_run_reports_its_error_and_steadiness(tiny):
    res = run_case(tiny)
    s = res.summary()
    assert 0 < s["eta_star_error"] < 1 and isinstance(s["steady"], bool) and s["cycles_run"] == tiny.cycles
    # beside eta* on the result itself (issue 42): the analysis' statistics, and in its repr
    st = res.analysis.statistics
    assert res.eta_star_error == st.eta_star_error == s["eta_star_error"] and res.steady is st.steady is s["steady"]
    assert repr(res).startswith(f"RunResult(eta_star={res.eta_star:.6g}, eta_star_error={res.eta_star_error:.6g}, "
                                f"steady={res.steady!r}, mode=")


def test_a_run_without_an_analysis_has_no_error_and_no_steadiness(tiny):
    import math

    res = run_case(dataclasses.replace(tiny, cycles=3), analyze=False)
    assert res.analysis is None and math.isnan(res.eta_star_error) and res.steady is None


@pytest.mark.parametrize("bad", [0.0, -1.0, float("nan")])
def test_a_tolerance_that_is_not_positive_is_refused(tiny, bad):
    with pytest.raises(InputError, match="until_steady"):
        run_case(tiny, until_steady=bad)
