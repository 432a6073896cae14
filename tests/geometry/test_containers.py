"""Containers: the paper's floor capacity, the floor lattices, validation, drive length, meshes."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial.distance import pdist

from pdamper.errors import InputError
from pdamper.geometry import Cuboid, Cylinder, wall_distances

R = 0.005


def test_paper_cuboid_holds_48_spheres_in_one_layer():
    box = Cuboid()
    assert (box.length, box.width, box.height) == (0.120, 0.0404, 0.040)
    assert box.max_particles(R) == 48
    sites = box.floor_sites(R, 2 * R)
    assert sites.shape == (48, 2)
    # 12 along the length x 4 across the width
    assert len(np.unique(np.round(sites[:, 0], 12))) == 12
    assert len(np.unique(np.round(sites[:, 1], 12))) == 4


def test_cuboid_floor_sites_touch_the_minus_x_wall_first_and_stay_inside():
    box = Cuboid()
    sites = box.floor_sites(R, 2 * R)
    # ordered from the -x wall outwards, the first column against it
    assert np.all(np.diff(sites[:, 0]) >= 0)
    assert sites[0, 0] == pytest.approx(-box.length / 2 + R)
    # every sphere inside every wall (centre at least r from each)
    pts = np.column_stack([sites[:, 0], np.full(len(sites), R), sites[:, 1]])
    kinds, data, _ = box.walls()
    s, _ = wall_distances(kinds, np.ascontiguousarray(data), pts)
    assert np.all(s >= R - 1e-12)
    # centred across the width; neighbours one diameter apart (no overlap)
    assert np.mean(sites[:, 1]) == pytest.approx(0.0, abs=1e-15)
    assert pdist(sites).min() == pytest.approx(2 * R)


@pytest.mark.parametrize("dims,r,expected", [((0.120, 0.040, 0.04), 0.005, 48), ((0.119, 0.0404, 0.04), 0.005, 44),
                                             ((0.2, 0.1, 0.1), 0.005, 200), ((0.01, 0.01, 0.01), 0.006, 0)])
def test_cuboid_max_particles_is_the_square_layer_count(dims, r, expected):
    L, W, H = dims
    assert Cuboid(length=L, width=W, height=H).max_particles(r) == expected


def test_paper_cylinder_floor_sites_hold_44_spheres_inside_and_apart():
    cyl = Cylinder()
    assert (cyl.radius, cyl.height) == (0.039, 0.011)
    sites = cyl.floor_sites(R, 2 * R)
    assert len(sites) == 44 == cyl.max_particles(R)
    # the clearance law counts the floor area over (2r)^2, as the paper does: 48
    assert cyl.clearance_capacity(R) == 48
    assert Cuboid(length=0.12, width=0.0404, height=0.04).clearance_capacity(R) == 48
    assert np.all(np.hypot(sites[:, 0], sites[:, 1]) <= cyl.radius - R + 1e-12)
    assert pdist(sites).min() >= 2 * R - 1e-12
    # ordered from -x
    assert np.all(np.diff(sites[:, 0]) >= -1e-15)


@pytest.mark.parametrize("radius", [0.006, 0.02, 0.039, 0.1])
def test_cylinder_floor_sites_are_valid_for_other_sizes(radius):
    cyl = Cylinder(radius=radius, height=0.011)
    sites = cyl.floor_sites(R, 2 * R)
    assert len(sites) >= 1
    assert np.all(np.hypot(sites[:, 0], sites[:, 1]) <= radius - R + 1e-12)
    if len(sites) > 1:
        assert pdist(sites).min() >= 2 * R - 1e-12


def test_cylinder_too_small_for_a_sphere_has_no_sites():
    assert len(Cylinder(radius=0.004, height=0.011).floor_sites(R, 2 * R)) == 0


def test_drive_length_of_the_clearance():
    assert Cuboid().drive_length == 0.120
    assert Cylinder().drive_length == pytest.approx(0.078)


@pytest.mark.parametrize("make,field", [(lambda: Cuboid(length=-0.1), "container.length"),
                                        (lambda: Cuboid(width=0.0), "container.width"),
                                        (lambda: Cuboid(height=float("nan")), "container.height"),
                                        (lambda: Cylinder(radius=0.0), "container.radius"),
                                        (lambda: Cylinder(height=-1.0), "container.height")])
def test_non_physical_dimensions_are_rejected_naming_the_field(make, field):
    with pytest.raises(InputError, match=field):
        make()


def test_meshes_have_the_inner_dimensions():
    v, q = Cuboid().mesh()
    assert v.shape == (8, 3) and q.shape == (6, 4)
    np.testing.assert_allclose(v.min(axis=0), [-0.06, 0.0, -0.0202])
    np.testing.assert_allclose(v.max(axis=0), [0.06, 0.04, 0.0202])
    v, q = Cylinder().mesh(segments=16)
    assert v.shape == (32, 3) and q.shape == (16, 4)
    np.testing.assert_allclose(np.hypot(v[:, 0], v[:, 2]), 0.039)
