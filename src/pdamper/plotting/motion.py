"""Figures of the bed's motion from a recorded trajectory (paper Figs. 2, 3, 5a) and its animation.

All take a trajectory dict in the container frame (``time`` [s], ``position`` (F, N, 3) [m],
``radius``; as :class:`pdamper.run.RunResult` and :func:`pdamper.rundir.read_run` give
it) and a :class:`pdamper.params.Case` for the container, the drive and the transient.

* :func:`paths_figure` -- top view of the sphere paths in the container frame, one panel per run
  (the paper's Fig. 3: scattered vs rolling collect-and-collide), container outline, start and
  end positions, mode in the panel title.
* :func:`walls_figure` -- the bed against both end walls over the drive phase, in the lab frame
  (the paper's Fig. 5a from a simulation): the container's -x and +x walls, the bed's rear and
  front edge and its centre [mm].
* :func:`animate` -- top and side views of the moving container with the spheres, written as a
  GIF (Pillow) or MP4 (ffmpeg, when installed).
"""

from __future__ import annotations

import math
import shutil
from pathlib import Path

import numpy as np

from ..errors import InputError, shown
from .figure import MM as _MM, check_path, save

__all__ = ["paths_figure", "walls_figure", "animate", "ANIMATION_FORMATS", "ffmpeg_available"]

#: Animation formats by extension.
ANIMATION_FORMATS = (".gif", ".mp4")
#: Highest frame rate written per format [frames/s]; denser trajectories are thinned.
MAX_FPS = {".gif": 25.0, ".mp4": 30.0}

_WALL = "0.25"
_BED = "#1f77b4"


def ffmpeg_available() -> bool:
    """True when an ``ffmpeg`` executable is on the PATH (needed for MP4)."""
    return shutil.which("ffmpeg") is not None


def _outline(ax, container, view, **kw) -> list:
    """The container's walls seen from ``view`` ("top": x-z, "side": x-y) as polygon patches [mm]
    (the shape's, then its inner baffles'); returns the patches with their vertices [mm] (to
    move them with the container)."""
    from matplotlib.patches import Polygon

    style = dict(fill=False, edgecolor=_WALL, linewidth=1.6)
    style.update(kw)
    out = []
    for k, poly in enumerate(container.outline(view)):
        xy = np.asarray(poly) * _MM
        patch = Polygon(xy, closed=True, **(style if k == 0 else {**style, "fill": True, "facecolor": "0.8"}))
        ax.add_patch(patch)
        out.append((patch, xy))
    return out


def _extent(geo):
    """(half length along x, half width along z, height) [m] of the box around the container."""
    lo, hi = geo.bounding_box()
    return max(-lo[0], hi[0]), max(-lo[2], hi[2]), hi[1] - lo[1]


def _window(traj, case, cycles):
    """Frame indices of the last ``cycles`` drive cycles (all frames if None or too few)."""
    t = np.asarray(traj["time"])
    f = float(case.drive.frequency or 0.0)
    if cycles is None or f <= 0:
        return np.arange(t.size)
    keep = t >= t[-1] - cycles / f - 1e-12
    return np.flatnonzero(keep)


def paths_figure(runs, path=None, *, cycles: float | None = 2.0, figsize=None, dpi: int = 150):
    """Top view of the sphere paths in the container frame (the paper's Fig. 3).

    Each path is coloured by time (the drive cycle Ωt/2π when every run has a drive frequency,
    else t [s]) with a labelled colorbar: one for all panels when they cover the same times, else
    one per panel.

    Parameters
    ----------
    runs : list of (label, trajectory, case)
        One panel each, side by side; ``label`` is the panel title (the mode is added when it
        can be classified).
    path : output file (.png, .svg, .pdf), optional.
    cycles : draw the last ``cycles`` drive cycles (None: all frames).
    """
    from matplotlib import colormaps
    from matplotlib.collections import LineCollection
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    from ..analysis.modes import classify_trajectory

    target = check_path(path)
    runs = list(runs)
    if not runs:
        raise InputError("paths_figure: no runs given")
    geo0 = runs[0][2].container.geometry
    lx, lz, _ = _extent(geo0)
    width = 4.2 * lx / max(lz, 1e-9) * 0.55 + 0.6
    freqs = [float(case.drive.frequency or 0.0) for _, _, case in runs]
    in_cycles = all(f > 0 for f in freqs)
    windows = []
    for (_, traj, case), f in zip(runs, freqs):
        idx = _window(traj, case, cycles)
        t = np.asarray(traj["time"])[idx]
        windows.append((idx, t * f if in_cycles else t))
    spans = [(float(c.min()), float(c.max())) if c.size else (0.0, 1.0) for _, c in windows]
    shared = all(math.isclose(a, spans[0][0], abs_tol=1e-6 * max(1.0, abs(a)))
                 and math.isclose(b, spans[0][1], abs_tol=1e-6 * max(1.0, abs(b))) for a, b in spans)
    fig = Figure(figsize=figsize or (min(6.0, width) * len(runs) + (0.9 if shared else 0.9 * len(runs)), 3.3),
                 layout="constrained")
    axes = fig.subplots(1, len(runs), squeeze=False)[0]
    cmap = colormaps["viridis"]
    label = ("time Ωt/2π [drive cycles]" if in_cycles else "time t [s]")
    lines = []
    for ax, (name, traj, case), (idx, clock), span in zip(axes, runs, windows, spans):
        geo = case.container.geometry
        pos = np.asarray(traj["position"])[idx]
        rad = np.broadcast_to(np.asarray(traj["radius"], dtype=float), pos.shape[1])
        _outline(ax, case.container, "top")
        # each sphere's path as segments between frames, coloured by the time at their middle
        xz = pos[:, :, [0, 2]].transpose(1, 0, 2) * _MM          # (N, F, 2)
        segs = np.stack([xz[:, :-1], xz[:, 1:]], axis=2).reshape(-1, 2, 2)
        mid = np.tile((clock[:-1] + clock[1:]) / 2, pos.shape[1])
        norm = Normalize(*(spans[0] if shared else span))
        coll = LineCollection(segs, cmap=cmap, norm=norm, linewidths=0.8, alpha=0.9)
        coll.set_array(mid)
        ax.add_collection(coll)
        lines.append(coll)
        _circles(ax, pos[-1, :, 0], pos[-1, :, 2], rad, facecolor="none", edgecolor="0.35", lw=0.6)
        try:
            mode, _ = classify_trajectory(traj, case)
            title = f"{name}\nmode: {mode}"
        except ValueError:
            title = name
        ax.set_title(title, fontsize=9.5)
        ex, ez, _ = _extent(geo)
        ax.set_xlim(-ex * _MM - 3, ex * _MM + 3)
        ax.set_ylim(-ez * _MM - 3, ez * _MM + 3)
        ax.set_aspect("equal")
        ax.set_xlabel("x (along the drive) [mm]")
        ax.set_ylabel("z [mm]")
        if not shared:
            fig.colorbar(coll, ax=ax, label=label, shrink=0.9, pad=0.02)
    if shared:
        cb = fig.colorbar(lines[0], ax=list(axes), label=label, shrink=0.9, pad=0.02)
        if in_cycles and len(set(freqs)) == 1:  # the same clock in seconds on the other side
            sec = cb.ax.secondary_yaxis("left", functions=(lambda c, f=freqs[0]: c / f, lambda s, f=freqs[0]: s * f))
            sec.set_ylabel("t [s]", fontsize=8)
            sec.tick_params(labelsize=7)
    n_cyc = f"last {cycles:g} cycles" if cycles is not None else "all frames"
    fig.suptitle(f"Sphere paths in the container frame, top view ({n_cyc}, coloured by time; circles: last frame)",
                 fontsize=10)
    if target is not None:
        save(fig, target, dpi)
    return fig


def _circles(ax, x, y, r, **kw):
    """Circles of radius ``r`` [m] at (x, y) [m] in data units (mm); returns the collection."""
    from matplotlib.collections import EllipseCollection

    d = 2 * np.asarray(r) * _MM
    coll = EllipseCollection(d, d, np.zeros_like(d), units="xy", offsets=np.column_stack([x, y]) * _MM,
                             offset_transform=ax.transData, **kw)
    ax.add_collection(coll)
    return coll


def walls_figure(traj, case, path=None, *, cycles: float | None = 3.0, figsize=(7.5, 5.4), dpi: int = 150):
    """The bed between the two end walls over the drive phase, lab frame (the paper's Fig. 5a).

    Draws the container's -x and +x end walls x_c -+ L/2, the bed's rear and front edges
    (min and max of x -+ r over the spheres) as a band and the bed centre [mm] over
    Omega t / (2 pi) (drive cycles) for the last ``cycles`` cycles; below, the gaps between the
    bed and each end wall [mm] (0 while it touches that wall); the mode in the title.
    """
    from matplotlib.figure import Figure

    from ..analysis.modes import case_clearance, classify_trajectory
    from ..geometry.track import container_track

    target = check_path(path)
    drive = case.drive
    off, _, dvec = container_track(traj, case)
    idx = _window(traj, case, cycles)
    t = np.asarray(traj["time"])[idx]
    pos = np.asarray(traj["position"])[idx]
    rad = np.broadcast_to(np.asarray(traj["radius"], dtype=float), pos.shape[1])
    d = np.array([dvec[0], 0.0, dvec[2]])
    d /= np.linalg.norm(d)
    s = pos @ d
    xc = off[idx] @ d
    length, h = case_clearance(case)
    f = float(drive.frequency or 0.0)
    phase = t * f if f > 0 else t
    fig = Figure(figsize=figsize, layout="constrained")
    ax, gaps = fig.subplots(2, 1, sharex=True, height_ratios=[2.2, 1.0])
    ax.plot(phase, (xc - length / 2) * _MM, color=_WALL, lw=2.0, label="-x wall")
    ax.plot(phase, (xc + length / 2) * _MM, color=_WALL, lw=2.0, ls="--", label="+x wall")
    rear = (s - rad).min(axis=1) + xc
    front = (s + rad).max(axis=1) + xc
    ax.fill_between(phase, rear * _MM, front * _MM, color=_BED, alpha=0.25, lw=0, label="bed (rear to front edge)")
    ax.plot(phase, (s.mean(axis=1) + xc) * _MM, color=_BED, lw=1.5, label="bed centre")
    # the gaps between the bed and each end wall (container frame): 0 while the bed touches it
    gaps.plot(phase, ((s - rad).min(axis=1) + length / 2) * _MM, color="C3", lw=1.3, label="bed to -x wall")
    gaps.plot(phase, (length / 2 - (s + rad).max(axis=1)) * _MM, color="C2", lw=1.3, ls="--", label="bed to +x wall")
    gaps.axhline(h * _MM, color="0.6", lw=0.8, ls=":", label="clearance h")
    gaps.set_ylabel("gap [mm]")
    gaps.set_ylim(bottom=-0.03 * h * _MM)
    gaps.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8.5, frameon=False)
    gaps.set_xlabel("drive cycles  Ωt / 2π [-]" if f > 0 else "time [s]")
    gaps.grid(True, color="0.9", lw=0.6)
    ax.set_ylabel("position in the lab frame [mm]")
    ax.grid(True, color="0.9", lw=0.6)
    try:
        mode, _ = classify_trajectory(traj, case)
    except ValueError:
        mode = None
    stroke = drive.stroke
    head = f"X = {stroke * _MM:.3g} mm, f = {f:g} Hz, h = {h * _MM:.3g} mm" if stroke else ""
    ax.set_title(f"Bed against both end walls ({head})" + (f"\nmode: {mode}" if mode else ""), fontsize=10)
    ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8.5, frameon=False)
    if target is not None:
        save(fig, target, dpi)
    return fig


def animate(traj, case, path, *, speed: float = 1.0, cycles: float | None = None, max_frames: int = 300,
            dpi: int = 90, progress=None) -> Path:
    """Animation of the top (x-z) and side (x-y) views of the moving container with the spheres.

    ``path`` ends in ``.gif`` (Pillow, always available) or ``.mp4`` (needs ffmpeg on the
    PATH). ``speed``: playback speed (1: real time, 0.5: slow motion). ``cycles``: only the last
    ``cycles`` drive cycles. Frames are thinned evenly to at most :data:`MAX_FPS` frames per
    second of playback and at most ``max_frames`` frames. Spheres are coloured by their speed relative to the container.
    Returns the path.
    """
    import matplotlib.animation as manim
    from matplotlib.figure import Figure

    target = Path(path)
    ext = target.suffix.lower()
    if ext not in ANIMATION_FORMATS:
        raise InputError(f"animation file {shown(str(target))}: unknown format {shown(target.suffix or '(no extension)')}; "
                         f"end the name with {' or '.join(ANIMATION_FORMATS)}")
    if ext == ".mp4" and not ffmpeg_available():
        raise InputError(f"animation file {shown(str(target))}: MP4 needs ffmpeg, which is not installed; "
                         "install it (e.g. apt-get install ffmpeg) or write a .gif")
    if not target.parent.is_dir():
        raise InputError(f"animation file {shown(str(target))}: folder {shown(str(target.parent))} does not exist")
    if not (speed > 0 and math.isfinite(speed)):
        raise InputError(f"animation speed {shown(speed)}: must be > 0 (1: real time)")
    idx = _window(traj, case, cycles)
    t_all = np.asarray(traj["time"])
    dt0 = float(np.median(np.diff(t_all))) if t_all.size > 1 else 0.1
    # players clamp GIF frame delays below 20 ms (often to 100 ms): show at most MAX_FPS frames/s
    step = max(1, int(math.ceil(speed / dt0 / MAX_FPS[ext] - 1e-9)), int(math.ceil(idx.size / max_frames)))
    idx = idx[::step]
    t = np.asarray(traj["time"])[idx]
    pos = np.asarray(traj["position"])[idx]
    vel = np.asarray(traj["velocity"])[idx] if "velocity" in traj else np.zeros_like(pos)
    rad = np.broadcast_to(np.asarray(traj["radius"], dtype=float), pos.shape[1])
    from ..geometry.track import container_track

    drive = case.drive
    shift = container_track(traj, case)[0][idx]   # container origin in the lab frame (F, 3)
    xc = shift[:, 0]
    geo = case.container.geometry
    lx, lz, hy = _extent(geo)
    reach = lx + float(np.max(np.abs(xc))) + 0.004
    speed_rel = np.linalg.norm(vel, axis=2)
    vmax = max(float(np.percentile(speed_rel, 99)), 1e-6)

    fig = Figure(figsize=(7.2, 4.6), layout="constrained")
    top, side = fig.subplots(2, 1, height_ratios=[2 * lz + 0.004, hy + 0.004], sharex=True)
    for ax in (top, side):
        ax.set_aspect("equal")
        ax.set_xlim(-reach * _MM, reach * _MM)
        ax.grid(True, color="0.92", lw=0.5)
    top.set_ylim(-(lz + 0.002) * _MM, (lz + 0.002) * _MM)
    side.set_ylim(-0.002 * _MM, (hy + 0.002) * _MM)
    top.set_ylabel("z [mm]")
    side.set_ylabel("y [mm]")
    side.set_xlabel("x, lab frame [mm]")
    top_walls = _outline(top, case.container, "top", linewidth=1.8)
    side_walls = _outline(side, case.container, "side", linewidth=1.8)
    from matplotlib import colormaps
    from matplotlib.colors import Normalize

    norm = Normalize(0.0, vmax)
    cmap = colormaps["plasma"]
    kw = dict(cmap=cmap, norm=norm, edgecolor="0.2", linewidths=0.4)
    tc = _circles(top, pos[0, :, 0], pos[0, :, 2], rad, **kw)
    sc = _circles(side, pos[0, :, 0], pos[0, :, 1], rad, **kw)
    cb = fig.colorbar(tc, ax=[top, side], shrink=0.8, pad=0.01)
    cb.set_label("speed relative to the container [m/s]")
    label = top.text(0.01, 1.02, "", transform=top.transAxes, fontsize=9)
    stroke = drive.stroke
    freq = drive.frequency
    fig.suptitle(f"{case.n_particles} spheres" + (f", X = {stroke * _MM:.3g} mm, f = {freq:g} Hz" if stroke else "")
                 + " (top: floor plane, bottom: side view)", fontsize=10)

    def draw(k):
        off = shift[k]
        p = pos[k] + off
        for patch, xy in top_walls:
            patch.set_xy(xy + off[[0, 2]] * _MM)
        for patch, xy in side_walls:
            patch.set_xy(xy + off[[0, 1]] * _MM)
        tc.set_offsets(p[:, [0, 2]] * _MM)
        sc.set_offsets(p[:, [0, 1]] * _MM)
        tc.set_array(speed_rel[k])
        sc.set_array(speed_rel[k])
        label.set_text(f"t = {t[k]:.2f} s" + (f",  Ωt/2π = {t[k] * freq:.2f}" if freq else ""))
        if progress is not None:
            progress(k + 1, len(t))
        return (tc, sc, label, *(p for p, _ in top_walls + side_walls))

    dt = float(np.median(np.diff(t))) if t.size > 1 else 0.1
    fps = max(1.0, round(speed / dt, 3))  # rounded: GIF delays are whole centiseconds, int(1000/fps) truncates
    anim = manim.FuncAnimation(fig, draw, frames=len(t), blit=False)
    writer = manim.PillowWriter(fps=fps) if ext == ".gif" else manim.FFMpegWriter(fps=fps, bitrate=1800)
    try:
        anim.save(str(target), writer=writer, dpi=dpi)
    except OSError as exc:
        raise InputError(f"animation file {shown(str(target))} cannot be written: {exc.strerror or exc}") from None
    return target
