"""Plausibility before anything runs: a bare number is SI, and a 13 m stroke is caught with the fix."""

from __future__ import annotations

import pytest

from pdamper.config import load_case, with_overrides
from pdamper.errors import InputError
from pdamper.plausible import LiftOffWarning, check_case, check_memory, memory_needed
from pathlib import Path

EXAMPLE = load_case(Path(__file__).parents[1] / "examples" / "cuboid_36.toml")


@pytest.mark.parametrize("over, words", [
    ({"drive.stroke": 13}, r"drive.stroke = 13 m is 108 times the container's length 0.12 m.*did you mean '13mm'"),
    ({"container.length": 120}, r"container.length = 120 m .*did you mean '120mm'"),
    ({"particles.radius": 5}, r"particles.radius = 5 m .*did you mean '5mm'"),
    ({"particles.radius": "25mm"}, r"diameter 50 mm does not fit in the container \(height 40 mm\)"),
    ({"drive.frequency": "2000Hz"}, r"peak acceleration .* beyond any damper test"),
])
def test_implausible_inputs_are_refused_with_a_fix(over, words):
    with pytest.raises(InputError, match=words):
        check_case(with_overrides(EXAMPLE, over))


def test_whole_cycles_for_the_analysis_and_lift_off_is_said():
    check_case(EXAMPLE, analyze=True)  # the paper's case: nothing to say
    with pytest.raises(InputError, match=r"run.cycles = 2.5 leaves no whole cycle after the 2 dropped"):
        check_case(with_overrides(EXAMPLE, {"run.cycles": 2.5}), analyze=True)
    with pytest.warns(UserWarning, match="only one cycle is analysed"):
        check_case(with_overrides(EXAMPLE, {"run.cycles": 3}), analyze=True)
    with pytest.warns(LiftOffWarning, match=r"peak acceleration 1.3 g exceeds g"):
        check_case(with_overrides(EXAMPLE, {"drive.stroke": "80mm"}))


def test_memory_is_estimated_and_a_run_that_cannot_fit_is_refused():
    # 20 cycles at 2 Hz + 0.1 s settling at 1 kHz: 10 100 samples x 13 arrays x 8 bytes
    assert memory_needed(EXAMPLE) == pytest.approx(10_100 * 13 * 8)
    with pytest.raises(InputError, match=r"would record .* GiB .* GiB are free; run fewer cycles"):
        check_memory(with_overrides(EXAMPLE, {"run.cycles": 1e9}))
