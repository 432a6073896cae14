"""The fields figure: one interpolated line per frequency and mode-family segment, never across a
jump; the seed band; the jump marked where the fields jump."""

from __future__ import annotations

import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402

from pdamper.analysis.fields import DamperFields  # noqa: E402
from pdamper.errors import InputError  # noqa: E402
from pdamper.plotting.fields import fields_figure  # noqa: E402

from fields_helpers import COLLIDE, FREQS, OTHER, STROKES, results  # noqa: E402


def test_lines_stop_at_the_jump_and_the_jump_is_marked(tmp_path):
    step = np.array(STROKES) > 0.012
    eta = np.where(step, 0.9, 0.2)[:, None, None] + np.array([0.0, 0.05])[None, None, :]  # two seeds apart
    modes = np.where(step, COLLIDE, OTHER)[:, None, None].repeat(3, 1).repeat(2, 2)
    f = DamperFields.from_results(results(STROKES, FREQS, eta, modes=modes, seeds=2))
    fig = fields_figure(f, tmp_path / "f.png")
    assert (tmp_path / "f.png").stat().st_size > 0
    eta_ax, mass_ax = fig.axes[:2]
    curves = [ln for ln in eta_ax.lines if len(ln.get_xdata()) == 60]
    assert len(curves) == 2 * len(FREQS)  # one per frequency and segment
    for ln in curves:
        x = np.asarray(ln.get_xdata())
        assert x.max() <= 10.0 + 1e-9 or x.min() >= 20.0 - 1e-9, "no line crosses the jump interval (10-20 mm)"
    jump = math.sqrt(10.0 * 20.0)
    marks = [ln for ln in eta_ax.lines if np.allclose(ln.get_xdata(), jump)]
    assert len(marks) == len(FREQS)
    # the band spans the two seeds; the right panel is m_eff / m_bed
    band = eta_ax.collections[0].get_paths()[0].vertices[:, 1]
    assert band.min() == pytest.approx(0.2) and band.max() == pytest.approx(0.25)
    assert [ln for ln in mass_ax.lines if len(ln.get_xdata()) == 60][0].get_ydata()[0] == pytest.approx(0.3)


def test_fields_without_a_bed_mass_are_refused():
    ds = results(STROKES, [2.0], 0.5)
    ds.attrs["bed_mass_kg"] = float("nan")
    with pytest.raises(InputError, match="bed mass"):
        fields_figure(DamperFields.from_results(ds))
