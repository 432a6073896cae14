"""Wall primitives: signed distance and inward normal of planes and of the cylinder's curved wall,
the vectorised form against the scalar one, and the Hertz radius the engine gives each wall."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.contact.hertz_gonthier import effective_radius, hertz_stiffness
from pdamper.geometry import CYLINDER_INSIDE, PLANE, Cuboid, Cylinder, wall_distance, wall_distances
from pdamper.geometry.walls import cylinder_inside, plane
from pdamper.materials import PVC, STEEL_S235, effective_modulus
from pdamper.params import Case, Container, InitialState, ParticleSet
from pdamper.simulation import Simulation

PAPER_BOX = Cuboid()  # 120 x 40.4 x 40 mm
PAPER_CYL = Cylinder()  # R = 39 mm, H = 11 mm


def _all(kinds, data, p):
    return [wall_distance(kinds[w], data, w, *p) for w in range(len(kinds))]


# --------------------------------------------------------------------- cuboid planes

def test_cuboid_walls_are_six_planes_named_in_order():
    kinds, data, names = PAPER_BOX.walls()
    assert names == ["x_min", "x_max", "floor", "lid", "z_min", "z_max"]
    assert np.all(kinds == PLANE)
    assert data.shape == (6, 7)
    # unit normals
    np.testing.assert_allclose(np.linalg.norm(data[:, :3], axis=1), 1.0)


def test_cuboid_distances_inside_are_gaps_to_each_wall_and_normals_point_inwards():
    kinds, data, _ = PAPER_BOX.walls()
    L, W, H = PAPER_BOX.length, PAPER_BOX.width, PAPER_BOX.height
    p = (0.011, 0.007, -0.003)
    got = _all(kinds, data, p)
    expected_s = [p[0] + L / 2, L / 2 - p[0], p[1], H - p[1], p[2] + W / 2, W / 2 - p[2]]
    expected_n = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    for (s, nx, ny, nz), es, en in zip(got, expected_s, expected_n):
        assert s == pytest.approx(es, abs=1e-15)
        assert (nx, ny, nz) == en


def test_cuboid_distance_is_zero_on_a_wall_and_negative_outside():
    kinds, data, _ = PAPER_BOX.walls()
    L = PAPER_BOX.length
    s_on, *_ = wall_distance(kinds[0], data, 0, -L / 2, 0.01, 0.0)
    assert s_on == pytest.approx(0.0, abs=1e-15)
    s_out, *_ = wall_distance(kinds[0], data, 0, -L / 2 - 0.002, 0.01, 0.0)
    assert s_out == pytest.approx(-0.002, abs=1e-15)
    s_below, *_ = wall_distance(kinds[2], data, 2, 0.0, -0.001, 0.0)
    assert s_below == pytest.approx(-0.001, abs=1e-15)
    s_above_lid, *_ = wall_distance(kinds[3], data, 3, 0.0, PAPER_BOX.height + 0.003, 0.0)
    assert s_above_lid == pytest.approx(-0.003, abs=1e-15)


def test_plane_row_normalises_its_normal():
    row = plane((0.0, 3.0, 4.0), 0.5)
    np.testing.assert_allclose(row[:3], [0.0, 0.6, 0.8])
    assert row[3] == 0.5
    s, *n = wall_distance(PLANE, row[None, :], 0, 0.0, 1.0, 1.0)
    assert s == pytest.approx(0.6 + 0.8 - 0.5)
    np.testing.assert_allclose(n, [0.0, 0.6, 0.8])


# --------------------------------------------------------------------- cylinder

def test_cylinder_walls_floor_lid_and_curved_wall():
    kinds, data, names = PAPER_CYL.walls()
    assert names == ["floor", "lid", "curved"]
    assert list(kinds) == [PLANE, PLANE, CYLINDER_INSIDE]
    np.testing.assert_allclose(data[2], [0, 0, 0, 0, 1, 0, PAPER_CYL.radius])


@pytest.mark.parametrize("rho", [0.0005, 0.02, 0.034, 0.039, 0.041])
@pytest.mark.parametrize("theta", [0.0, 0.7, 2.0, -2.9])
def test_curved_wall_distance_is_radius_minus_axial_distance_and_normal_points_to_the_axis(rho, theta):
    kinds, data, _ = PAPER_CYL.walls()
    R = PAPER_CYL.radius
    y = 0.004  # the height along the axis does not matter
    p = (rho * math.cos(theta), y, rho * math.sin(theta))
    s, nx, ny, nz = wall_distance(kinds[2], data, 2, *p)
    assert s == pytest.approx(R - rho, abs=1e-15)  # > 0 inside, 0 on the wall, < 0 outside
    np.testing.assert_allclose([nx, ny, nz], [-math.cos(theta), 0.0, -math.sin(theta)], atol=1e-12)


def test_curved_wall_on_the_axis_gives_radius_and_a_unit_normal_perpendicular_to_the_axis():
    kinds, data, _ = PAPER_CYL.walls()
    s, nx, ny, nz = wall_distance(kinds[2], data, 2, 0.0, 0.005, 0.0)
    assert s == PAPER_CYL.radius
    n = np.array([nx, ny, nz])
    assert np.linalg.norm(n) == pytest.approx(1.0)
    assert abs(n[1]) < 1e-15  # perpendicular to the y axis
    # an oblique axis, on the axis: still a unit vector perpendicular to it
    axis = np.array([0.3, 0.9, 0.2])
    row = cylinder_inside((0.01, 0.0, -0.02), axis, 0.05)
    a = row[3:6]
    p = np.array([0.01, 0.0, -0.02]) + 0.7 * a
    s, *n = wall_distance(CYLINDER_INSIDE, row[None, :], 0, *p)
    assert s == pytest.approx(0.05)
    assert np.linalg.norm(n) == pytest.approx(1.0)
    assert abs(np.dot(n, a)) < 1e-12


def test_oblique_cylinder_distance_matches_geometry():
    rng = np.random.default_rng(5)
    axis = np.array([0.2, 1.0, -0.4])
    c = np.array([0.003, -0.01, 0.002])
    R = 0.03
    row = cylinder_inside(c, axis, R)[None, :]
    a = axis / np.linalg.norm(axis)
    for p in rng.uniform(-0.05, 0.05, (50, 3)):
        q = (p - c) - np.dot(p - c, a) * a
        rho = np.linalg.norm(q)
        s, *n = wall_distance(CYLINDER_INSIDE, row, 0, *p)
        assert s == pytest.approx(R - rho, abs=1e-14)
        np.testing.assert_allclose(n, -q / rho, atol=1e-12)


# --------------------------------------------------------------------- vectorised

@pytest.mark.parametrize("geometry", [PAPER_BOX, PAPER_CYL, Cuboid(length=0.2, width=0.1, height=0.1)])
def test_vectorised_distances_agree_with_the_scalar_function(geometry):
    kinds, data, _ = geometry.walls()
    data = np.ascontiguousarray(data)
    rng = np.random.default_rng(11)
    pts = rng.uniform(-0.07, 0.07, (200, 3))
    pts[:10, 0] = 0.0  # some on the cylinder's axis
    pts[:10, 2] = 0.0
    s, nrm = wall_distances(kinds, data, pts)
    assert s.shape == (200, len(kinds)) and nrm.shape == (200, len(kinds), 3)
    for i in range(len(pts)):
        for w in range(len(kinds)):
            d, nx, ny, nz = wall_distance(kinds[w], data, w, *pts[i])
            assert s[i, w] == d
            assert tuple(nrm[i, w]) == (nx, ny, nz)


# --------------------------------------------------------------------- Hertz radius per wall

def test_engine_uses_the_concave_hertz_radius_for_the_curved_wall():
    r = 0.005
    case = Case(particles=(ParticleSet(count=3, radius=r),), container=Container(geometry=PAPER_CYL),
                cycles=1, drop_cycles=0, initial=InitialState(jitter=0.0))
    sim = Simulation(case)
    R = PAPER_CYL.radius
    concave = 1.0 / (1.0 / r - 1.0 / R)
    assert concave == pytest.approx(effective_radius(r, concave_radius=R))
    assert concave > r  # a concave wall is a softer, wider contact than a flat one
    np.testing.assert_allclose(sim.walls.effective_radius[:, 2], concave, rtol=1e-14)
    np.testing.assert_allclose(sim.walls.effective_radius[:, :2], r)  # floor and lid are flat
    es = effective_modulus(STEEL_S235, PVC)
    np.testing.assert_allclose(sim.walls.stiffness[:, 2], hertz_stiffness(es, concave), rtol=1e-14)
    np.testing.assert_allclose(sim.walls.stiffness[:, 0], hertz_stiffness(es, r), rtol=1e-14)


def test_engine_uses_the_sphere_radius_for_every_cuboid_wall():
    radii = (0.005, 0.003)
    case = Case(particles=tuple(ParticleSet(count=2, radius=r) for r in radii),
                container=Container(geometry=PAPER_BOX), cycles=1, drop_cycles=0,
                initial=InitialState(jitter=0.0))
    sim = Simulation(case)
    np.testing.assert_allclose(sim.walls.effective_radius, np.repeat(np.array([0.005, 0.005, 0.003, 0.003])[:, None], 6, axis=1))
