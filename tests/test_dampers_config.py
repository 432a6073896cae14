"""Several dampers in a config file: damper_dof = [..] and [[damper]] tables (pdamper.config,
pdamper.params.Damper): read, written back, and refused with one line where they do not fit."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.config import dumps_case, loads_case
from pdamper.errors import InputError

SDOF = '[structure]\nmass = "7kg"\nnatural_frequency = "2Hz"\ndisplacement = "5mm"\n'


@pytest.fixture()
def matrices(tmp_path):
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]]) * 3000.0
    np.savez(tmp_path / "m.npz", M=np.eye(3) * 2.0, K=K)
    return tmp_path, f'[structure]\nmatrices = "{tmp_path / "m.npz"}"\ndamping_ratio = 0.01\ndisplacement = "5mm"\n'


def test_a_list_of_damper_dofs_puts_the_same_damper_at_each(matrices):
    _, st = matrices
    case = loads_case("[particles]\ncount = 8\n" + st + "damper_dof = [2, 0]\n")
    assert case.drive.damper_dof == (2, 0) and case.damper_count == 2 and case.in_loop
    assert [d.n_particles for d in case.damper_beds()] == [8, 8]
    np.testing.assert_allclose(case.drive.damper_shapes()[1], case.drive.dof_shapes()[1][0])
    assert loads_case(dumps_case(case)) == case
    one = loads_case("[particles]\ncount = 8\n" + st + "damper_dof = [2]\n")
    assert one.drive.damper_dof == 2 and not one.in_loop  # one damper: the compiled tight coupling


def test_damper_tables_have_their_own_container_filling_and_place(matrices):
    tmp, st = matrices
    text = ('[container]\nlength = "120mm"\nmass = "50g"\n[particles]\ncount = 36\n' + st +
            '[[damper]]\ndof = 2\n[[damper]]\ndof = 1\nangle = "90deg"\n[damper.container]\nlength = "150mm"\n'
            '[damper.particles]\ncount = 40\n')
    case = loads_case(text)
    a, b = case.damper_beds()
    assert case.drive.damper_dof == (2, 1)
    assert (a.container.geometry.length, a.particles[0].count) == (0.12, 36)
    assert (b.container.geometry.length, b.container.mass, b.particles[0].count) == (0.15, 0.05, 40)
    assert b.angle == pytest.approx(np.pi / 2) and a.angle is None
    back = loads_case(dumps_case(case))
    assert back == case
    # each empty container's mass carried at its point
    s = case.running_drive
    assert s.describe().endswith("carrying the containers' 0.05, 0.05 kg, free decay from 5 mm")


def test_one_table_is_the_case_itself():
    case = loads_case("[particles]\ncount = 4\n" + SDOF + "[[damper]]\n[damper.particles]\ncount = 12\n")
    assert case.dampers == () and case.particles[0].count == 12 and not case.in_loop


def test_two_tables_on_one_mode_sit_on_its_dof():
    case = loads_case("[particles]\ncount = 4\n" + SDOF + "[[damper]]\n[[damper]]\n")
    assert case.damper_count == 2 and [case.damper_point(k) for k in range(2)] == [0, 0]


@pytest.mark.parametrize("extra, words", [
    ("[[damper]]\ndof = 1\n[[damper]]\ndof = 2\n", "has one point the dampers sit on; leave dof out"),
    ("[[damper]]\nnode = 1\n[[damper]]\n", "has one point the dampers sit on; leave node out"),
    ("[[damper]]\ncolour = 1\n", "unknown key 'colour' in [damper]"),
    ("[[damper]]\n[[damper]]\nsize = 1\n", "unknown key 'size' in [damper]; allowed keys: dof, node, angle"),
    ("[[damper]]\nangle = '10deg'\n", "one damper moves along the structure's direction"),
    ("[[damper]]\ncontainer = 3\n[[damper]]\n", "container = 3: give a table"),
])
def test_damper_tables_that_do_not_fit_give_one_line(extra, words):
    with pytest.raises(InputError) as err:
        loads_case("[particles]\ncount = 4\n" + SDOF + extra)
    assert words in str(err.value) and "\n" not in str(err.value)


def test_tables_against_the_structures_points(matrices):
    _, st = matrices
    base = "[particles]\ncount = 4\n" + st
    for extra, words in (
        ("damper_dof = [2, 0]\n[[damper]]\n[[damper]]\n[[damper]]\n", "3 tables, but the structure has 2 damper points"),
        ("damper_dof = [2, 0]\n[[damper]]\ndof = 2\n[[damper]]\ndof = 1\n", "damper_dof = [2, 0] and the [[damper]] "
                                                                            "tables' dof [2, 1] differ"),
        ("[[damper]]\ndof = 2\n[[damper]]\n", "[[damper]] #2 has no dof"),
        ("[[damper]]\nnode = 2\n[[damper]]\nnode = 1\n", "placed by dof = ..."),
        ("damper_dof = [2, 7]\n", "damper_dof = [2, 7]; must be a dof index from 0 to 2"),
        ("damper_dof = []\n", "damper_dof = []: give a whole number or a list of them"),
        ("damper_dof = [1.5]\n", "damper_dof[0] = 1.5 must be a whole number"),
    ):
        with pytest.raises(InputError) as err:
            loads_case(base + extra)
        assert words in str(err.value), (extra, str(err.value))


def test_damper_tables_need_a_structure():
    with pytest.raises(InputError, match=r"^<config>: \[\[damper\]\] tables put dampers on a structure"):
        loads_case("[particles]\ncount = 4\n[[damper]]\n[[damper]]\n")
