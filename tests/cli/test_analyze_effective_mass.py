"""``pdamper analyze`` reports the effective mass and the equivalent damping of a record."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

import pdamper.cli.analyze  # noqa: F401  (registers the command)
from pdamper.cli.common import main

F_DRIVE, X, M, C, K, M_C = 2.0, 0.012, 0.149, 4.0, 30.0, 0.08
W = 2 * math.pi * F_DRIVE


@pytest.fixture
def record(tmp_path):
    """``F = (m_c + m) x'' + c x' + k x`` for 20 cycles at 1 kHz, written in ms, kN and mm."""
    t = np.arange(10_000) / 1000.0
    x = X * np.sin(W * t + 0.4)
    force = (M_C + M) * -W**2 * x + C * X * W * np.cos(W * t + 0.4) + K * x
    path = tmp_path / "rig.csv"
    np.savetxt(path, np.column_stack([t * 1e3, force / 1e3, x * 1e3]), delimiter=",",
               header="time [ms],force [kN],position [mm]", comments="", fmt="%.17g")
    return path


def test_json_gives_m_minus_k_over_omega2_and_c_with_the_container_removed(record):
    res = CliRunner().invoke(main, ["analyze", str(record), "--container-mass", "80g", "--json"])
    assert res.exit_code == 0, res.output
    out = json.loads(res.stdout)
    assert out["effective_mass_kg"] == pytest.approx(M - K / W**2, rel=1e-9)
    assert out["equivalent_damping_N_s_per_m"] == pytest.approx(C, rel=1e-9)
    assert out["container_mass_kg"] == pytest.approx(M_C, rel=1e-15)


def test_without_the_container_mass_it_stays_in_and_the_table_says_so(record):
    res = CliRunner().invoke(main, ["analyze", str(record), "--json"])
    assert json.loads(res.stdout)["effective_mass_kg"] == pytest.approx(M_C + M - K / W**2, rel=1e-9)
    table = CliRunner().invoke(main, ["analyze", str(record)]).output
    assert "effective mass m_eff" in table and "container mass included (--container-mass)" in table
    assert f"{C:.6g} N s/m" in table
    table = CliRunner().invoke(main, ["analyze", str(record), "--container-mass", "80g"]).output
    assert f"{(M - K / W**2) * 1e3:.6g} g" in table and "container m_c = 80 g" in table


def test_a_negative_container_mass_is_refused(record):
    res = CliRunner().invoke(main, ["analyze", str(record), "--container-mass", "-5g"])
    assert res.exit_code != 0 and "container mass" in res.output
