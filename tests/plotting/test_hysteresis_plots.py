"""The hysteresis figure (pdamper.plotting.hysteresis): the loops it draws are the analysis's."""

from __future__ import annotations

import numpy as np

F_HZ, X = 2.0, 0.012
W = 2 * np.pi * F_HZ
T = np.arange(0.0, 6.0, 2e-4)
POS = X * np.sin(W * T)
FORCE = 3.0 * W * X * np.cos(W * T) + 5.0 * np.clip(np.sin(2 * W * T), 0.9, None) - 4.5


def test_the_loops_are_drawn(tmp_path):
    from pdamper.plotting.hysteresis import plot_hysteresis

    fig = plot_hysteresis(T, FORCE, POS, F_HZ, tmp_path / "loop.png", harmonics=(1, 10))
    assert (tmp_path / "loop.png").stat().st_size > 10_000
    lines = fig.axes[0].get_lines()
    first = fig.loops[0]
    np.testing.assert_array_equal(lines[1].get_ydata(), first.force)  # the first harmonic, after the samples
    assert [lp.harmonics for lp in fig.loops] == [1, 10] and "mJ a cycle" in lines[1].get_label()
