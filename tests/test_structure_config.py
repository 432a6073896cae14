"""[structure] in config files: reading, writing back, and one-line errors naming the field."""

import math

import pytest

from pdamper.config import dumps_case, loads_case
from pdamper.errors import InputError
from pdamper.structure import CoupledStructure

BASE = """
[particles]
count = 4
[numerics]
integrator = "verlet"
[structure]
mass = "7kg"
"""


def test_natural_frequency_or_stiffness_and_round_trip():
    case = loads_case(BASE + 'natural_frequency = "2Hz"\ndamping_ratio = 0.01\ndisplacement = "10mm"\n')
    s = case.drive
    assert isinstance(s, CoupledStructure)
    assert s.stiffness == pytest.approx(7 * (4 * math.pi) ** 2) and s.natural_frequency == pytest.approx(2.0)
    assert case.duration == pytest.approx(case.cycles / 2.0)
    assert loads_case(dumps_case(case)) == case
    forced = loads_case(BASE + 'stiffness = 1105\nforce_amplitude = "0.4N"\nforce_frequency = "1.9Hz"\n')
    assert forced.drive.force_amplitude == 0.4 and forced.drive.frequency == 1.9
    assert loads_case(dumps_case(forced)) == forced


@pytest.mark.parametrize("extra, words", [
    ('natural_frequency = "2Hz"\n', ["nothing moves it", "displacement"]),
    ('stiffness = 1105\nnatural_frequency = "2Hz"\ndisplacement = "1cm"\n', ["exactly one of", "stiffness"]),
    ('stiffness = -3\ndisplacement = "1cm"\n', ["[structure] stiffness = -3", "> 0"]),
    ('stiffness = 1105\ndamping_ratio = 1.5\ndisplacement = "1cm"\n', ["damping_ratio = 1.5", "[0, 1)"]),
    ('stiffness = 1105\nforce_amplitude = "1N"\n', ["force_frequency is missing"]),
    ('stiffness = 1105\ndisplacement = "1kg"\n', ["[structure] displacement"]),
    ('stiffness = 1105\ndisplacment = "1cm"\n', ["unknown key 'displacment'", "displacement"]),
])
def test_errors_name_the_field(extra, words):
    with pytest.raises(InputError) as err:
        loads_case(BASE + extra)
    msg = str(err.value)
    assert "\n" not in msg
    for w in words:
        assert w in msg


def test_a_drive_beside_a_structure_is_the_rig_and_either_integrator_is_taken():
    # issue 30: a [drive] beside a [structure] is the damper's rig drive (Case.rig), no longer refused
    both = loads_case('[drive]\nstroke = "1cm"\n' + BASE + 'stiffness = 1105\ndisplacement = "1cm"\n')
    assert both.drive.coupled and both.rig.stroke == pytest.approx(0.01) and not both.rig.coupled
    case = loads_case(BASE.replace('"verlet"', '"gear"') + 'stiffness = 1105\ndisplacement = "1cm"\n')
    assert case.numerics.integrator == "gear" and case.drive.kind == "structure"
