"""Figure of an analysed record: writes every format, refuses what it cannot draw."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.analysis import analyze_record, complex_power
from pdamper.errors import InputError
from pdamper.plotting.analysis import plot_analysis


@pytest.fixture(scope="module")
def result():
    t = np.arange(10_000) * 1e-3
    w = 2 * np.pi * 2.0
    x = 0.01 * np.sin(w * t)
    v = 0.01 * w * np.cos(w * t)
    force = 3.0 * v * np.clip(t, 0, 1) - 0.4 * w**2 * x
    return analyze_record(t, force, position=x, bed_mass=0.149)


@pytest.mark.parametrize("ext, magic", [(".png", b"\x89PNG"), (".svg", b"<?xml"), (".pdf", b"%PDF")])
def test_writes_each_format(tmp_path, result, ext, magic):
    path = tmp_path / "sub" / f"analysis{ext}"
    fig = plot_analysis(result, path, title="synthetic record")
    assert path.stat().st_size > 1000
    assert path.read_bytes()[:5].startswith(magic)
    ax_f, ax_e = fig.axes[:2]
    assert "[N]" in ax_f.get_ylabel() or "[mN]" in ax_f.get_ylabel()
    assert ax_e.get_xlabel() == "time t [s]"
    assert "J]" in ax_e.get_ylabel()
    # one bar per whole cycle, dropped ones in grey
    assert len(ax_e.patches) >= result.cycle_energies_J.size


def test_returns_figure_without_saving(result):
    fig = plot_analysis(result)
    assert len(fig.axes) == 3           # force, energy, twin velocity axis


def test_unknown_format_and_missing_signals(tmp_path, result):
    with pytest.raises(InputError, match="unknown format '.jpeg'"):
        plot_analysis(result, tmp_path / "x.jpeg")
    t = np.arange(2000) * 1e-3
    v = np.cos(4 * np.pi * t)
    bare = complex_power(t, v, v, keep_signals=False)
    with pytest.raises(InputError, match="keep_signals=True"):
        plot_analysis(bare, tmp_path / "x.png")
