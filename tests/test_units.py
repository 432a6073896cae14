"""Quantities with units at the edges: ``parse_quantity`` and ``unit_factor``."""

from __future__ import annotations

import math

import pytest

from pdamper.errors import InputError
from pdamper.units import COMMON_UNITS, DIMENSIONS, _registry, parse_quantity, unit_factor


@pytest.mark.parametrize("text,dimension,expected", [
    ("13mm", "length", 0.013),
    ("120mm", "length", 0.12),
    ("40.4 mm", "length", 0.0404),
    ("12cm", "length", 0.12),
    ("20µm", "length", 2e-5),      # micro sign
    ("20μm", "length", 2e-5),      # Greek mu
    ("20um", "length", 2e-5),
    ("2 inch", "length", 0.0508),  # not in the table: pint
    ("5ms", "time", 0.005),
    ("2us", "time", 2e-6),
    ("2Hz", "frequency", 2.0),
    ("1.5kHz", "frequency", 1500.0),
    ("120/min", "frequency", 2.0),
    ("149g", "mass", 0.149),
    ("0.5kN", "force", 500.0),
    ("208GPa", "pressure", 208e9),
    ("1.5 GPa", "pressure", 1.5e9),
    ("7900kg/m^3", "density", 7900.0),
    ("7.9 g/cm^3", "density", 7900.0),
    ("5mm/s", "velocity", 0.005),
    ("0.1 m/s", "velocity", 0.1),
    ("9.81m/s^2", "acceleration", 9.81),
    ("90%", "dimensionless", 0.9),
])
def test_good_inputs(text, dimension, expected):
    assert parse_quantity(text, dimension) == expected  # exact: rounded to 15 digits


@pytest.mark.parametrize("text,expected", [("3deg", math.radians(3)), ("0.1deg", math.radians(0.1)),
                                           ("-1deg", math.radians(-1)), ("0.5 rad", 0.5),
                                           ("1 turn", 2 * math.pi), ("30 arcmin", math.radians(0.5))])
def test_angles(text, expected):
    assert parse_quantity(text, "angle") == pytest.approx(expected, rel=1e-14)


def test_13mm_is_exactly_0_013():
    assert parse_quantity("13mm", "length") == 0.013
    assert 13 * 1e-3 != 0.013  # the raw product carries conversion noise
    assert unit_factor("mm", "length") == 0.001
    assert unit_factor("um", "length") == 1e-6


@pytest.mark.parametrize("value", [0.12, "0.12", " 0.12 ", "1.2e-1", "12e-2"])
def test_plain_numbers_are_si(value):
    assert parse_quantity(value, "length") == pytest.approx(0.12)


@pytest.mark.parametrize("value", [0.1 + 0.2, "0.30000000000000004", 2 ** -60])
def test_plain_numbers_pass_through_unrounded(value):
    # Configs written back in plain SI must read back bit for bit.
    assert parse_quantity(value, "length") == float(value)


@pytest.mark.parametrize("value,dimension,words", [
    ("5 percent", "length", ["'5 percent' is not a length", "no physical dimension",
                             "bare number is taken in m"]),
    ("5 deg", "length", ["'5 deg' is not a length", "no physical dimension"]),
    ("12kg", "length", ["'12kg' is not a length", "its unit is kg", "'120mm'"]),
    ("2Hz", "length", ["is not a length"]),
    ("3mm", "angle", ["'3mm' is not an angle", "'3deg'"]),
    ("5 percent", "angle", ["is not an angle"]),
    ("1 kg", "acceleration", ["is not an acceleration"]),
    ("1g", "acceleration", ["is not an acceleration"]),
    ("5 deg/s", "velocity", ["is not a velocity", "contains an angle"]),
    ("5mm", "dimensionless", ["is not a pure number"]),
    ("3deg", "dimensionless", ["is not a pure number"]),
    ("twelve mm", "length", ["cannot read 'twelve mm' as a length"]),
    ("12 parsecs per", "length", ["cannot read"]),
    ("", "time", ["empty value; give a time"]),
    ("   ", "angle", ["empty value; give an angle"]),
    (True, "mass", ["expected a mass"]),
    ("nan", "length", ["not a finite number"]),
    ("inf mm", "length", ["not a finite number"]),
    (float("inf"), "frequency", ["not a finite number"]),
])
def test_bad_inputs_name_the_field_the_value_and_what_is_allowed(value, dimension, words):
    with pytest.raises(InputError) as exc:
        parse_quantity(value, dimension, name="--x")
    msg = str(exc.value)
    assert msg.startswith("--x: ") and "\n" not in msg
    for word in words:
        assert word in msg, msg
    assert " a angle" not in msg and " a acceleration" not in msg


def test_micro_sign_is_kept_in_messages():
    with pytest.raises(InputError, match="'20µm' is not a time"):
        parse_quantity("20µm", "time")


def test_unknown_dimension_is_a_programming_error():
    with pytest.raises(ValueError, match="unknown dimension"):
        parse_quantity("1m", "lenght")


@pytest.mark.parametrize("unit", sorted(COMMON_UNITS))
def test_fast_table_agrees_with_pint(unit):
    dimension, factor = COMMON_UNITS[unit]
    q = _registry().Quantity(f"1 {unit}")
    reference = q.to("radian" if dimension == "angle" else DIMENSIONS[dimension]).magnitude
    assert factor == pytest.approx(reference, rel=1e-15)
    assert parse_quantity(f"7 {unit}", dimension) == pytest.approx(7 * reference, rel=1e-14)


def test_common_units_do_not_import_pint():
    import subprocess
    import sys

    code = ("import sys; from pdamper.units import parse_quantity as p; "
            "p('120mm', 'length'); p('2Hz', 'frequency'); p('3deg', 'angle'); p('149g', 'mass'); "
            "print('pint' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


# --- the Python API's conversion: to_si and the quantities decorator (issue 17, part 4) ---

import numpy as np  # noqa: E402
import pint  # noqa: E402

from pdamper.units import quantities, to_si  # noqa: E402

U = pint.UnitRegistry()


def test_parse_quantity_takes_pint_quantities():
    assert parse_quantity(13 * U.mm, "length") == 0.013
    assert parse_quantity(3 * U.deg, "angle") == pytest.approx(math.radians(3), rel=1e-14)
    with pytest.raises(InputError, match="expected one value"):
        parse_quantity([1, 2] * U.mm, "length")
    with pytest.raises(InputError, match="'5 kg' is not a length"):
        parse_quantity(5 * U.kg, "length")


def test_to_si_leaves_numbers_and_arrays_as_they_are():
    a = np.array([0.1, 0.2])
    for v in (0.12, 3, a, None, np.float64(0.5)):
        assert to_si(v, "length") is v


def test_to_si_texts_quantities_and_lists():
    assert to_si("120mm", "length") == 0.12
    assert to_si(120 * U.mm, "length") == 0.12
    np.testing.assert_array_equal(to_si([1.0, 2.0] * U.s, "time"), [1.0, 2.0])
    assert to_si(("5mm", 0.01), "length") == (0.005, 0.01)
    assert to_si("1.1 kN/m", None, unit="N/m") == 1100.0
    assert to_si(2 * U.kN / U.m, None, unit="N/m") == 2000.0
    with pytest.raises(InputError, match=r"k: '2 kg' is not in N/m.*e\.g\. '1 N/m'"):
        to_si("2 kg", None, unit="N/m", name="k")


def test_quantities_decorator():
    @quantities(x="length", f="frequency")
    def g(x, *, f=1.0):
        return x * f

    assert g("2mm", f="3Hz") == g(0.002, f=3.0) == pytest.approx(0.006)
    assert g(2 * U.mm, f=3 * U.Hz) == pytest.approx(0.006)
    assert g.__quantities__ == {"x": "length", "f": "frequency"}
    with pytest.raises(InputError, match="x: '2 s' is not a length"):
        g("2 s")
    with pytest.raises(TypeError, match="has no argument"):
        quantities(y="length")(lambda x: x)
