"""``pdamper analyze``: a measured record file in, energy per cycle and eta* out."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from click.testing import CliRunner

import pdamper.cli.analyze  # noqa: F401  (registers the command)
from pdamper.cli.common import main

F_DRIVE, X, C, M_BED = 2.0, 0.012, 4.0, 0.149
W = 2 * np.pi * F_DRIVE
EXACT = np.pi * C * W * X**2          # viscous damper: pi c Omega X^2 [J]


def write_record(path, *, cycles=20, fs=1000.0, transient=False, header=None, noise_motion=False):
    """Viscous damper plus container inertia, written in ms, kN and mm."""
    t = np.arange(int(cycles * fs / F_DRIVE)) / fs
    x = X * np.sin(W * t)
    v = X * W * np.cos(W * t)
    force = C * v - 0.5 * W**2 * x
    if transient:
        force = C * v * np.clip(t / 2.0, 0, 1) - 0.5 * W**2 * x
    if noise_motion:
        x = np.random.default_rng(0).normal(size=t.size)
    header = header or "time [ms],force [kN],position [mm]"
    np.savetxt(path, np.column_stack([t * 1e3, force / 1e3, x * 1e3]), delimiter=",",
               header=header, comments="", fmt="%.17g")
    return path


def run(*args):
    return CliRunner().invoke(main, ["analyze", *map(str, args)])


@pytest.fixture
def record(tmp_path):
    return write_record(tmp_path / "run.csv")


def test_reproduces_viscous_energy_from_mm_ms_kn_record(record):
    res = run(record, "--bed-mass", "149g", "--json")
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["energy_per_cycle_J"] == pytest.approx(EXACT, rel=1e-6)
    assert out["mean_power_check_J"] == pytest.approx(EXACT, rel=1e-6)
    assert out["eta_star"] == pytest.approx(C / (M_BED * W), rel=1e-6)
    assert out["frequency_hz"] == pytest.approx(F_DRIVE, rel=1e-9)
    assert out["cycles_used"] == 18
    assert out["window_s"] == pytest.approx([1.0, 10.0])
    assert len(out["cycle_energies_J"]) == 20
    assert out["velocity_amplitude_m_s"] == pytest.approx(X * W, rel=1e-9)
    re, im = out["complex_power_W"]
    assert re == pytest.approx(EXACT * F_DRIVE, rel=1e-6) and isinstance(im, float)
    assert out["motion"] == "position" and out["steady"] is True


def test_human_table(record):
    res = run(record, "--bed-mass", "0.149", "--frequency", "2Hz", "--drop-cycles", "3")
    assert res.exit_code == 0, res.output
    text = res.stdout
    assert "energy per cycle E~_diss" in text and f"{EXACT:.6g} J" in text
    assert "reduced loss factor eta*" in text and "m_bed = 149 g" in text
    assert "17 whole cycles, first 3 dropped" in text
    assert text.count("dropped") == 1 + 3
    assert "given" in text


def test_without_bed_mass_eta_is_not_reported(record):
    res = run(record)
    assert res.exit_code == 0
    assert "eta* not reported" in res.stdout and "--bed-mass" in res.stdout
    out = json.loads(run(record, "--json").stdout)
    assert out["eta_star"] is None


def test_plot_is_written(record, tmp_path):
    png = tmp_path / "fig.png"
    res = run(record, "--bed-mass", "149g", "--plot", png)
    assert res.exit_code == 0, res.output
    assert png.stat().st_size > 1000
    assert f"plot written to {png}" in res.stdout


def test_unsteady_record_gets_a_note(tmp_path):
    p = write_record(tmp_path / "ramp.csv", transient=True)
    res = run(p, "--drop-cycles", "0")
    assert res.exit_code == 0
    assert "may not be steady" in res.stdout
    assert json.loads(run(p, "--drop-cycles", "0", "--json").stdout)["steady"] is False
    assert "may not be steady" not in run(p, "--drop-cycles", "5").stdout


def test_column_options(tmp_path):
    p = write_record(tmp_path / "r.csv", header="t [ms],F_x [kN],pos [mm]")
    res = run(p, "--time-column", "t", "--force-column", "F_x", "--position-column", "pos", "--json")
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["energy_per_cycle_J"] == pytest.approx(EXACT, rel=1e-6)


def _bad_cases(tmp_path):
    ok = write_record(tmp_path / "ok.csv")
    short = write_record(tmp_path / "short.csv", cycles=2.5)
    noise = write_record(tmp_path / "noise.csv", noise_motion=True)
    files = {
        "empty": "",
        "nocol": "time,force\n0,1\n",
        "two": "time,force,position,velocity\n0,1,2,3\n0.001,1,2,3\n",
        "text": "time,force,position\n0,1,2\n0.001,oops,2\n",
        "nan": "time,force,position\n0,1,2\n0.001,nan,2\n",
        "unit": "time [fortnight/s],force,position\n0,1,2\n",
        "jitter": "time,force,position\n0,1,0\n0.001,1,1\n0.0025,1,0\n0.003,1,-1\n",
        "reverse": "time,force,position\n0.002,1,0\n0.001,1,1\n0,1,0\n",
    }
    paths = {}
    for name, text in files.items():
        p = tmp_path / f"{name}.csv"
        p.write_text(text)
        paths[name] = p
    return [
        ([tmp_path / "missing.csv"], "not found"),
        ([tmp_path], "directory"),
        ([paths["empty"]], "empty"),
        ([paths["nocol"]], "no motion column"),
        ([paths["two"]], "2 motion columns.*choose.*--position-column position"),
        ([paths["text"]], "line 3, column 'force': cannot read 'oops'"),
        ([paths["nan"]], "not a finite number"),
        ([paths["unit"]], "not a unit of time"),
        ([paths["jitter"], "--frequency", "100Hz"], "holds 0.3 cycles"),
        ([paths["reverse"]], "increase strictly"),
        ([short], "holds 2.5 cycles.*--drop-cycles"),
        ([noise], "no clear drive peak"),
        ([ok, "--frequency", "600Hz"], "Nyquist"),
        ([ok, "--frequency", "0"], "positive"),
        ([ok, "--frequency=-2Hz"], "positive"),
        ([ok, "--frequency", "fast"], "--frequency"),
        ([ok, "--frequency", "2kg"], "not a frequency"),
        ([ok, "--bed-mass", "0g"], "bed mass must be positive"),
        ([ok, "--bed-mass=-5g"], "bed mass must be positive"),
        ([ok, "--bed-mass", "3m"], "not a mass"),
        ([ok, "--drop-cycles", "-1"], "0 or more"),
        ([ok, "--drop-cycles", "two"], "drop-cycles"),
        ([ok, "--position-column", "position", "--velocity-column", "v"], "only one of"),
        ([ok, "--velocity-column", "speed"], "no velocity column"),
        ([ok, "--plot", tmp_path / "fig.jpg"], "unknown format"),
        ([ok, "--no-such-option"], "No such option"),
        ([], "Missing argument"),
    ]


def test_every_bad_input_is_one_error_line_with_exit_code_2(tmp_path):
    import re

    for args, pattern in _bad_cases(tmp_path):
        res = run(*args)
        assert res.exit_code == 2, (args, res.output)
        assert res.stdout == "", (args, res.stdout)
        lines = res.stderr.strip().splitlines()
        assert len(lines) == 1, (args, res.stderr)
        assert lines[0].startswith("Error: "), (args, lines)
        assert re.search(pattern, lines[0]), (pattern, lines[0])
        assert "Traceback" not in res.output


def test_installed_command_missing_file_has_no_traceback(tmp_path):
    code = "import sys; from pdamper.cli import main; sys.argv[0] = 'pdamper'; main()"
    proc = subprocess.run([sys.executable, "-c", code, "analyze", str(tmp_path / "nope.csv")],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2
    assert proc.stderr.strip().splitlines() == [f"Error: record file not found: {tmp_path / 'nope.csv'}"]
