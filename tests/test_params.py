"""Parameter objects take numbers (SI), unit texts and pint quantities (issue 17, part 4).

The conversion is driven by each field's spec (:func:`pdamper.schema.convert_fields`); plain
numbers are left as the very objects given, so a case built from SI floats does not move.
"""

from __future__ import annotations

import dataclasses
import math

import pint
import pytest

import pdamper
from pdamper import (Case, ContactModel, Container, CoupledStructure, Cuboid, Cylinder, HarmonicDrive, InitialState,
                     Material, Numerics, ParticleSet, Recording, SampledDrive, Still, ThorntonRestitution,
                     TabulatedRestitution, ConstantRestitution)
from pdamper.errors import InputError
from pdamper.params import with_stroke

U = pint.UnitRegistry()


def test_the_issue_example_cuboid_from_texts():
    # was: "'120mm' m; must be a positive length"
    assert Cuboid(length="120mm", width="40.4 mm", height="4cm") == Cuboid(length=0.12, width=0.0404, height=0.04)


@pytest.mark.parametrize("make, field, expected", [
    (lambda v: Cuboid(length=v), "length", 0.12),
    (lambda v: Cylinder(radius=v), "radius", 0.12),
    (lambda v: ParticleSet(count=1, radius=v), "radius", 0.12),
    (lambda v: HarmonicDrive(stroke=v), "stroke", 0.12),
    (lambda v: Numerics(gear_tolerance=v), "gear_tolerance", 0.12),
    (lambda v: InitialState(jitter=v), "jitter", 0.12),
])
@pytest.mark.parametrize("given", ["120mm", "12 cm", 120 * U.mm, 0.12 * U.m, 0.12])
def test_lengths_in_any_form(make, field, expected, given):
    assert getattr(make(given), field) == expected


def test_every_dimension_of_a_case():
    d = HarmonicDrive(stroke=12 * U.mm, frequency="120/min", angle="90deg")
    assert (d.stroke, d.frequency, d.angle) == (0.012, 2.0, pytest.approx(math.pi / 2))
    m = Material(name="x", youngs_modulus="208GPa", poisson_ratio="30%", density=7.9 * U.g / U.cm**3)
    assert (m.youngs_modulus, m.poisson_ratio, m.density) == (208e9, 0.3, 7900.0)
    assert Recording(sample_rate="1kHz", trajectory_fps=50 * U.Hz).sample_rate == 1000.0
    n = Numerics(time_step="2us", max_impact_speed="50cm/s", max_time_step=10 * U.us, skin="1mm")
    assert (n.time_step, n.max_impact_speed, n.max_time_step, n.skin) == (2e-6, 0.5, 1e-5, 0.001)
    assert ContactModel(v_in_floor="1mm/s", tau="1000 s/m").v_in_floor == 0.001
    assert InitialState(settle_time="100ms").settle_time == 0.1
    assert Container(mass="150g", tilt=("0.1deg", 0.1 * U.deg, 0.0)).tilt[:2] == (pytest.approx(math.radians(0.1)),) * 2
    assert Case(particles=ParticleSet(count=2), gravity="1 g_0").gravity == pytest.approx(9.80665)
    s = CoupledStructure(mass="7kg", stiffness="1.105 kN/m", displacement="1cm", force_amplitude=0 * U.N)
    assert (s.mass, s.stiffness, s.displacement) == (7.0, 1105.0, 0.01)
    assert Still(duration_s="500ms").duration_s == 0.5
    assert ThorntonRestitution(yield_pressure="1GPa").yield_pressure == 1e9
    t = TabulatedRestitution(speeds=["0.1m/s", "1m/s"], values=[0.9, "80%"])
    assert (t.speeds, t.values) == ((0.1, 1.0), (0.9, 0.8))
    assert ConstantRestitution(value="90%").value == 0.9


def test_lists_and_rows():
    d = SampledDrive(time=["0s", "10ms", "20ms", "30ms"], position=[0.0, "1mm", "2mm", "1mm"])
    assert d.time == (0.0, 0.01, 0.02, 0.03) and d.position == (0.0, 0.001, 0.002, 0.001)
    i = InitialState(positions=[["5mm", "5mm", 0.0]], spins=[["10rad/s", 0, 0]])
    assert i.positions == [[0.005, 0.005, 0.0]] and i.spins == [[10.0, 0, 0]]


def test_floats_are_passed_on_untouched():
    x = 0.0123456789012345678  # any float, not one with a short decimal form
    assert HarmonicDrive(stroke=x).stroke is x
    c = Case(particles=ParticleSet(count=36), drive=HarmonicDrive(stroke=x))
    assert dataclasses.replace(c) == c and c.drive.stroke is x


@pytest.mark.parametrize("make, message", [
    (lambda: Cuboid(length="12kg"), "container.length: '12kg' is not a length (its unit is kg); use a unit such as "
                                    "'120mm' or 0.12"),
    (lambda: HarmonicDrive(stroke=3 * U.deg), "drive.stroke: '3 deg' is not a length"),
    (lambda: HarmonicDrive(stroke=0.01, frequency="2mm"), "drive.frequency: '2mm' is not a frequency"),
    (lambda: HarmonicDrive(stroke=0.01, angle="3mm"), "drive.angle: '3mm' is not an angle"),
    (lambda: Material(name="x", youngs_modulus="208 kg", poisson_ratio=0.3, density=7900),
     "material.youngs_modulus: '208 kg' is not a pressure"),
    (lambda: CoupledStructure(mass=7, stiffness="3 kg", displacement=0.01), "structure.stiffness: '3 kg' is not in N/m"),
    (lambda: ParticleSet(count=1, radius="five mm"), "particles.radius: cannot read 'five mm' as a length"),
    (lambda: Container(tilt="0.1deg"), "give three angles"),
])
def test_wrong_dimension_says_what_is_expected_with_an_example(make, message):
    with pytest.raises(InputError) as info:
        make()
    assert message in str(info.value)
    assert "\n" not in str(info.value)


def test_with_stroke_takes_units():
    c = Case(particles=ParticleSet(count=36))
    assert with_stroke(c, "13mm").drive.stroke == 0.013 == with_stroke(c, 13 * U.mm).drive.stroke


def test_the_public_api_accepts_pint_quantities_of_another_registry():
    other = pint.UnitRegistry()
    assert pdamper.Cuboid(length=other.Quantity(120, "mm")).length == 0.12
