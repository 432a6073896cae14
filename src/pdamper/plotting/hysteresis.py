"""The damper's hysteresis loop drawn: force against the container's displacement over a cycle,
raw (the window's samples, grey), filtered to its first harmonics and reduced to the first harmonic
(the ellipse whose area is the complex power's energy per cycle), with the energy of each in the
legend (:func:`pdamper.analysis.hysteresis.hysteresis_loop`).

Matplotlib's object API with the Agg canvas (no pyplot), as every figure of pdamper.
"""

from __future__ import annotations

import numpy as np

from ..analysis.hysteresis import hysteresis_loop
from .figure import check_path, save

__all__ = ["plot_hysteresis"]


def plot_hysteresis(time, force, position, frequency, path=None, *, drop_cycles: int = 2, harmonics=(1, 10),
                    title: str | None = None, figsize=(6.4, 4.8), dpi: int = 150):
    """Draw the hysteresis loop of a record (``time`` [s], ``force`` [N], ``position`` [m], the
    drive ``frequency`` [Hz]; a run's ``result.signals``): the raw samples of the analysed window
    and one loop for each number of ``harmonics`` (1: the first-harmonic ellipse; 10: filtered);
    saved to ``path`` if given (``.png``, ``.svg``, ``.pdf``). Returns the matplotlib Figure; its
    loops are ``fig.loops`` (the :class:`~pdamper.analysis.hysteresis.HysteresisLoop` of each)."""
    path = check_path(path, create_folder=True)
    loops = [hysteresis_loop(time, force, position, frequency, drop_cycles=drop_cycles, harmonics=k)
             for k in harmonics]

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    t = np.asarray(time, dtype=float)
    a, b = loops[0].window_s
    inside = (t >= a) & (t <= b)
    ax.plot(1e3 * np.asarray(position)[inside], np.asarray(force)[inside], color="0.75", lw=0.5,
            label=f"samples ({loops[0].cycles} cycles)")
    styles = {1: ("tab:red", 1.8, "first harmonic")}
    for loop in loops:
        color, lw, name = styles.get(loop.harmonics, ("tab:blue", 1.3, f"{loop.harmonics} harmonics"))
        ax.plot(1e3 * loop.position, loop.force, color=color, lw=lw,
                label=f"{name}: {1e3 * loop.energy_per_cycle_J:.4g} mJ a cycle")
    ax.axhline(0.0, color="0.4", lw=0.5)
    ax.axvline(0.0, color="0.4", lw=0.5)
    ax.set_xlabel("container displacement x [mm]")
    ax.set_ylabel("driving force F [N]")
    ax.set_title(title or f"hysteresis loop at {loops[0].frequency_hz:.4g} Hz", fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    fig.loops = loops
    if path is not None:
        save(fig, path, dpi)
    return fig
