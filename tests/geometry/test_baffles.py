"""Inner baffles: the plate's signed distance, its place among the walls, and spheres that hit it
or pass under its gap."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.config import case_from_dict, case_to_dict, loads_case
from pdamper.errors import InputError
from pdamper.geometry import Baffle, Cuboid, Cylinder
from pdamper.geometry.walls import BOX_OUTSIDE, box_outside, wall_distances
from pdamper.materials import SILICONE
from pdamper.params import Container

from ..dem_fixtures import BOX, R, run, still_case


def _distance(row, p):
    s, n = wall_distances(np.array([BOX_OUTSIDE]), row[None, :], np.asarray([p], dtype=float))
    return s[0, 0], n[0, 0]


def test_the_plate_distance_is_euclidean_from_faces_edges_and_inside():
    row = box_outside((0.0, 0.02, 0.0), (0.001, 0.01, np.inf))
    s, n = _distance(row, (0.004, 0.02, 0.3))                   # in front of the face
    assert s == pytest.approx(0.003) and n == pytest.approx([1.0, 0.0, 0.0])
    s, n = _distance(row, (-0.004, 0.006, 0.0))                 # below-behind the lower edge
    assert s == pytest.approx(np.hypot(0.003, 0.004)) and n == pytest.approx([-0.6, -0.8, 0.0])
    s, n = _distance(row, (0.0005, 0.02, 0.0))                  # inside: the nearest face, negative
    assert s == pytest.approx(-0.0005) and n == pytest.approx([1.0, 0.0, 0.0])


def test_a_container_lists_its_baffles_after_its_walls_and_draws_them():
    c = Container(geometry=Cuboid(), baffles=(Baffle(position=-0.02), Baffle(position=0.02, gap_below=0.012)))
    kinds, data, names = c.walls()
    assert names[-2:] == ["baffle 1", "baffle 2"] and list(kinds[-2:]) == [BOX_OUTSIDE, BOX_OUTSIDE]
    assert data[-1, 1] - data[-1, 4] == pytest.approx(0.012)     # the lower edge sits 12 mm over the floor
    side = c.outline("side")
    assert len(side) == 3 and side[2][:, 1].min() == pytest.approx(0.012)
    assert "2 baffles" in c.describe()


@pytest.mark.parametrize("baffle, match", [
    (Baffle(position=0.07), "not inside the container"),
    (Baffle(position=0.0, gap_below=0.03, gap_above=0.011), "leave no plate"),
])
def test_a_baffle_that_does_not_stand_in_the_container_is_an_input_error(baffle, match):
    with pytest.raises(InputError, match=match):
        Container(geometry=Cuboid(), baffles=(baffle,))
    with pytest.raises(InputError, match="thickness"):
        Baffle(position=0.0, thickness=0.0)


def test_baffles_are_read_from_a_config_with_units_and_written_back():
    case = loads_case("""
[container]
baffles = [{position = "-20mm"}, {position = "20mm", gap_below = "12mm", material = "silicone"}]
[particles]
count = 12
""")
    b = case.container.baffles
    assert b[0].position == pytest.approx(-0.02) and b[1].gap_below == pytest.approx(0.012)
    assert b[1].material == SILICONE and b[0].material is None
    assert case_from_dict(case_to_dict(case)) == case
    with pytest.raises(InputError, match="position is missing"):
        loads_case("[container]\nbaffles = [{gap_below = '1mm'}]\n[particles]\ncount = 4\n")
    with pytest.raises(InputError, match="unknown key|not allowed|gap"):
        loads_case("[container]\nbaffles = [{position = '1mm', gap = '1mm'}]\n[particles]\ncount = 4\n")


def test_the_initial_block_leaves_the_baffles_free():
    case = loads_case("""
[container]
baffles = [{position = "-20mm"}, {position = "20mm"}]
[particles]
count = 36
""")
    from pdamper.initial import initial_positions

    pos = initial_positions(case, np.random.default_rng(0))
    for b in case.container.baffles:
        assert np.all(np.abs(pos[:, 0] - b.position) >= b.thickness / 2 + 0.005 - 1e-9)


@pytest.mark.parametrize("gap_below, passes", [(0.0, False), (0.012, True)])
def test_a_sphere_rebounds_from_a_plate_or_rolls_under_its_gap(gap_below, passes):
    # a sphere rolling at 0.2 m/s along x towards a plate at x = 0 (box 200 mm long)
    baffle = Baffle(position=0.0, thickness=0.002, gap_below=gap_below)
    case = still_case([(-0.03, R, 0.0)], [(0.2, 0.0, 0.0)], duration=0.3, mu=0.1, gravity=9.81, eps=0.9,
                      baffles=(baffle,))
    sim, res = run(case)
    x_end = sim.bodies.position[0, 0]
    if passes:
        assert x_end > 0.001 + R                                   # past the plate, under its gap
    else:
        assert x_end < -0.001 - R                                  # back in front of the plate
        assert sim.bodies.velocity[0, 0] < 0                       # moving away: it rebounded
    assert res.energy.balance_error() < 1e-3


def test_a_cylinder_takes_baffles_too():
    c = Container(geometry=Cylinder(), baffles=(Baffle(position=0.0, gap_above=0.004),))
    assert c.walls()[2][-1] == "baffle 1"
    assert len(c.outline("top")) == 2
