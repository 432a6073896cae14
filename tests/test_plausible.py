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
    ({"particles.radius": "25mm"}, r"diameter 50 mm does not fit in the container \(container.height = 40 mm\)"),
    ({"drive.frequency": "2000Hz"}, r"peak acceleration .* beyond any damper test"),
    # issue 24: every length a bare number makes absurd, angles beyond a turn
    ({"initial.jitter": "13"}, r"initial.jitter = 13 m is larger than the container's floor .*did you mean '13mm'"),
    ({"initial.settle_time": 100}, r"initial.settle_time = 100 s: .*did you mean '100ms'"),
    ({"container.width": 40.4}, r"container.width = 40.4 m .*did you mean '40.4mm'"),
    ({"container.height": "40"}, r"container.height = 40 m .*did you mean '40mm'"),
    ({"drive.angle": 1e30}, r"drive.angle = 1e\+30 rad is beyond a full turn"),
    ({"drive.angle": 90}, r"drive.angle = 90 rad is beyond a full turn .*did you mean '90deg'"),
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
    with pytest.warns(LiftOffWarning, match=r"peak acceleration 12.6 m/s\^2 \(1.3 g\) exceeds gravity \(9.81 m/s\^2\)"):
        check_case(with_overrides(EXAMPLE, {"drive.stroke": "80mm"}))


def test_memory_is_estimated_and_a_run_that_cannot_fit_is_refused():
    # 20 cycles at 2 Hz + 0.1 s settling at 1 kHz: 10 100 samples x 13 arrays x 8 bytes
    assert memory_needed(EXAMPLE) == pytest.approx(10_100 * 13 * 8)
    with pytest.raises(InputError, match=r"would record .* GiB .* GiB are free; run fewer cycles"):
        check_memory(with_overrides(EXAMPLE, {"run.cycles": 1e9}))


def test_a_tiny_gravity_is_not_taken_for_a_violent_drive():
    # issue 24: gravity 1e-30 m/s^2 was refused as "peak acceleration 2e30 g ... beyond any damper test"
    with pytest.warns(LiftOffWarning, match=r"exceeds gravity \(1e-30 m/s\^2\)"):
        check_case(with_overrides(EXAMPLE, {"run.gravity": 1e-30}))


@pytest.mark.parametrize("gravity", [1e19, 100.5, -1.0])
def test_gravity_outside_0_to_100_is_refused_with_the_reason(gravity):
    with pytest.raises(InputError, match=r"^\[run\] gravity = .* must be in \[0, 100\] m/s\^2: 0 for no gravity, "
                                         r"9.81 on Earth; above 100 \(ten g\)"):
        with_overrides(EXAMPLE, {"run.gravity": gravity})


@pytest.mark.parametrize("key, value, words", [
    ("contact.v_in_floor", 0.0, r"\[contact\] v_in_floor = 0.0; must be > 0 m/s"),
    ("particles.radius", -1.0, r"\[particles\] radius = -1.0; must be > 0 m"),
    ("numerics.gear_tolerance", 0, r"\[numerics\] gear_tolerance = 0(.0)?; must be > 0 m"),
    ("recording.sample_rate", -5, r"\[recording\] sample_rate = -5(.0)?; must be > 0 Hz"),
])
def test_messages_name_the_config_key_not_the_class(key, value, words):
    with pytest.raises(InputError, match=words) as info:
        load_case(Path(__file__).parents[1] / "examples" / "cuboid_36.toml", {key: value})
    assert "contactmodel" not in str(info.value) and "particleset" not in str(info.value)


# ------------------------------------------------ a stacked bed that only its symmetry keeps (issue 39 item 5)

VERTICAL = load_case(Path(__file__).parents[1] / "examples" / "vertical_96.toml")


def test_a_stacked_bed_without_tilt_is_said_to_have_two_states_whatever_the_law():
    import warnings

    from pdamper.plausible import SymmetricBedWarning, symmetric_stack

    flat = with_overrides(VERTICAL, {"container.tilt": "0deg"})
    assert symmetric_stack(flat) == 2
    for law in ("tanh", "spring"):
        with pytest.warns(SymmetricBedWarning, match=r"stacked in 2 layers.*two states.*'tanh' \(the default\) the "
                                                     r"seed picks one.*'spring' the crystal stands.*container.tilt"):
            check_case(with_overrides(flat, {"contact.tangential": law}))
    # the paper's tilt (the example's default), one layer, a scatter or given positions: nothing to say
    quiet = [VERTICAL, with_overrides(flat, {"particles.count": 48, "initial.layers": "one"}),
             with_overrides(EXAMPLE, {"container.tilt": "0deg"})]
    for case in quiet:
        assert symmetric_stack(case) == 0
        with warnings.catch_warnings():
            warnings.simplefilter("error", SymmetricBedWarning)
            check_case(case)
