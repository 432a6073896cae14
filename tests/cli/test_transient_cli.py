"""``pdamper transient`` and ``pdamper response --sweep/--dofs``: the JSON keys, the table, the figure,
and nothing written when a run fails."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from dem_fixtures import locked_case
from pdamper.cli import main

HAMMER = 'kind = "force_history"\ntime = [0, 0.05, 0.1]\nforce = [0, 2.0, 0]\nduration = "0.5s"'
KEYS = ("dofs", "peak_m", "rms_m", "peak_bare_m", "rms_bare_m", "peak_reduction", "rms_reduction")
EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
#: the examples cut short (8 spheres, 0.1 s of load after 20 ms of settling): that they run, not their physics
SHORT = ["--set", "particles.count=8", "--set", "initial.settle_time=0.02s"]


def run(args):
    return CliRunner().invoke(main, args)


@pytest.fixture
def config(tmp_path):
    path = tmp_path / "locked.toml"
    path.write_text(locked_case(HAMMER, text=True))
    return path


def test_transient_json_table_and_plot(config, tmp_path):
    r = run(["transient", str(config), "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert all(len(s[k]) == 1 for k in KEYS) and s["dofs"] == [0]
    assert 0 < s["peak_reduction"][0] and s["peak_m"][0] == pytest.approx(s["damper_peak_m"])
    png = tmp_path / "t.png"
    r = run(["transient", str(config), "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "peak [mm]" in r.output and "ratio" in r.output and png.stat().st_size > 10_000


@pytest.mark.parametrize("args, words", [
    (["--dofs", "7"], "--dofs: 7 is not a dof of this structure (0 to 0)"),
    (["--dofs", "0:x"], "is not a range START:STOP"),
    (["--set", "load.scale=abc"], "[load] scale"),
])
def test_a_bad_transient_says_one_line_and_writes_nothing(config, tmp_path, args, words):
    png = tmp_path / "t.png"
    r = run(["transient", str(config), "--plot", str(png), *args])
    assert r.exit_code == 2 and words in r.output and r.output.count("\n") == 1, r.output
    assert not png.exists() and list(tmp_path.iterdir()) == [config]


def test_a_transient_that_fails_in_its_run_writes_no_figure(config, tmp_path, monkeypatch):
    from pdamper.errors import SimulationError
    from pdamper.simulation import Simulation

    def broken(self, **kw):
        raise SimulationError("the run went wrong at t = 0.2 s")

    monkeypatch.setattr(Simulation, "run", broken)
    png = tmp_path / "t.png"
    r = run(["transient", str(config), "--plot", str(png)])
    assert r.exit_code == 2 and "Error: the run went wrong" in r.output
    assert list(tmp_path.iterdir()) == [config]


def test_transient_needs_a_load_in_time(tmp_path):
    path = tmp_path / "decay.toml"
    path.write_text('[particles]\ncount = 4\n[structure]\nmass = "7kg"\nnatural_frequency = "2Hz"\n'
                    'displacement = "5mm"\n')
    r = run(["transient", str(path)])
    assert r.exit_code == 2 and "needs a load in time" in r.output


def test_response_sweep_and_dofs(config, tmp_path):
    """A stepped sine both ways on the locked bed (short: the keys, not the physics, which
    tests/studies/test_transient.py checks)."""
    png = tmp_path / "s.png"
    args = ["response", str(config), "--force", "1N", "--frequencies", "2.9Hz,3.1Hz", "--cycles", "4",
            "--measure-cycles", "2", "--sweep", "both", "--dofs", "0"]
    r = run([*args, "--json"])
    assert r.exit_code == 0, r.output
    up, down = json.loads(r.stdout)["sweeps"]
    assert up["sweep"] == "up" and up["frequencies_hz"] == [2.9, 3.1] and down["frequencies_hz"] == [3.1, 2.9]
    for s in (up, down):
        assert s["dofs"] == [0] and s["response_amplitude_m"][0] == pytest.approx(s["damper_amplitude_m"])
        assert s["method"] == "dem" and len(s["amplitude_bare_sweep_m"]) == 2
    r = run([*args, "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "--sweep up" in r.output and "--sweep down" in r.output and "up and down differ" in r.output
    assert "every dof asked for" in r.output and png.stat().st_size > 10_000
    r = run([*args[:-4], "--sweep", "up", "--start", "bare"])
    assert r.exit_code == 2 and "--start does not apply to --sweep" in r.output


@pytest.mark.parametrize("name", ["frame_quake", "mast_quake", "mast_hammer", "structure_random"])
def test_transient_runs_on_the_examples(name):
    """Each loaded example (the mast's: its FE matrices) runs; the damper's dof of the per-dof
    lists is the damper point, with and without the damper."""
    r = run(["transient", str(EXAMPLES / f"{name}.toml"), *SHORT, "--set", "load.duration=0.1s", "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["duration_s"] == pytest.approx(0.1) and all(len(s[k]) == s.get("dof_count", 1) for k in KEYS)
    k = s["dofs"].index(38 if "dof_count" in s else 0)  # the mast's tip, the container's place
    assert s["peak_m"][k] == pytest.approx(s["damper_peak_m"], rel=1e-9)
    assert s["peak_bare_m"][k] == pytest.approx(s["damper_peak_bare_m"], rel=1e-9) and s["damper_peak_bare_m"] > 0
    assert s["energy_balance_error"] is None if s["ground"] else s["energy_balance_error"] < 1e-3
    assert ("random" in s) == (name == "structure_random")


def test_response_sweep_runs_on_the_fe_mast_over_the_fields(tmp_path):
    """The stepped sine on the FE mast with the fields of its 36-sphere bed drawn under it (its
    second mode, beyond the fields' frequencies: --extrapolate; 3 cycles a step: that it runs, not
    its physics): every dof asked for, the tip's the damper point's."""
    png = tmp_path / "sweep.png"
    fields = Path(__file__).resolve().parents[1] / "studies" / "data" / "fields_36_mast.nc"
    r = run(["response", str(EXAMPLES / "mast_fe.toml"), "--set", "initial.settle_time=0.02s", "--force", "0.3N",
             "--frequencies", "12.5Hz,12.75Hz", "--cycles", "3", "--measure-cycles", "1", "--sweep", "up", "--dofs",
             "18,38", "--fields", str(fields), "--extrapolate", "--plot", str(png), "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["sweep"] == "up" and s["frequencies_hz"] == [12.5, 12.75] and "fields_jump_frequencies_hz" in s
    assert s["dofs"] == [18, 38] and s["response_amplitude_m"][1] == pytest.approx(s["damper_amplitude_m"])
    assert all(a > 0 for a in s["response_amplitude_m"][0]) and png.stat().st_size > 10_000
