"""Several dampers through the studies: transient, decay and response run the coupling loop, with
locked beds (a row of spheres wall to wall: each the structure's rigid mass at its point, exactly
solved) so each answer has a closed form."""

from __future__ import annotations

import numpy as np
import pytest

from dem_fixtures import locked_case
from pdamper.config import loads_case
from pdamper.studies.structure import run_decay, run_response
from pdamper.studies.transient import run_transient

PULSE = 'kind = "force_history"\ntime = [0, 0.01, 0.02, 0.0201]\nforce = [0, 20.0, 0, 0]\nduration = 0.4'


@pytest.fixture(scope="module")
def frame(tmp_path_factory):
    """A 4-storey shear frame as matrices (2 kg floors, 3 kN/m storeys, Rayleigh damping)."""
    n, m, k = 4, 2.0, 3000.0
    K = np.diag([2 * k] * (n - 1) + [k]) - k * (np.eye(n, k=1) + np.eye(n, k=-1))
    path = tmp_path_factory.mktemp("frame") / "shear.npz"
    np.savez(path, M=np.eye(n) * m, K=K)
    return f'matrices = "{path}"\ndamper_dof = [3, 1]\nrayleigh = [0.3, 0.001]'


def test_transient_with_two_dampers_reports_each_and_is_the_frame_carrying_them(frame):
    case = locked_case(PULSE, structure=frame)
    s = run_transient(case).summary
    assert s["dampers"] == 2 and len(s["damper_points_peak_m"]) == 2 and s["bed_masses_kg"] == [case.bed_mass] * 2
    assert s["coupling"]["coupling"] == "loop" and s["coupling"]["dampers"] == 2
    solid = case.running_drive.carrying([case.bed_mass, case.bed_mass])
    from pdamper.structure.linear import dof_response

    t = np.arange(1, 401) * 1e-3
    _, x = dof_response(solid, t)
    np.testing.assert_allclose(s["peak_m"], np.max(np.abs(x), axis=0), rtol=3e-5)
    assert s["energy_balance_error"] < 1e-3  # the coupled ledger, under a force
    assert s["damper_points_peak_m"][0] == pytest.approx(s["peak_m"][3]) and s["damper_points_peak_m"][1] == \
        pytest.approx(s["peak_m"][1])
    assert all(r < 1 for r in s["peak_reduction"])  # a rigid mass lowers a pulse's peak here


def test_decay_with_two_dampers_on_one_mode():
    """Two [[damper]] tables of locked beds on one mode released from 3 mm: the decay of the mode
    carrying both beds (closed form)."""
    text = locked_case(PULSE, text=True).split("[load]")[0].replace('damping_ratio = 0.02',
                                                                      'damping_ratio = 0.02\ndisplacement = "3mm"')
    case = loads_case(text + "[run]\ncycles = 2\n[[damper]]\n[[damper]]\n")
    res = run_decay(case)
    assert res.summary["dampers"] == 2
    solid = case.running_drive.carrying(2 * case.bed_mass)
    exact = solid.motion(res.time)[0]
    assert np.max(np.abs(res.damped - exact)) < 3e-5 * 3e-3


def test_response_with_two_dampers_is_the_solid_mass_curve(frame):
    """A harmonic force at one frequency, two locked beds: the amplitude after the run equals the
    structure carrying both beds run the same way (exactly), and the solid-mass closed form is that
    structure's steady amplitude."""
    case = loads_case(locked_case(PULSE, structure=frame, text=True).split("[load]")[0]
                      .replace("rayleigh = [0.3, 0.001]", 'rayleigh = [3.0, 0.001]\nforce_amplitude = "5N"\n'
                               'force_frequency = "3Hz"') + "[run]\ncycles = 6\n")
    res = run_response(case, [2.8], force_amplitude=5.0, measure_cycles=2)
    p = res.points[0]
    assert len(p["damper_points_amplitude_m"]) == 2
    from pdamper.analysis.decay import harmonic_amplitude
    from pdamper.structure.backend import bare_modal_states

    solid = case.running_drive.carrying([case.bed_mass, case.bed_mass])
    import dataclasses

    forced = dataclasses.replace(case.drive, force_amplitude=5.0, force_frequency=2.8, displacement=0.0,
                                 velocity=0.0).carrying([case.bed_mass, case.bed_mass])
    t = np.arange(1, int(6 / 2.8 * 1000) + 1) * 1e-3  # the run's samples: whole ones in 6 periods
    q, _, _ = bare_modal_states(forced, t)
    x = q @ forced.damper_shapes()[0]
    assert p["amplitude_m"] == pytest.approx(harmonic_amplitude(t, x, 2.8, cycles=2), rel=1e-4)
    expected = solid.steady_amplitude([2.8], 5.0)[0]
    assert res.summary["amplitude_solid_mass_m"][0] == pytest.approx(expected, rel=1e-12)
