"""Run directories: files with units, an exact read-back, atomic writes, no clobbering."""

from __future__ import annotations

import json
import math
import errno
import os

import numpy as np
import pytest

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.excitation import HarmonicDrive
from pdamper.rundir import check_run_dir, read_run, write_run
from pdamper.params import Case, ParticleSet, Recording
from pdamper.recorders.energy import COLUMNS, EnergyLedger
from pdamper.recorders.signals import Signals
from pdamper.run import RunResult, analyze_signals


def synthetic_result(trajectory: bool = True) -> RunResult:
    """A RunResult with made-up signals (a viscous bed, F = c v_c), without running the DEM."""
    case = Case(particles=(ParticleSet(count=4),), drive=HarmonicDrive(stroke=0.01, frequency=2.0),
                recording=Recording(sample_rate=200.0, trajectory_fps=10.0 if trajectory else 0.0),
                cycles=4, drop_cycles=1)
    fs = case.recording.sample_rate
    n = int(case.duration * fs)
    t_mid = (np.arange(n) + 0.5) / fs
    _, v, _ = case.drive.motion(t_mid)
    signals = Signals.from_run(case, 1.0 / fs, 0.3 * v + 1e-3 * np.sin(7.0 * t_mid))
    rng = np.random.default_rng(1)
    eng = np.cumsum(rng.random((n, len(COLUMNS))) * 1e-6, axis=0)
    energy = EnergyLedger.from_array(signals.time_end, eng)
    traj = None
    if trajectory:
        k = int(case.duration * case.recording.trajectory_fps)
        traj = {"time": (np.arange(k) + 1) / case.recording.trajectory_fps,
                "position": rng.random((k, 4, 3)), "velocity": rng.random((k, 4, 3)), "spin": rng.random((k, 4, 3)),
                "radius": np.full(4, 0.005)}
    return RunResult(case=case, signals=signals, energy=energy, analysis=analyze_signals(case, signals), trajectory=traj,
                     steps=12345, time_step_s=2e-6, wall_time_s=0.25, neighbour_search="direct")


def test_files_and_headers_carry_units(tmp_path):
    res = synthetic_result()
    out = write_run(res, tmp_path / "runs" / "a")  # parents are created
    names = sorted(p.name for p in out.iterdir())
    assert names == ["config.toml", "energy.csv", "result.json", "signals.csv", "trajectory.npz"]
    assert (out / "signals.csv").read_text().splitlines()[0] == "time [s],force [N],velocity [m/s],position [m]"
    assert (out / "energy.csv").read_text().splitlines()[0] == (
        "time [s],kinetic [J],rotational [J],potential [J],elastic [J],work [J],damping [J],friction [J]")
    meta = json.loads((out / "result.json").read_text())
    from pdamper import __version__

    assert meta["pdamper_version"] == __version__
    assert meta["format"]["name"] == "pdamper-run"
    for key in ("eta_star", "energy_per_cycle_J", "steps", "wall_time_s"):
        assert key in meta["summary"]
    assert meta["summary"]["steps"] == 12345
    assert meta["analysis"]["eta_star"] == pytest.approx(res.eta_star, rel=1e-15)
    assert meta["summary"]["eta_star"] == pytest.approx(res.eta_star, rel=1e-15)


def test_read_run_gives_back_exactly_what_was_written(tmp_path):
    res = synthetic_result()
    stored = read_run(write_run(res, tmp_path / "r"))
    assert stored.case == res.case
    assert load_case(tmp_path / "r" / "config.toml") == res.case
    for name in ("time", "time_end", "force", "velocity", "position"):
        np.testing.assert_array_equal(getattr(stored.signals, name), getattr(res.signals, name))
    for name in ("time",) + tuple(COLUMNS):
        np.testing.assert_array_equal(getattr(stored.energy, name), getattr(res.energy, name))
    for name, arr in res.trajectory.items():
        np.testing.assert_array_equal(stored.trajectory[name], arr)
    for key, value in res.summary().items():
        got = stored.summary[key]
        if isinstance(value, float) and math.isnan(value):
            assert math.isnan(got)
        else:
            assert got == value, key
    assert stored.analysis == json.loads(json.dumps(res.analysis.to_dict()))
    # the re-read signals analyse to the same eta*
    assert analyze_signals(stored.case, stored.signals).eta_star == res.eta_star


def test_no_temporary_files_are_left(tmp_path):
    out = write_run(synthetic_result(), tmp_path / "r")
    assert not [p for p in out.iterdir() if p.name.startswith(".")]


def test_a_failed_write_leaves_no_result_json_and_no_temp_file(tmp_path, monkeypatch):
    real = os.replace

    def boom(src, dst):
        if str(dst).endswith("energy.csv"):
            raise OSError(errno.ENOSPC, "No space left on device")
        return real(src, dst)

    from pdamper.io import files

    monkeypatch.setattr(files.os, "replace", boom)
    with pytest.raises(InputError, match=r"cannot write .*energy.csv: no space left on the device \(ENOSPC\)"):
        write_run(synthetic_result(), tmp_path / "r")
    names = sorted(p.name for p in (tmp_path / "r").iterdir())
    assert names == ["config.toml", "signals.csv"]  # result.json (the completion mark) was never written
    with pytest.raises(InputError, match="interrupted"):
        read_run(tmp_path / "r")


def test_an_existing_run_directory_is_overwritten_and_stale_files_go(tmp_path):
    out = write_run(synthetic_result(trajectory=True), tmp_path / "r")
    assert (out / "trajectory.npz").exists()
    write_run(synthetic_result(trajectory=False), out)
    assert not (out / "trajectory.npz").exists()
    assert read_run(out).trajectory is None


def test_an_empty_directory_is_used(tmp_path):
    (tmp_path / "empty").mkdir()
    write_run(synthetic_result(trajectory=False), tmp_path / "empty")
    assert (tmp_path / "empty" / "result.json").exists()


def test_a_foreign_non_empty_directory_is_refused(tmp_path):
    (tmp_path / "notes.txt").write_text("mine")
    with pytest.raises(InputError, match="not empty and is not a pdamper run directory"):
        write_run(synthetic_result(), tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]
    with pytest.raises(InputError, match="not empty"):
        check_run_dir(tmp_path)


def test_a_file_is_refused_as_run_directory(tmp_path):
    (tmp_path / "f").write_text("x")
    with pytest.raises(InputError, match="is a file"):
        check_run_dir(tmp_path / "f")


def test_read_run_errors(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_run(tmp_path / "missing")
    (tmp_path / "d").mkdir()
    (tmp_path / "d" / "result.json").write_text('{"something": 1}')
    with pytest.raises(InputError, match="not written by pdamper"):
        read_run(tmp_path / "d")
