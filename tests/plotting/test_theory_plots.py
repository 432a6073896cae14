"""Figures of the closed-form laws (Fig. 4 overlay, Fig. 5)."""

import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from pdamper import theory  # noqa: E402
from pdamper.errors import InputError  # noqa: E402
from pdamper.plotting.theory import (  # noqa: E402
    draw_theory_curves,
    rolling_phase_figure,
    theory_figure,
)


@pytest.mark.parametrize("ext", ["png", "svg", "pdf"])
def test_theory_figure_is_written_in_the_format_asked(tmp_path, ext):
    path = tmp_path / f"eta.{ext}"
    fig = theory_figure(0.03, path=path)
    assert isinstance(fig, Figure)
    assert path.stat().st_size > 1000


def test_curves_drawn_onto_a_given_axes_for_overlays():
    ax = Figure().add_subplot()
    ax.plot([13.0, 20.0], [0.8, 0.6], "o", label="DEM")  # data already on the axes stays
    strokes = np.geomspace(0.5e-3, 50e-3, 40)
    draw_theory_curves(ax, 0.03, strokes)
    assert ax.get_xscale() == "log"
    assert "[mm]" in ax.get_xlabel() and "η*" in ax.get_ylabel()
    labels = [line.get_label() for line in ax.get_lines()]
    assert "DEM" in labels
    assert any("rolling" in s for s in labels) and any("scattered" in s for s in labels)
    assert any("bouncing" in s for s in labels)
    x_opt_line = next(line for line in ax.get_lines() if "X_{opt}" in line.get_label())
    assert x_opt_line.get_xdata()[0] == pytest.approx(theory.optimal_stroke(0.03) * 1e3)
    rolling = next(line for line in ax.get_lines() if line.get_label().startswith("rolling"))
    x_mm, eta = rolling.get_xdata(), rolling.get_ydata()
    assert x_mm.max() == pytest.approx(50.0)
    assert eta[0] == pytest.approx(theory.ETA_MAX, rel=1e-9)
    np.testing.assert_allclose(eta, theory.eta_rolling(x_mm / 1e3, 0.03))


def test_bouncing_can_be_left_out():
    ax = Figure().add_subplot()
    draw_theory_curves(ax, 0.01, bouncing=False)
    assert not any("bouncing" in line.get_label() for line in ax.get_lines())


def test_fig5_has_two_panels_and_can_be_saved(tmp_path):
    path = tmp_path / "fig5.png"
    fig = rolling_phase_figure(0.5, path=path)
    assert len(fig.axes) == 2
    assert path.stat().st_size > 1000
    ax_a = fig.axes[0]
    bed = next(line for line in ax_a.get_lines() if "bed" in line.get_label())
    theta, x_over_x = bed.get_xdata(), bed.get_ydata()
    assert theta[-1] == pytest.approx(theory.impact_phase_rolling(0.5, 1.0))
    # The bed ends on the impacting wall: x_p/X = sin θ_i + h/X.
    assert x_over_x[-1] == pytest.approx(math.sin(theta[-1]) + 2.0, rel=1e-9)


def test_fig5_at_the_optimum_hits_at_pi():
    fig = rolling_phase_figure(theory.X_OPT_OVER_H)
    bed = next(line for line in fig.axes[0].get_lines() if "bed" in line.get_label())
    assert bed.get_xdata()[-1] == pytest.approx(math.pi)


@pytest.mark.parametrize("call", [
    lambda p: theory_figure(0.03, path=p / "eta.xyz"),
    lambda p: theory_figure(0.03, path=p / "no_such_dir" / "eta.png"),
    lambda p: theory_figure(0.0),
    lambda p: theory_figure(0.03, operating_stroke=-1.0),
    lambda p: draw_theory_curves(Figure().add_subplot(), 0.03, strokes=[]),
    lambda p: rolling_phase_figure(0.3),
])
def test_bad_plot_inputs(tmp_path, call):
    with pytest.raises(InputError):
        call(tmp_path)


def test_the_laws_figure_marks_lift_off_and_the_tilt_bound():
    # issue 24: the laws were drawn beyond the lift-off stroke unmarked, and no tilt bound with --tilt
    from pdamper import theory
    from pdamper.plotting.theory import theory_figure

    h, f = 0.030, 2.0
    x_lift = theory.max_stroke_no_liftoff(f)
    x_tilt = theory.min_stroke_tilt(math.radians(3.0), f)
    fig = theory_figure(h, liftoff_stroke=x_lift, tilt_stroke=x_tilt)
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert any(lab.startswith("lift-off: A") and f"above {x_lift * 1e3:.3g} mm" in lab for lab in labels), labels
    assert any(f"below the tilt bound {x_tilt * 1e3:.3g} mm" in lab for lab in labels), labels
    spans = {p.get_label(): p.get_window_extent() for p in ax.patches if p.get_label().startswith(("lift", "below"))}
    assert len(spans) == 2
    x_lines = sorted(line.get_xdata()[0] for line in ax.get_lines() if line.get_linestyle() in ("-", "--")
                     and len(set(line.get_xdata())) == 1)
    assert any(abs(x - x_lift * 1e3) < 1e-9 for x in x_lines) and any(abs(x - x_tilt * 1e3) < 1e-9 for x in x_lines)
    # without them: nothing shaded (the figure of before)
    plain = theory_figure(h).axes[0]
    assert not [p for p in plain.patches if p.get_label().startswith(("lift", "below"))]
