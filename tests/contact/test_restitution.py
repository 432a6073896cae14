"""The restitution-law protocol (pdamper.contact.restitution): a new law is one class and one
registration line; a law of a user's own runs and is written to config files as its table; one that
cannot be tabulated once for every contact is refused in one line saying how."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import pytest

from dem_fixtures import TINY_CONFIG
from pdamper.config import case_from_dict, case_to_dict, loads_case
from pdamper.contact import (RESTITUTION_LAWS, SPEED_GRID, ConstantRestitution, RestitutionLaw, TabulatedRestitution,
                             ThorntonRestitution, kernel_law, register_restitution, restitution_value, tabulate_law)
from pdamper.engine.build import build
from pdamper.errors import InputError
from pdamper.schema import param


@dataclass(frozen=True, kw_only=True)
class LinearDrop(RestitutionLaw):
    """A law for the test: eps = high - slope * v, held at >= 0.5 (one class, one registration)."""

    high: float = param(0.95, dimension="dimensionless")
    slope: float = param(0.1, unit="s/m")
    kind: str = param("linear_drop", kind="tag", key="law")

    def restitution(self, speed, **_):
        return np.maximum(self.high - self.slope * np.asarray(speed, dtype=float), 0.5)


class Softening:
    """A user's own law: any object with restitution(speed)."""

    def restitution(self, speed):
        return 0.95 - 0.1 * np.tanh(np.asarray(speed, dtype=float))


class NeedsTheContact:
    """A user's law that needs the contact's E* (as Thornton's does)."""

    def restitution(self, speed, *, e_star):
        return np.full(np.shape(speed), 0.9)


@pytest.fixture
def linear_drop():
    register_restitution(LinearDrop)
    yield LinearDrop
    RESTITUTION_LAWS.pop("linear_drop")


def _tiny(law):
    case = loads_case(TINY_CONFIG)
    return dataclasses.replace(case, contact=dataclasses.replace(case.contact, restitution=law))


def test_the_laws_register_themselves_in_the_order_of_the_messages():
    assert list(RESTITUTION_LAWS) == ["constant", "table", "thornton"]
    assert RESTITUTION_LAWS["thornton"] is ThorntonRestitution


def test_a_new_law_is_one_class_and_one_registration_line(linear_drop):
    text = TINY_CONFIG + '\n[contact]\nrestitution = {law = "linear_drop", high = 0.9, slope = "0.2 s/m"}\n'
    case = loads_case(text)
    assert case.contact.restitution == LinearDrop(high=0.9, slope=0.2)
    # written back as its own table, read back to the same case
    assert case_to_dict(case)["contact"]["restitution"] == {"law": "linear_drop", "high": 0.9, "slope": 0.2}
    assert case_from_dict(case_to_dict(case)) == case
    # the kernels hold its table over impact speed
    table = build(case).table
    eps = np.maximum(0.9 - 0.2 * SPEED_GRID, 0.5)
    from pdamper.contact import DAMPING_LAWS

    np.testing.assert_array_equal(table.coefficient[0], DAMPING_LAWS[case.contact.damping].coefficient(eps))
    assert np.all(table.yield_pressure == 0.0)
    # its keys are checked like any law's
    with pytest.raises(InputError, match=r"law = 'linear_drop' needs 'slope'"):
        loads_case(TINY_CONFIG + '\n[contact]\nrestitution = {law = "linear_drop", high = 0.9}\n')


def test_the_three_laws_are_written_as_before():
    assert restitution_value(ConstantRestitution(value=0.8)) == 0.8
    assert restitution_value(TabulatedRestitution(speeds=(0.1, 1.0), values=(0.95, 0.8))) == {
        "law": "table", "speeds": [0.1, 1.0], "values": [0.95, 0.8]}
    assert restitution_value(ThorntonRestitution(yield_pressure=2e9)) == {"law": "thornton", "yield_pressure": 2e9}


def test_a_users_law_is_written_as_its_table_and_the_kernels_get_the_same_bits():
    own = _tiny(Softening())
    written = case_to_dict(own)["contact"]["restitution"]
    assert written["law"] == "table" and written["speeds"] == SPEED_GRID.tolist()
    read_back = case_from_dict(case_to_dict(own))
    assert read_back.contact.restitution == TabulatedRestitution.from_law(Softening())
    a, b = build(own).table, build(read_back).table
    for name in ("coefficient", "tangential_damping", "yield_pressure", "modulus", "friction"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
    np.testing.assert_array_equal(kernel_law(Softening()).kernel_table()[0], tabulate_law(Softening()))


def test_a_law_that_needs_the_contact_is_refused_in_one_line_saying_how_to_tabulate_it():
    for action in (lambda: case_to_dict(_tiny(NeedsTheContact())), lambda: build(_tiny(NeedsTheContact()))):
        with pytest.raises(InputError) as err:
            action()
        msg = str(err.value)
        assert "\n" not in msg and "object at 0x" not in msg
        assert msg.startswith("restitution law NeedsTheContact: its restitution(speed) needs more than the impact speed")
        assert "pdamper.TabulatedRestitution(speeds=pdamper.contact.SPEED_GRID, values=law.restitution(" in msg
    # the call it names works
    import pdamper
    from pdamper import contact

    law = NeedsTheContact()
    made = pdamper.TabulatedRestitution(speeds=contact.SPEED_GRID, values=law.restitution(contact.SPEED_GRID, e_star=1e9))
    assert made.values[0] == 0.9


def test_an_object_without_restitution_is_refused_in_one_line():
    with pytest.raises(InputError, match=r"^restitution law object: has no restitution\(speed\) method"):
        kernel_law(object())
