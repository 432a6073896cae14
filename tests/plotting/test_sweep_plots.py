"""Stroke-sweep figures (η*(X) like the paper's Fig. 4, energy per cycle) on synthetic data."""

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

from pdamper import theory  # noqa: E402
from pdamper.errors import InputError  # noqa: E402
from pdamper.plotting.sweep import energy_figure, sweep_figure  # noqa: E402

STROKES = np.geomspace(0.5e-3, 50e-3, 12)
BED_MASS = 0.2  # kg
FREQ = 2.0  # Hz


def _eta(strokes, h, seeds, rng):
    """η* like a DEM sweep: 0.05-0.3 below X_opt, a little under the rolling law above."""
    x_opt = theory.optimal_stroke(h)
    rolling = 0.9 * theory.eta_rolling(np.maximum(strokes, x_opt), h)
    base = np.where(strokes >= x_opt, rolling, 0.05 + 0.25 * strokes / x_opt)
    return base[:, None] + rng.normal(0.0, 0.03, (strokes.size, seeds))


def make_sweep(seeds=3, clearances=(0.03,), labels=None, strokes=STROKES, seed=0):
    """A results dataset shaped like the sweep engine's (a ``setting`` dim if several)."""
    rng = np.random.default_rng(seed)
    eta = np.stack([_eta(strokes, h, seeds, rng) for h in clearances])
    v = 2 * np.pi * FREQ * strokes
    energy = eta * np.pi * BED_MASS * (v ** 2)[None, :, None]
    dims = ("setting", "stroke", "seed")
    ds = xr.Dataset(
        {"eta_star": (dims, eta, {"units": "1"}),
         "energy_per_cycle": (dims, energy, {"units": "J"})},
        coords={"stroke": ("stroke", strokes, {"units": "m"}), "seed": np.arange(seeds),
                "setting": labels or [f"h = {h * 1e3:g} mm" for h in clearances]},
        attrs={"frequency_hz": FREQ, "particles": 36, "max_particles": 48, "shape": "cuboid",
               "pdamper_version": "test"})
    if len(clearances) == 1:
        ds = ds.isel(setting=0, drop=True)
        ds.attrs["clearance_m"] = clearances[0]
        ds.attrs["x_opt_m"] = theory.optimal_stroke(clearances[0])
    else:
        ds["clearance"] = ("setting", np.asarray(clearances, dtype=float), {"units": "m"})
    return ds


def _labels(fig):
    return [t.get_text() for legend in fig.legends for t in legend.get_texts()]


def _means(ax):
    """The mean lines (one per setting), in drawing order."""
    return [ln for ln in ax.get_lines() if (ln.get_gid() or "").startswith("mean ")]


def _points(line):
    """(x, y) of a line without the NaN gaps that break it."""
    x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
    keep = ~(np.isnan(y) & ~np.isin(x, STROKES * 1e3))
    return x[keep], y[keep]


def _lines(ax, prefix):
    return [ln for ln in ax.get_lines() if ln.get_label().startswith(prefix)]


@pytest.mark.parametrize("seeds", [1, 3])
def test_eta_figure_axes_and_theory(seeds):
    fig = sweep_figure(make_sweep(seeds=seeds))
    assert isinstance(fig, Figure)
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "linear"
    assert ax.get_xlabel() == "stroke X [mm]"
    assert ax.get_ylabel() == "reduced loss factor η* [-]"
    lo, hi = ax.get_xlim()
    assert lo < 0.5 and hi > 50.0  # strokes are drawn in mm
    # the mean line over seeds, in mm, at every stroke
    x, y = _points(_means(ax)[0])
    np.testing.assert_allclose(x, STROKES * 1e3)
    eta = make_sweep(seeds=seeds).eta_star.values
    np.testing.assert_allclose(y, eta.mean(axis=1))
    # the laws for h = 30 mm with X_opt and η*_max
    assert _lines(ax, "rolling") and _lines(ax, "scattered")
    x_opt = next(ln for ln in ax.get_lines() if "X_{opt}" in ln.get_label())
    assert x_opt.get_xdata()[0] == pytest.approx(theory.optimal_stroke(0.03) * 1e3)
    eta_max = next(ln for ln in ax.get_lines() if "max" in ln.get_label())
    assert eta_max.get_ydata()[0] == pytest.approx(20 / (7 * np.pi))
    assert not _lines(ax, "bouncing")
    labels = _labels(fig)
    assert "DEM" in labels
    assert ("single seeds" in labels) == (seeds > 1)
    assert ax.get_legend() is None  # the legend sits outside the axes, over no data


def test_spread_band_and_single_seeds_drawn_for_several_seeds():
    ds = make_sweep(seeds=3)
    ax = sweep_figure(ds).axes[0]
    assert len(ax.collections) == 3  # the band (fill_between) on each side of X_opt + seed dots (scatter)
    dots = next(c for c in ax.collections if c.get_offsets().shape[0] == ds.eta_star.size)
    np.testing.assert_allclose(np.sort(dots.get_offsets()[:, 1]),
                               np.sort(ds.eta_star.values.ravel()))
    ax1 = sweep_figure(make_sweep(seeds=1)).axes[0]
    assert len(ax1.collections) == 0  # one seed: no spread to show


def test_settings_get_one_colour_each_and_theory_per_clearance():
    ds = make_sweep(clearances=(0.03, 0.01), labels=["N_p = 36", "N_p = 44"])
    fig = sweep_figure(ds)
    ax = fig.axes[0]
    labels = _labels(fig)
    assert "DEM, N_p = 36" in labels and "DEM, N_p = 44" in labels
    means = _means(ax)
    assert len(means) == 2 and means[0].get_color() != means[1].get_color()
    x_opts = sorted(ln.get_xdata()[0] for ln in ax.get_lines() if "X_{opt}" in ln.get_label())
    assert x_opts == pytest.approx([theory.optimal_stroke(0.01) * 1e3,
                                    theory.optimal_stroke(0.03) * 1e3])
    assert any("h = 10 mm" in s for s in labels) and any("h = 30 mm" in s for s in labels)


def test_settings_sharing_a_clearance_draw_the_laws_once():
    ds = make_sweep(clearances=(0.03, 0.03, 0.03), labels=["μ = 0.01", "μ = 0.1", "μ = 1"])
    ax = sweep_figure(ds).axes[0]
    assert len(_lines(ax, "rolling")) == 1 and len(_lines(ax, "scattered")) == 1


def test_numeric_setting_coordinate_and_clearance_from_x_opt():
    ds = make_sweep(clearances=(0.03, 0.03)).assign_coords(setting=[0.01, 0.1])
    ds = ds.drop_vars("clearance").rename({"setting": "mu"})
    ds.attrs["x_opt_m"] = theory.optimal_stroke(0.03)
    fig = sweep_figure(ds)
    assert "DEM, mu = 0.01" in _labels(fig)
    x_opt = next(ln for ln in fig.axes[0].get_lines() if "X_{opt}" in ln.get_label())
    assert x_opt.get_xdata()[0] == pytest.approx(theory.optimal_stroke(0.03) * 1e3)


def test_partially_computed_sweep_plots_what_is_there():
    ds = make_sweep(seeds=3, clearances=(0.03, 0.01), labels=["a", "b"])
    eta = ds.eta_star.values
    eta[:, 8:, :] = np.nan  # not computed yet
    eta[0, 2, 1:] = np.nan  # one seed done at this stroke
    eta[1, :, :] = np.nan  # a setting with nothing yet
    ds["eta_star"] = (ds.eta_star.dims, eta)
    fig = sweep_figure(ds)
    ax = fig.axes[0]
    x, y = _points(_means(ax)[0])
    np.testing.assert_allclose(x, STROKES[:8] * 1e3)
    assert np.all(np.isfinite(y))
    assert "DEM, b (no data yet)" in _labels(fig)
    assert "cases computed" in ax.get_title()
    assert ax.get_xlim()[1] > 50.0  # the axis spans the whole planned sweep


def test_nothing_computed_yet_still_gives_a_figure(tmp_path):
    ds = make_sweep()
    ds["eta_star"][:] = np.nan
    ds["energy_per_cycle"][:] = np.nan
    fig = sweep_figure(ds, tmp_path / "empty.png")
    assert any("no computed cases" in t.get_text() for t in fig.axes[0].texts)
    energy_figure(ds, tmp_path / "empty_energy.png")
    assert (tmp_path / "empty.png").stat().st_size > 1000


@pytest.mark.parametrize("ext", ["png", "svg", "pdf"])
def test_files_written_in_the_format_asked(tmp_path, ext):
    ds = make_sweep(clearances=(0.03, 0.01), labels=["N_p = 36", "N_p = 44"])
    eta_path, energy_path = tmp_path / f"eta.{ext}", tmp_path / f"energy.{ext}"
    sweep_figure(ds, eta_path)
    energy_figure(ds, energy_path)
    for path in (eta_path, energy_path):
        assert path.stat().st_size > 1000
    head = eta_path.read_bytes()[:8]
    assert {"png": b"\x89PNG", "pdf": b"%PDF", "svg": b"<?xml"}[ext] in head


def test_title_from_argument_attribute_or_attributes():
    ds = make_sweep()
    assert "cuboid" in sweep_figure(ds).get_suptitle()
    assert "h = 30 mm" in sweep_figure(ds).get_suptitle()
    ds.attrs["title"] = "Fig. 4a"
    assert sweep_figure(ds).get_suptitle() == "Fig. 4a"
    assert sweep_figure(ds, title="mine").get_suptitle() == "mine"


def test_theory_can_be_left_out():
    ax = sweep_figure(make_sweep(), theory=False).axes[0]
    assert not _lines(ax, "rolling") and not any("X_{opt}" in ln.get_label()
                                                 for ln in ax.get_lines())
    assert not any("max" in ln.get_label() for ln in ax.get_lines())
    assert ax.get_xscale() == "log"


def test_energy_figure_log_log_in_mJ_with_laws():
    ds = make_sweep(seeds=3)
    ds.attrs["bed_mass_kg"] = BED_MASS
    ax = energy_figure(ds).axes[0]
    assert ax.get_xscale() == "log" and ax.get_yscale() == "log"
    assert ax.get_xlabel() == "stroke X [mm]" and "[mJ]" in ax.get_ylabel()
    np.testing.assert_allclose(_points(_means(ax)[0])[1], ds.energy_per_cycle.values.mean(axis=1) * 1e3)
    rolling = _lines(ax, "rolling")[0]
    x = rolling.get_xdata() / 1e3
    expected = theory.energy_per_cycle_rolling(x, 0.03, frequency=FREQ, bed_mass=BED_MASS)
    np.testing.assert_allclose(rolling.get_ydata(), expected * 1e3, rtol=1e-9)


def test_energy_figure_without_bed_mass_marks_x_opt_only_and_survives_values_below_zero():
    ds = make_sweep(seeds=3)
    energy = ds.energy_per_cycle.values
    energy[0, :] = -1e-6  # a stroke whose seeds all took energy out: mean < 0
    energy[1, 0] = -1e-6
    ds["energy_per_cycle"] = (ds.energy_per_cycle.dims, energy)
    ax = energy_figure(ds).axes[0]
    assert not _lines(ax, "rolling")
    assert any("X_{opt}" in ln.get_label() for ln in ax.get_lines())
    y = _points(_means(ax)[0])[1]
    assert np.isnan(y[0]) and np.all(y[1:] > 0)
    assert "<= 0" in ax.get_title()


@pytest.mark.parametrize("make, match", [
    (lambda ds: ds.drop_vars("eta_star"), "no variable 'eta_star'"),
    (lambda ds: ds.rename({"stroke": "amplitude"}), "no 'stroke' dimension"),
    (lambda ds: ds.eta_star, "expected an xarray.Dataset"),
    (lambda ds: ds.assign_coords(stroke=-ds.stroke), "finite and > 0"),
    (lambda ds: ds.expand_dims(a=2, b=2), "at most one study dimension"),
])
def test_bad_input_says_what_is_wrong(make, match):
    with pytest.raises(InputError, match=match):
        sweep_figure(make(make_sweep()))


def test_energy_figure_needs_energy():
    with pytest.raises(InputError, match="no variable 'energy_per_cycle'"):
        energy_figure(make_sweep().drop_vars("energy_per_cycle"))


@pytest.mark.parametrize("name, match", [("eta.jpgx", "unknown format"),
                                         ("missing/eta.png", "does not exist")])
def test_bad_path_refused_before_drawing(tmp_path, name, match):
    with pytest.raises(InputError, match=match):
        sweep_figure(make_sweep(), tmp_path / name)


def _with_modes(ds, rolling_from):
    """Give ``ds`` a ``mode`` variable: scattered below the stroke ``rolling_from`` [m], rolling from it."""
    rolling = ds.stroke.values >= rolling_from
    mode = np.where(rolling, "rolling-collect-and-collide", "scattered")
    ds["mode"] = (("stroke", "seed"), np.repeat(mode[:, None], ds.sizes["seed"], axis=1))
    return ds


def test_the_mean_line_is_broken_between_the_strokes_either_side_of_x_opt():
    ds = make_sweep(seeds=3)
    x_opt = theory.optimal_stroke(0.03) * 1e3
    ax = sweep_figure(ds).axes[0]
    x = np.asarray(_means(ax)[0].get_xdata(), float)
    y = np.asarray(_means(ax)[0].get_ydata(), float)
    below = np.flatnonzero((x < x_opt) & np.isfinite(y))[-1]
    assert x[below + 2] > x_opt and np.isnan(y[below + 1])   # no segment joins the two sides
    assert np.isfinite(y).sum() == STROKES.size and np.isnan(y).sum() == 1   # one break only
    # the band too: one fill each side, neither reaching across X_opt
    bands = [c for c in ax.collections if c.get_offsets().shape[0] != ds.eta_star.size]
    spans = sorted((p.vertices[:, 0].min(), p.vertices[:, 0].max()) for c in bands for p in c.get_paths())
    assert len(spans) == 2 and spans[0][1] < x_opt < spans[1][0]


def test_a_mode_change_breaks_the_line_too():
    ds = _with_modes(make_sweep(seeds=1), rolling_from=STROKES[3])   # rolling far below X_opt
    y = np.asarray(_means(sweep_figure(ds).axes[0])[0].get_ydata(), float)
    assert np.isnan(y).sum() == 2 and np.isnan(y[3])   # after the 3rd stroke (mode) and at X_opt


def test_each_point_is_marked_by_its_mode_with_a_legend():
    from matplotlib.colors import to_rgba

    from pdamper.plotting.modes import mode_style

    ds = _with_modes(make_sweep(seeds=3), rolling_from=theory.optimal_stroke(0.03))
    ds["mode"][1, 0] = "single-sided"   # seeds disagree: the majority marks the point
    fig = sweep_figure(ds)
    ax = fig.axes[0]
    marks = {ln.get_gid(): ln for ln in ax.get_lines() if (ln.get_gid() or "").startswith("mode ")}
    assert set(marks) == {"mode scattered DEM", "mode rolling-collect-and-collide DEM"}
    x_opt = theory.optimal_stroke(0.03) * 1e3
    for mode, ln in ((m, marks[f"mode {m} DEM"]) for m in ("scattered", "rolling-collect-and-collide")):
        look = mode_style(mode)
        assert ln.get_marker() == look["marker"] and to_rgba(ln.get_markerfacecolor()) == to_rgba(look["color"])
        x = np.asarray(ln.get_xdata())
        assert np.all(x < x_opt) if mode == "scattered" else np.all(x > x_opt)
    assert marks["mode scattered DEM"].get_marker() != marks["mode rolling-collect-and-collide DEM"].get_marker()
    labels = _labels(fig)
    assert "mode: scattered" in labels and "mode: rolling-collect-and-collide" in labels
    assert "mode: single-sided" not in labels   # a minority of seeds marks no point


def test_a_mode_the_style_table_does_not_list_gets_its_own_look():
    from pdamper.plotting.modes import MODE_COLOURS, mode_style

    ds = _with_modes(make_sweep(seeds=1), rolling_from=theory.optimal_stroke(0.03))
    ds["mode"][:4, 0] = "gliding"   # e.g. a mode just added to pdamper.analysis.modes.MODES
    fig = sweep_figure(ds)
    look = mode_style("gliding")
    assert look["color"] not in MODE_COLOURS.values()
    assert look["marker"] not in {mode_style(m)["marker"] for m in MODE_COLOURS if m != "unknown"}
    assert "mode: gliding" in _labels(fig)
    mark = next(ln for ln in fig.axes[0].get_lines() if ln.get_gid() == "mode gliding DEM")
    assert mark.get_marker() == look["marker"] and len(mark.get_xdata()) == 4


def test_results_without_modes_keep_a_marker_per_setting():
    ds = make_sweep(clearances=(0.03, 0.01), labels=["N_p = 36", "N_p = 44"])
    ax = sweep_figure(ds).axes[0]
    assert not any((ln.get_gid() or "").startswith("mode ") for ln in ax.get_lines())
    assert [ln.get_marker() for ln in _means(ax)] == ["o", "s"]


@pytest.mark.parametrize("lo, hi", [(0.5e-3, 50e-3), (4e-3, 25e-3), (10e-3, 15e-3), (2.2e-3, 9e-3)])
def test_the_stroke_axis_labels_at_least_three_ticks(lo, hi):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    fig = sweep_figure(make_sweep(strokes=np.geomspace(lo, hi, 6)))
    FigureCanvasAgg(fig).draw()
    ax = fig.axes[0]
    a, b = ax.get_xlim()
    shown = [t.get_text() for t in ax.get_xticklabels() if a <= t.get_position()[0] <= b and t.get_text()]
    assert len(shown) >= 3, shown


def _study(panels=("N_p = 36", "N_p = 44"), per_panel=4):
    """A study dataset like 'pdamper study tilt': settings on a 'setting' dim with a 'panel' coordinate."""
    h = {"N_p = 36": 0.03, "N_p = 44": 0.01}
    labels, clear, panel = [], [], []
    for p in panels:
        for k in range(per_panel):
            labels.append(f"{p[-2:]}, setting {k}")
            clear.append(h[p])
            panel.append(p)
    ds = make_sweep(seeds=1, clearances=tuple(clear), labels=labels)
    x_opts = [theory.optimal_stroke(c) for c in clear]
    mode = np.where(STROKES[None, :] >= np.array(x_opts)[:, None], "rolling-collect-and-collide", "scattered")
    mode[-1, :3] = "single-sided"
    ds["mode"] = (("setting", "stroke", "seed"), mode[:, :, None])
    return ds.assign_coords(panel=("setting", panel)).assign_attrs(title="tilt-like")


def test_a_study_with_two_fillings_draws_panels_a_and_b_aligned_and_uncrowded():
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    from pdamper.plotting.sweep import study_figure

    fig = study_figure(_study())
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    r = canvas.get_renderer()
    a, b = fig.axes[:2]
    assert [a.get_title(), b.get_title()] == ["(a) N_p = 36", "(b) N_p = 44"]
    assert a.get_position().y0 == pytest.approx(b.get_position().y0)       # the panels line up
    assert a.get_position().height == pytest.approx(b.get_position().height)
    assert a.get_ylim() == b.get_ylim()                                       # one η* axis
    # each panel's legend: its 4 settings and its X_opt, under it, over no data
    for ax, n in ((a, "36"), (b, "44")):
        texts = [t.get_text() for t in ax.get_legend().get_texts()]
        assert sum(s.startswith(f"DEM, {n}") for s in texts) == 4 and len(texts) == 5
        assert any("X_{opt}" in s for s in texts)
        assert not ax.get_legend().get_window_extent(r).overlaps(ax.get_window_extent(r))
    # modes, single seeds and the shared laws once, at the bottom of the figure
    shared = [t.get_text() for t in fig.legends[0].get_texts()]
    assert len(shared) == len(set(shared))
    assert {"mode: scattered", "mode: rolling-collect-and-collide", "mode: single-sided"} <= set(shared)
    assert any(s.startswith("rolling collect-and-collide") for s in shared)
    assert not any(s.startswith("DEM") or "X_{opt}" in s for s in shared)
    # one mean line per setting, each broken at its panel's X_opt
    for ax, h in ((a, 0.03), (b, 0.01)):
        for line in _means(ax):
            y = np.asarray(line.get_ydata(), float)
            x = np.asarray(line.get_xdata(), float)
            assert np.isnan(y).sum() >= 1
            gap = x[np.isnan(y)][0]
            assert x[np.isfinite(y)][x[np.isfinite(y)] < gap].max() < theory.optimal_stroke(h) * 1e3
