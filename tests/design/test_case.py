"""One case for a design (issue 30, item 5): a ``[drive]`` beside a ``[structure]`` is the damper's
rig drive (``Case.rig``); ``pdamper design --write-case`` writes the design as one such case, which
reads back as the same Case and on which sweep, fields and response run unchanged."""

import json
import math

import pytest
from click.testing import CliRunner

from pdamper.cli.common import main
from pdamper.config import case_from_dict, case_to_dict, dumps_case, load_case, loads_case
from pdamper.design import design_case, design_for_structure, load_structure
from pdamper.errors import InputError
from pdamper.excitation import HarmonicDrive
from pdamper.schema import replace
from pdamper.studies import SweepSpec

from design_helpers import F_N, FRAME, M

JOINT = FRAME.read_text(encoding="utf-8") + '\n[drive]\nstroke = "15mm"\nfrequency = "2.995Hz"\n'


def test_a_drive_beside_a_structure_is_the_rig_and_round_trips():
    case = loads_case(JOINT)
    assert case.drive.coupled and case.drive.force_amplitude == pytest.approx(1.5)
    assert case.rig == HarmonicDrive(stroke=0.015, frequency=2.995)
    text = dumps_case(case)
    assert text.index("[drive]") < text.index("[structure]")  # the rig after [particles], the structure last
    assert loads_case(text) == case and dumps_case(loads_case(text)) == text
    # the damper alone on its rig: what a sweep runs
    rig = case.on_rig
    assert rig.drive == case.rig and rig.rig is None and rig.particles == case.particles
    assert loads_case(FRAME.read_text(encoding="utf-8")).on_rig.rig is None  # no rig: the case itself
    spec = SweepSpec(base=case, strokes=[0.012, 0.015])
    assert spec.base == rig and spec.case({"drive.stroke": 0.012}, 0).drive.stroke == 0.012
    # a key of the rig by replace, as the config reader takes it
    point = {"drive.stroke": 0.012}
    assert replace(case, point) == case_from_dict(case_to_dict(case), point)
    assert replace(case, point).rig.stroke == 0.012 and replace(case, point).drive == case.drive


def test_a_rig_stands_only_beside_a_structure():
    with pytest.raises(InputError, match="rig drive stands beside a structure only"):
        replace(loads_case(JOINT), {"drive": load_case(FRAME).drive}).on_rig  # noqa: B018
    structure_only = load_case(FRAME)
    with pytest.raises(InputError, match=r"this case's drive is a \[structure\], not a \[drive\]"):
        replace(structure_only, {"drive.stroke": 0.012})
    with pytest.raises(InputError, match=r"drive is its \[structure\]; a \[drive\] beside it .* written in the file"):
        load_case(FRAME, {"drive.stroke": 0.012})


def _design(tmp_path, *extra):
    out = tmp_path / "frame_design.toml"
    args = ["design", "--structure", str(FRAME), "--force", "1.5N", "--target-ratio", "0.6", "--length",
            "100mm:130mm", "--write-case", str(out), *extra]
    r = CliRunner().invoke(main, args)
    assert r.exit_code == 0, r.output
    return out, r


def test_the_written_case_is_the_design_and_says_how_it_was_made(tmp_path):
    out, r = _design(tmp_path, "--json")
    d = json.loads(r.stdout)
    assert d["case_file"] == str(out)
    sd = design_for_structure(load_structure(FRAME).drive, force=1.5, target_ratio=0.6, length_range=(0.1, 0.13))
    expected = design_case(sd, load_structure(FRAME))
    case = load_case(out)
    assert case == expected  # reading it back gives the design's Case
    text = out.read_text(encoding="utf-8")
    assert text.endswith(dumps_case(case, name=out.name))  # the config after the header, as pdamper writes it
    fill = d["filling"]
    assert case.particles[0].count == fill["particles"]
    assert case.container.geometry.drive_length == pytest.approx(fill["length_m"])
    assert case.drive.force_amplitude == 1.5
    assert case.drive.force_frequency == pytest.approx(d["frequency_hz"], abs=1e-4)  # rounded to 0.1 mHz
    assert (case.drive.displacement, case.drive.velocity) == (0.0, 0.0)  # forced from rest
    assert case.rig.stroke == pytest.approx(d["damper_stroke_m"], abs=1e-7)  # rounded to 0.1 um
    assert case.rig.frequency == case.drive.force_frequency
    head = text.split("\n\n# pdamper case configuration")[0]
    assert all(line.startswith("#") for line in head.splitlines() if line)
    assert "--target-ratio 0.6" in head and "--length 100mm:130mm" in head
    assert f"ratio {d['reduction']:.3g}" in head and f"kept >= {d['margin']:.3g} X_opt" in head
    assert "DEM check:    not run" in head and "pdamper sweep frame_design.toml" in head


@pytest.mark.slow
def test_sweep_fields_and_response_run_on_the_written_case(tmp_path):
    out, _ = _design(tmp_path)
    store, fields = tmp_path / "sweep", tmp_path / "fields.nc"
    case = load_case(out)
    x, f = case.rig.stroke, case.rig.frequency
    runner = CliRunner()
    r = runner.invoke(main, ["sweep", str(out), "--vary", f"drive.stroke={0.6 * x}m,{1.2 * x}m", "--vary",
                             f"drive.frequency={0.98 * f}Hz,{1.02 * f}Hz", "--cycles", "3", "--set",
                             "run.drop_cycles=1", "--workers", "1", "--out", str(store), "--json"])
    assert r.exit_code == 0, r.output
    swept = json.loads(r.stdout)
    assert swept["failed_cases"] == 0 and len(swept["points"]) == 4
    assert all(p["eta_star_mean"] > 0 for p in swept["points"])  # the damper on its rig: eta* (a structure has none)
    r = runner.invoke(main, ["fields", str(store), "--out", str(fields), "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.stdout)["bed_mass_kg"] == pytest.approx(case.bed_mass)
    r = runner.invoke(main, ["response", str(out), "--fields", str(fields), "--frequencies",
                             f"{0.99 * f}Hz:{1.01 * f}Hz:3", "--extrapolate", "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["peak_reduction"] < 1.0 and len(s["frequencies_hz"]) == 3
    r = runner.invoke(main, ["response", str(out), "--frequencies", f"{f}Hz", "--cycles", "3", "--measure-cycles", "1",
                             "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["frequencies_hz"] == [pytest.approx(f)] and s["amplitude_damped_m"][0] > 0


def test_transient_runs_on_the_written_case(tmp_path):
    """``pdamper transient`` takes the written case as it is: the design's force from rest (one
    cycle here); the bare structure's swing grows as the undamped resonance's, pi n F / K after n
    cycles (to 2 %: the structure's damping and the design's resonance 0.1 % off the bare one)."""
    out, r = _design(tmp_path, "--json")
    d = json.loads(r.stdout)
    head = out.read_text(encoding="utf-8").split("\n\n# pdamper case configuration")[0]
    assert "pdamper transient frame_design.toml" in head and "Left out" not in head
    r = CliRunner().invoke(main, ["transient", str(out), "--set", "run.cycles=1", "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    f, k = d["frequency_hz"], load_structure(FRAME).drive.stiffness
    assert s["duration_s"] == pytest.approx(1 / f, rel=1e-4) and s["load_peak"] == pytest.approx(1.5, rel=1e-3)
    assert s["damper_peak_bare_m"] == pytest.approx(math.pi * 1.5 / k, rel=0.02)
    assert s["dofs"] == [0] and s["peak_m"][0] == pytest.approx(s["damper_peak_m"], rel=1e-9)


def test_a_load_in_time_of_the_structure_file_is_left_out_and_said(tmp_path):
    """A structure file with a [load] (an accelerogram) designs as the same structure; the case is
    forced by the design's force, its [load] left out, which the header says."""
    quake = FRAME.parent / "frame_quake.toml"
    assert load_structure(quake).drive.load.ground  # the file's load: an accelerogram
    out = tmp_path / "q.toml"
    r = CliRunner().invoke(main, ["design", "--structure", str(quake), "--force", "1.5N", "--target-ratio", "0.6",
                                  "--length", "100mm:130mm", "--write-case", str(out)])
    assert r.exit_code == 0, r.output
    case = load_case(out)
    head, config = out.read_text(encoding="utf-8").split("\n\n# pdamper case configuration")
    assert case.drive.load is None and case.drive.force_amplitude == 1.5 and "\n[load]" not in config
    assert "Left out:     the structure file's [load] (ground acceleration" in head


def test_a_structure_only_file_takes_the_paper_container_and_spheres(tmp_path):
    p = tmp_path / "frame.toml"
    p.write_text('[structure]\nmass = "25kg"\nnatural_frequency = "3Hz"\ndamping_ratio = 0.003\n')
    case = load_structure(p)
    assert (case.container.geometry.length, case.container.geometry.width) == pytest.approx((0.12, 0.0404))
    assert case.particles[0].radius == pytest.approx(0.005)
    assert case.drive.mass == pytest.approx(M) and case.drive.natural_frequency == pytest.approx(F_N)
    r = CliRunner().invoke(main, ["design", "--structure", str(p), "--force", "1.5N", "--json"])
    full = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--json"])
    assert r.exit_code == 0 and full.exit_code == 0, r.output + full.output
    only, ex = json.loads(r.stdout), json.loads(full.stdout)
    assert only["filling"] == ex["filling"] and only["amplitude_damper_m"] == ex["amplitude_damper_m"]


def test_a_harmonic_case_writes_its_config_the_verify_sweep_stores():
    # the sweep store writes each case's config: DriveBase.config_extra must be the drive's method
    from pdamper.config import dumps_case, loads_case
    from pdamper.excitation import HarmonicDrive
    from pdamper.params import Case, ParticleSet

    case = Case(particles=(ParticleSet(count=36),), drive=HarmonicDrive(stroke=0.015, frequency=2.995))
    assert HarmonicDrive(stroke=0.015, frequency=2.995).config_extra() == {}
    again = loads_case(dumps_case(case))
    assert again.drive == case.drive and again.particles == case.particles


def test_a_structure_file_at_rest_under_0_N_is_designed_for_the_force_given(tmp_path):
    """issue 39, item 6: a [structure] whose force_amplitude is 0 N and that has no start ("nothing
    moves it" to pdamper run) is designed for --force as a file without the key is; the text names the
    structure's modes (frequency, zeta, the shape at the damper)."""
    keys = '[structure]\nmass = "25kg"\nnatural_frequency = "3Hz"\ndamping_ratio = 0.003\n'
    zero, none = tmp_path / "zero.toml", tmp_path / "none.toml"
    zero.write_text(keys + 'force_amplitude = "0N"\n')
    none.write_text(keys)
    out = [CliRunner().invoke(main, ["design", "--structure", str(p), "--force", "0.4N", "--json"]) for p in (zero, none)]
    assert all(r.exit_code == 0 for r in out), [r.output for r in out]
    a, b = (json.loads(r.stdout) for r in out)
    assert a["filling"] == b["filling"] and a["amplitude_damper_m"] == b["amplitude_damper_m"]
    assert a["mode_table"] == {"frequency_hz": [pytest.approx(3.0)], "damping_ratio": [pytest.approx(0.003)],
                               "phi_damper": [1.0], "mass_at_damper_kg": [pytest.approx(25.0)]}
    text = CliRunner().invoke(main, ["design", "--structure", str(zero), "--force", "0.4N"]).output
    assert "  modes                 1: 3 Hz, zeta 0.3 %, phi_d 1 (25 kg at the damper)" in text.splitlines()[1]
    # a start that moves it is left as it is, and a bad value is still the reader's to refuse
    bad = tmp_path / "bad.toml"
    bad.write_text(keys + 'force_amplitude = "-1N"\n')
    r = CliRunner().invoke(main, ["design", "--structure", str(bad), "--force", "0.4N"])
    assert r.exit_code == 2 and "force_amplitude" in r.output
