"""``pdamper run --trajectory``, ``pdamper animate``, ``pdamper export`` and ``pdamper plot modes``.

One tiny DEM run (8 spheres, 3 cycles at 2 Hz = 1.5 s) with a trajectory at 20 frames/s (30 frames) is shared.
"""

import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from click.testing import CliRunner
from PIL import Image

from pdamper.analysis.modes import MODES
from pdamper.cli import main
from pdamper.rundir import read_run


def invoke(args):
    return CliRunner().invoke(main, args)


@pytest.fixture(scope="module")
def traj_run(tiny, tmp_path_factory):
    out = tmp_path_factory.mktemp("runs") / "r"
    result = invoke(["run", str(tiny), "--trajectory", "--fps", "20", "--json", "--out", str(out)])
    assert result.exit_code == 0, result.output
    return json.loads(result.stdout), out


def test_run_with_trajectory_stores_frames_and_reports_the_mode(traj_run):
    data, out = traj_run
    assert data["mode"] in MODES and 0 <= data["mode_features"]["sync"] <= 1
    run = read_run(out)
    tr = run.trajectory
    assert tr["position"].shape == (30, 8, 3) and tr["velocity"].shape == (30, 8, 3) and tr["spin"].shape == (30, 8, 3)
    np.testing.assert_allclose(np.diff(tr["time"]), 0.05)
    # the container pose: x_c = X sin(2 pi f t) along the drive (x, up to the 0.1 deg tilts)
    xc = 0.013 * np.sin(2 * np.pi * 2.0 * tr["time"])
    np.testing.assert_allclose(tr["container_position"][:, 0], xc, rtol=1e-5, atol=1e-9)
    assert np.abs(tr["container_position"][:, 1:]).max() < 1e-4
    assert run.case.recording.trajectory_fps == 20
    assert run.summary["mode"] == data["mode"]


def test_run_without_trajectory_still_reports_a_mode(tiny):
    result = invoke(["run", str(tiny), "--cycles", "2"])
    assert result.exit_code == 0, result.output
    assert "motion mode" in result.output


def test_fps_without_trajectory_or_not_positive_is_an_error(tiny):
    result = invoke(["run", str(tiny), "--fps", "50"])
    assert result.exit_code == 2 and result.output.strip() == \
        "Error: --fps sets the frame rate of --trajectory; add --trajectory"
    result = invoke(["run", str(tiny), "--trajectory", "--fps", "0"])
    assert result.exit_code == 2 and "give a positive frame rate" in result.output
    result = invoke(["run", str(tiny), "--trajectory", "--fps", "2kHz"])
    assert result.exit_code == 2 and "exceeds sample_rate" in result.output


def test_animate_writes_gif_paths_and_walls(traj_run, tmp_path):
    _, out = traj_run
    result = invoke(["animate", str(out), "--out", str(tmp_path / "a.gif"), "--cycles", "1", "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["mode"] in MODES
    with Image.open(tmp_path / "a.gif") as im:
        assert im.n_frames == 11   # the last cycle (0.5 s) at 20 frames/s, both ends
    assert (out / "paths.png").is_file() and (out / "walls.png").is_file()


def test_export_writes_a_pvd_series(traj_run, tmp_path):
    _, out = traj_run
    result = invoke(["export", str(out), "--out", str(tmp_path / "vtk"), "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["frames"] == 30
    sets = ET.parse(data["particles"]).getroot().findall("Collection/DataSet")
    assert len(sets) == 30
    piece = ET.parse(tmp_path / "vtk" / sets[0].get("file")).getroot().find("PolyData/Piece")
    assert piece.get("NumberOfPoints") == "8"


def test_animate_and_export_of_a_run_without_trajectory_say_how_to_record_one(tiny, tmp_path):
    out = tmp_path / "plain"
    assert invoke(["run", str(tiny), "--cycles", "2", "--out", str(out)]).exit_code == 0
    for cmd in ("animate", "export"):
        result = invoke([cmd, str(out)])
        assert result.exit_code == 2
        assert result.output.startswith("Error: ") and "--trajectory --out" in result.output
        assert len(result.output.strip().splitlines()) == 1


def test_animate_of_a_missing_directory(tmp_path):
    result = invoke(["animate", str(tmp_path / "nope")])
    assert result.exit_code == 2 and "run directory not found" in result.output


@pytest.mark.slow
def test_plot_modes_of_a_store(tiny, tmp_path):
    store = tmp_path / "store"
    result = invoke(["sweep", str(tiny), "--strokes", "2mm,13mm", "--cycles", "2", "--workers", "1", "--out", str(store),
                     "--json"])
    assert result.exit_code == 0, result.output
    result = invoke(["plot", "modes", str(store), "--out", str(tmp_path / "m.png"), "--json"])
    assert result.exit_code == 0, result.output
    data = json.loads(result.stdout)
    assert data["rows"][0]["label"] == "N_p = 8" and all(m in MODES for m in data["rows"][0]["modes"])
    assert (tmp_path / "m.png").is_file()
    # the store resumed (nothing runs again) in text: the overrides of --set echoed under the header (issue 39)
    result = invoke(["sweep", str(tiny), "--strokes", "2mm,13mm", "--cycles", "2", "--workers", "1", "--out", str(store),
                     "--set", "particles.count=8"])
    assert result.exit_code == 0, result.output
    assert result.stdout.splitlines()[1] == "  --set                 particles.count=8"


def test_plot_modes_errors(tmp_path):
    result = invoke(["plot", "modes", str(tmp_path / "none")])
    assert result.exit_code == 2 and result.output.startswith("Error: ")
    result = invoke(["plot", "nothing"])
    assert result.exit_code == 2 and result.output.startswith("Error: No such command")


def test_a_container_on_a_coupled_structure_records_its_own_motion(tmp_path):
    """With [structure] the container pose in the trajectory is the structure's recorded motion,
    not a prescribed drive; the mode is judged at the structure's frequency (f_n in free decay)."""
    from pathlib import Path

    from pdamper import load_case, run_case

    cfg = Path(__file__).resolve().parents[2] / "examples" / "structure_36.toml"
    case = load_case(cfg, {"particles.count": 8, "run.cycles": 0.5, "recording.trajectory_fps": 50,
                           "initial.settle_time": "20ms"})
    res = run_case(case)
    tr = res.trajectory
    at = np.searchsorted(res.structure.time, tr["time"] - 1e-12)
    np.testing.assert_allclose(tr["container_position"][:, 0], res.structure.displacement[at], rtol=1e-4)
    # released from 20 mm at t = 0: ~20 mm cos(2 pi 2 Hz t) at the first frame
    assert tr["container_position"][0, 0] == pytest.approx(0.02 * np.cos(2 * np.pi * 2 * tr["time"][0]), rel=0.01)
    assert res.mode in MODES
