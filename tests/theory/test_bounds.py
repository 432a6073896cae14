"""Operating bounds: A = XΩ² < g and the tilt bound A cos α > g sin α (Sects. 4.2, 6.2)."""

import math

import pytest

from pdamper import theory
from pdamper.errors import InputError


def test_tilt_of_three_degrees_needs_half_a_metre_per_second_squared():
    assert theory.min_acceleration_tilt(math.radians(3)) == pytest.approx(0.514, abs=5e-4)
    assert theory.min_acceleration_tilt(0.0) == 0.0


def test_min_stroke_for_the_tilt():
    tilt, f = math.radians(3), 2.0
    x_min = theory.min_stroke_tilt(tilt, f)
    assert theory.acceleration_amplitude(x_min, f) == pytest.approx(
        theory.min_acceleration_tilt(tilt), rel=1e-14)


def test_paper_accelerations_at_the_optima():
    # Sect. 6.2: A(12 mm) = 1.9 m/s² and A(4 mm) = 0.63 m/s² at 2 Hz.
    assert theory.acceleration_amplitude(0.012, 2.0) == pytest.approx(1.9, abs=0.01)
    assert theory.acceleration_amplitude(0.004, 2.0) == pytest.approx(0.63, abs=0.005)


def test_liftoff_stroke_reaches_g_and_gravity_can_be_changed():
    for g in (9.81, 1.62):
        x = theory.max_stroke_no_liftoff(2.0, gravity=g)
        assert theory.acceleration_amplitude(x, 2.0) == pytest.approx(g, rel=1e-14)
    assert theory.min_acceleration_tilt(math.radians(3), gravity=1.62) == pytest.approx(
        1.62 * math.tan(math.radians(3)))


def test_velocity_amplitude():
    assert theory.velocity_amplitude(0.01, 2.0) == pytest.approx(0.01 * 4 * math.pi)
    assert theory.angular_frequency(2.0) == pytest.approx(4 * math.pi)


@pytest.mark.parametrize("tilt", [-0.01, math.pi / 2, 2.0, math.nan, "95deg", "3mm"])
def test_bad_tilt(tilt):
    with pytest.raises(InputError, match="tilt"):
        theory.min_acceleration_tilt(tilt)


def test_tilt_in_degrees():
    # "3deg" was refused when the theory took SI floats only; now it is 3 degrees
    assert theory.min_acceleration_tilt("3deg") == pytest.approx(theory.min_acceleration_tilt(math.radians(3)),
                                                                 rel=1e-14)


@pytest.mark.parametrize("call", [
    lambda: theory.max_stroke_no_liftoff(0.0),
    lambda: theory.max_stroke_no_liftoff(2.0, gravity=-9.81),
    lambda: theory.acceleration_amplitude(-0.01, 2.0),
    lambda: theory.min_stroke_tilt(0.05, math.inf),
])
def test_bad_inputs(call):
    with pytest.raises(InputError):
        call()
