"""Every motion mode of the classifier has a look of its own in the one table, and the mode map
draws the vertical and baffled beds' modes with it."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

from pdamper.analysis.modes import MODES  # noqa: E402
from pdamper.plotting.mode_looks import MODE_COLOURS, MODE_HATCHES, MODE_MARKERS, mode_order, mode_style  # noqa: E402
from pdamper.plotting.modes import mode_map_figure  # noqa: E402


def test_every_mode_is_listed_with_a_colour_and_a_marker_of_its_own():
    for table in (MODE_COLOURS, MODE_MARKERS, MODE_HATCHES):
        assert set(MODES) <= set(table)
    assert len({MODE_COLOURS[m] for m in MODES}) == len(MODES)
    assert len({MODE_MARKERS[m] for m in MODES}) == len(MODES)
    # the efficient collect-and-collide modes are plain on the design map, the others hatched
    plain = {m for m in MODES if not MODE_HATCHES[m]}
    assert plain == {"rolling-collect-and-collide", "bouncing-collect-and-collide", "compartment-collect-and-collide"}
    assert mode_order()[-2:] == ["unknown", "failed"] and set(MODES) <= set(mode_order())


def test_the_mode_map_colours_the_vertical_modes_by_the_table():
    strokes = np.array([0.0005, 0.004, 0.007, 0.012, 0.02])
    modes = np.array([["locked"], ["fluidised"], ["bouncing-collect-and-collide"], ["bouncing-collect-and-collide"],
                      ["bouncing-bed"]])
    ds = xr.Dataset({"eta_star": (("stroke", "seed"), np.array([[0.0], [0.72], [0.96], [0.77], [0.5]])),
                     "mode": (("stroke", "seed"), modes)},
                    coords={"stroke": ("stroke", strokes, {"units": "m"}), "seed": [0]}, attrs={"particles": 96})
    fig = mode_map_figure([ds])
    ax = fig.axes[-1]
    colours = [to_rgba(p.get_facecolor()) for p in ax.patches][:len(strokes)]
    assert colours == [to_rgba(mode_style(m)["color"]) for m in modes[:, 0]]
