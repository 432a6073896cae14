"""The design for a structure (pdamper.design.search; issue 22, item 6): the mode as the balance
sees it, the margin above X_opt, the 25 kg / 3 Hz frame, modal and FE structures, bad inputs."""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from pdamper import theory as th
from pdamper.cli.common import main
from pdamper.design import auto_margin, design_for_structure, load_structure, operating_points, structure_mode
from pdamper.errors import InputError

from design_helpers import EXAMPLES, F0, FRAME, F_N, K, M, SPHERE, ZETA, frame


def test_the_mode_of_one_degree_of_freedom_and_its_bare_amplitude():
    md = structure_mode(frame())
    assert (md.mass, md.stiffness, md.damping) == pytest.approx((M, K, 2 * ZETA * math.sqrt(K * M)))
    assert md.frequency == pytest.approx(F_N) and md.phi_damper == md.phi_force == 1.0
    # without the damper: F / (c omega_n) = F / (2 zeta K)
    d = design_for_structure(frame(), force=F0)
    assert d.amplitude_damper_bare_m == pytest.approx(F0 / (2 * ZETA * K), rel=1e-12)


@pytest.mark.slow
def test_design_lowers_the_amplitude_and_operates_at_its_margin_above_x_opt():
    d = design_for_structure(frame(), force=F0, length_range=(0.08, 0.2), max_mass_ratio=0.01)
    assert d.amplitude_damper_m < d.amplitude_damper_bare_m
    assert d.amplitude_damper_m < d.amplitude_damper_solid_m  # not the added mass: the dissipation
    assert d.margin == auto_margin(d.filling.particles / d.filling.max_particles) and not d.margin_given
    assert d.stroke_over_x_opt >= d.margin
    assert d.filling.bed_mass_kg <= 0.01 * M * (1 + 1e-12)
    assert 0.08 <= d.filling.length_m <= 0.2
    # the modal damping: the amplitude is F / (2 zeta_total K) at the damped resonance
    assert d.zeta_total == pytest.approx(d.zeta_structure + d.zeta_damper, rel=1e-12)
    assert d.amplitude_damper_m == pytest.approx(F0 / (2 * d.zeta_total * K), rel=1e-6)
    assert d.zeta_total > d.zeta_bare
    # the margin costs amplitude: without it the laws would put the stroke nearer X_opt (more eta*)
    free = design_for_structure(frame(), force=F0, length_range=(0.08, 0.2), max_mass_ratio=0.01, margin=1.0)
    assert free.amplitude_damper_m <= d.amplitude_damper_m
    assert free.stroke_over_x_opt < d.stroke_over_x_opt
    # no filling of the range does better with the margin: one sphere fewer breaks it, one more damps less
    fill = d.filling
    md = structure_mode(frame())
    for k in (fill.particles - 1, fill.particles + 1):
        if 1 <= k < fill.max_particles and k * SPHERE <= 0.01 * M:
            x_opt = th.optimal_stroke(th.clearance(fill.length_m, k, fill.max_particles))
            pts = [p for p in operating_points(md, F0, x_opt=x_opt, bed_mass=k * SPHERE) if p.stable]
            margin = auto_margin(k / fill.max_particles)
            assert (any(p.stroke_over_x_opt < margin or p.state != "rolling" for p in pts)
                    or max(p.stroke_m for p in pts) >= d.amplitude_damper_m * (1 - 1e-6))


def test_the_frame_example_gives_a_filling_and_amplitudes():
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--mode", "1", "--force", "1.5N", "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    fill = d["filling"]
    assert 1 <= fill["particles"] < fill["max_particles"]
    assert fill["bed_mass_kg"] == pytest.approx(fill["particles"] * SPHERE)
    assert fill["clearance_m"] == pytest.approx(fill["length_m"] * (1 - fill["particles"] / fill["max_particles"]))
    assert d["damper_stroke_m"] / fill["x_opt_m"] >= 1.2
    assert d["amplitude_damper_m"] < d["amplitude_damper_bare_m"]
    assert d["frequency_hz"] < d["natural_frequency_hz"]  # the bed's effective mass lowers the resonance
    assert d["added_modal_mass_kg"] == pytest.approx(d["effective_mass_kg"])  # phi_d = 1
    assert d["energy_per_cycle_J"] == pytest.approx(
        math.pi * d["eta_star"] * fill["bed_mass_kg"] * (d["damper_stroke_m"] * 2 * math.pi * d["frequency_hz"]) ** 2)
    # the work of the force per cycle is what the structure and the damper take
    c = 2 * ZETA * math.sqrt(K * M)
    om = 2 * math.pi * d["frequency_hz"]
    assert math.pi * F0 * d["damper_stroke_m"] == pytest.approx(
        math.pi * c * om * d["damper_stroke_m"] ** 2 + d["energy_per_cycle_J"], rel=1e-9)
    assert d["damper_stroke_m"] * om**2 < th.GRAVITY  # no lift-off with the damper
    text = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N"]).output
    assert f"{d['margin']:.3g} X_opt" in text and "without damper" in text and "added mass" in text
    assert "modal damping" in text


def test_a_mode_of_a_modal_structure_uses_its_shape():
    case = load_structure(EXAMPLES / "mast_modal.toml")
    d = design_for_structure(case.drive, force=0.4, mode=1)
    assert d.phi_response == pytest.approx(0.3395)
    assert d.amplitude_response_m == pytest.approx(0.3395 * d.amplitude_damper_m, rel=1e-12)
    assert d.amplitude_damper_m < d.amplitude_damper_bare_m and d.stroke_over_x_opt >= d.margin
    assert any("other modes" in w for w in d.warnings)


@pytest.mark.parametrize("args, words", [
    (["--mode", "2"], ["--mode 2", "1 mode"]),
    (["--mode", "0"], ["--mode 0"]),
    (["--force", "0N"], ["--force"]),
    (["--force", "-1N"], ["--force"]),
    (["--force", "0.01N"], ["no filling", "its margin (by the filling fraction", "47 fillings tried"]),
    (["--force", "5N"], ["no filling", "lift"]),
    (["--stroke", "10mm"], ["--stroke", "--structure"]),
    (["--shape", "cylinder", "--width", "30mm"], ["--width", "cylinder", "cuboid"]),
])
def test_bad_inputs_name_the_option(args, words):
    base = ["design", "--structure", str(FRAME), "--force", "1.5N"]
    if "--force" in args:
        base = base[:-2]
    r = CliRunner().invoke(main, base + args)
    assert r.exit_code != 0
    assert all(w in r.output for w in words), r.output


def test_a_file_without_structure_and_a_mode_beyond_the_modes(tmp_path):
    p = tmp_path / "frame.toml"
    p.write_text('[particles]\ncount = 36\n')
    with pytest.raises(InputError, match=r"\[structure\]"):
        load_structure(p)
    r = CliRunner().invoke(main, ["design", "--structure", str(p), "--force", "1.5N"])
    assert r.exit_code != 0 and "[structure]" in r.output
    case = load_structure(EXAMPLES / "mast_modal.toml")
    with pytest.raises(InputError, match=r"^mode 3: the structure has 2 modes \(give 1 to 2"):
        design_for_structure(case.drive, force=0.4, mode=3)
    with pytest.raises(InputError, match="^force = 0.0 N is not allowed"):
        design_for_structure(frame(), force=0.0)
    r = CliRunner().invoke(main, ["design", "--frequency", "2Hz", "--stroke", "10mm", "--length", "120mm",
                                  "--width", "40.4mm", "--sphere-radius", "5mm", "--force", "1N"])
    assert r.exit_code != 0 and "--force" in r.output and "--structure" in r.output


def test_fe_modes_are_reported_in_physical_masses_at_the_damper():
    r = CliRunner().invoke(main, ["design", "--structure", str(EXAMPLES / "mast_fe.toml"), "--force", "0.3N",
                                  "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["modal_mass_kg"] == pytest.approx(1.0)  # mass-normalised FE modes ...
    assert d["mass_at_damper_kg"] == pytest.approx(1.0 / d["phi_damper"] ** 2, rel=1e-12)  # ... M at the damper
    # the mast: the beam's first mode at the tip is a quarter of its 31.9 kg (docs/structure.md)
    assert d["mass_at_damper_kg"] == pytest.approx(31.9 / 4, rel=0.01)
    assert d["mass_ratio"] == pytest.approx(d["filling"]["bed_mass_kg"] / d["mass_at_damper_kg"], rel=1e-12)
    text = CliRunner().invoke(main, ["design", "--structure", str(EXAMPLES / "mast_fe.toml"), "--force", "0.3N"]).output
    header = text.splitlines()[0]
    assert f"M = {d['mass_at_damper_kg']:.4g} kg at the damper" in header and "m = 1 kg" not in header.split("(")[0]
    added = next(line for line in text.splitlines() if line.strip().startswith("added mass"))
    assert f"{1e3 * d['effective_mass_kg']:.4g} g" in added and "at the damper" in added
    assert added.split()[2] != f"{1e3 * d['added_modal_mass_kg']:.4g}"  # not the mode-normalised number first


def test_the_filling_warnings_and_the_margin_note_are_the_designs_own():
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--margin", "1.4", "--json"])
    d = json.loads(r.stdout)
    fill = d["filling"]
    assert fill["particles"] > 36  # a larger margin, a smaller clearance: more spheres than the default's 36
    assert d["damper_stroke_m"] / fill["x_opt_m"] >= 1.4 and d["margin"] == 1.4 and d["margin_given"]
    x_opt_36 = th.optimal_stroke(th.clearance(0.12, 36, 48))
    assert not any("marginal" in w or f"{x_opt_36 * 1e3:.4g} mm" in w for w in fill["warnings"] + d["warnings"])
    text = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--margin", "1.4"]).output
    note = next(line for line in text.splitlines() if line.strip().startswith("margin:"))
    phi = fill["particles"] / fill["max_particles"]
    assert (f"X >= 1.4 X_opt (--margin 1.4; the default for this bed, {100 * phi:.3g} % filled, is "
            f"{auto_margin(phi):.3g}") in note
    default = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N"]).output
    note = next(line for line in default.splitlines() if line.strip().startswith("margin:"))
    assert "X >= 1.2 X_opt (the default for a bed 75 % filled" in note  # 36 of 48


def test_the_empty_containers_mass_moves_with_the_structure():
    """[container] mass is a key of the damper: the design and the runs put it on the structure at
    the damper (a 0.5 kg container on the 25 kg frame lowers its mode by sqrt(25/25.5))."""
    base = load_structure(FRAME)
    heavy = load_structure(FRAME, {"container.mass": "0.5kg"})
    s = heavy.running_drive
    assert s.mass == pytest.approx(25.5) and s.damping == pytest.approx(base.drive.damping, rel=1e-12)
    assert s.natural_frequency == pytest.approx(3.0 * math.sqrt(25 / 25.5), rel=1e-12)
    d0 = design_for_structure(base.drive, force=F0)
    d1 = design_for_structure(heavy.drive, force=F0, container_mass=heavy.container.mass)
    assert d1.natural_frequency_hz == pytest.approx(3.0 * math.sqrt(25 / 25.5), rel=1e-9)
    assert d1.mass_at_damper_kg == pytest.approx(25.5) and d1.container_mass_kg == 0.5
    assert d1.natural_frequency_hz < d0.natural_frequency_hz
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--json"])
    assert json.loads(r.stdout)["container_mass_kg"] == 0.0


def test_a_modal_structure_carries_the_container_as_the_full_model_does(tmp_path):
    """Two modes as data with a rigid mass at the damper against the same mass added to the
    two-dof M matrix: the carried modes' frequencies are the matrix model's eigenfrequencies."""
    from scipy.linalg import eigh

    from pdamper.structure import ModalStructure

    M2 = np.diag([3.0, 2.0])
    K2 = np.array([[600.0, -200.0], [-200.0, 400.0]])
    np.savez(tmp_path / "two.npz", M=M2, K=K2)
    s = ModalStructure(matrices=str(tmp_path / "two.npz"), damper_dof=1, damping_ratio=0.01, displacement=0.001)
    carried = s.carrying(0.4)
    exact = np.sqrt(eigh(K2, M2 + np.diag([0.0, 0.4]), eigvals_only=True)) / (2 * math.pi)
    np.testing.assert_allclose(carried.mode_frequencies, exact, rtol=1e-12)
    assert s.carrying(0.0) is s and carried == s  # a derived object, not a new config
    # a one-mode modal structure carries as the single mode does
    one = ModalStructure(modes=({"frequency": 3.0, "damping_ratio": ZETA, "modal_mass": M, "damper": 1.0},),
                         displacement=0.001)
    np.testing.assert_allclose(one.carrying(0.5).mode_frequencies, [frame().carrying(0.5).natural_frequency],
                               rtol=1e-12)
    np.testing.assert_allclose(one.carrying(0.5).mode_damping_ratios, [frame().carrying(0.5).damping_ratio],
                               rtol=1e-12)


def test_a_cylinder_is_designed_for_a_structure_too():
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--shape", "cylinder",
                                  "--length-range", "70mm:100mm", "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    fill = d["filling"]
    assert fill["shape"] == "cylinder" and 0.07 <= fill["length_m"] <= 0.1
    assert fill["clearance_m"] == pytest.approx(fill["length_m"] * (1 - fill["particles"] / fill["max_particles"]))
    assert d["damper_stroke_m"] / fill["x_opt_m"] >= 1.2
