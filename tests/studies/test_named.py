"""The paper's studies: each builds its settings with the one change it is about, and a study
runs into one dataset with a setting dimension."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.contact import ThorntonRestitution
from pdamper.errors import InputError
from pdamper.studies.named import STUDIES, run_study, study_settings


#: the paper's studies (SPEC section 5); beyond the paper: the vertical drive (one setting)
PAPER_STUDIES = {"fig4", "friction", "modulus", "density", "restitution", "radius", "tilt", "cylinder", "cylinder-tilt"}


def test_every_study_of_spec_section_5_exists():
    assert set(STUDIES) == PAPER_STUDIES | {"vertical"}


@pytest.mark.parametrize("name", sorted(STUDIES))
def test_each_study_builds_valid_distinct_settings(name):
    settings = study_settings(name)
    labels = [lbl for lbl, _ in settings]
    assert len(set(labels)) == len(labels) >= (2 if name in PAPER_STUDIES else 1)
    cases = [case for _, case in settings]
    assert all(a != b for i, a in enumerate(cases) for b in cases[i + 1:])  # every setting differs


def test_the_settings_change_what_they_say():
    fr = dict(study_settings("friction"))
    assert fr["36, mu = 0.01"].contact.friction == 0.01 and fr["44, mu = 1"].n_particles == 44
    e = dict(study_settings("modulus"))
    assert e["E = 405 GPa"].particles[0].material.youngs_modulus == pytest.approx(405e9)
    r = dict(study_settings("radius"))
    assert r["r = 2.5 mm, N_p = 176"].particles[0].radius == 0.0025 and r["r = 2.5 mm, N_p = 176"].n_particles == 176
    t = dict(study_settings("tilt"))
    assert t["44, 3 deg about z"].container.tilt == pytest.approx((math.radians(0.1), math.radians(0.1), math.radians(3)))
    cor = dict(study_settings("restitution"))
    assert isinstance(cor["eps(v), Thornton p_y = 2 GPa"].contact.restitution, ThorntonRestitution)
    cyl = dict(study_settings("cylinder"))
    assert cyl["cylinder N_p = 42"].container.geometry.shape == "cylinder"


def test_an_unknown_study_suggests_the_near_name():
    with pytest.raises(InputError, match="did you mean 'friction'"):
        study_settings("frction")


@pytest.mark.slow
def test_a_study_runs_into_one_dataset_with_a_setting_dimension(tmp_path):
    ds = run_study("fig4", tmp_path / "s", strokes=(0.013,), seeds=(0,), cycles=2.5, drop_cycles=1, workers=2,
                   progress=False)
    assert ds.eta_star.dims == ("setting", "stroke", "seed") and ds.sizes["setting"] == 2
    assert ds.setting.values.tolist() == ["N_p = 36", "N_p = 44"]
    np.testing.assert_allclose(ds.clearance.values, [0.03, 0.01])
    assert np.all(np.isfinite(ds.eta_star.values))
    assert (tmp_path / "s" / "study.nc").exists()
    # resumable: nothing runs again
    stamps = sorted(p.stat().st_mtime_ns for p in (tmp_path / "s").rglob("cases/*.json"))
    run_study("fig4", tmp_path / "s", strokes=(0.013,), seeds=(0,), cycles=2.5, drop_cycles=1, workers=2,
              progress=False)
    assert sorted(p.stat().st_mtime_ns for p in (tmp_path / "s").rglob("cases/*.json")) == stamps


@pytest.mark.slow
def test_a_users_study_file_runs_and_bad_files_are_explained(tiny_config, tmp_path):
    from pdamper.errors import InputError
    from pdamper.plotting.sweep import study_figure
    from pdamper.studies.named import load_study

    study = tmp_path / "mine.toml"
    study.write_text(f'''title = "mine"
vary = ["drive.stroke=2mm:12mm:2"]
[[setting]]
label = "mu = 0.05"
config = "{tiny_config.name}"
set = {{ "contact.friction" = 0.05 }}
panel = "first"
[[setting]]
label = "mu = 0.5"
config = "{tiny_config.name}"
set = {{ "contact.friction" = 0.5 }}
panel = "second"
''')
    (tmp_path / tiny_config.name).write_text(tiny_config.read_text())
    s = load_study(study)
    assert [c.contact.friction for _, c, _ in s.settings] == [0.05, 0.5] and s.vary == ("drive.stroke=2mm:12mm:2",)
    ds = run_study(study, tmp_path / "out", seeds=(0,), workers=1, progress=False)
    assert ds.eta_star.dims == ("setting", "stroke", "seed") and ds.panel.values.tolist() == ["first", "second"]
    assert ds.stroke.values == pytest.approx([0.002, 0.012]) and np.isfinite(ds.eta_star.values).all()
    fig = study_figure(ds, tmp_path / "mine.png")
    assert [ax.get_title() for ax in fig.axes[:2]] == ["(a) first", "(b) second"]
    assert (tmp_path / "mine.png").exists()
    for text, words in [('title = "x"\n', "no settings"),
                        ('titel = "x"\n', "did you mean 'title'"),
                        ('[[setting]]\nlabel = "a"\nbase = "cuboid_63"\n', "did you mean 'cuboid_36'"),
                        ('[[setting]]\nlabel = "a"\nbase = "cuboid_36"\nset = { "contact.frction" = 1 }\n',
                         "did you mean 'friction'"),
                        ('[[setting]]\nlabel = "a"\n', "exactly one of base")]:
        bad = tmp_path / "bad.toml"
        bad.write_text(text)
        with pytest.raises(InputError, match=words):
            load_study(bad)
