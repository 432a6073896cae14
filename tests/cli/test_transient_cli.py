"""``pdamper transient`` and ``pdamper response --sweep/--dofs``: the JSON keys, the table, the figure,
and nothing written when a run fails."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
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


#: a storey of 3 m on the locked bed's structure, and two limits
CODES = ["--set", "structure.storey_height=3m", "--limit", "drift=0.02%", "--limit", "acceleration=0.1m/s^2"]


def test_transient_json_table_and_plot(config, tmp_path):
    r = run(["transient", str(config), "--json", *CODES])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert all(len(s[k]) == 1 for k in KEYS) and s["dofs"] == [0]
    assert 0 < s["peak_reduction"][0] and s["peak_m"][0] == pytest.approx(s["damper_peak_m"])
    # what codes ask for, per dof and storey, with and without the damper, and the verdicts
    c = s["codes"]
    for key in ("acceleration_peak_m_s2", "acceleration_peak_bare_m_s2", "acceleration_rms_m_s2",
                "acceleration_rms_bare_m_s2", "acceleration_peak_reduction", "drift_ratio_peak", "drift_ratio_peak_bare",
                "drift_ratio_rms", "drift_ratio_residual", "drift_ratio_residual_bare"):
        assert len(c[key]) == 1, key
    assert c["dofs"] == [0] and c["storeys"] == [0] and c["storey_heights_m"] == [3.0]
    assert c["drift_ratio_peak"][0] == pytest.approx(s["peak_m"][0] / 3.0, rel=1e-12)
    drift, acc = c["limits"]["drift"], c["limits"]["acceleration"]
    assert drift["limit"] == pytest.approx(2e-4) and acc["limit"] == 0.1 and acc["labels"] == [0]
    assert acc["verdict"] == ["pass" if c["acceleration_peak_m_s2"][0] <= 0.1 else "exceed"]
    assert drift["met"] == (c["drift_ratio_peak"][0] <= 2e-4) and drift["verdict_bare"][0] in ("pass", "exceed")
    (tm,) = s["tmd_equivalent"]
    assert tm["mass_ratio"] == [pytest.approx(s["mass_ratio"])] and tm["equivalent_mass_kg"] == pytest.approx(
        s["bed_mass_kg"], rel=1e-2)  # the locked bed: its mass
    assert s["mode_table"]["frequency_hz"] == [pytest.approx(3.0, rel=1e-2)]
    png = tmp_path / "t.png"
    r = run(["transient", str(config), "--plot", str(png), *CODES])
    assert r.exit_code == 0, r.output
    assert "peak [mm]" in r.output and "ratio" in r.output and png.stat().st_size > 10_000
    lines = r.output.splitlines()
    assert lines[1] == "  --set                 structure.storey_height=3m"  # the overrides echoed (issue 39)
    assert lines[2] == "  modes                 1: 3 Hz, zeta 2 %, phi_d 1 (2 kg at the damper)"
    for words in ("floor accelerations [m/s^2] over the record", "inter-storey drift ratios [%]",
                  "limit peak inter-storey drift ratio <= 0.02 %: with the damper",
                  "limit peak absolute floor acceleration <= 0.1 m/s^2", "the damper as an equivalent TMD",
                  "Den Hartog"):
        assert words in r.output, words


@pytest.mark.parametrize("args, words", [
    (["--dofs", "7"], "--dofs: 7 is not a dof of this structure (0 to 0)"),
    (["--dofs", "0:x"], "is not a range START:STOP"),
    (["--set", "load.scale=abc"], "[load] scale"),
    (["--limit", "drfit=0.5%"], "--limit 'drfit=0.5%': unknown quantity 'drfit'"),
    (["--limit", "acceleration=3mm"], "--limit acceleration"),
    (["--set", "structure.storey_heights=[3, 3]"], "storey_heights has 2 heights for 1 dofs"),
    (["--set", "structure.dof_names=['a', 'b']"], "dof_names has 2 names; the structure has 1 dof"),
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


@pytest.mark.slow
def test_response_sweep_and_dofs(config, tmp_path):
    """A stepped sine both ways on the locked bed (short: the keys, not the physics, which
    tests/studies/test_transient.py checks)."""
    png = tmp_path / "s.png"
    args = ["response", str(config), "--force", "1N", "--frequencies", "2.9Hz,3.1Hz", "--cycles", "4",
            "--measure-cycles", "2", "--sweep", "both", "--dofs", "0"]
    r = run([*args, "--json", "--limit", "acceleration=0.1m/s^2"])
    assert r.exit_code == 0, r.output
    up, down = json.loads(r.stdout)["sweeps"]
    assert up["sweep"] == "up" and up["frequencies_hz"] == [2.9, 3.1] and down["frequencies_hz"] == [3.1, 2.9]
    for s in (up, down):
        assert s["dofs"] == [0] and s["response_amplitude_m"][0] == pytest.approx(s["damper_amplitude_m"])
        assert s["method"] == "dem" and len(s["amplitude_bare_sweep_m"]) == 2
        # what codes ask for, step by step over the measured periods: the peak acceleration at least
        # (2 pi f)^2 times the amplitude fitted there (up to the second difference's error; more where
        # the short steps have not settled), the largest over the steps reported; without the damper
        # the steady closed form's (2 pi f)^2 |x^|
        c = s["codes"]
        f = np.array(s["frequencies_hz"])
        w2 = (2 * np.pi * f) ** 2
        acc = np.array(c["by_frequency"]["acceleration_peak_m_s2"][0])
        assert np.all(acc >= 0.97 * w2 * np.array(s["damper_amplitude_m"])) and np.all(acc < 2 * w2 * np.array(
            s["damper_amplitude_m"]))
        assert c["acceleration_peak_m_s2"][0] == pytest.approx(acc.max())
        assert c["by_frequency_bare"]["acceleration_peak_m_s2"][0] == pytest.approx(w2 * np.array(s["amplitude_bare_m"]),
                                                                                     rel=1e-9)
        assert c["limits"]["acceleration"]["verdict"] == ["pass" if acc.max() <= 0.1 else "exceed"]
    r = run([*args, "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "--sweep up" in r.output and "--sweep down" in r.output and "up and down differ" in r.output
    assert "every dof asked for" in r.output and png.stat().st_size > 10_000
    assert "floor accelerations [m/s^2]" in r.output
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
    assert s["energy_balance_error"] < 1e-3  # a ground acceleration's too (issue 42)
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


def test_floors_are_labelled_by_the_names_the_user_gave(tmp_path):
    """issue 39, item 6: [structure] dof_names label the dofs (tables, JSON, --dofs by name or index),
    the storeys' chain and its floors (storey_dofs by name), the drift table between named floors."""
    import numpy as np

    k = 2000.0
    np.savez(tmp_path / "frame3.npz", M=np.diag([2.0, 2.0, 2.0]),
             K=k * np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 1]]))
    structure = ('matrices = "frame3.npz"\ndamper_dof = 2\ndamping_ratio = 0.02\n'
                 'dof_names = ["floor 1", "floor 2", "roof"]\nstorey_heights = ["3.5m", "3m", "3m"]\n'
                 'storey_dofs = ["floor 1", 1, "roof"]')
    path = tmp_path / "frame3.toml"
    path.write_text(locked_case('kind = "ground_acceleration"\ntime = [0, 0.05, 0.1, 0.15]\n'
                                'acceleration = [0, 1.0, -1.0, 0]\nduration = "0.3s"', structure=structure, text=True))
    r = run(["transient", str(path), "--dofs", "roof,0", "--json", "--limit", "drift=0.1%"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["dofs"] == ["roof", "floor 1"] and s["codes"]["dofs"] == ["roof", "floor 1"]
    c = s["codes"]
    assert c["storeys"] == ["floor 1", "floor 2", "roof"] and c["storey_heights_m"] == [3.5, 3.0, 3.0]
    assert c["storey_between"] == [["ground", "floor 1"], ["floor 1", "floor 2"], ["floor 2", "roof"]]
    assert c["limits"]["drift"]["labels"] == c["storeys"] and len(c["limits"]["drift"]["verdict"]) == 3
    # a ground acceleration: the absolute accelerations are not the relative ones
    assert len(s["tmd_equivalent"][0]["modes"]) == 3 and "ground's acceleration" in c["acceleration_note"]
    r = run(["transient", str(path), "--dofs", "roof"])
    assert r.exit_code == 0, r.output
    table = r.output.splitlines()
    assert any(line.split()[:1] == ["roof"] and len(line.split()) == 7 for line in table), r.output
    assert any("floor 1 - floor 2" in line for line in table) and "      roof" in r.output
    r = run(["transient", str(path), "--dofs", "attic"])
    assert r.exit_code == 2 and "--dofs: 'attic' is not a dof of this structure (floor 1, floor 2, roof (or 0 to 2))" \
        in r.output
