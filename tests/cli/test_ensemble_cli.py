"""``--uncertain U.toml --samples N`` on the command line (pdamper.cli.ensemble): the report and its
JSON (``ensemble = {samples, peak_ratio, rms_ratio, eta_star}``, percentiles per dof) from a store
whose samples are all there (nothing runs), and the one-line refusals (a run ensemble's JSON from a
DEM run: tests/studies/test_ensemble.py, the kill -9 test)."""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

from ensemble_helpers import STIFFNESS_TOML, SYNTHETIC_CASE, synthetic_store
from pdamper.cli import main


def run(args):
    return CliRunner().invoke(main, args)


@pytest.fixture
def synthetic(tmp_path):
    """A finished transient ensemble of 24 samples and the files the command reads to find it again."""
    rng = np.random.default_rng(2)
    ratios = [(float(a), float(b)) for a, b in zip(rng.uniform(0.5, 0.9, 24), rng.uniform(0.4, 0.8, 24))]
    spec, store = synthetic_store(tmp_path, ratios)
    (tmp_path / "case.toml").write_text(SYNTHETIC_CASE)
    (tmp_path / "U.toml").write_text(STIFFNESS_TOML)
    return tmp_path, ratios


def _args(folder, *more):
    return ["transient", str(folder / "case.toml"), "--uncertain", str(folder / "U.toml"), "--samples", "24",
            "--dofs", "damper,response", "--store", str(folder / "store"), *more]


def test_the_report_of_a_transient_ensemble_in_json(synthetic):
    folder, ratios = synthetic
    before = {f.name: f.read_bytes() for f in (folder / "store" / "cases").glob("*.json")}
    r = run(_args(folder, "--target-peak-ratio", "0.7", "--target-rms-ratio", "0.6", "--json",
                  "--plot", str(folder / "cdf.png"), "--tornado", str(folder / "tornado.png")))
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)["ensemble"]
    assert {f.name: f.read_bytes() for f in (folder / "store" / "cases").glob("*.json")} == before  # none ran
    assert s["samples"] == s["finished"] == 24 and s["eta_star"] is None and s["dofs"] == ["damper", "response"]
    p = np.percentile(np.array(ratios), [5, 50, 95], axis=0)
    for k, q in enumerate(("p05", "p50", "p95")):
        assert s["peak_ratio"][q] == pytest.approx(p[k].tolist())
        assert s["rms_ratio"][q] == pytest.approx((0.9 * p[k]).tolist())
    met = sum(max(x) <= 0.7 for x in ratios)
    assert s["targets"]["peak_ratio"]["met"] == met and s["targets"]["peak_ratio"]["method"] == "wilson"
    assert (folder / "cdf.png").exists() and (folder / "tornado.png").exists()


def test_the_report_as_text(synthetic):
    folder, _ = synthetic
    r = run(_args(folder, "--target-peak-ratio", "0.7"))
    assert r.exit_code == 0, r.output
    assert "24 samples (Latin hypercube) of 1 unknowns, 24 finished" in r.output
    assert "    damper" in r.output and "response" in r.output and "Wilson" in r.output
    assert "what moves peak_ratio" in r.output


@pytest.mark.parametrize("args, words", [
    (["run", "{tiny}", "--samples", "3"], "--samples, --store belong to an ensemble: give --uncertain U.toml"),
    (["run", "{tiny}", "--uncertain", "{u}", "--trajectory"], "--trajectory belongs to one run"),
    (["sweep", "{tiny}", "--uncertain", "{u}", "--seeds", "2"], 'key = "initial.seed"'),
    (["run", "{tiny}", "--uncertain", "{bad}"], "[[unknown]] #1 (key = 'contact.friction'): distribution = 'gauss'"),
    (["run", "{tiny}", "--uncertain", "{u}", "--tornado", "t.txt"], "unknown format '.txt'"),
])
def test_a_refusal_is_one_line(tiny, tmp_path, args, words):
    (tmp_path / "U.toml").write_text('[[unknown]]\nkey = "contact.friction"\ndistribution = "uniform"\n'
                                     'low = 0.05\nhigh = 0.3\n')
    (tmp_path / "bad.toml").write_text('[[unknown]]\nkey = "contact.friction"\ndistribution = "gauss"\n')
    r = run([a.format(tiny=tiny, u=tmp_path / "U.toml", bad=tmp_path / "bad.toml") for a in args]
            + ["--store", str(tmp_path / "store")] * ("sweep" not in args))
    assert r.exit_code == 2 and "Traceback" not in r.output, r.output
    lines = [ln for ln in r.output.splitlines() if ln.startswith("Error:")]
    assert len(lines) == 1 and words in lines[0], r.output
    assert not (tmp_path / "store" / "cases").exists() or not any((tmp_path / "store" / "cases").iterdir())
