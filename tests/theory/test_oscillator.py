"""The closed-form linear oscillator: its own equation of motion, its limits, its input checks."""

import math

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.theory import free_decay, natural_frequency, oscillator_response, steady_amplitude

M, K, Z = 7.0, 1105.0, 0.01


def test_response_satisfies_the_equation_of_motion_and_the_start():
    t = np.linspace(0, 5, 20001)
    x, v, a = oscillator_response(t, mass=M, stiffness=K, damping_ratio=Z, force_amplitude=0.3,
                                  force_frequency=1.7, displacement=0.004, velocity=-0.02)
    assert x[0] == pytest.approx(0.004, abs=1e-15) and v[0] == pytest.approx(-0.02, abs=1e-15)
    # v is dx/dt and a is dv/dt (central differences)
    dt = t[1] - t[0]
    assert np.max(np.abs(np.gradient(x, dt)[1:-1] - v[1:-1])) < 1e-5
    assert np.max(np.abs(np.gradient(v, dt)[1:-1] - a[1:-1])) < 1e-4


def test_free_decay_envelope_and_steady_amplitude_at_resonance():
    w = math.sqrt(K / M)
    wd = w * math.sqrt(1 - Z * Z)
    t = 2 * math.pi / wd * np.arange(5)
    assert np.allclose(free_decay(t, mass=M, stiffness=K, damping_ratio=Z, displacement=0.01),
                       0.01 * np.exp(-Z * w * t), rtol=1e-12)
    fn = natural_frequency(M, K)
    assert steady_amplitude(fn, mass=M, stiffness=K, damping_ratio=Z, force_amplitude=1.0) == pytest.approx(
        1 / K / (2 * Z), rel=1e-12)
    assert steady_amplitude(1e-6, mass=M, stiffness=K, damping_ratio=Z, force_amplitude=1.0) == pytest.approx(1 / K)


def test_forced_response_tends_to_the_steady_amplitude():
    f = 1.8
    t = np.linspace(60, 62, 4001)
    x, _, _ = oscillator_response(t, mass=M, stiffness=K, damping_ratio=0.05, force_amplitude=0.5, force_frequency=f)
    assert np.max(np.abs(x)) == pytest.approx(
        steady_amplitude(f, mass=M, stiffness=K, damping_ratio=0.05, force_amplitude=0.5), rel=1e-4)


@pytest.mark.parametrize("kw, word", [({"damping_ratio": 1.0}, "damping_ratio"), ({"mass": -1.0}, "mass"),
                                      ({"stiffness": 0.0}, "stiffness")])
def test_bad_inputs_name_the_field(kw, word):
    args = dict(mass=M, stiffness=K, damping_ratio=Z, displacement=0.01) | kw
    with pytest.raises(InputError, match=word):
        free_decay(0.0, **args)
