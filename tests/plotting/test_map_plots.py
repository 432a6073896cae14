"""The design map (η* over two keys): its ticks and its mode hatching come from the one mode style table."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402

from pdamper.plotting.map import map_figure  # noqa: E402
from pdamper.plotting.modes import mode_style  # noqa: E402


def _grid(modes):
    strokes, freqs = np.geomspace(0.005, 0.03, 6), np.array([1.0, 2.0, 3.0, 4.0])
    eta = np.random.default_rng(0).uniform(0, 1, (6, 4, 1))
    return xr.Dataset({"eta_star": (("stroke", "frequency", "seed"), eta),
                       "mode": (("stroke", "frequency", "seed"), np.full((6, 4, 1), modes))},
                      coords={"stroke": ("stroke", strokes, {"units": "m", "config_key": "drive.stroke",
                                                             "spacing": "log"}),
                              "frequency": ("frequency", freqs, {"units": "Hz", "config_key": "drive.frequency"}),
                              "seed": [0]},
                      attrs={"x_opt_m": 0.012, "gravity_m_s2": 9.81, "particles": 36, "shape": "cuboid"})


def _labels(ax, axis):
    lo, hi = sorted(ax.get_xlim() if axis == "x" else ax.get_ylim())
    ticks = ax.get_xticklabels() if axis == "x" else ax.get_yticklabels()
    k = 0 if axis == "x" else 1
    return [t.get_text() for t in ticks if lo <= t.get_position()[k] <= hi and t.get_text()]


def test_both_axes_have_three_or_more_labelled_ticks_and_none_overlap():
    fig = map_figure(_grid("scattered"), x="drive.stroke", y="frequency")
    FigureCanvasAgg(fig).draw()
    ax = fig.axes[0]
    assert len(_labels(ax, "x")) >= 3 and len(_labels(ax, "y")) >= 3
    boxes = [t.get_window_extent() for t in ax.get_xticklabels() if t.get_text()
             and ax.get_xlim()[0] <= t.get_position()[0] <= ax.get_xlim()[1]]
    assert not any(a.overlaps(b) for i, a in enumerate(boxes) for b in boxes[i + 1:])   # no "9 10" pile-up


def test_hatches_and_legend_follow_the_mode_style_table_also_for_a_new_mode():
    fig = map_figure(_grid("swaying"), x="drive.stroke", y="frequency")   # a mode the table does not list
    ax = fig.axes[0]
    hatches = {p.get_hatch() for p in ax.patches}
    assert hatches == {mode_style("swaying")["hatch"]} and hatches != {""}
    assert "swaying" in [t.get_text() for t in ax.get_legend().get_texts()]
