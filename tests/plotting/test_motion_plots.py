"""Motion figures (sphere paths, bed against the walls, animation) and the mode map, on synthetic data."""

import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
import xarray as xr  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402
from PIL import Image  # noqa: E402

from pdamper.errors import InputError  # noqa: E402
from pdamper.params import Case, Container, ParticleSet  # noqa: E402
from pdamper.excitation import HarmonicDrive  # noqa: E402
from pdamper.plotting.modes import MODE_COLOURS, mode_map_figure, mode_rows  # noqa: E402
from pdamper.plotting.motion import animate, paths_figure, walls_figure  # noqa: E402

R = 0.005
CASE = Case(particles=(ParticleSet(count=36),), drive=HarmonicDrive(stroke=0.015), cycles=3, drop_cycles=1)


def rolling_trajectory(fps=50.0, cycles=3):
    """36 spheres in a 9 x 4 block, wall to wall once a cycle (container frame)."""
    t = np.arange(1, int(cycles * fps / 2) + 1) / fps
    xs = (np.arange(9) - 4) * 2 * R
    zs = (np.arange(4) - 1.5) * 2 * R
    sites = np.array([(x, z) for x in xs for z in zs])
    centre = 0.015 * np.clip(1.6 * np.sin(2 * np.pi * 2 * t - 2.0), -1, 1)
    pos = np.zeros((t.size, 36, 3))
    pos[:, :, 0] = sites[:, 0] + centre[:, None]
    pos[:, :, 1] = R
    pos[:, :, 2] = sites[:, 1]
    vel = np.gradient(pos, t, axis=0)
    return {"time": t, "position": pos, "velocity": vel, "spin": np.zeros_like(pos), "radius": np.full(36, R)}


def _title_texts(fig):
    return " ".join(ax.get_title() for ax in fig.axes)


def test_paths_figure_one_panel_per_run_with_the_mode(tmp_path):
    tr = rolling_trajectory()
    still = {**tr, "position": np.repeat(tr["position"][:1], len(tr["time"]), axis=0)}
    still["position"][:, :, 0] -= still["position"][0, :, 0].min() + 0.06 - R  # on the -x wall
    tilted = Case(particles=(ParticleSet(count=36),), drive=HarmonicDrive(stroke=0.002), cycles=3, drop_cycles=1,
                  container=Container(tilt=(0.0, 0.0, math.radians(3.0))))   # the -x wall is the low one
    fig = paths_figure([("moving", tr, CASE), ("resting", still, tilted)], tmp_path / "paths.png")
    assert isinstance(fig, Figure) and len(fig.axes) == 3   # two panels and their colorbar
    assert "rolling-collect-and-collide" in fig.axes[0].get_title()
    assert "single-sided" in fig.axes[1].get_title()
    assert "[mm]" in fig.axes[0].get_xlabel()
    assert (tmp_path / "paths.png").stat().st_size > 10_000


def _colorbars(fig):
    return [ax for ax in fig.axes if ax.get_label() == "<colorbar>"]


def test_paths_are_coloured_by_time_with_a_labelled_colorbar():
    tr = rolling_trajectory()
    fig = paths_figure([("a", tr, CASE), ("b", tr, CASE)], cycles=2.0)
    bars = _colorbars(fig)
    assert len(bars) == 1 and bars[0].get_ylabel() == "time Ωt/2π [drive cycles]"   # one, shared
    from matplotlib.collections import LineCollection

    paths = next(c for c in fig.axes[0].collections if isinstance(c, LineCollection))
    t = tr["time"][tr["time"] >= tr["time"][-1] - 1.0 - 1e-12]   # the last 2 cycles at 2 Hz
    per_sphere = paths.get_array().reshape(36, t.size - 1)
    np.testing.assert_allclose(per_sphere[0], (t[:-1] + t[1:]) / 2 * 2.0)   # drive cycles, in time order
    assert paths.norm.vmin == pytest.approx(t[0] * 2.0) and paths.norm.vmax == pytest.approx(t[-1] * 2.0)
    assert len(paths.get_segments()) == 36 * (t.size - 1)


def test_paths_of_different_times_get_a_colorbar_each_and_seconds_without_a_drive_frequency():
    from pdamper.excitation import Still

    tr = rolling_trajectory()
    short = {k: (v[: len(v) // 2] if k != "radius" else v) for k, v in tr.items()}
    fig = paths_figure([("long", tr, CASE), ("short", short, CASE)])
    assert len(_colorbars(fig)) == 2
    still = Case(particles=(ParticleSet(count=36),), drive=Still(duration_s=1.5), cycles=1, drop_cycles=0)
    fig = paths_figure([("still", tr, still)], cycles=None)
    assert [ax.get_ylabel() for ax in _colorbars(fig)] == ["time t [s]"]


def test_walls_figure_draws_both_walls_and_the_bed(tmp_path):
    fig = walls_figure(rolling_trajectory(), CASE, tmp_path / "walls.svg")
    ax = fig.axes[0]
    labels = [line.get_label() for line in ax.get_lines()]
    assert {"-x wall", "+x wall", "bed centre"} <= set(labels)
    wall = ax.get_lines()[0].get_ydata()
    assert wall.max() - wall.min() == pytest.approx(30.0, abs=0.5)   # 2 X [mm] over whole cycles
    assert "mode: rolling-collect-and-collide" in ax.get_title()
    assert (tmp_path / "walls.svg").is_file()


def test_animation_gif_has_one_frame_per_trajectory_frame(tmp_path):
    out = animate(rolling_trajectory(fps=20.0, cycles=1), CASE, tmp_path / "a.gif", dpi=40)
    with Image.open(out) as im:
        assert im.n_frames == 10
        assert im.info["duration"] == 50   # real time: 20 frames/s


def test_animation_thins_dense_trajectories_for_gif_players(tmp_path):
    out = animate(rolling_trajectory(fps=100.0, cycles=1), CASE, tmp_path / "a.gif", dpi=40)
    with Image.open(out) as im:
        assert im.n_frames == 13 and im.info["duration"] == 40   # every 4th frame, 25 frames/s


def test_animation_errors_are_one_line_input_errors(tmp_path):
    tr = rolling_trajectory(cycles=1)
    with pytest.raises(InputError, match=r"\.gif or \.mp4"):
        animate(tr, CASE, tmp_path / "a.avi")
    with pytest.raises(InputError, match="does not exist"):
        animate(tr, CASE, tmp_path / "missing" / "a.gif")
    with pytest.raises(InputError, match="speed"):
        animate(tr, CASE, tmp_path / "a.gif", speed=0.0)


def _sweep(modes, particles=36, x_opt=0.01223):
    strokes = np.array([0.002, 0.006, 0.013, 0.03])
    eta = np.array([[0.05, 0.06], [0.1, 0.12], [0.8, 0.82], [0.5, 0.52]])
    ds = xr.Dataset({"eta_star": (("stroke", "seed"), eta), "mode": (("stroke", "seed"), np.array(modes))},
                    coords={"stroke": strokes, "seed": [0, 1]})
    ds.attrs.update(particles=particles, x_opt_m=x_opt)
    return ds


def test_mode_map_rows_take_the_majority_over_seeds(tmp_path):
    a = _sweep([["scattered"] * 2, ["scattered", "single-sided"], ["rolling-collect-and-collide"] * 2,
                ["rolling-collect-and-collide", ""]])
    b = _sweep([["single-sided"] * 2] * 2 + [["rolling-collect-and-collide"] * 2] * 2, particles=44, x_opt=0.00408)
    fig = mode_map_figure([a, b], tmp_path / "modes.png")
    rows = mode_rows([a, b])
    assert [r["label"] for r in rows] == ["N_p = 36", "N_p = 44"]
    ax = fig.axes[1]
    colours = [tuple(p.get_facecolor()) for p in ax.patches]
    assert len(colours) == 8   # every computed cell drawn
    from matplotlib.colors import to_rgba

    assert colours[0] == to_rgba(MODE_COLOURS["scattered"]) and colours[4] == to_rgba(MODE_COLOURS["single-sided"])
    assert [t.get_text() for t in ax.get_yticklabels()] == ["N_p = 36", "N_p = 44"]
    assert (tmp_path / "modes.png").stat().st_size > 10_000


def test_mode_map_of_a_study_has_a_row_per_setting():
    a = _sweep([["scattered"] * 2] * 4)
    both = xr.concat([a.assign_coords(setting="mu = 0.01").expand_dims("setting"),
                      a.assign_coords(setting="mu = 1").expand_dims("setting")], dim="setting")
    both["x_opt"] = ("setting", [0.012, 0.012])
    assert [r["label"] for r in mode_rows([both])] == ["mu = 0.01", "mu = 1"]


def test_mode_map_row_labels_same_filling_and_given():
    a = _sweep([["scattered"] * 2] * 4, particles=44)
    b = _sweep([["single-sided"] * 2] * 4, particles=44)
    assert [r["label"] for r in mode_rows([a, b], ["s44", "s44t"])] == ["N_p = 44 (s44)", "N_p = 44 (s44t)"]
    assert [r["label"] for r in mode_rows([a, b], ["s44", "s44t"], ["flat", "tilted"])] == ["flat", "tilted"]
    with pytest.raises(InputError, match="1 row label"):
        mode_rows([a, b], labels=["only one"])


def test_results_without_modes_are_refused_with_a_way_out():
    ds = _sweep([["scattered"] * 2] * 4).drop_vars("mode")
    with pytest.raises(InputError, match="re-run the sweep"):
        mode_map_figure([ds])


def _shown_ticks(fig, ax, axis="x"):
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    FigureCanvasAgg(fig).draw()
    a, b = ax.get_xlim() if axis == "x" else ax.get_ylim()
    labels = ax.get_xticklabels() if axis == "x" else ax.get_yticklabels()
    k = 0 if axis == "x" else 1
    return [t.get_text() for t in labels if min(a, b) <= t.get_position()[k] <= max(a, b) and t.get_text()]


def test_mode_map_labels_at_least_three_strokes_on_both_panels():
    ds = _sweep([["scattered"] * 2] * 2 + [["rolling-collect-and-collide"] * 2] * 2)
    ds = ds.assign_coords(stroke=[0.004, 0.008, 0.013, 0.025])   # under one decade: 1 decade tick before
    fig = mode_map_figure([ds])
    top, bottom = fig.axes[:2]
    assert len(_shown_ticks(fig, bottom)) >= 3 and len(_shown_ticks(fig, top)) >= 3
    assert len(_shown_ticks(fig, top, "y")) >= 3


def test_mode_map_eta_line_is_broken_at_x_opt():
    ds = _sweep([["scattered"] * 2] * 2 + [["rolling-collect-and-collide"] * 2] * 2)
    line = mode_map_figure([ds]).axes[0].get_lines()[0]
    y = np.asarray(line.get_ydata(), float)
    assert np.isnan(y).sum() == 1 and np.isnan(y[2])   # between 6 mm and 13 mm (X_opt 12.2 mm)
