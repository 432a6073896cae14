"""``structure.stiffness_scale`` and ``structure.mass_scale`` (pdamper.structure.base): K and M of every
structure model times the scales, against the closed forms of the scaled structure.

Scaling K by s_k and M by s_m keeps the mode shapes (mass-normalised to the unscaled M) and scales the
modal masses by s_m and the modal stiffnesses by s_k: every frequency moves by sqrt(s_k / s_m), the
static compliance by 1 / s_k, a ground acceleration's participation L = Phi^T M r by s_m; the damping
ratios stay as given."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.config import dumps_case, load_case, loads_case
from pdamper.errors import InputError
from pdamper.structure import CoupledStructure
from pdamper.theory.oscillator import steady_amplitude

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_a_single_mode_runs_with_its_scales_and_keeps_its_numbers():
    s = CoupledStructure(mass=7.0, stiffness=1105.0, damping_ratio=0.005, force_amplitude=0.4, force_frequency=2.0,
                         stiffness_scale=0.81, mass_scale=1.1)
    assert (s.mass, s.stiffness, s.stiffness_scale, s.mass_scale) == (7.0, 1105.0, 0.81, 1.1)  # as given
    f = np.linspace(1.5, 2.5, 7)
    exact = steady_amplitude(f, mass=7.7, stiffness=1105.0 * 0.81, damping_ratio=0.005, force_amplitude=0.4)
    np.testing.assert_allclose(s.steady_amplitude(f, 0.4), exact, rtol=1e-12)
    assert s.natural_frequency == pytest.approx(math.sqrt(1105.0 * 0.81 / 7.7) / (2 * math.pi), rel=1e-15)
    runs = s.carrying(0.0)  # what runs: the scales taken in, nothing to scale twice
    assert (runs.mass, runs.stiffness, runs.stiffness_scale, runs.mass_scale) == (7.0 * 1.1, 1105.0 * 0.81, 1.0, 1.0)
    assert runs.damping == pytest.approx(s.damping, rel=1e-15) and runs.carrying(0.0) is runs
    with_container = s.carrying(0.3)
    assert with_container.mass == pytest.approx(7.7 + 0.3, rel=1e-15) and with_container.damping == pytest.approx(
        s.damping, rel=1e-15)


@pytest.mark.parametrize("name", ["mast_modal", "mast_fe", "frame_quake", "structure_36"])
def test_every_model_scales_its_frequencies_and_keeps_shapes_and_damping(name):
    plain = load_case(EXAMPLES / f"{name}.toml").drive
    case = load_case(EXAMPLES / f"{name}.toml", {"structure.stiffness_scale": 0.8, "structure.mass_scale": 1.25})
    s = case.drive
    np.testing.assert_allclose(s.mode_frequencies, plain.mode_frequencies * math.sqrt(0.8 / 1.25), rtol=1e-12)
    np.testing.assert_allclose(s.mode_damping_ratios, plain.mode_damping_ratios, rtol=1e-12)
    m0, k0, _, pd0, _, _ = plain.modal_arrays()
    m, k, _, pd, _, _ = s.modal_arrays()
    np.testing.assert_allclose(m, 1.25 * m0, rtol=1e-12)
    np.testing.assert_allclose(k, 0.8 * k0, rtol=1e-12)
    np.testing.assert_allclose(pd, pd0, rtol=0, atol=0)
    np.testing.assert_allclose(s.dof_shapes()[1], plain.dof_shapes()[1], rtol=0, atol=0)
    # the case as written reads back into the same structure (an FE model keeps the scales beside its files)
    again = loads_case(dumps_case(case), base_dir=EXAMPLES).drive
    np.testing.assert_allclose(again.mode_frequencies, s.mode_frequencies, rtol=1e-15)
    np.testing.assert_allclose(again.modal_arrays()[0], m, rtol=1e-15)


def test_an_fe_model_scales_its_static_compliance_and_its_ground_participation():
    plain = load_case(EXAMPLES / "mast_fe.toml").drive
    s = load_case(EXAMPLES / "mast_fe.toml", {"structure.stiffness_scale": 0.5, "structure.mass_scale": 2.0}).drive
    # the compliance at the damper from the kept modes, sum phi_d^2 / k_k: 1 / stiffness_scale of the model's
    comp = lambda x: float(np.sum(x.modal_arrays()[3] ** 2 / x.modal_arrays()[1]))  # noqa: E731
    assert comp(s) == pytest.approx(comp(plain) / 0.5, rel=1e-12)
    assert s.truncation_error == pytest.approx(plain.truncation_error, rel=1e-12)
    np.testing.assert_allclose(s.ground_participation(), 2.0 * plain.ground_participation(), rtol=1e-12)


@pytest.mark.parametrize("value", [0, -0.1, "abc", float("nan"), float("inf"), True, 1e300, 0.001])
def test_a_scale_that_is_no_factor_of_a_model_is_one_line(value):
    with pytest.raises(InputError, match=r"structure\] stiffness_scale.*(must be a number from 0.01 to 100|cannot "
                                         r"read|must be a number|not a finite|expected a pure number)"):
        load_case(EXAMPLES / "structure_36.toml", {"structure.stiffness_scale": value})
