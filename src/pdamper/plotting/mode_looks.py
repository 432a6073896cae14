"""The look of each motion mode (colour, marker, hatching) in every figure that shows modes: the
sweep figure's markers, the mode map, the design map. Apart from the figures, so each of them
can import it.
"""

from __future__ import annotations

__all__ = ["MODE_COLOURS", "MODE_MARKERS", "MODE_HATCHES", "mode_style", "mode_order", "mode_rank"]

# The one place where the motion modes get their look (the mode map, the sweep figure's markers, the
# design map's hatching). A mode of pdamper.analysis.modes.MODES that is not listed here still gets a
# colour, marker and hatch of its own from the spare ones below (see mode_style), so adding a mode to
# the classifier needs no change here; list it to choose its look.

#: Colour of each mode (cases without a mode: white, failed: black).
MODE_COLOURS = {
    "locked": "#636363",
    "scattered": "#9ecae1",
    "rolling-collect-and-collide": "#31a354",
    "swaying": "#c7e9c0",
    "single-sided": "#fd8d3c",
    "lift-off": "#de2d26",
    "compartment-collect-and-collide": "#1b9e77",
    "bouncing-collect-and-collide": "#006d2c",
    "bouncing-bed": "#8c510a",
    "fluidised": "#9e9ac8",
    "unknown": "#ffffff",
    "failed": "#000000",
}
#: Marker of each mode on η*(X) curves.
MODE_MARKERS = {
    "locked": "p",
    "scattered": "o",
    "rolling-collect-and-collide": "s",
    "swaying": "v",
    "single-sided": "^",
    "lift-off": "D",
    "compartment-collect-and-collide": "P",
    "bouncing-collect-and-collide": "h",
    "bouncing-bed": "<",
    "fluidised": "*",
    "unknown": "o",
    "failed": "X",
}
#: Hatching of each mode on the design map (the collect-and-collide modes plain).
MODE_HATCHES = {
    "locked": "++",
    "scattered": "..",
    "rolling-collect-and-collide": "",
    "swaying": "--",
    "single-sided": "//",
    "lift-off": "oo",
    "compartment-collect-and-collide": "",
    "bouncing-collect-and-collide": "",
    "bouncing-bed": "\\\\",
    "fluidised": "**",
    "unknown": "",
    "failed": "xx",
}
_SPARE_COLOURS = ("#756bb1", "#e7ba52", "#8c6d31", "#e377c2", "#17becf", "#bcbd22")
_SPARE_MARKERS = (">", "d", "8", "H", "1", "2")
_SPARE_HATCHES = ("||", "x.", "oo..", "..--", "|*", "O")


def mode_order() -> list[str]:
    """Every mode with a look, in legend order: those of :data:`MODE_COLOURS`, then any of the
    classifier's modes (:data:`pdamper.analysis.modes.MODES`) it does not list, ``unknown`` and
    ``failed`` last."""
    from ..analysis.modes import MODES

    ends = ("unknown", "failed")
    order = [m for m in MODE_COLOURS if m not in ends] + [m for m in MODES if m not in MODE_COLOURS]
    return order + list(ends)


def mode_style(mode: str) -> dict:
    """``{"color", "marker", "hatch"}`` of a motion mode: from :data:`MODE_COLOURS`,
    :data:`MODE_MARKERS` and :data:`MODE_HATCHES`; a mode they do not list (e.g. one just added to
    :data:`pdamper.analysis.modes.MODES`) gets a spare colour, marker and hatch of its own, fixed by
    its place in the classifier's list (or its name).

    >>> mode_style("scattered")["marker"]
    'o'
    """
    mode = str(mode)
    if mode in MODE_COLOURS:
        return {"color": MODE_COLOURS[mode], "marker": MODE_MARKERS.get(mode, "o"),
                "hatch": MODE_HATCHES.get(mode, "")}
    unlisted = [m for m in mode_order() if m not in MODE_COLOURS]
    k = unlisted.index(mode) if mode in unlisted else len(unlisted) + sum(map(ord, mode))
    return {"color": _SPARE_COLOURS[k % len(_SPARE_COLOURS)], "marker": _SPARE_MARKERS[k % len(_SPARE_MARKERS)],
            "hatch": _SPARE_HATCHES[k % len(_SPARE_HATCHES)]}


def mode_rank(mode: str) -> int:
    """Place of a mode in the legend order (:func:`mode_order`); a mode without a look comes last."""
    order = mode_order()
    return order.index(mode) if mode in order else len(order)
