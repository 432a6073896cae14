"""Container tilt: an orthonormal rotation composed x, then y, then z (as documented in
``pdamper.geometry.tilt``); gravity and the drive direction as seen from the tilted container."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from pdamper.geometry.tilt import container_vectors, rotation
from pdamper.params import PAPER_TILT

from dem_fixtures import R, run, still_case

G = 9.81


@pytest.mark.parametrize("tilt", [(0.0, 0.0, 0.0), PAPER_TILT, (0.3, -0.2, 0.5), (-0.7, 0.6, 0.1)])
def test_rotation_is_orthonormal_and_proper(tilt):
    q = rotation(tilt)
    np.testing.assert_allclose(q @ q.T, np.eye(3), atol=1e-15)
    assert np.linalg.det(q) == pytest.approx(1.0, abs=1e-14)


def test_rotation_order_is_x_then_y_then_z_intrinsic():
    tilt = (0.3, -0.2, 0.5)
    # intrinsic rotations about the container's own x, then y, then z: Q = Rx Ry Rz
    expected = Rotation.from_euler("XYZ", tilt).as_matrix()
    np.testing.assert_allclose(rotation(tilt), expected, atol=1e-15)
    # the order matters at these angles (so the documentation has to say which one)
    other = Rotation.from_euler("ZYX", tilt[::-1]).as_matrix()
    assert np.max(np.abs(rotation(tilt) - other)) > 1e-2


def test_single_axis_rotations_have_the_right_sense():
    a = 0.2
    ex, ey, ez = np.eye(3)
    # right-handed: about z, x turns towards y
    np.testing.assert_allclose(rotation((0, 0, a)) @ ex, [math.cos(a), math.sin(a), 0], atol=1e-15)
    # about x, y turns towards z
    np.testing.assert_allclose(rotation((a, 0, 0)) @ ey, [0, math.cos(a), math.sin(a)], atol=1e-15)
    # about y, z turns towards x
    np.testing.assert_allclose(rotation((0, a, 0)) @ ez, [math.sin(a), 0, math.cos(a)], atol=1e-15)


@pytest.mark.parametrize("alpha", [math.radians(0.1), math.radians(3.0), 0.5])
def test_tilt_about_z_gives_gravity_an_x_component_minus_g_sin_alpha(alpha):
    g, d = container_vectors((0.0, 0.0, alpha), G, 0.0)
    np.testing.assert_allclose(g, [-G * math.sin(alpha), -G * math.cos(alpha), 0.0], atol=1e-14)
    # the drive stays horizontal in the lab: seen from the pitched container it leaves the floor plane
    np.testing.assert_allclose(d, [math.cos(alpha), -math.sin(alpha), 0.0], atol=1e-15)
    assert np.linalg.norm(g) == pytest.approx(G)


@pytest.mark.parametrize("alpha", [math.radians(0.1), math.radians(3.0)])
def test_tilt_about_x_gives_gravity_a_z_component(alpha):
    g, d = container_vectors((alpha, 0.0, 0.0), G, 0.0)
    np.testing.assert_allclose(g, [0.0, -G * math.cos(alpha), G * math.sin(alpha)], atol=1e-14)
    np.testing.assert_allclose(d, [1.0, 0.0, 0.0], atol=1e-15)


@pytest.mark.parametrize("beta", [math.radians(0.1), math.radians(10.0), -0.4])
def test_tilt_about_y_turns_the_drive_direction_and_leaves_gravity_alone(beta):
    g, d = container_vectors((0.0, beta, 0.0), G, 0.0)
    np.testing.assert_allclose(g, [0.0, -G, 0.0], atol=1e-14)
    np.testing.assert_allclose(d, [math.cos(beta), 0.0, math.sin(beta)], atol=1e-15)
    # equivalent to turning the drive angle the other way in an untilted container
    _, d2 = container_vectors((0.0, 0.0, 0.0), G, beta)
    np.testing.assert_allclose(d2, [math.cos(beta), 0.0, math.sin(beta)], atol=1e-15)


def test_combined_tilt_gravity_follows_the_documented_order():
    ax, ay, az = 0.3, -0.2, 0.5
    g, _ = container_vectors((ax, ay, az), G, 0.0)
    q = rotation((ax, ay, az))
    np.testing.assert_allclose(g, q.T @ [0.0, -G, 0.0], atol=1e-14)
    # closed form for x then z (no y): g_c = g (-cos ax sin az, -cos ax cos az, sin ax)
    g2, _ = container_vectors((ax, 0.0, az), G, 0.0)
    np.testing.assert_allclose(g2, G * np.array([-math.cos(ax) * math.sin(az), -math.cos(ax) * math.cos(az),
                                                 math.sin(ax)]), atol=1e-14)


def test_drive_angle_is_measured_from_lab_x_towards_lab_z():
    _, d = container_vectors((0.0, 0.0, 0.0), G, math.radians(90.0))
    np.testing.assert_allclose(d, [0.0, 0.0, 1.0], atol=1e-15)


@pytest.mark.parametrize("axis,component,sign", [(2, 0, -1.0), (0, 2, +1.0)])
def test_a_sphere_on_the_tilted_floor_rolls_downhill(axis, component, sign):
    # +alpha about z lowers the -x end; +alpha about x lowers the +z side
    tilt = [0.0, 0.0, 0.0]
    tilt[axis] = math.radians(2.0)
    sim, _ = run(still_case([[0.0, R, 0.0]], [[0, 0, 0]], duration=0.05, mu=0.1, gravity=G, tilt=tuple(tilt)))
    assert sign * sim.bodies.velocity[0, component] > 0.0
    assert sim.bodies.velocity[0, component] == pytest.approx(sign * 5 / 7 * G * math.sin(math.radians(2.0)) * 0.05, rel=0.02)
