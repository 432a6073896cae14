"""Sweeps over any config keys: axes, an N-dimensional store that resumes and refuses, kept
signals and re-analysis, results that open without writing, the named studies' cases unchanged."""

from __future__ import annotations

import hashlib
import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from sweep_helpers import kill_after

from pdamper.config import dumps_case, load_case
from pdamper.errors import InputError
from pdamper.studies import Axis, ResultStore, SweepSpec, open_results, parse_axis, run_sweep
from pdamper.studies.reanalyze import reanalyze

DATA = Path(__file__).parent / "data"


# --------------------------------------------------------------------------- axes

def test_ranges_are_log_for_the_stroke_linear_otherwise_and_say_so():
    a = parse_axis("drive.stroke=0.5mm:50mm:3")
    assert a.spacing == "log" and a.values == pytest.approx((0.0005, 0.005, 0.05))
    f = parse_axis("drive.frequency=1Hz:4Hz:4")
    assert f.spacing == "linear" and f.values == pytest.approx((1.0, 2.0, 3.0, 4.0)) and f.name == "frequency"
    assert parse_axis("drive.frequency=1Hz:4Hz:3:log").values == pytest.approx((1.0, 2.0, 4.0))
    assert parse_axis("drive.stroke=10mm:30mm:3:linear").values == pytest.approx((0.01, 0.02, 0.03))
    n = parse_axis("particles.count=30:44:8")
    assert n.values == (30, 32, 34, 36, 38, 40, 42, 44) and all(isinstance(v, int) for v in n.values)
    mu = parse_axis("contact.friction=1,0.01,0.1")
    assert mu.values == (0.01, 0.1, 1.0) and mu.spacing == "list"
    assert parse_axis("numerics.integrator=gear,verlet").values == ("gear", "verlet")
    assert parse_axis("container.tilt=0.1deg,3deg").values == pytest.approx((np.radians(0.1), np.radians(3)))


@pytest.mark.parametrize("text, words", [
    ("drive.strok=1mm:2mm:2", "did you mean 'stroke'"),
    ("drive.stroke", "write KEY=VALUES"),
    ("drive.stroke=1mm:2mm", "FIRST:LAST:COUNT"),
    ("drive.stroke=1s:2s:2", "is not a length"),
    ("particles.count=30:31:8", "whole numbers do not fit"),
    ("contact.friction=0:1:3:log", "log spacing needs FIRST > 0"),
    ("numerics.integrator=gear:verlet:2", "a text key takes a list"),
    ("contact.pair=1,2", "cannot be a sweep axis"),
])
def test_bad_axes_are_explained(text, words):
    with pytest.raises(InputError, match=words):
        parse_axis(text)


def test_a_spec_checks_every_value_before_anything_runs(tiny_config):
    base = load_case(tiny_config)
    with pytest.raises(InputError, match="friction"):
        SweepSpec(base=base, axes=[Axis(key="contact.friction", values=(0.1, -1.0))], seeds=(0,))
    with pytest.raises(InputError, match="both"):
        SweepSpec(base=base, axes=[Axis(key="drive.stroke", values=(0.01,))], strokes=(0.02,))
    spec = SweepSpec(base=base, strokes=(0.002, 0.012), axes=[Axis(key="contact.friction", values=(0.01, 1.0))])
    assert spec.dims() == ("stroke", "friction", "seed")
    assert [(p["drive.stroke"], p["contact.friction"]) for p in spec.points()] == [
        (0.002, 0.01), (0.002, 1.0), (0.012, 0.01), (0.012, 1.0)]
    case = spec.case({"drive.stroke": 0.012, "contact.friction": 1.0}, 3)
    assert (case.drive.stroke, case.contact.friction, case.initial.seed) == (0.012, 1.0, 3)


# --------------------------------------------------------------------------- store

def _grid(cfg, frictions=(0.01, 1.0), strokes=(0.002, 0.012), seeds=(0,), **over):
    return SweepSpec(base=load_case(cfg, over or None), strokes=strokes,
                     axes=[Axis(key="contact.friction", values=frictions)], seeds=seeds)


@pytest.mark.slow
def test_a_two_dimensional_sweep_keeps_signals_reanalyses_and_opens_without_writing(tiny_config, tmp_path):
    store = tmp_path / "grid"
    ds = run_sweep(_grid(tiny_config), store, workers=2, progress=False, history="pdamper sweep (test)")
    assert ds.eta_star.dims == ("stroke", "friction", "seed") and ds.eta_star.shape == (2, 2, 1)
    assert np.all(np.isfinite(ds.eta_star.values))
    # CF-style attributes a scientist can use anywhere
    assert ds.attrs["Conventions"].startswith("CF-") and "pdamper sweep (test)" in ds.attrs["history"]
    assert ds.friction.attrs["config_key"] == "contact.friction" and ds.stroke.attrs["units"] == "m"
    assert "eq." not in ds.eta_star.attrs["long_name"]
    # each case's signals are kept; re-analysis with the run's settings gives the run's numbers exactly
    key = str(ds.case_key.values[0, 0, 0])
    sig = ResultStore.open(store).signals(key)
    assert sig.force.size == sig.time.size > 0 and sig.force.attrs["units"] == "N"
    # the time is the signals' coordinate, and the file names its case (issue 42)
    assert sig.force.dims == ("time",) and "time" in sig.indexes and sig.time.attrs["units"] == "s"
    assert (sig.attrs["case_key"], sig.attrs["seed"], sig.attrs["stroke_m"]) == (key, 0, float(ds.stroke[0]))
    assert json.loads(sig.attrs["point"]) == {"drive.stroke": float(ds.stroke[0]), "contact.friction": 0.01}
    same = reanalyze(store)
    for v in ("eta_star", "energy_per_cycle", "ledger_energy_per_cycle", "velocity_amplitude"):
        np.testing.assert_array_equal(same[v].values, ds[v].values)
    assert same.attrs["reanalysed"] == 4
    dropped = reanalyze(store, drop_cycles=2)
    assert dropped.attrs["drop_cycles"] == 2 and not np.array_equal(dropped.eta_star.values, ds.eta_star.values)
    with pytest.raises(InputError, match="leaves nothing"):
        reanalyze(store, drop_cycles=3)
    # opening the store (and re-analysing) changes no file
    before = {p: (p.stat().st_mtime_ns, p.read_bytes()) for p in store.rglob("*") if p.is_file()}
    opened = open_results(store)
    reanalyze(store, drop_cycles=1)
    np.testing.assert_array_equal(opened.eta_star.values, ds.eta_star.values)
    assert {p: (p.stat().st_mtime_ns, p.read_bytes()) for p in store.rglob("*") if p.is_file()} == before
    # the same grid with another config is refused; so is another set of varied keys
    with pytest.raises(InputError, match="different configuration"):
        ResultStore.create_or_open(store, _grid(tiny_config, **{"drive.frequency": "3Hz"}))
    with pytest.raises(InputError, match="varies drive.stroke, contact.friction"):
        ResultStore.create_or_open(store, SweepSpec(base=load_case(tiny_config), strokes=(0.002,)))
    # without signals nothing is kept and re-analysis says so
    bare = run_sweep(_grid(tiny_config, frictions=(0.1,), strokes=(0.002,)), tmp_path / "bare", workers=1,
                     progress=False, keep="none")
    assert not list((tmp_path / "bare" / "cases").glob("*.signals.nc"))
    assert reanalyze(tmp_path / "bare").attrs["not_reanalysed"] == 1 and np.isfinite(bare.eta_star).all()


@pytest.mark.slow
def test_a_two_dimensional_sweep_resumes_after_kill_minus_nine(tiny_config, tmp_path):
    store = tmp_path / "store"
    cmd = [sys.executable, "-m", "pdamper.cli", "sweep", str(tiny_config), "--vary", "drive.stroke=1mm:20mm:3",
           "--vary", "contact.friction=0.01,0.1", "--seeds", "1", "--workers", "1", "--out", str(store), "--json"]
    done_before = kill_after(cmd, store)
    assert 2 <= len(done_before) < 6
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    after = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    assert len(after) == 6 and all(after[k] == v for k, v in done_before.items())  # not recomputed
    report = json.loads(out.stdout)
    assert report["dims"] == {"drive.stroke": pytest.approx([0.001, 0.001 * 20 ** 0.5, 0.02]),
                              "contact.friction": [0.01, 0.1]}
    assert len(report["points"]) == 6 and report["failed_cases"] == 0


def test_a_stroke_store_of_the_previous_format_opens_and_resumes(tiny_config, tmp_path):
    spec = SweepSpec(base=load_case(tiny_config), strokes=(0.002, 0.012), seeds=(0,))
    ResultStore.create_or_open(tmp_path / "old", spec)
    # as pdamper-sweep-store/1 wrote it: strokes instead of axes, case files without a point
    meta = json.loads((tmp_path / "old" / "store.json").read_text())
    old = {k: meta[k] for k in ("fingerprint", "config", "seeds", "pdamper_version", "base")}
    old.update(format="pdamper-sweep-store/1", strokes=meta["strokes"])
    (tmp_path / "old" / "store.json").write_text(json.dumps(old))
    (tmp_path / "old" / "cases" / "X0.002_seed0.json").write_text(json.dumps(
        {"key": "X0.002_seed0", "stroke": 0.002, "seed": 0, "eta_star": 0.25, "mode": "scattered"}))
    ds = open_results(tmp_path / "old")
    assert ds.eta_star.sel(stroke=0.002, seed=0) == 0.25 and np.isnan(ds.eta_star.sel(stroke=0.012, seed=0))
    assert np.isfinite(ds.attrs["x_opt_m"])
    again = ResultStore.create_or_open(tmp_path / "old", spec)  # same fingerprint: accepted
    assert again.has("X0.002_seed0") and not again.has("X0.012_seed0")


def test_the_named_studies_build_the_same_cases_as_before():
    """Each setting's full config (and so its store fingerprint) as pdamper 0.1.0 built it, but for the
    default Gear tolerance (1e-10 m then, 1e-9 m now: the file was rewritten after checking that each
    config with 1e-10 m put back gives 0.1.0's hash)."""
    from pdamper.studies.named import STUDIES, study_settings

    golden = json.loads((DATA / "study_cases.json").read_text())
    assert set(golden) == set(STUDIES)
    for name in STUDIES:
        now = [[label, hashlib.sha256(dumps_case(c, name="x").split("\n", 3)[3].encode()).hexdigest()]
               for label, c in study_settings(name)]
        assert now == golden[name], name


def test_the_map_draws_x_opt_and_the_lift_off_bound(tmp_path):
    import xarray as xr

    from pdamper.plotting.map import map_figure, results_figure

    strokes, freqs = np.geomspace(0.005, 0.03, 4), np.array([1.0, 2.0, 3.0])
    eta = np.random.default_rng(0).uniform(0, 1, (4, 3, 2))
    ds = xr.Dataset({"eta_star": (("stroke", "frequency", "seed"), eta),
                     "mode": (("stroke", "frequency", "seed"), np.full((4, 3, 2), "scattered"))},
                    coords={"stroke": ("stroke", strokes, {"units": "m", "config_key": "drive.stroke", "spacing": "log"}),
                            "frequency": ("frequency", freqs, {"units": "Hz", "config_key": "drive.frequency"}),
                            "seed": [0, 1]},
                    attrs={"x_opt_m": 0.012, "gravity_m_s2": 9.81, "particles": 36, "shape": "cuboid"})
    fig = map_figure(ds, tmp_path / "map.png", x="drive.stroke", y="frequency")
    ax = fig.axes[0]
    lines = {ln.get_label(): ln for ln in ax.get_lines()}
    assert np.allclose(lines["X_opt (theory)"].get_xdata(), 12.0)  # mm
    x, f = lines["lift-off bound A = g"].get_xdata() / 1e3, lines["lift-off bound A = g"].get_ydata()
    np.testing.assert_allclose(x * (2 * np.pi * f) ** 2, 9.81)  # A = X Omega^2 = g along the line
    assert (tmp_path / "map.png").stat().st_size > 10_000
    with pytest.raises(InputError, match="not a dimension"):
        map_figure(ds, x="contact.friction")
    line = results_figure(ds.sel(stroke=strokes[0]), tmp_path / "line.png")
    assert line.axes[0].get_xlabel().startswith("drive frequency") or "frequency" in line.axes[0].get_xlabel()
