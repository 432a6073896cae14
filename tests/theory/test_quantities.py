"""Every public theory function takes SI numbers, unit texts and pint quantities (issue 17, part 4)."""

from __future__ import annotations

import inspect
import math

import numpy as np
import pint
import pytest

from pdamper import theory
from pdamper.errors import InputError

U = pint.UnitRegistry()


def _functions():
    return [getattr(theory, n) for n in theory.__all__
            if inspect.isfunction(getattr(theory, n)) and not n.isupper()]


@pytest.mark.parametrize("func", _functions(), ids=lambda f: f.__name__)
def test_every_function_declares_the_dimension_of_its_quantities(func):
    declared = getattr(func, "__quantities__", None)
    assert declared, f"{func.__name__} is not decorated with pdamper.units.quantities"
    params = inspect.signature(func).parameters
    assert set(declared) <= set(params)
    # every argument that is a physical quantity by name is declared
    for name in params:
        if name in ("stroke", "clearance", "frequency", "bed_mass", "length", "tilt", "gravity", "mass", "stiffness"):
            assert name in declared, (func.__name__, name)


def test_the_issue_example():
    assert theory.clearance("120mm", 36, 48) == theory.clearance(0.12, 36, 48) == pytest.approx(0.03, rel=1e-12)
    assert theory.clearance(120 * U.mm, 36, 48) == theory.clearance(0.12, 36, 48)


@pytest.mark.parametrize("call", [
    lambda s, h, f, m: theory.eta_theory(s, h),
    lambda s, h, f, m: theory.energy_per_cycle_rolling(s, h, frequency=f, bed_mass=m),
    lambda s, h, f, m: theory.energy_per_cycle_scattered(s, h, frequency=f, bed_mass=m),
    lambda s, h, f, m: theory.energy_per_cycle_bouncing(s, h, frequency=f, bed_mass=m),
    lambda s, h, f, m: theory.acceleration_amplitude(s, f),
    lambda s, h, f, m: theory.optimal_stroke(h),
])
def test_texts_quantities_and_floats_agree(call):
    floats = call(0.015, 0.03, 2.0, 0.149)
    assert call("15mm", "3cm", "2Hz", "149g") == floats
    assert call(15 * U.mm, 30 * U.mm, 2 * U.Hz, 149 * U.g) == floats


def test_arrays_lists_and_pint_arrays():
    x = np.array([0.01, 0.015, 0.02])
    want = theory.eta_theory(x, 0.03)
    np.testing.assert_array_equal(theory.eta_theory(x * 1e3 * U.mm, "30mm"), want)
    np.testing.assert_array_equal(theory.eta_theory(["10mm", "15mm", 0.02], 0.03), want)


def test_angles_and_accelerations():
    assert theory.min_stroke_tilt("3deg", "2Hz", gravity="9.81 m/s^2") == pytest.approx(
        theory.min_stroke_tilt(math.radians(3), 2.0), rel=1e-14)
    assert theory.max_stroke_no_liftoff(2 * U.Hz, gravity="1 g_0") == pytest.approx(
        theory.max_stroke_no_liftoff(2.0, gravity=9.80665), rel=1e-14)
    assert theory.steady_amplitude("2Hz", mass="7kg", stiffness="1.105 kN/m", damping_ratio="0.5%",
                                   force_amplitude="0.4N") == theory.steady_amplitude(
        2.0, mass=7.0, stiffness=1105.0, damping_ratio=0.005, force_amplitude=0.4)


def test_floats_pass_through_unchanged():
    # bit for bit: the fast path hands SI floats on as they are
    x, h = 0.0123456789012345, 0.0301234567890123
    assert theory.eta_rolling(x, h) == theory.eta_rolling.__wrapped__(x, h)


@pytest.mark.parametrize("call, message", [
    (lambda: theory.clearance("12kg", 36, 48), "length: '12kg' is not a length (its unit is kg); use a unit such as "
                                               "'120mm' or 0.12"),
    (lambda: theory.eta_theory(0.01, 3 * U.s), "clearance: '3 s' is not a length"),
    (lambda: theory.angular_frequency("2mm"), "frequency: '2mm' is not a frequency"),
    (lambda: theory.min_acceleration_tilt("3mm"), "tilt: '3mm' is not an angle"),
    (lambda: theory.energy_per_cycle_rolling(0.015, 0.03, frequency=2.0, bed_mass="149mm"),
     "bed_mass: '149mm' is not a mass"),
    (lambda: theory.natural_frequency(7.0, "3 kg"), "stiffness: '3 kg' is not in N/m"),
    (lambda: theory.eta_theory(["10mm", "2 s"], 0.03), "stroke[1]: '2 s' is not a length"),
])
def test_wrong_dimensions(call, message):
    with pytest.raises(InputError) as info:
        call()
    assert message in str(info.value)
