"""Sweep specification: strokes, seeds, keys, the cases it makes."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies import SweepSpec, parse_strokes, stroke_grid
from pdamper.studies.sweep import case_key


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
