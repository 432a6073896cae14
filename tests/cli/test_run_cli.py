"""``pdamper run``: JSON and table output, the run directory, one-line errors.

The DEM runs here are tiny (8 spheres, 3 cycles at 2 Hz, 50 ms settling: a few seconds each).
"""

import json

import numpy as np
import pytest
from click.testing import CliRunner

from pdamper.cli import main
from pdamper.config import load_case
from pdamper.rundir import read_run

from dem_fixtures import TINY_CONFIG as TINY  # noqa: E402


def invoke(args):
    return CliRunner().invoke(main, args)


@pytest.fixture(scope="module")
def json_run(tiny, tmp_path_factory):
    out = tmp_path_factory.mktemp("runs") / "r1"
    result = invoke(["run", str(tiny), "--json", "--out", str(out)])
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout), out


def test_json_has_the_summary(json_run):
    data, out = json_run
    for key in ("eta_star", "energy_per_cycle_J", "steps", "wall_time_s", "us_per_step",
                "ledger_dissipated_per_cycle_J", "energy_balance_error"):
        assert key in data, key
    assert 0 < data["eta_star"] < 3
    assert data["energy_per_cycle_J"] > 0
    assert data["steps"] > 1000 and data["wall_time_s"] > 0
    assert data["stroke_m"] == pytest.approx(0.013)
    assert data["particles"] == 8
    assert data["run_dir"] == str(out)


def test_out_writes_a_run_directory_that_recreates_the_case(json_run, tiny):
    data, out = json_run
    for name in ("config.toml", "signals.csv", "energy.csv", "result.json"):
        assert (out / name).is_file(), name
    assert load_case(out / "config.toml") == load_case(tiny)
    stored = read_run(out)
    assert stored.summary["eta_star"] == data["eta_star"]
    assert stored.summary["steps"] == data["steps"]


def test_rerunning_the_stored_config_repeats_the_run_bit_for_bit(json_run, tmp_path):
    data, out = json_run
    again = tmp_path / "again"
    result = invoke(["run", str(out / "config.toml"), "--json", "--out", str(again)])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["eta_star"] == data["eta_star"]
    a, b = read_run(out), read_run(again)
    np.testing.assert_array_equal(a.signals.force, b.signals.force)
    assert (out / "signals.csv").read_bytes() == (again / "signals.csv").read_bytes()


def test_table_output_with_overrides(tiny):
    result = invoke(["run", str(tiny), "--stroke", "3mm", "--cycles", "2", "--seed", "1", "--set", "particles.count=8"])
    assert result.exit_code == 0, result.output
    text = result.stdout
    assert text.splitlines()[1] == "  --set                 particles.count=8"  # the overrides echoed (issue 39)
    for words in ("eta*", "energy per cycle", "[mJ]", "ledger dissipation", "energy balance error",
                  "steps", "[us/step]", "wall time", "X = 3 mm", "2 cycles"):
        assert words in text, words
    assert "Traceback" not in result.output
    # issue 24: the steadiness line belongs to eta* and stands right under it, before the motion mode
    lines = text.splitlines()
    k = next(i for i, line in enumerate(lines) if line.strip().startswith("eta*"))
    assert "standard error over the cycles" in lines[k + 1] and lines[k + 2].strip().startswith("motion mode")


@pytest.mark.slow
def test_set_overrides_any_key(tiny, tmp_path):
    out = tmp_path / "r"
    result = invoke(["run", str(tiny), "--set", "particles.count=4", "--set", "run.cycles=2",
                     "--set", "numerics.neighbour_search=cells", "--json", "--out", str(out)])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["particles"] == 4 and data["neighbour_search"] == "cells"
    case = load_case(out / "config.toml")
    assert case.n_particles == 4 and case.cycles == 2


def one_line_error(result, *words):
    assert result.exit_code == 2, result.output
    assert "Traceback" not in result.output
    lines = [ln for ln in result.output.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("Error: "), result.output
    for w in words:
        assert w in lines[0], (w, lines[0])


def test_missing_config_file(tmp_path):
    one_line_error(invoke(["run", str(tmp_path / "nope.toml")]), "config file not found")


def test_bad_config_key_suggests_the_near_match(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(TINY.replace("stroke =", "stroek ="))
    one_line_error(invoke(["run", str(p)]), "unknown key 'stroek' in [drive]", "did you mean 'stroke'?")


def test_toml_syntax_error(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("[particles]\ncount = 8\n[drive]\nstroke = 13mm\n")
    one_line_error(invoke(["run", str(p)]), "invalid TOML", "line 4")


def test_bad_option_values(tiny):
    one_line_error(invoke(["run", str(tiny), "--stroke", "2Hz"]), "--stroke", "not a length")
    one_line_error(invoke(["run", str(tiny), "--integrator", "euler"]), "euler")
    one_line_error(invoke(["run", str(tiny), "--set", "drive.stroek=3mm"]), "did you mean 'stroke'?")
    one_line_error(invoke(["run", str(tiny), "--set", "nonsense"]), "section.key=value")
    one_line_error(invoke(["run", str(tiny), "--cycles", "1"]), "nothing after dropping 1 cycles")


def test_foreign_out_directory_is_refused_before_running(tiny, tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    one_line_error(invoke(["run", str(tiny), "--out", str(tmp_path)]), "not a pdamper run directory")


def test_help_mentions_the_options():
    result = invoke(["run", "--help"])
    assert result.exit_code == 0
    for opt in ("--stroke", "--frequency", "--cycles", "--seed", "--integrator", "--json", "--out", "--set"):
        assert opt in result.output
