"""Sweep specification: strokes, seeds, keys, the cases it makes."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies import SweepSpec, parse_strokes, stroke_grid
from pdamper.studies.sweep import case_key, parse_axis


def test_the_paper_grid_is_40_log_spaced_strokes_from_half_a_millimetre_to_50():
    x = parse_strokes("0.5mm:50mm:40")
    assert len(x) == 40 and x[0] == pytest.approx(5e-4) and x[-1] == pytest.approx(0.05)
    np.testing.assert_allclose(np.diff(np.log(x)), np.log(100) / 39)


def test_a_list_of_strokes_is_sorted_and_deduplicated():
    np.testing.assert_allclose(parse_strokes("13mm, 5mm,13mm"), [0.005, 0.013])


@pytest.mark.parametrize("bad, words", [("0.5mm:50mm", "FIRST:LAST:COUNT"), ("1mm:2mm:x", "not a whole number"),
                                        ("5Hz:6mm:3", "not a length"), ("-1mm", "positive"),
                                        ("2mm:1mm:3", "first <= last")])
def test_bad_strokes_are_explained(bad, words):
    with pytest.raises(InputError, match=words):
        parse_strokes(bad)


def test_stroke_grid_of_one_point():
    assert stroke_grid(0.01, 0.01, 1).tolist() == [0.01]


def test_spec_makes_one_case_per_stroke_and_seed(tiny_config):
    base = load_case(tiny_config)
    spec = SweepSpec(base=base, strokes=[0.01, 0.002], seeds=[1, 0])
    items = spec.items()
    assert [(p["drive.stroke"], s) for _, p, s in items] == [(0.002, 0), (0.002, 1), (0.01, 0), (0.01, 1)]
    c = spec.case(0.01, 1)
    assert c.drive.stroke == 0.01 and c.initial.seed == 1 and c.n_particles == 8
    assert len({k for k, _, _ in items}) == 4
    assert case_key(0.002, 1) == "X0.002_seed1"


def test_spec_needs_a_harmonic_drive_and_positive_strokes(tiny_config):
    from pdamper.excitation import Still
    import dataclasses

    base = load_case(tiny_config)
    with pytest.raises(InputError, match="harmonic drive"):
        SweepSpec(base=dataclasses.replace(base, drive=Still(duration_s=1.0)), strokes=[0.01], seeds=[0])
    with pytest.raises(InputError, match="positive"):
        SweepSpec(base=base, strokes=[0.0], seeds=[0])


def _counting(monkeypatch):
    """Count the calls of pdamper.plausible.check_case (the real one still runs)."""
    import pdamper.plausible as plausible

    calls = []
    real = plausible.check_case

    def counted(case, **kw):
        calls.append(case)
        return real(case, **kw)

    monkeypatch.setattr(plausible, "check_case", counted)
    return calls


def test_a_point_is_checked_once_when_the_spec_is_made_and_not_again_when_it_runs(tiny_config, monkeypatch):
    from pdamper.run import run_case
    from pdamper.studies.sweep import run_one

    base = load_case(tiny_config)
    calls = _counting(monkeypatch)
    spec = SweepSpec(base=base, axes=(parse_axis("drive.frequency=2Hz,2.2Hz"),), strokes=[0.01, 0.012],
                     seeds=[0, 1, 2])
    assert len(calls) == 4  # the 2 x 2 points once each, whatever the seeds
    assert sorted((c.drive.stroke, c.drive.frequency) for c in calls) == [
        (0.01, 2.0), (0.01, 2.2), (0.012, 2.0), (0.012, 2.2)]
    case = spec.case(spec.points()[0], 1)
    calls.clear()
    assert "failed" not in run_one(case, keep="none", checked=True)
    assert calls == []  # a sweep's point runs unchecked: its spec checked it
    run_case(case)
    assert len(calls) == 1  # a run on its own is checked once (whole cycles for its analysis included)


def test_a_sweep_runs_its_points_as_checked_and_says_what_their_check_warned_of(tiny_config, monkeypatch):
    import pdamper.studies.executor as executor
    import pdamper.studies.sweep as sweep
    from pdamper.plausible import LiftOffWarning

    base = load_case(tiny_config)
    spec = SweepSpec(base=base, strokes=[0.01, 0.07], seeds=[0])  # 70 mm at 2 Hz: 11 m/s^2, the bed lifts off
    said = spec.cautions(spec.points())
    assert [c for c, _ in said] == [LiftOffWarning] and "lifts off" in said[0][1]
    assert spec.cautions([{"drive.stroke": 0.01}]) == []
    # a store's point, its stroke read back to 15 digits (ResultStore.on_grid), is the same point
    assert spec.cautions([{"drive.stroke": math.nextafter(0.07, 1.0)}]) == said
    seen = {}

    class Stop(Exception):
        pass

    def record(items, run, on_result, **kw):
        seen.update(items=items, run=run, kw=kw)
        raise Stop

    with monkeypatch.context() as m:
        m.setattr(sweep, "run_cases_of", record)
        with pytest.raises(Stop):
            sweep.run_sweep(spec, tiny_config.parent / "store", workers=1, progress=False)
    assert seen["run"].keywords["checked"] is True and seen["kw"]["spec"] is spec and len(seen["items"]) == 2
    ran = []
    monkeypatch.setattr(executor, "execute", lambda items, fn, on_result, **kw: ran.extend(items))
    with pytest.warns(LiftOffWarning, match="lifts off"):  # said when the sweep runs the point, once
        sweep.run_cases_of(seen["items"], seen["run"], lambda *a: None, spec=spec, workers=1)
    assert len(ran) == 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the point that does not lift off runs without a word
        sweep.run_cases_of([it for it in seen["items"] if it[1]["drive.stroke"] == 0.01], seen["run"],
                           lambda *a: None, spec=spec, workers=1)
