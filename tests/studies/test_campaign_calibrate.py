"""From the rig to a calibrated model: records -> campaign -> DEM next to it -> calibration.

The synthetic campaign is made by pdamper itself at mu = 0.3 (8 spheres, 8 cycles, seed 11, 2 %
force noise) at 3, 20 and 30 mm, where the small bed's eta* depends on friction; the calibration
must recover mu within +-0.07 (issue: 'pdamper calibrate recovers a known friction coefficient').
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from pdamper.cli import main
from pdamper.config import loads_case, with_overrides
from pdamper.errors import InputError
from pdamper.run import run_case
from pdamper.studies.calibrate import calibrate, parse_fit
from pdamper.studies.campaign import analyze_records, campaign_dataset

from dem_fixtures import TINY_CONFIG  # noqa: E402

CASE = TINY_CONFIG.replace("cycles = 3", "cycles = 8").replace("drop_cycles = 1", "drop_cycles = 2")
assert "cycles = 8" in CASE and "drop_cycles = 2" in CASE
MU_TRUE = 0.3
STROKES = ("3mm", "20mm", "30mm")


@pytest.fixture(scope="module")
def rig(tmp_path_factory):
    """Logger files of the synthetic rig (preamble, ; and decimal commas, position in mm)."""
    d = tmp_path_factory.mktemp("rig")
    (d / "model.toml").write_text(CASE)
    rng = np.random.default_rng(0)
    base = loads_case(CASE)
    for x in STROKES:
        r = run_case(with_overrides(base, {"drive.stroke": x, "contact.friction": MU_TRUE, "initial.seed": 11}))
        s = r.signals
        F = s.force + rng.normal(0.0, 0.02 * np.std(s.force), s.force.size)
        rows = "\n".join(f"{t:.6f};{f:.6f};{p * 1e3:.6f}".replace(".", ",") for t, f, p in zip(s.time, F, s.position))
        (d / f"x{x}.txt").write_text(f"Device: synthetic rig\nStroke: {x}\nTime;Force;Position\ns;N;mm\n{rows}\n")
    (d / "broken.txt").write_text("Device: synthetic rig\nno data\n")
    return d, base


def test_a_folder_of_logger_files_becomes_a_campaign(rig, tmp_path):
    d, base = rig
    out = CliRunner().invoke(main, ["campaign", str(d), "--bed-mass", f"{base.bed_mass * 1e3!r}g", "--json",
                                    "--out", str(tmp_path / "camp"), "--plot", str(tmp_path / "camp.png")])
    assert out.exit_code == 0, out.output
    report = json.loads(out.stdout)
    recs = sorted(report["records"], key=lambda r: r["stroke_m"])
    assert [round(r["stroke_m"] * 1e3, 3) for r in recs] == [3.0, 20.0, 30.0]  # measured from the motion
    for r in recs:
        assert {"file", "stroke_m", "frequency_hz", "eta_star", "energy_per_cycle_J", "cycles_used"} <= set(r)
        assert r["frequency_hz"] == pytest.approx(2.0, rel=1e-6) and r["cycles_used"] == 6
    assert [f["file"].endswith("broken.txt") for f in report["failed"]] == [True]  # reported, the rest go on
    assert "skipped" in out.stderr
    from pdamper.studies import open_results

    ds = open_results(tmp_path / "camp" / "campaign.nc")
    assert ds.eta_star.dims == ("stroke", "seed") and ds.stroke.attrs["units"] == "m"
    assert np.all(ds.eta_star_error.values > 0) and (tmp_path / "camp.png").stat().st_size > 10_000
    # the same records analysed one by one give the same eta*
    one = run_case(with_overrides(base, {"drive.stroke": "20mm", "contact.friction": MU_TRUE, "initial.seed": 11}))
    assert ds.eta_star.sel(stroke=0.02, method="nearest").values[0] == pytest.approx(one.eta_star, abs=0.01)


@pytest.mark.slow
def test_calibration_recovers_the_friction_of_a_synthetic_campaign(rig, tmp_path):
    d, base = rig
    files = [d / f"x{x}.txt" for x in STROKES]
    points, failures = analyze_records(files, bed_mass=base.bed_mass)
    assert not failures
    camp = campaign_dataset(points, bed_mass=base.bed_mass)
    cal = calibrate(camp, base, [parse_fit("contact.friction=0.05:1")], out=tmp_path / "cal", seeds=(0, 1), workers=2,
                    progress=False)
    mu, sigma = cal.best["contact.friction"], cal.uncertainty["contact.friction"]
    assert abs(mu - MU_TRUE) <= 0.07, (mu, sigma)
    assert 0 < sigma < 0.2 and cal.convex and math.isfinite(cal.misfit)
    assert len(cal.points) == 14  # two rounds of 7
    # interrupted or not, a second call resumes from the stores: no new DEM case
    stamp = {p: p.stat().st_mtime_ns for p in (tmp_path / "cal").rglob("*.json")}
    again = calibrate(camp, base, [parse_fit("contact.friction=0.05:1")], out=tmp_path / "cal", seeds=(0, 1),
                      workers=2, progress=False)
    assert again.best == cal.best
    assert {p: p.stat().st_mtime_ns for p in (tmp_path / "cal").rglob("*.json") if p.name != "store.json"} == \
        {p: t for p, t in stamp.items() if p.name != "store.json"}


@pytest.mark.parametrize("text, words", [
    ("contact.friction", "KEY=LOW:HIGH"),
    ("contact.friction=1:0.1", "LOW < HIGH"),
    ("contact.frction=0.1:1", "did you mean 'friction'"),
    ("numerics.integrator=0:1", "only a number"),
    ("contact.friction=0:1:log", "needs LOW > 0"),
])
def test_bad_fits_are_explained(text, words):
    with pytest.raises(InputError, match=words):
        parse_fit(text)
    f = parse_fit("container.tilt=0deg:3deg")
    assert (f.low, f.high, f.log) == (0.0, pytest.approx(math.radians(3)), False)
    assert parse_fit("contact.friction=0.01:1").log
