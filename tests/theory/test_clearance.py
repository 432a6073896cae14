"""Clearance, eq. (6), and the container length of cuboid and cylinder."""

import math

import pytest

from pdamper.errors import InputError
from pdamper.theory import clearance, container_length


def test_paper_clearances_for_the_cuboid():
    # Sect. 4.2: L = 120 mm, N_p,max = 48 gives h_36 = 30 mm and h_44 = 10 mm.
    assert clearance(0.120, 36, 48) == pytest.approx(0.030, rel=1e-12)
    assert clearance(0.120, 44, 48) == pytest.approx(0.010, rel=1e-12)


def test_cylinder_uses_twice_the_radius():
    length = container_length("cylinder", container_radius=0.039)
    assert length == pytest.approx(0.078, rel=1e-12)
    # Sect. 6.3: 30 and 42 spheres give about the cuboid's 30 and 10 mm.
    assert clearance(length, 30, 48) == pytest.approx(0.02925, rel=1e-12)
    assert clearance(length, 42, 48) == pytest.approx(0.00975, rel=1e-12)


def test_cuboid_length_is_passed_through():
    assert container_length("cuboid", length=0.12) == 0.12


def test_full_layer_has_no_clearance_and_one_sphere_almost_all():
    assert clearance(0.12, 48, 48) == 0.0
    assert clearance(0.12, 1, 48) == pytest.approx(0.12 * 47 / 48)


def test_whole_valued_floats_count_as_particle_numbers():
    assert clearance(0.12, 36.0, 48.0) == clearance(0.12, 36, 48)


@pytest.mark.parametrize(
    "args, field",
    [
        ((0.12, 50, 48), "particles = 50"),
        ((0.12, 0, 48), "particles = 0"),
        ((0.12, -3, 48), "particles = -3"),
        ((0.12, 36.5, 48), "particles = 36.5"),
        ((0.12, True, 48), "particles = True"),
        ((0.12, 36, 0), "max_particles = 0"),
        ((0.12, 36, math.inf), "max_particles = inf"),
        ((-0.12, 36, 48), "length = -0.12"),
        ((0.0, 36, 48), "length = 0"),
        ((math.nan, 36, 48), "length = nan"),
        (("12kg", 36, 48), "length: '12kg' is not a length"),
    ],
)
def test_bad_clearance_inputs_name_the_field_and_value(args, field):
    with pytest.raises(InputError) as info:
        clearance(*args)
    assert field in str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(
    "kwargs, text",
    [
        ({"shape": "sphere", "length": 0.1}, "cuboid, cylinder"),
        ({"shape": "cuboid"}, "length"),
        ({"shape": "cuboid", "length": 0.1, "container_radius": 0.04}, "cylinder only"),
        ({"shape": "cylinder"}, "container_radius"),
        ({"shape": "cylinder", "container_radius": 0.04, "length": 0.1}, "cuboid only"),
        ({"shape": "cylinder", "container_radius": -0.04}, "container_radius = -0.04"),
        ({"shape": "cylinder", "container_radius": "4cm", "radius": 0.04}, "give container_radius only"),
    ],
)
def test_bad_container_inputs(kwargs, text):
    with pytest.raises(InputError) as info:
        container_length(**kwargs)
    assert text in str(info.value)


def test_old_radius_keyword_still_works_and_warns():
    with pytest.warns(DeprecationWarning, match="container_radius"):
        old = container_length("cylinder", radius=0.039)
    assert old == container_length("cylinder", container_radius=0.039) == container_length("cylinder", None, "39mm")
