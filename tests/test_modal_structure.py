"""Structures of several modes (``[structure] modes`` or ``matrices``): the compiled modal step
against the modal superposition of the closed forms, the truncation error, the example mast's
matrices against the cantilever's closed form, the coupled ledger with a bed, the config errors."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.config import case_from_dict, case_to_dict, load_case, loads_case
from pdamper.errors import InputError
from pdamper.structure import CoupledStructure, ModalStructure
from pdamper.params import Case, Numerics, ParticleSet
from pdamper.run import run_case
from pdamper.simulation import run_bare_structure
from pdamper.theory import oscillator_response
from script_loader import load_script

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
TWO = ({"frequency": 2.0, "damping_ratio": 0.005, "modal_mass": 7.0, "damper": 1.0, "force": 1.0, "response": 0.4},
       {"frequency": 5.3, "damping_ratio": 0.01, "modal_mass": 3.0, "damper": -0.6, "force": 0.8, "response": 1.2})


def _mast():
    return load_script("examples/mast_matrices.py")


def _superposition(t, modes, q0, v0, f0=0.0, ff=0.0):
    """x at the damper and at the response point: sum over the modes of each mode's closed form
    (theory.oscillator_response with the generalised force phi_f F0)."""
    x = np.zeros_like(t)
    xr = np.zeros_like(t)
    for m, a, b in zip(modes, q0, v0):
        k = m["modal_mass"] * (2 * math.pi * m["frequency"]) ** 2
        q, _, _ = oscillator_response(t, mass=m["modal_mass"], stiffness=k, damping_ratio=m["damping_ratio"],
                                      force_amplitude=m["force"] * f0, force_frequency=ff, displacement=a, velocity=b)
        x += m["damper"] * q
        xr += m["response"] * q
    return x, xr


def test_two_mode_free_decay_is_the_modal_superposition():
    s = ModalStructure(modes=TWO, displacement=0.02)
    # released in the static shape of a load at the damper: q_k = phi_k(d) P / k_k, x_d = 20 mm
    k = np.array([m["modal_mass"] * (2 * math.pi * m["frequency"]) ** 2 for m in TWO])
    pd = np.array([m["damper"] for m in TWO])
    q0 = pd / k * 0.02 / np.sum(pd**2 / k)
    rec = run_bare_structure(s, 8.0, sample_rate=1000.0, time_step=1e-5)
    x, xr = _superposition(rec.time, TWO, q0, np.zeros(2))
    assert np.max(np.abs(rec.displacement - x)) / 0.02 < 1e-6
    assert np.max(np.abs(rec.response_displacement - xr)) / 0.02 < 1e-6
    # both modes are in the motion: without the second, the response point would be off by far
    # more than the step's error
    _, xr1 = _superposition(rec.time, TWO[:1], q0[:1], np.zeros(1))
    assert np.max(np.abs(rec.response_displacement - xr1)) > 0.05 * np.max(np.abs(xr))
    assert rec.balance_error() < 1e-6


def test_two_mode_forced_response_from_rest_and_its_steady_amplitude():
    s = ModalStructure(modes=TWO, force_amplitude=0.4, force_frequency=2.1, displacement=0.003, velocity=0.01)
    rec = run_bare_structure(s, 12.0, sample_rate=1000.0, time_step=1e-5)
    q0, v0 = s.initial_modes()
    x, xr = _superposition(rec.time, TWO, q0, v0, f0=0.4, ff=2.1)
    scale = np.max(np.abs(x))
    assert np.max(np.abs(rec.displacement - x)) / scale < 1e-6
    assert np.max(np.abs(rec.response_displacement - xr)) / np.max(np.abs(xr)) < 1e-6
    # the steady amplitude: |sum_k phi_d phi_f F0 / (k_k - m_k W^2 + i c_k W)|
    w = 2 * math.pi * 2.1
    h = sum(m["damper"] * m["force"] * 0.4 / (m["modal_mass"] * ((2 * math.pi * m["frequency"]) ** 2 - w * w)
                                              + 2j * m["damping_ratio"] * m["modal_mass"] * 2 * math.pi
                                              * m["frequency"] * w) for m in TWO)
    assert s.steady_amplitude([2.1], 0.4)[0] == pytest.approx(abs(h), rel=1e-12)
    assert rec.balance_error() < 1e-6


def test_one_mode_given_as_data_is_the_single_mode_structure():
    one = ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.005, "modal_mass": 7.0, "damper": 1.0},),
                         displacement=0.02)
    single = CoupledStructure(mass=7.0, stiffness=7.0 * (4 * math.pi) ** 2, damping_ratio=0.005, displacement=0.02)
    a, b = run_bare_structure(one, 3.0), run_bare_structure(single, 3.0)
    assert np.max(np.abs(a.displacement - b.displacement)) < 1e-12 * 0.02
    assert one.steady_amplitude([1.9, 2.0], 0.4, added_mass=0.15) == pytest.approx(
        single.steady_amplitude([1.9, 2.0], 0.4, added_mass=0.15), rel=1e-9)


def test_mast_matrices_give_the_cantilever_frequencies():
    from scipy.linalg import eigh

    mast = _mast()
    z = np.load(EXAMPLES / "mast.npz")
    M, K = z["M"], z["K"]
    assert np.array_equal(M, mast.cantilever_matrices()[0]) and np.array_equal(K, mast.cantilever_matrices()[1])
    w2 = eigh(K, M, eigvals_only=True, subset_by_index=[0, 1])
    f = np.sqrt(w2) / (2 * math.pi)
    f1, f2 = mast.closed_form_frequencies()
    assert f[0] == pytest.approx(f1, rel=1e-5) and f[1] == pytest.approx(f2, rel=1e-5)
    assert f1 == pytest.approx(2.0, rel=0.01)
    # cubic beam elements are exact for a static tip load: (K^-1)_tip = L^3 / (3 EI)
    area, inertia = mast.section()
    tip = np.linalg.solve(K, np.eye(K.shape[0])[:, 38])[38]
    assert tip == pytest.approx(mast.LENGTH**3 / (3 * mast.E * inertia), rel=1e-10)


def test_the_modal_example_is_the_fe_example_s_first_two_modes():
    modal = load_case(EXAMPLES / "mast_modal.toml").drive
    fe = load_case(EXAMPLES / "mast_fe.toml").drive
    assert modal.n_modes == 2 and fe.n_modes == 4
    assert modal.mode_frequencies == pytest.approx(fe.mode_frequencies[:2], rel=1e-4)
    # the FE modes are mass-normalised (m = 1): at the tip the modal mass is 1 / phi_tip^2
    m = fe._modal
    assert modal._modal["modal_mass"] == pytest.approx(1 / m["damper"][:2] ** 2, rel=1e-3)
    assert modal._modal["response"] == pytest.approx(m["response"][:2] / m["damper"][:2], abs=1e-4)


def test_truncation_error_is_the_static_compliance_missed_by_the_dropped_modes(tmp_path):
    z = np.load(EXAMPLES / "mast.npz")
    full = np.linalg.solve(z["K"], np.eye(40)[:, 38])[38]
    errs = []
    for kept in (1, 2, 4, 8):
        s = ModalStructure(matrices=str(EXAMPLES / "mast.npz"), damper_dof=38, damping_ratio=0.005,
                           modes_kept=kept, displacement=0.01)
        pd = s._modal["damper"]
        w2 = (2 * math.pi * s.mode_frequencies) ** 2
        assert s.truncation_error == pytest.approx((full - np.sum(pd**2 / w2)) / full, rel=1e-9)
        errs.append(s.truncation_error)
    # the cantilever: mode 1 at the tip has k_1 = (beta_1 L)^4 EI / (4 L^3) against 3 EI / L^3 statically,
    # so the first mode alone misses 1 - 12 / (beta_1 L)^4 = 0.0293 of the tip compliance
    assert errs[0] == pytest.approx(1 - 12 / 1.87510407**4, rel=1e-3)
    assert all(a > b > 0 for a, b in zip(errs, errs[1:]))
    assert errs[2] < 1e-3
    summary = s.structure_summary()
    assert summary["truncation_error"] == errs[-1] and summary["dofs"] == 40 and summary["modes_kept"] == 8


def test_matrix_market_and_harwell_boeing_files_give_the_npz_modes(tmp_path):
    import scipy.io
    import scipy.sparse

    z = np.load(EXAMPLES / "mast.npz")
    scipy.io.mmwrite(tmp_path / "M.mtx", z["M"])
    scipy.io.mmwrite(tmp_path / "K.mtx", z["K"])
    scipy.io.hb_write(tmp_path / "K.rua", scipy.sparse.csc_matrix(z["K"]))
    text = f"""
[particles]
count = 1
[structure]
matrices = {{ M = "M.mtx", K = "{{K}}" }}
damper_dof = 38
rayleigh = [0.0, 4e-4]
modes_kept = 3
displacement = "10mm"
"""
    ref = ModalStructure(matrices=str(EXAMPLES / "mast.npz"), damper_dof=38, rayleigh=(0.0, 4e-4), modes_kept=3,
                         displacement=0.01)
    for k in ("K.mtx", "K.rua"):
        s = loads_case(text.replace("{K}", k), base_dir=tmp_path).drive
        assert s.mode_frequencies == pytest.approx(ref.mode_frequencies, rel=1e-9)
        # Rayleigh: zeta_k = beta omega_k / 2
        assert s._modal["damping_ratio"] == pytest.approx(4e-4 * 2 * math.pi * ref.mode_frequencies / 2, rel=1e-9)


def test_config_round_trip_and_replace(tmp_path, monkeypatch):
    from pdamper.config import dumps_case

    monkeypatch.chdir(tmp_path)  # the matrices file is found wherever the written config is read
    for name in ("mast_modal", "mast_fe"):
        case = load_case(EXAMPLES / f"{name}.toml")
        again = case_from_dict(case_to_dict(case))
        assert again.drive.mode_frequencies == pytest.approx(case.drive.mode_frequencies, rel=1e-12)
        assert again == case
        assert loads_case(dumps_case(case)) == case
    from pdamper.schema import replace

    fe = load_case(EXAMPLES / "mast_fe.toml")
    assert replace(fe, {"structure.modes_kept": 2}).drive.n_modes == 2


def _case(structure_text: str) -> str:
    return "[particles]\ncount = 1\n[structure]\n" + structure_text


MODE = '{ frequency = "2Hz", damping_ratio = 0.005, modal_mass = "7kg", damper = 1.0 }'


@pytest.mark.parametrize("text, words", [
    (f'modes = [{MODE.replace("damper = 1.0", "damper = 0.0")}]\ndisplacement = "1cm"', "modes[0].damper = 0"),
    (f'modes = [{MODE.replace("frequency", "freq")}]\ndisplacement = "1cm"', "unknown key 'freq'"),
    ('modes = [{ frequency = "2Hz", damping_ratio = 0.005, damper = 1.0 }]\ndisplacement = "1cm"',
     "modes[0].modal_mass is missing"),
    (f'modes = [{MODE}]\nmatrices = "mast.npz"\ndisplacement = "1cm"', "both are given"),
    (f'modes = [{MODE}]\nmass = "7kg"\ndisplacement = "1cm"', "[structure] mass is a key of the single-mode"),
    ('mass = "7kg"\nnatural_frequency = "2Hz"\ndamper_dof = 3\ndisplacement = "1cm"', "damper_dof is a key"),
    (f'modes = [{MODE}]\ndamper_dof = 3\ndisplacement = "1cm"', "[structure] damper_dof belongs to matrices"),
    ('matrices = "mast.npz"\ndamping_ratio = 0.005\ndisplacement = "1cm"', "damper_dof is missing"),
    ('matrices = "mast.npz"\ndamper_dof = 40\ndamping_ratio = 0.005\ndisplacement = "1cm"',
     "damper_dof = 40; must be a dof index from 0 to 39"),
    ('matrices = "mast.npz"\ndamper_dof = 38\nresponse_dof = -1\ndamping_ratio = 0.005\ndisplacement = "1cm"',
     "response_dof = -1"),
    ('matrices = "mast.npz"\ndamper_dof = 38\nmodes_kept = 41\ndamping_ratio = 0.005\ndisplacement = "1cm"',
     "modes_kept = 41; must be from 1 to the number of dofs, 40"),
    ('matrices = "mast.npz"\ndamper_dof = 38\nmodes_kept = 4\ndisplacement = "1cm"', "exactly one damping"),
    ('matrices = "mast.npz"\ndamper_dof = 38\ndamping_ratio = 0.005\ndisplacement = "1cm"',
     "keep modes below 1000 Hz"),
    ('matrices = "nowhere.npz"\ndamper_dof = 3\ndamping_ratio = 0.005\ndisplacement = "1cm"', "file not found"),
])
def test_config_errors_name_the_key(text, words):
    with pytest.raises(InputError) as err:
        loads_case(_case(text), base_dir=EXAMPLES)
    assert words in str(err.value)


@pytest.mark.parametrize("bad, words", [
    ("M_not_spd", "M is not positive definite"),
    ("K_not_symmetric", "K is not symmetric"),
    ("K_singular", "K is not positive definite"),
    ("no_K", "has no array 'K'"),
    ("zero_at_damper", "every kept mode shape is zero there"),
])
def test_matrix_errors(tmp_path, bad, words):
    M = np.diag([2.0, 1.0, 1.0])
    K = np.array([[3.0, -1.0, 0.0], [-1.0, 2.0, 0.0], [0.0, 0.0, 5.0]]) * 100
    arrays = {"M": M, "K": K}
    dof = 0
    if bad == "M_not_spd":
        arrays["M"] = np.diag([2.0, -1.0, 1.0])
    elif bad == "K_not_symmetric":
        arrays["K"] = K + np.triu(np.ones((3, 3)), 1)
    elif bad == "K_singular":
        arrays["K"] = np.array([[1.0, -1.0, 0.0], [-1.0, 1.0, 0.0], [0.0, 0.0, 5.0]])
    elif bad == "no_K":
        del arrays["K"]
    else:
        dof = 2  # uncoupled from the two kept modes (the third mode, 5 Hz^2, lives at dof 2 alone)
    np.savez(tmp_path / "m.npz", **arrays)
    kept = 2 if bad == "zero_at_damper" else 3
    with pytest.raises(InputError) as err:
        ModalStructure(matrices=str(tmp_path / "m.npz"), damper_dof=dof, damping_ratio=0.01, modes_kept=kept,
                       displacement=0.01)
    assert words in str(err.value)


@pytest.mark.parametrize("integrator", ["verlet", "gear"])
def test_a_negligible_bed_leaves_the_two_mode_closed_form(integrator):
    # one 4 g sphere on modes of 7 t and 3 t: the coupled path (hold, release, recording) gives the
    # bare modal superposition, with either integrator
    modes = tuple(dict(m, modal_mass=1000 * m["modal_mass"]) for m in TWO)
    s = ModalStructure(modes=modes, displacement=0.004)
    case = Case(particles=(ParticleSet(count=1),), drive=s, numerics=Numerics(integrator=integrator),
                cycles=2, drop_cycles=0)
    res = run_case(case)
    rec = res.structure
    x, xr = _superposition(rec.time, modes, *s.initial_modes())
    assert np.max(np.abs(rec.displacement - x)) / 0.004 < 1e-5
    assert np.max(np.abs(rec.response_displacement - xr)) / 0.004 < 1e-5
    assert rec.balance_error(res.energy) < 1e-5


@pytest.mark.parametrize("integrator", ["verlet", "gear"])
def test_the_coupled_ledger_of_two_modes_and_a_bed_closes(integrator):
    case = load_case(EXAMPLES / "mast_modal.toml", {"particles.count": 16, "run.cycles": 2,
                                                    "numerics.integrator": integrator})
    res = run_case(case)
    rec = res.structure
    assert rec.balance_error(res.energy) < 5e-3
    # the bed took energy from the structure: without its share the balance is far off
    assert rec.balance_error() > 20 * rec.balance_error(res.energy)
    assert res.energy.damping[-1] + res.energy.friction[-1] > 1e-3 * rec.initial_energy
    s = res.summary()
    assert s["damper_stroke_max_m"] == pytest.approx(0.02, rel=1e-3)
    assert s["structure_amplitude_m"] < s["damper_stroke_m"]  # mid-height moves less than the tip
    assert s["modes_kept"] == 2


@pytest.mark.parametrize("integrator", ["verlet", "gear"])
def test_the_empty_container_rides_on_the_structure_in_a_run(integrator):
    # one 4 g sphere on a 7 t mode carrying a 700 kg container: the run is the closed form of the
    # mode with M + m_c (10 % more mass: 4.7 % lower frequency), not of M alone
    from pdamper.params import Container
    from pdamper.theory.oscillator import oscillator_response

    s = CoupledStructure(mass=7000.0, stiffness=7000.0 * (4 * np.pi) ** 2, damping_ratio=0.005, displacement=0.004)
    case = Case(particles=(ParticleSet(count=1),), drive=s, container=Container(mass=700.0),
                numerics=Numerics(integrator=integrator), cycles=2, drop_cycles=0)
    rec = run_case(case).structure
    carried = oscillator_response(rec.time, mass=7700.0, stiffness=s.stiffness, damping_ratio=s.damping /
                                  (2 * np.sqrt(s.stiffness * 7700.0)), displacement=0.004)[0]
    alone = oscillator_response(rec.time, mass=7000.0, stiffness=s.stiffness, damping_ratio=0.005,
                                displacement=0.004)[0]
    assert np.max(np.abs(rec.displacement - carried)) / 0.004 < 1e-5
    assert np.max(np.abs(rec.displacement - alone)) / 0.004 > 0.1
    assert rec.mass_kg == 7700.0


def test_rayleigh_damping_given_as_zeta_at_two_modes():
    from pdamper.structure import rayleigh_coefficients

    mast = EXAMPLES / "mast.npz"
    kw = dict(matrices=str(mast), damper_dof=38, modes_kept=4, displacement=0.01)
    s = ModalStructure(rayleigh_modes=(1, 3), rayleigh_ratios=(0.01, 0.02), **kw)
    z, w = s.mode_damping_ratios, 2 * np.pi * s.mode_frequencies
    assert z[0] == pytest.approx(0.01, rel=1e-12) and z[2] == pytest.approx(0.02, rel=1e-12)
    alpha, beta = rayleigh_coefficients((w[0], w[2]), (0.01, 0.02))
    np.testing.assert_allclose(z, alpha / (2 * w) + beta * w / 2, rtol=1e-12)  # every mode from the two
    same = ModalStructure(rayleigh=(alpha, beta), **kw)  # the [alpha, beta] form gives the same modes
    np.testing.assert_allclose(same.mode_damping_ratios, z, rtol=1e-12)
    # a mode beyond the kept ones may set it: its frequency is computed for the fit
    far = ModalStructure(rayleigh_modes=(1, 6), rayleigh_ratios=(0.01, 0.01), **kw)
    assert far.n_modes == 4 and far.mode_damping_ratios[0] == pytest.approx(0.01, rel=1e-12)
    assert s.structure_summary()["mode_damping_ratios"] == pytest.approx(z.tolist())
    for bad, words in ((dict(rayleigh_modes=(1, 3)), "rayleigh_ratios is missing"),
                       (dict(rayleigh_modes=(1, 1), rayleigh_ratios=(0.01, 0.01)), "two different mode numbers"),
                       (dict(rayleigh_modes=(1, 3), rayleigh_ratios=(0.01, 1.5)), "rayleigh_ratios"),
                       (dict(rayleigh_modes=(1, 3), rayleigh_ratios=(0.01, 0.01), damping_ratio=0.01),
                        "exactly one damping"),
                       (dict(rayleigh_modes=(1, 2), rayleigh_ratios=(0.05, 0.0)), "negative damping ratio")):
        with pytest.raises(InputError, match=words):
            ModalStructure(**kw, **bad)


def test_rayleigh_by_two_modes_from_a_config_round_trips_and_prints_each_zeta(tmp_path):
    from click.testing import CliRunner

    from pdamper.cli.common import main
    from pdamper.config import dumps_case, loads_case

    text = ("[particles]\ncount = 1\n[structure]\nmatrices = 'mast.npz'\ndamper_dof = 38\nmodes_kept = 3\n"
            "rayleigh_modes = [1, 3]\nrayleigh_ratios = [0.01, 0.01]\ndisplacement = '10mm'\n")
    case = loads_case(text, base_dir=EXAMPLES)
    assert case.drive.rayleigh_modes == (1, 3)
    assert loads_case(dumps_case(case)) == case
    cfg = tmp_path / "r.toml"
    cfg.write_text(dumps_case(case))
    r = CliRunner().invoke(main, ["run", str(cfg), "--set", "run.cycles=0.2", "--set", "run.drop_cycles=0",
                                  "--json"])
    assert r.exit_code == 0, r.output
    out = __import__("json").loads(r.stdout)
    assert out["mode_damping_ratios"][0] == pytest.approx(0.01) and out["mode_damping_ratios"][2] == pytest.approx(0.01)
