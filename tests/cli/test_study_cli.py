"""``pdamper study --set``: a config key set in every setting's case, part of each store's
configuration (a store made with other overrides is refused, never mixed)."""

from __future__ import annotations

import json
import math

import pytest
from click.testing import CliRunner

from pdamper.cli import main
from pdamper.config import loads_case
from pdamper.errors import InputError
from pdamper.studies.named import STUDIES, load_study, run_study

STUDY = """title = "mine"
vary = ["drive.stroke=2mm:12mm:2"]
[[setting]]
label = "mu = 0.05"
config = "{config}"
set = {{ "contact.friction" = 0.05 }}
[[setting]]
label = "mu = 0.5"
config = "{config}"
set = {{ "contact.friction" = 0.5 }}
"""


@pytest.fixture(scope="module")
def study_file(tiny):
    path = tiny.parent / "mine.toml"
    path.write_text(STUDY.format(config=tiny.name))
    return path


def _stored_case(store_dir):
    return loads_case(json.loads((store_dir / "store.json").read_text())["config"])


@pytest.mark.slow
def test_set_reaches_every_setting_and_a_store_refuses_other_overrides(study_file, tmp_path):
    out = tmp_path / "s"
    args = ["study", str(study_file), "--strokes", "13mm", "--cycles", "2", "--workers", "1", "--out", str(out)]
    r = CliRunner().invoke(main, args + ["--set", "contact.tangential=spring", "--set", "contact.restitution=0.8", "--json"])
    assert r.exit_code == 0, r.output
    summary = json.loads(r.output)
    assert summary["overrides"] == {"contact.tangential": "spring", "contact.restitution": 0.8}
    assert summary["title"] == "mine (contact.tangential = spring, contact.restitution = 0.8)"
    for slug, mu in [("mu_0.05", 0.05), ("mu_0.5", 0.5)]:
        case = _stored_case(out / slug)  # the setting's own key kept, the overrides added
        assert (case.contact.tangential, case.contact.friction, case.contact.restitution.value) == ("spring", mu, 0.8)
    assert all(math.isfinite(v[0]) for v in summary["eta_star_mean"].values()) and summary["failed_cases"] == 0
    stamps = sorted(p.stat().st_mtime_ns for p in out.rglob("cases/*.json"))
    # the same overrides resume (nothing runs again); others, or none, are refused with the difference named
    r = CliRunner().invoke(main, args + ["--set", "contact.tangential=spring", "--set", "contact.restitution=0.8"])
    assert r.exit_code == 0, r.output
    assert "  --set                 contact.tangential=spring, contact.restitution=0.8" in r.output.splitlines()
    assert sorted(p.stat().st_mtime_ns for p in out.rglob("cases/*.json")) == stamps
    r = CliRunner().invoke(main, args + ["--set", "contact.restitution=0.8"])
    assert r.exit_code == 2
    assert "different configuration (contact.tangential = 'spring' there, the default now)" in r.output
    r = CliRunner().invoke(main, args + ["--set", "contact.tangential=spring"])
    assert r.exit_code == 2 and "contact.restitution = 0.8 there, 0.9 now" in r.output
    assert sorted(p.stat().st_mtime_ns for p in out.rglob("cases/*.json")) == stamps


@pytest.mark.parametrize("key, words", [
    ("contact.friction=0.2", "setting 'mu = 0.05' of study 'mine' sets contact.friction itself"),
    ("drive.stroke=3mm", "study 'mine' varies drive.stroke; .*give --strokes instead"),
    ("contact.tangentail=spring", "setting 'mu = 0.05'.*did you mean 'tangential'"),
    ("contact.tangential=sprung", "setting 'mu = 0.05'.*tangential"),
])
def test_set_of_a_compared_or_unknown_key_is_refused_before_anything_runs(study_file, tmp_path, key, words):
    r = CliRunner().invoke(main, ["study", str(study_file), "--set", key, "--out", str(tmp_path / "s")])
    assert r.exit_code == 2 and r.output.startswith("Error: --set")
    assert not (tmp_path / "s").exists()
    with pytest.raises(InputError, match=words):
        run_study(study_file, tmp_path / "s", seeds=(0,), overrides=dict([key.split("=")]))


@pytest.mark.parametrize("name", sorted(STUDIES))
def test_every_shipped_study_takes_the_spring_law_in_every_setting(name):
    from pdamper.studies.named import _check_overrides, _overridden
    from pdamper.studies.sweep import parse_axis

    study = load_study(name)
    spring = {"contact.tangential": "spring"}
    _check_overrides(study, spring, [parse_axis(v) for v in study.vary])
    cases = [_overridden(case, spring, label) for label, case, _ in study.settings]
    assert {c.contact.tangential for c in cases} == {"spring"}
    # only the law changed: with it set back, every setting is the study's own
    assert [_overridden(c, {"contact.tangential": "tanh"}, "") for c in cases] == [c for _, c, _ in study.settings]


@pytest.mark.parametrize("key, words", [
    ("contact.tangentail=spring", "did you mean 'tangential'"),
    ("drive.stroke=3mm", "Error: override drive.stroke = 3mm: the validation runs every study on the paper's strokes"),
])
def test_validate_set_refuses_an_unknown_or_compared_key_before_anything_runs(tmp_path, key, words):
    out = tmp_path / "v"
    r = CliRunner().invoke(main, ["validate", "--quick", "--set", key, "--out", str(out)])
    assert r.exit_code == 2 and words in r.output and "--strokes" not in r.output.split("pdamper study")[0]
    assert not out.exists()
