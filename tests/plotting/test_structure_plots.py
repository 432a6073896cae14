"""Structure figures: built from synthetic results, labelled, saved."""

import math
from types import SimpleNamespace

import numpy as np

from pdamper.analysis import decay_damping, extrema
from pdamper.structure import CoupledStructure
from pdamper.params import Case, Numerics, ParticleSet
from pdamper.plotting.structure import decay_figure, response_figure


def _decay():
    t = np.arange(1, 5001) * 1e-3
    w = 4 * math.pi
    bare = 0.02 * np.exp(-0.005 * w * t) * np.cos(w * t)
    damped = 0.02 * np.exp(-0.015 * w * t) * np.cos(w * t)
    summary = dict(particles=36, mass_ratio=0.021, initial_displacement_m=0.02, mass_kg=7.0,
                   natural_frequency_hz=2.0, damping_ratio=0.005, x_opt_m=0.0122)
    return SimpleNamespace(time=t, bare=bare, damped=damped, envelope_bare=extrema(t, bare),
                           envelope_damped=extrema(t, damped), zeta_bare=decay_damping(t, bare),
                           zeta_damped=decay_damping(t, damped), summary=summary)


def test_decay_figure(tmp_path):
    fig = decay_figure(_decay(), tmp_path / "d.png")
    ax_t, ax_z = fig.axes[:2]
    assert "[mm]" in ax_t.get_ylabel() and "[s]" in ax_t.get_xlabel() and "[%]" in ax_z.get_ylabel()
    labels = [t.get_text() for t in ax_t.get_legend().get_texts()]
    assert any("without damper" in s for s in labels) and any("with damper" in s for s in labels)
    assert (tmp_path / "d.png").stat().st_size > 10_000


def test_response_figure(tmp_path):
    s = CoupledStructure(mass=7.0, stiffness=1105.0, damping_ratio=0.005, force_amplitude=0.4, force_frequency=2.0)
    case = Case(particles=(ParticleSet(count=36),), drive=s, numerics=Numerics(integrator="verlet"))
    f = np.array([1.9, 2.0, 2.1])
    res = SimpleNamespace(case=case, frequencies=f, force_amplitude=0.4, damped=np.array([0.005, 0.01, 0.006]),
                          bare_run=np.array([0.006, 0.03, 0.008]),
                          summary=dict(measure_cycles=8, cycles=30, particles=36, x_opt_m=0.0122))
    fig = response_figure(res, tmp_path / "r.pdf")
    ax = fig.axes[0]
    assert "[Hz]" in ax.get_xlabel() and "[mm]" in ax.get_ylabel()
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any("solid mass" in s for s in labels) and any("with damper" in s for s in labels)
    assert (tmp_path / "r.pdf").exists()


def test_decay_legends_cover_no_curve_and_not_the_last_peaks():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    res = _decay()
    res.damped = res.bare * 0.999   # a weak damper: the last peaks stay high, in the upper right
    res.envelope_damped = extrema(res.time, res.damped)
    fig = decay_figure(res)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    for ax in fig.axes[:2]:
        box = ax.get_legend().get_window_extent(renderer)
        assert not box.overlaps(ax.get_window_extent(renderer))   # outside the axes: over no data
    ax_t = fig.axes[0]
    te, ae = res.envelope_damped
    last = ax_t.transData.transform(np.column_stack([te[-5:], ae[-5:] * 1e3]))
    assert not any(ax_t.get_legend().get_window_extent(renderer).contains(x, y) for x, y in last)
    # everything still on the figure
    fig_box = fig.bbox
    for ax in fig.axes[:2]:
        b = ax.get_legend().get_window_extent(renderer)
        assert b.x0 >= fig_box.x0 - 1 and b.y0 >= fig_box.y0 - 1 and b.x1 <= fig_box.x1 + 1
