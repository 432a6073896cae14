"""Prescribed container motion: harmonic, sampled (spline), still; the compiled evaluation used in
the time loop agrees with the Python one; validation messages."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.excitation import HarmonicDrive, SampledDrive, Still
from pdamper.engine.build import drive_bundle
from pdamper.kernels.drive import drive_motion


def _kernel(drive, t):
    b = drive_bundle(drive)
    return np.array([drive_motion(b, float(tt)) for tt in np.atleast_1d(t)]).T


def test_harmonic_drive_amplitudes():
    d = HarmonicDrive(stroke=0.012, frequency=2.0)
    assert d.omega == pytest.approx(4 * math.pi)
    assert d.velocity_amplitude == pytest.approx(0.012 * 4 * math.pi)
    assert d.acceleration_amplitude == pytest.approx(0.012 * (4 * math.pi) ** 2)
    assert d.duration(20) == pytest.approx(10.0)
    t = np.linspace(0, 1, 101)
    x, v, a = d.motion(t)
    np.testing.assert_allclose(x, 0.012 * np.sin(d.omega * t), atol=1e-17)
    np.testing.assert_allclose(v, 0.012 * d.omega * np.cos(d.omega * t), atol=1e-16)
    np.testing.assert_allclose(a, -d.omega**2 * x, atol=1e-14)


@pytest.mark.parametrize("drive", [HarmonicDrive(stroke=0.012, frequency=2.0), HarmonicDrive(stroke=0.003, frequency=7.5)])
def test_compiled_harmonic_motion_matches_python_and_rests_before_the_start(drive):
    t = np.linspace(0, 0.7, 57)
    np.testing.assert_allclose(_kernel(drive, t), np.array(drive.motion(t)), rtol=1e-14, atol=1e-16)
    # settling (t < 0): at rest at x(0)
    np.testing.assert_array_equal(_kernel(drive, [-0.05, -1e-9]), np.zeros((3, 2)))


def test_still_drive_is_zero_everywhere():
    d = Still(duration_s=0.3)
    assert d.duration(5) == 0.3
    x, v, a = d.motion(np.linspace(0, 1, 5))
    assert not x.any() and not v.any() and not a.any()
    np.testing.assert_array_equal(_kernel(d, [0.0, 0.1, -1.0]), np.zeros((3, 3)))


def _sampled_sine(X=0.012, f=2.0, rate=1000.0, cycles=2, **kw):
    t = np.arange(0, cycles / f + 0.5 / rate, 1 / rate)
    return SampledDrive(time=tuple(t), position=tuple(X * np.sin(2 * math.pi * f * t)), frequency=f, **kw), t


def test_sampled_sine_is_interpolated_smoothly_between_samples():
    X, f = 0.012, 2.0
    drive, t = _sampled_sine(X, f)
    w = 2 * math.pi * f
    tt = np.linspace(0.01, t[-1] - 0.01, 997)  # between samples, away from the not-a-knot ends
    x, v, a = drive.motion(tt)
    np.testing.assert_allclose(x, X * np.sin(w * tt), atol=1e-9 * X)
    np.testing.assert_allclose(v, X * w * np.cos(w * tt), atol=1e-6 * X * w)
    np.testing.assert_allclose(a, -X * w * w * np.sin(w * tt), atol=2e-3 * X * w * w)
    assert drive.duration() == pytest.approx(t[-1])


def test_compiled_sampled_motion_matches_the_spline():
    drive, t = _sampled_sine(rate=200.0)
    tt = np.linspace(1e-9, t[-1], 301)  # the drive starts at 0+ (at t <= 0 it is at rest)
    np.testing.assert_allclose(_kernel(drive, tt), np.array(drive.motion(tt)), rtol=1e-10, atol=1e-13)
    np.testing.assert_allclose(_kernel(drive, [0.0])[1:], 0.0)


def test_compiled_sampled_motion_holds_still_outside_the_record():
    drive, t = _sampled_sine(rate=200.0)
    x0 = drive.motion(np.array([0.0]))[0][0]
    np.testing.assert_allclose(_kernel(drive, [-0.1]), [[x0], [0.0], [0.0]], atol=1e-15)
    x_end = drive.motion(np.array([t[-1]]))[0][0]
    got = _kernel(drive, [t[-1] + 0.01, t[-1] + 1.0])
    np.testing.assert_allclose(got[0], x_end, atol=1e-12)
    np.testing.assert_array_equal(got[1:], 0.0)


def test_given_velocities_are_honoured_by_a_hermite_spline():
    t = np.linspace(0, 1, 11)
    x = t**2
    v = 2 * t
    d = SampledDrive(time=tuple(t), position=tuple(x), velocity=tuple(v))
    _, vv, _ = d.motion(t)
    np.testing.assert_allclose(vv, v, atol=1e-12)
    # a cubic Hermite reproduces a quadratic exactly in between
    tt = np.linspace(0, 1, 37)
    np.testing.assert_allclose(d.motion(tt)[0], tt**2, atol=1e-14)
    np.testing.assert_allclose(_kernel(d, tt)[0], tt**2, atol=1e-14)


def test_sampled_time_is_shifted_to_start_at_zero():
    d = SampledDrive(time=(5.0, 5.1, 5.2, 5.3), position=(0.0, 0.1, 0.2, 0.3))
    assert d.time == pytest.approx((0.0, 0.1, 0.2, 0.3))


@pytest.mark.parametrize("kwargs,match", [
    (dict(stroke=0.0), "drive.stroke"),
    (dict(stroke=-0.01), "drive.stroke"),
    (dict(stroke=0.01, frequency=0.0), "drive.frequency"),
    (dict(stroke=0.01, frequency=float("inf")), "drive.frequency"),
    (dict(stroke=0.01, angle=float("nan")), "drive.angle"),
])
def test_harmonic_validation(kwargs, match):
    with pytest.raises(InputError, match=match):
        HarmonicDrive(**kwargs)


@pytest.mark.parametrize("kwargs,match", [
    (dict(time=(0, 1, 2), position=(0, 1, 2)), ">= 4 times"),
    (dict(time=(0, 1, 2, 3), position=(0, 1, 2)), ">= 4 times"),
    (dict(time=(0, 1, 1, 3), position=(0, 1, 2, 3)), "increase strictly"),
    (dict(time=(0, 1, 2, float("nan")), position=(0, 1, 2, 3)), "finite"),
    (dict(time=(0, 1, 2, 3), position=(0, 1, 2, 3), velocity=(0, 1)), "velocity must have"),
])
def test_sampled_validation(kwargs, match):
    with pytest.raises(InputError, match=match):
        SampledDrive(**kwargs)


def test_still_validation():
    with pytest.raises(InputError, match="drive.duration"):
        Still(duration_s=0.0)
