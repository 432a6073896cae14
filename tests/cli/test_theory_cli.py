"""``pdamper theory``: JSON, table, plots and one-line errors."""

import json
import math

import pytest
from click.testing import CliRunner

import pdamper.cli.theory  # noqa: F401  (registers the command)
from pdamper import theory
from pdamper.cli.common import main

BASE = ["theory", "--length", "120mm", "--particles", "36", "--max-particles", "48",
        "--frequency", "2Hz"]


def run(args):
    return CliRunner().invoke(main, args)


def run_json(args):
    result = run(args + ["--json"])
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout)


def test_json_keys_and_values_for_the_paper_cuboid():
    out = run_json(BASE + ["--tilt", "3deg"])
    assert out["clearance_m"] == pytest.approx(0.030, rel=1e-12)
    assert out["x_opt_m"] == pytest.approx(theory.X_OPT_OVER_H * 0.030, rel=1e-12)
    assert out["x_opt_over_h"] == pytest.approx(0.40752, abs=1e-5)
    assert out["eta_max"] == pytest.approx(20 / (7 * math.pi), rel=1e-12)
    assert out["accel_at_x_opt_m_s2"] == pytest.approx(out["x_opt_m"] * (4 * math.pi) ** 2)
    assert out["max_stroke_no_liftoff_m"] == pytest.approx(9.81 / (4 * math.pi) ** 2)
    assert out["min_accel_tilt_m_s2"] == pytest.approx(0.514, abs=5e-4)
    omega = 4 * math.pi
    assert out["min_stroke_tilt_m"] == pytest.approx(out["min_accel_tilt_m_s2"] / omega**2)
    assert out["x_opt_bouncing_m"] == pytest.approx(0.030 / math.pi)
    assert out["eta_max_bouncing"] == pytest.approx(4 / math.pi)
    assert out["plots"] == []
    # A = 1.93 m/s² is less than 10 g tan 3°: the paper's 36-sphere case is tilt-sensitive.
    assert any("tilt-sensitive" in w for w in out["warnings"])


def test_without_tilt_or_mass_the_optional_keys_are_absent():
    out = run_json(BASE)
    assert "min_accel_tilt_m_s2" not in out and "energy_per_cycle_at_x_opt_J" not in out
    assert out["warnings"] == []


def test_bed_mass_gives_energies_and_stroke_gives_the_operating_point():
    out = run_json(BASE + ["--bed-mass", "149g", "--stroke", "15mm"])
    v_opt = out["x_opt_m"] * 4 * math.pi
    assert out["energy_per_cycle_at_x_opt_J"] == pytest.approx(20 / 7 * 0.149 * v_opt**2)
    assert out["regime"] == "rolling collect-and-collide"
    assert out["eta_at_stroke"] == pytest.approx(theory.eta_rolling(0.015, 0.03))
    assert out["energy_per_cycle_at_stroke_j"] == out["energy_per_cycle_at_stroke_J"]  # old key kept
    assert out["energy_per_cycle_at_stroke_J"] == pytest.approx(
        theory.energy_per_cycle_rolling(0.015, 0.03, frequency=2.0, bed_mass=0.149))
    low = run_json(BASE + ["--stroke", "5mm"])
    assert low["regime"] == "scattered" and low["eta_rolling_at_stroke"] is None


def test_cylinder_uses_l_equal_2r():
    out = run_json(["theory", "--shape", "cylinder", "--container-radius", "39mm", "--particles", "42",
                    "--max-particles", "48", "--frequency", "2Hz"])
    assert out["length_m"] == pytest.approx(0.078)
    assert out["clearance_m"] == pytest.approx(0.00975)


def test_x_opt_does_not_depend_on_frequency():
    a = run_json(BASE)
    b = run_json(BASE[:-1] + ["7Hz"])
    assert a["x_opt_m"] == b["x_opt_m"]
    assert b["accel_at_x_opt_m_s2"] > a["accel_at_x_opt_m_s2"]


def test_liftoff_warning_when_x_opt_needs_more_than_g():
    out = run_json(BASE[:-1] + ["8Hz"])
    assert any("lifts off" in w for w in out["warnings"])


def test_human_table_has_units():
    result = run(BASE + ["--tilt", "3deg", "--bed-mass", "149g"])
    assert result.exit_code == 0, result.output
    text = result.stdout
    for needle in ["clearance h", "30 mm", "optimal stroke X_opt", "12.23 mm", "0.9095",
                   "m/s^2", "62.12 mm", "0.5141 m/s^2", " J "]:
        assert needle in text


def test_plot_files_are_written(tmp_path):
    eta_png, fig5_svg = tmp_path / "eta.png", tmp_path / "fig5.svg"
    out = run_json(BASE + ["--stroke", "15mm", "--plot", str(eta_png), "--fig5", str(fig5_svg)])
    assert eta_png.stat().st_size > 1000 and fig5_svg.stat().st_size > 1000
    assert out["plots"] == [str(eta_png), str(fig5_svg)]


@pytest.mark.parametrize("particles", ["30", "36", "42", "44"])
def test_fig5_at_x_opt_for_any_filling(tmp_path, particles):
    # X_opt/h recomputed from X_opt and h may fall an ulp below X_OPT_OVER_H (42 in a cylinder).
    fig5 = tmp_path / "fig5.png"
    for shape in (["--length", "120mm"], ["--shape", "cylinder", "--container-radius", "39mm"]):
        result = run(["theory", *shape, "--particles", particles, "--max-particles", "48",
                      "--frequency", "2Hz", "--fig5", str(fig5)])
        assert result.exit_code == 0, result.output
        assert fig5.stat().st_size > 1000


OPTS = ["--max-particles", "48", "--frequency", "2Hz"]


@pytest.mark.parametrize("args", [
    ["--length", "120mm", "--particles", "50", *OPTS],
    ["--length", "120mm", "--particles", "0", *OPTS],
    ["--length", "120mm", "--particles", "48", *OPTS],
    ["--length", "-120mm", "--particles", "36", *OPTS],
    ["--length", "0mm", "--particles", "36", *OPTS],
    ["--length", "120mm", "--particles", "36", "--max-particles", "0", "--frequency", "2Hz"],
    ["--length", "120mm", "--particles", "36", "--max-particles", "48", "--frequency", "0Hz"],
    ["--length", "120mm", "--particles", "36", "--max-particles", "48", "--frequency", "-2Hz"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--tilt", "90deg"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--tilt", "-1deg"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--tilt", "3"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--gravity", "0"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--bed-mass", "-1g"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--stroke", "0mm"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--kappa", "-1"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--plot", "eta.xyz"],
    ["--length", "120mm", "--particles", "36", *OPTS, "--plot", "/no/such/dir/eta.png"],
    ["--shape", "cylinder", "--particles", "36", *OPTS],
    ["--shape", "cylinder", "--container-radius", "39mm", "--length", "120mm", "--particles", "36", *OPTS],
    ["--container-radius", "39mm", "--particles", "36", *OPTS],
    ["--particles", "36", *OPTS],
])
def test_bad_input_is_one_error_line_with_exit_code_2(args):
    result = run(["theory", *args])
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and lines[0].startswith("Error: ")
    assert result.stdout == ""


@pytest.mark.parametrize("args", [
    ["--length", "12kg", "--particles", "36", *OPTS],
    ["--length", "120mm", "--particles", "many", *OPTS],
    ["--length", "120mm", "--particles", "36", "--frequency", "2Hz"],
])
def test_unreadable_options_give_exit_code_2_and_one_error_line(args):
    # Parsing errors come from click: a usage hint plus one "Error:" line, never a traceback.
    result = run(["theory", *args])
    assert result.exit_code == 2
    assert "Traceback" not in result.output
    assert sum(line.startswith("Error: ") for line in result.stderr.splitlines()) == 1


def test_old_radius_option_still_works_and_warns():
    new = ["theory", "--shape", "cylinder", "--container-radius", "39mm", "--particles", "42", "--max-particles",
           "48", "--frequency", "2Hz", "--json"]
    old = [("--radius" if a == "--container-radius" else a) for a in new]
    r_new, r_old = CliRunner().invoke(main, new), CliRunner().invoke(main, old)
    assert r_new.exit_code == r_old.exit_code == 0, r_old.output
    assert json.loads(r_old.stdout) == json.loads(r_new.stdout)
    assert "--radius is deprecated; use --container-radius" in r_old.stderr
    assert "deprecated" not in r_new.stderr
    assert json.loads(r_new.stdout)["container_radius_m"] == pytest.approx(0.039)
    both = CliRunner().invoke(main, new + ["--radius", "39mm"])
    assert both.exit_code != 0 and "give --container-radius only" in both.output
