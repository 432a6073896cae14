"""Structure figures: built from synthetic results, labelled, saved."""

import math
from types import SimpleNamespace

import numpy as np
import pytest

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


def _dem_response(force=0.4, damped=(0.005, 0.01, 0.006), f=(1.9, 2.0, 2.1)):
    s = CoupledStructure(mass=7.0, stiffness=1105.0, damping_ratio=0.005, force_amplitude=force, force_frequency=2.0)
    case = Case(particles=(ParticleSet(count=36),), drive=s, numerics=Numerics(integrator="verlet"))
    f = np.asarray(f, dtype=float)
    return SimpleNamespace(case=case, frequencies=f, force_amplitude=force, damped=np.asarray(damped, dtype=float),
                           bare_run=np.full(f.size, 0.006),
                           summary=dict(measure_cycles=8, cycles=30, particles=36, x_opt_m=0.0122,
                                        phase_damped_rad=[-0.3] * f.size))


def _labels(fig):
    return [t.get_text() for t in fig.legends[0].get_texts()]


def test_response_figure(tmp_path):
    fig = response_figure(_dem_response(), tmp_path / "r.pdf")
    ax_a, ax_n, ax_p = fig.axes[:3]
    assert "[Hz]" in ax_p.get_xlabel() and "[mm]" in ax_a.get_ylabel()
    assert "[mm/N]" in ax_n.get_ylabel() and "phase" in ax_p.get_ylabel() and "[deg]" in ax_p.get_ylabel()
    labels = _labels(fig)
    assert any("solid mass" in s for s in labels) and any("with damper" in s for s in labels)
    assert (tmp_path / "r.pdf").exists()


def test_response_legend_covers_no_panel():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = response_figure(_dem_response())
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    r = canvas.get_renderer()
    box = fig.legends[0].get_window_extent(r)
    assert all(not box.overlaps(ax.get_window_extent(r)) for ax in fig.axes)
    assert box.x0 >= fig.bbox.x0 - 1 and box.x1 <= fig.bbox.x1 + 1 and box.y0 >= fig.bbox.y0 - 1


def test_dem_points_are_not_joined_across_a_jump():
    # 12 mm then 4 mm: the DEM jumped from one branch to the other between 2.0 and 2.05 Hz
    res = _dem_response(damped=(0.008, 0.010, 0.012, 0.004, 0.0035), f=(1.9, 1.95, 2.0, 2.05, 2.1))
    fig = response_figure(res)
    ax = fig.axes[0]
    red_lines = [ln for ln in ax.get_lines() if ln.get_color() == "tab:red" and ln.get_linestyle() != "None"]
    spans = sorted((float(ln.get_xdata()[0]), float(ln.get_xdata()[-1])) for ln in red_lines)
    assert spans == [(1.9, 2.0), (2.05, 2.1)]


def test_the_bare_amplitude_over_the_force_and_the_phase_are_the_closed_forms():
    res = _dem_response()
    fig = response_figure([res, _dem_response(force=0.2)])
    ax_a, ax_n, ax_p = fig.axes[:3]
    s = res.case.drive
    blue = [ln for ln in ax_n.get_lines() if ln.get_color() == "tab:blue" and len(ln.get_xdata()) > 100]
    assert len(blue) == 2  # one per force ...
    np.testing.assert_allclose(blue[0].get_ydata(), blue[1].get_ydata(), rtol=1e-12)  # ... the same over F0
    f = blue[0].get_xdata()
    np.testing.assert_allclose(blue[0].get_ydata(), s.steady_amplitude(f, 1.0) * 1e3, rtol=1e-9)
    phase = [ln for ln in ax_p.get_lines() if ln.get_color() == "tab:blue"][0]
    k = np.argmin(np.abs(phase.get_xdata() - s.natural_frequency))
    assert phase.get_ydata()[k] == pytest.approx(-90.0, abs=1.0)  # the bare phase passes -90 deg at f_n
    assert any("F$_0$ = 0.2 N" in t for t in _labels(fig))


def test_a_motion_family_keeps_its_colour_from_figure_to_figure():
    from pdamper.plotting.structure import _C_FAMILY, _draw_fields
    from matplotlib.figure import Figure

    def fields(families):
        sols = [[SimpleNamespace(stable=True, family=fam, damper_amplitude_m=0.01 * (k + 1), damper_phasor=-0.01j)
                 for k, fam in enumerate(families)]] * 3
        return SimpleNamespace(frequencies=np.array([1.9, 2.0, 2.1]), solution=SimpleNamespace(solutions=sols),
                               summary={})

    colours = {}
    for families in (["other"], ["collide"], ["other", "collide"], ["collide", "other/collide", "other"]):
        ax = Figure().subplots()
        _draw_fields(ax, fields(families))
        for ln in ax.get_lines():
            colours.setdefault(ln.get_label(), set()).add(ln.get_color())
    assert all(len(c) == 1 for c in colours.values()), colours  # one colour per family, whatever else is drawn
    assert colours["with damper, from the fields (rolling collect-and-collide bed)"] == {_C_FAMILY["collide"]}
    assert colours["with damper, from the fields (scattered or swaying bed)"] == {_C_FAMILY["other"]}


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
