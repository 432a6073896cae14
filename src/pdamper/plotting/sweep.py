"""Figures of a stroke sweep: η*(X) like the paper's Fig. 4, and the energy per cycle over X.

Both take the results dataset of a sweep or study (:mod:`xarray`): dimensions ``stroke``
(strokes in m) and ``seed``, optionally one study dimension such as ``setting``; data variables
``eta_star`` and ``energy_per_cycle`` [J], NaN where a case has not been computed yet. A partly
computed sweep plots what is there.

* :func:`sweep_figure` -- η* over X on a log axis: per setting the mean over seeds (line with
  markers), the min-max spread across seeds (band) and the single seeds (faint dots); the
  analytical laws for the clearance (scattered eq. (8) below X_opt, rolling eq. (14) above,
  X_opt eq. (17) marked) and η*_max = 20/(7π) as a faint line.
* :func:`energy_figure` -- energy dissipated per cycle [mJ] over X, log-log, mean and band; the
  laws too when the dataset knows the bed mass (attribute ``bed_mass_kg``).

Figures are built with :class:`matplotlib.figure.Figure` (no pyplot, no display needed) and
saved to the format the file name says (``.png``, ``.svg``, ``.pdf``).
"""

from __future__ import annotations

import math

import numpy as np

from .. import theory as _th
from ..errors import InputError, shown
from .figure import MM as _MM, FORMATS, check_path, save, stroke_axis
from .theory import draw_theory_curves

__all__ = ["sweep_figure", "study_figure", "energy_figure", "FORMATS"]

_STROKE_UNITS = {"m": 1.0, "mm": 1e-3}  # stroke coordinate units -> metres
_MARKERS = ("o", "s", "^", "D", "v", "P", "X", "<", ">", "h")
_LINESTYLES = ("-", (0, (5, 2)), (0, (1, 1.5)), (0, (6, 2, 1, 2)))  # solid, dashed, dotted, dash-dot


# --------------------------------------------------------------------------- public figures

def sweep_figure(ds, path=None, *, title: str | None = None, theory: bool = True,
                 figsize=(7.5, 4.8), dpi: int = 150):
    """η*(X) of a stroke sweep, with the analytical laws (the paper's Fig. 4).

    Parameters
    ----------
    ds : xarray.Dataset
        Sweep results: variable ``eta_star`` with dimensions ``stroke`` [m] and ``seed``
        (optionally one more study dimension, e.g. ``setting``); NaN marks cases not yet
        computed. Attributes used if present: ``clearance_m`` (or a variable ``clearance``
        along the study dimension), ``x_opt_m``, ``frequency_hz``, ``particles``,
        ``max_particles``, ``shape``, ``title``, ``pdamper_version``.
    path : str or os.PathLike, optional
        Save the figure there; the extension picks the format (``.png``, ``.svg``, ``.pdf``).
    title : str, optional
        Figure title; default ``ds.attrs["title"]`` or one built from the attributes.
    theory : bool
        Draw the analytical laws (needs the clearance, or ``x_opt_m``) and η*_max.
    figsize : tuple of float
        Figure size [inch].
    dpi : int
        Resolution of raster output [dots per inch].

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        ``ds`` is not a sweep dataset (no ``eta_star``, no ``stroke`` dimension, ...) or
        ``path`` has an unknown extension or a missing folder.
    """
    from matplotlib.figure import Figure

    target = check_path(path)
    fig = Figure(figsize=figsize, layout="constrained")
    _sweep_into(fig, ds, title=title, theory=theory)
    if target is not None:
        save(fig, target, dpi)
    return fig


def study_figure(ds, path=None, *, title: str | None = None, theory: bool = True, dpi: int = 150):
    """η*(X) of a study: one panel per filling, (a), (b), ..., as the paper's figures, when the
    dataset's ``setting`` dimension has a ``panel`` coordinate with more than one value; else
    :func:`sweep_figure`.

    The panels sit side by side on one η* axis. Settings are told apart by colour and line style
    (each panel's legend under it, with its X_opt); the motion modes, the single seeds and the laws
    every panel shares are listed once, at the bottom of the figure."""
    from matplotlib.figure import Figure

    panels = list(dict.fromkeys(ds["panel"].values.tolist())) if "panel" in ds.coords else []
    if len(panels) < 2:
        return sweep_figure(ds, path, title=title, theory=theory, dpi=dpi)
    target = check_path(path)
    fig = Figure(figsize=(5.6 * len(panels), 6.4), layout="constrained")
    axes = fig.subplots(1, len(panels), sharey=True, squeeze=False)[0]
    drawn, sweeps = [], []
    for k, (ax, panel) in enumerate(zip(axes, panels)):
        part = ds.isel(setting=[i for i, p in enumerate(ds["panel"].values.tolist()) if p == panel])
        sw = _Sweep(part, "eta_star")
        data = _draw_panel(ax, sw, theory=theory)
        laws = [(h, s) for h, s in zip(*ax.get_legend_handles_labels()) if not s.startswith("_")]
        drawn.append((data, laws))
        sweeps.append(sw)
        ax.set_title(f"({chr(ord('a') + k)}) {panel}", fontsize="medium", pad=16)
        ax.text(0.5, 1.012, _note(sw), transform=ax.transAxes, ha="center", va="bottom", fontsize="small",
                color="0.35")
        if k:
            ax.set_ylabel("")
    axes[0].set_ylim(*_eta_limits(sweeps))
    # each panel's own entries (its settings, laws only it has) under it; the rest once, at the bottom
    per_panel = [{s for _, s in data + laws} for data, laws in drawn]
    common = set.intersection(*per_panel)
    shared, seen = [], set()
    from matplotlib.legend_handler import HandlerTuple

    for ax, (data, laws) in zip(axes, drawn):
        own = [(h, s) for h, s in data if s.startswith("DEM")] + [(h, s) for h, s in laws if s not in common]
        for h, s in data + laws:
            if (s in common or not s.startswith("DEM")) and (h, s) not in own and s not in seen:
                shared.append((h, s))
                seen.add(s)
        if own:
            ax.legend([h for h, _ in own], [s for _, s in own], loc="upper center", bbox_to_anchor=(0.5, -0.13),
                      ncols=1 if len(own) <= 3 else 2, fontsize="small", frameon=False,
                      handler_map={tuple: HandlerTuple(ndivide=1)}, handlelength=2.4)
    from .mode_looks import mode_rank

    modes = sorted((e for e in shared if e[1].startswith("mode: ")), key=lambda e: mode_rank(e[1][6:]))
    shared = [e for e in shared if e[1] == "single seeds"] + modes + [
        e for e in shared if e[1] != "single seeds" and not e[1].startswith("mode: ")]
    if shared:
        fig.legend([h for h, _ in shared], [s for _, s in shared], loc="outside lower center",
                   ncols=min(3, len(shared)), fontsize="small", frameon=False,
                   handler_map={tuple: HandlerTuple(ndivide=1)}, handlelength=2.4, columnspacing=1.5)
    if title or ds.attrs.get("title"):
        fig.suptitle(str(title or ds.attrs.get("title")), fontsize="large")
    if target is not None:
        save(fig, target, dpi)
    return fig


def _sweep_into(fig, ds, *, title, theory):
    """Draw η*(X) of ``ds`` into ``fig`` (a Figure or SubFigure): data, laws, axes, legend, titles."""
    sw = _Sweep(ds, "eta_star")
    ax = fig.add_subplot()
    handles = _draw_panel(ax, sw, theory=theory)
    ax.set_ylim(*_eta_limits([sw]))
    _legend(fig, ax, handles)
    _titles(fig, ax, sw, title)


def _draw_panel(ax, sw, *, theory):
    """η*(X) of one :class:`_Sweep` on ``ax``: data, laws (labelled on ``ax``), axes; returns the
    data's legend handles."""
    handles = _draw_data(ax, sw, scale=1.0)
    laws = sw.theory_clearances() if theory else []
    if laws:  # none where the horizontal laws do not apply (a vertical drive, a bed beyond one layer)
        for h, label, colour in laws:
            draw_theory_curves(ax, h, sw.strokes_m, bouncing=False, color=colour,
                               label=label, mark_x_opt=True)
        ax.axhline(_th.ETA_MAX, color="0.6", lw=0.9, ls=(0, (6, 3)), zorder=0.5,
                   label=f"$η^*_{{max}}$ = 20/(7π) = {_th.ETA_MAX:.3f}, eq. (16)")
    ax.set_xscale("log")
    stroke_axis(ax, sw.strokes_m)
    ax.set_xlabel("stroke X [mm]")
    ax.set_ylabel("reduced loss factor η* [-]")
    _grid(ax)
    if not sw.any_data:
        _no_data_note(ax)
    return handles


def _eta_limits(sweeps):
    """η* axis limits over the values of ``sweeps``: 0 (or a little below the lowest) to above 1."""
    vals = [r for sw in sweeps for r in sw.finite_range() if r is not None]
    lo, hi = (min(vals), max(vals)) if vals else (None, None)
    top = max(1.05, 1.08 * hi) if hi is not None else 1.05
    bottom = min(0.0, lo - 0.05 * (top - lo)) if lo is not None else 0.0
    return bottom, top


def energy_figure(ds, path=None, *, title: str | None = None, theory: bool = True,
                  figsize=(7.5, 4.8), dpi: int = 150):
    """Energy dissipated per cycle [mJ] over the stroke X of a sweep, log-log.

    Per setting the mean over seeds (line with markers), the min-max spread across seeds
    (band) and the single seeds (faint dots); X_opt of each clearance marked. When the dataset
    knows the bed mass (attribute ``bed_mass_kg``) and ``frequency_hz``, the scattered and
    rolling laws ``Ẽ = η* π m_bed V²`` with V = 2πfX are drawn too.

    Parameters
    ----------
    ds : xarray.Dataset
        Sweep results with ``energy_per_cycle`` [J] along ``stroke`` [m] and ``seed``
        (optionally one more study dimension); see :func:`sweep_figure`.
    path, title, figsize, dpi
        As in :func:`sweep_figure`.
    theory : bool
        Mark X_opt and draw the laws when the bed mass is known.

    Returns
    -------
    matplotlib.figure.Figure

    Raises
    ------
    InputError
        As :func:`sweep_figure`, for ``energy_per_cycle``.
    """
    target = check_path(path)
    sw = _Sweep(ds, "energy_per_cycle")
    fig, ax = _new_figure(figsize)
    handles = _draw_data(ax, sw, scale=1e3, log=True)

    if theory:
        mass = _attr_float(sw.ds, "bed_mass_kg")
        freq = _attr_float(sw.ds, "frequency_hz")
        for h, label, colour in sw.theory_clearances():
            x_opt = _th.optimal_stroke(h)
            lo, hi = float(sw.strokes_m.min()), float(sw.strokes_m.max())
            if mass is not None and freq is not None:
                _draw_energy_laws(ax, h, lo, hi, mass, freq, colour, label)
            if lo <= x_opt <= hi:
                ax.axvline(x_opt * _MM, color=colour, lw=1.0, ls=":",
                           label=f"$X_{{opt}}$ = {x_opt * _MM:.3g} mm, eq. (17){label}")

    ax.set_xscale("log")
    ax.set_yscale("log")
    stroke_axis(ax, sw.strokes_m)
    ax.set_xlabel("stroke X [mm]")
    ax.set_ylabel("energy dissipated per cycle [mJ]")
    lo, hi = sw.positive_range()
    if lo is not None:
        ax.set_ylim(lo * 1e3 / 2.0, hi * 1e3 * 2.0)
    _grid(ax)
    if not sw.any_data:
        _no_data_note(ax)
    _legend(fig, ax, handles)
    _titles(fig, ax, sw, title, log_note=True)
    if target is not None:
        save(fig, target, dpi)
    return fig


# --------------------------------------------------------------------------- the dataset

class _Sweep:
    """A validated view of a sweep dataset: strokes in m, values as (setting, stroke, seed)."""

    def __init__(self, ds, var: str):
        try:
            import xarray as xr
        except ImportError:  # pragma: no cover - xarray is a dependency
            raise InputError("plotting a sweep needs xarray; pip install xarray") from None
        if not isinstance(ds, xr.Dataset):
            raise InputError(f"sweep results: expected an xarray.Dataset (from "
                             f"pdamper.open_results), got {type(ds).__name__}")
        if var not in ds.data_vars:
            have = ", ".join(map(str, ds.data_vars)) or "none"
            raise InputError(f"sweep results: no variable {shown(var)} in the dataset (variables: "
                             f"{have}); give the dataset of a stroke sweep")
        da = ds[var]
        if "stroke" not in da.dims:
            raise InputError(f"sweep results: {shown(var)} has dimensions {tuple(da.dims)} but no "
                             "'stroke' dimension; a sweep dataset has dimensions ('stroke', "
                             "'seed') and optionally one study dimension such as 'setting'")
        extra = [d for d in da.dims if d not in ("stroke", "seed")]
        if len(extra) > 1:
            raise InputError(f"sweep results: {shown(var)} has dimensions {tuple(da.dims)}; at most "
                             "one study dimension besides 'stroke' and 'seed' can be plotted "
                             f"(select one of {extra} first, e.g. ds.isel({extra[-1]}=0))")
        if "seed" not in da.dims:
            da = da.expand_dims("seed", axis=-1)
        self.dim = extra[0] if extra else None
        da = da.transpose(*([self.dim] if self.dim else []), "stroke", "seed")
        self.ds = ds

        strokes = np.asarray(ds["stroke"].values)
        units = str(ds["stroke"].attrs.get("units", "m")).strip()
        if units not in _STROKE_UNITS:
            raise InputError(f"sweep results: stroke units {shown(units)} are not understood; "
                             "use 'm' (or 'mm')")
        try:
            strokes = strokes.astype(float) * _STROKE_UNITS[units]
        except (TypeError, ValueError):
            raise InputError("sweep results: the 'stroke' coordinate must hold numbers "
                             f"(strokes in m), got dtype {strokes.dtype}") from None
        if strokes.size == 0:
            raise InputError("sweep results: the 'stroke' dimension is empty")
        if not np.all(np.isfinite(strokes) & (strokes > 0)):
            raise InputError("sweep results: every stroke must be finite and > 0 m (log axis); "
                             f"got {strokes.min():g} .. {strokes.max():g}")
        order = np.argsort(strokes)
        self.strokes_m = strokes[order]

        try:
            vals = np.asarray(da.values, dtype=float)
        except (TypeError, ValueError):
            raise InputError(f"sweep results: {shown(var)} must hold numbers, got dtype "
                             f"{da.dtype}") from None
        if self.dim is None:
            vals = vals[None, ...]
        vals = vals[:, order, :].copy()
        vals[~np.isfinite(vals)] = np.nan
        self.values = vals  # (setting, stroke, seed)
        self.modes = self._modes(ds, order)
        self.n_seeds = vals.shape[2]
        self.any_data = bool(np.isfinite(vals).any())
        self.labels = self._setting_labels(da)

    def _modes(self, ds, order):
        """Motion modes as (setting, stroke, seed) text like ``values`` ('' where none), or None
        when the dataset has no ``mode`` variable of the same shape (results made before modes)."""
        if "mode" not in ds.data_vars:
            return None
        m = ds["mode"]
        dims = ([self.dim] if self.dim else []) + ["stroke"] + (["seed"] if "seed" in m.dims else [])
        if set(m.dims) != set(dims):
            return None
        m = np.asarray(m.transpose(*dims).values).astype(str)
        if "seed" not in dims:
            m = m[..., None]
        if self.dim is None:
            m = m[None, ...]
        m = m[:, order, :]
        if m.shape != self.values.shape:
            return None
        return np.where(np.isfinite(self.values), m, "")

    def x_opts(self) -> list[float | None]:
        """X_opt [m] of each setting, eq. (17) (None when the clearance is unknown)."""
        return [_th.optimal_stroke(h) if h is not None else None for h in self.clearances()]

    def _setting_labels(self, da) -> list[str]:
        if self.dim is None:
            return [""]
        n = da.sizes[self.dim]
        if self.dim in da.coords:
            out = []
            for v in np.asarray(da[self.dim].values):
                if isinstance(v, (str, np.str_)):
                    out.append(str(v))
                elif isinstance(v, (float, np.floating)):
                    out.append(f"{self.dim} = {float(v):g}")
                else:
                    out.append(f"{self.dim} = {v}")
            return out
        return [f"{self.dim} = {i}" for i in range(n)]

    def finite_range(self):
        v = self.values[np.isfinite(self.values)]
        return (float(v.min()), float(v.max())) if v.size else (None, None)

    def positive_range(self):
        v = self.values[np.isfinite(self.values) & (self.values > 0)]
        return (float(v.min()), float(v.max())) if v.size else (None, None)

    @property
    def nonpositive(self) -> int:
        """How many computed cases are <= 0 (not drawable on a log axis)."""
        with np.errstate(invalid="ignore"):
            return int((self.values <= 0).sum())

    def clearances(self) -> list[float | None]:
        """Clearance [m] per setting (None if unknown)."""
        n = self.values.shape[0]
        if self.dim is not None and "clearance" in self.ds.variables:
            c = self.ds["clearance"]
            if self.dim in c.dims and c.ndim == 1:
                vals = np.asarray(c.values, dtype=float)
                units = str(c.attrs.get("units", "m")).strip()
                vals = vals * _STROKE_UNITS.get(units, 1.0)
                return [float(v) if np.isfinite(v) and v > 0 else None for v in vals]
            if c.ndim == 0:
                return [_positive(float(c.values))] * n
        h = _attr_float(self.ds, "clearance_m")
        if h is None:
            x_opt = _attr_float(self.ds, "x_opt_m")
            if x_opt is not None:
                h = x_opt / _th.X_OPT_OVER_H
        return [h] * n

    def theory_clearances(self) -> list[tuple[float, str, object]]:
        """Distinct clearances, their legend suffix and the colour of their laws.

        One clearance: black, no suffix. Several: the colour of the setting that has it when
        only one setting does (so a law sits next to its data), else black / greys.
        """
        groups: list[tuple[float, list[int]]] = []
        for k, h in enumerate(self.clearances()):
            if h is None:
                continue
            for d, members in groups:
                if math.isclose(h, d, rel_tol=1e-6):
                    members.append(k)
                    break
            else:
                groups.append((h, [k]))
        if len(groups) == 1:
            return [(groups[0][0], "", "black")]
        colours = self.colours()
        neutral = iter(("black", "0.4", "0.6") * len(groups))
        return [(h, f", h = {h * _MM:.3g} mm",
                 colours[members[0]] if len(members) == 1 else next(neutral))
                for h, members in groups]

    def colours(self) -> list:
        """One colour per setting."""
        from matplotlib import colormaps

        n = self.values.shape[0]
        if n == 1:
            return ["tab:blue"]
        cmap = colormaps["tab10"]
        order = (0, 3, 2, 1, 4, 5, 6, 8, 9, 7)  # blue, red, green, orange, ...: far apart first
        return [cmap(order[i % 10]) for i in range(n)]


# --------------------------------------------------------------------------- drawing

def _new_figure(figsize):
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    return fig, fig.add_subplot()


def _draw_data(ax, sw: _Sweep, scale: float, log: bool = False) -> list:
    """Mean line, min-max band and single seeds per setting; returns legend handles.

    The mean is over every computed seed. The line and the band are broken where η* jumps: between
    the strokes on either side of the setting's X_opt (eq. (17)) and between strokes whose motion
    modes differ. When the dataset has motion modes, each mean is marked by the mode most of its
    seeds are in (marker and fill from :func:`pdamper.plotting.mode_looks.mode_style`, edge in the
    setting's colour) and the modes get legend entries. With ``log`` (a log y axis) a mean <= 0
    leaves a gap, a band reaching <= 0 runs to the bottom of the axes and dots <= 0 are left out.
    """
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ..analysis.modes import majority_mode
    from .mode_looks import mode_rank, mode_style

    x_mm = sw.strokes_m * _MM
    colours = sw.colours()
    handles = []
    seeds_drawn = False
    modes_seen: set[str] = set()
    floor = None
    if log:
        pos = sw.positive_range()[0]
        floor = pos * scale / 2.0 if pos is not None else None
    for k, (vals, label, colour, x_opt) in enumerate(zip(sw.values, sw.labels, colours, sw.x_opts())):
        vals = vals * scale
        have = np.isfinite(vals)
        count = have.sum(axis=1)
        rows = count > 0  # strokes with at least one computed seed
        marker = _MARKERS[k % len(_MARKERS)]
        style = _LINESTYLES[k % len(_LINESTYLES)]
        name = "DEM" if not label else f"DEM, {label}"
        point_marker = marker if sw.modes is None else None  # with modes: the mode's marker
        if not rows.any():
            handles.append((Line2D([], [], color=colour, marker=point_marker, ls=style, lw=1.4, ms=4.5),
                            f"{name} (no data yet)"))
            continue
        with np.errstate(all="ignore"):
            mean = np.nanmean(vals[rows], axis=1)
            lo = np.nanmin(vals[rows], axis=1)
            hi = np.nanmax(vals[rows], axis=1)
        xs = x_mm[rows]
        if log:
            mean = np.where(mean > 0, mean, np.nan)
            lo = np.maximum(lo, floor) if floor is not None else lo
        modes = ([majority_mode(c)[0] for c in sw.modes[k][rows]] if sw.modes is not None
                 else [""] * xs.size)
        segments = _segments(xs, modes, x_opt * _MM if x_opt is not None else None)
        gx, gy = _with_gaps(xs, mean, segments)
        line, = ax.plot(gx, gy, color=colour, lw=1.4, ls=style, marker=point_marker, ms=4.5, mfc=colour,
                        mec="white", mew=0.6, zorder=3, gid=f"mean {name}")
        if sw.modes is not None:
            for mode in sorted(set(modes), key=mode_rank):
                at = np.array([m == mode for m in modes])
                look = mode_style(mode) if mode else {"color": colour, "marker": marker}
                ax.plot(xs[at], mean[at], ls="", marker=look["marker"], ms=6.0, mfc=look["color"], mec=colour,
                        mew=1.4, zorder=4, gid=f"mode {mode or 'none'} {name}")
                if mode:
                    modes_seen.add(mode)
        handle = line
        spread = count[rows] > 1
        if spread.any():
            for a, b in segments:
                ax.fill_between(xs[a:b], np.where(spread, lo, mean)[a:b], np.where(spread, hi, mean)[a:b],
                                color=colour, alpha=0.18, lw=0, zorder=1)
            dots = have & (vals > 0) if log else have
            sx = np.repeat(x_mm[:, None], sw.n_seeds, axis=1)[dots]
            ax.scatter(sx, vals[dots], s=7, color=colour, alpha=0.35, lw=0, zorder=2)
            seeds_drawn = True
            handle = (Patch(color=colour, alpha=0.18, lw=0), line)
        handles.append((handle, name))
    if seeds_drawn:
        handles.append((Line2D([], [], ls="", marker="o", ms=3, color="0.45", alpha=0.6,
                               mew=0), "single seeds"))
    for mode in sorted(modes_seen, key=mode_rank):
        look = mode_style(mode)
        handles.append((Line2D([], [], ls="", marker=look["marker"], ms=6.0, mfc=look["color"], mec="0.3",
                               mew=1.0), f"mode: {mode}"))
    return handles


def _segments(xs, modes, x_opt) -> list[tuple[int, int]]:
    """Index ranges [a, b) of ``xs`` (sorted) drawn as one line: a new one starts past ``x_opt``
    (where η* jumps) and where the motion mode changes (empty modes join either side)."""
    cuts = [0]
    last = modes[0] if len(modes) else ""
    for i in range(1, len(xs)):
        across = x_opt is not None and xs[i - 1] < x_opt <= xs[i]
        if modes[i] and last and modes[i] != last:
            across = True
        if across:
            cuts.append(i)
        last = modes[i] or last
    cuts.append(len(xs))
    return [(a, b) for a, b in zip(cuts[:-1], cuts[1:])]


def _with_gaps(xs, ys, segments):
    """``xs``, ``ys`` with a NaN between consecutive segments, so one line is drawn broken there."""
    gx, gy = [], []
    for n, (a, b) in enumerate(segments):
        if n:
            gx.append(math.sqrt(xs[a - 1] * xs[a]))
            gy.append(np.nan)
        gx.extend(xs[a:b])
        gy.extend(ys[a:b])
    return np.asarray(gx, dtype=float), np.asarray(gy, dtype=float)


def _draw_energy_laws(ax, h, lo, hi, mass, freq, colour, label):
    x = np.geomspace(lo, hi, 400)
    x_opt = _th.optimal_stroke(h)
    scale = math.pi * mass * (2.0 * math.pi * freq) ** 2  # Ẽ = η* π m V², V = ΩX
    below, above = x[x < x_opt], x[x >= x_opt]
    if lo <= x_opt <= hi:
        below, above = np.append(below, x_opt), np.insert(above, 0, x_opt)
    if below.size:
        ax.plot(below * _MM, _th.eta_scattered(below, h) * scale * below ** 2 * 1e3,
                color=colour, lw=1.5, ls="-.", label=f"scattered, eq. (8), κ = 1{label}")
    if above.size:
        ax.plot(above * _MM, _th.eta_rolling(above, h) * scale * above ** 2 * 1e3,
                color=colour, lw=1.8, label=f"rolling collect-and-collide, eq. (14){label}")


def _grid(ax):
    ax.grid(True, which="major", alpha=0.3)
    ax.grid(True, which="minor", axis="x", alpha=0.1)


def _no_data_note(ax):
    ax.text(0.5, 0.5, "no computed cases yet", transform=ax.transAxes, ha="center",
            va="center", color="0.4", fontsize="medium")


def _legend(fig, ax, data_handles):
    """One legend outside the axes (right), data first, then the laws: never over data."""
    from matplotlib.legend_handler import HandlerTuple

    handles = [h for h, _ in data_handles]
    labels = [s for _, s in data_handles]
    for h, s in zip(*ax.get_legend_handles_labels()):
        if not s.startswith("_"):
            handles.append(h)
            labels.append(s)
    if not handles:
        return
    fig.legend(handles, labels, loc="outside lower center", ncols=2, fontsize="small",
               frameon=False, handler_map={tuple: HandlerTuple(ndivide=1)},
               handlelength=2.4, columnspacing=1.5)


def _titles(fig, ax, sw: _Sweep, title, log_note=False):
    if title is None:
        title = sw.ds.attrs.get("title") or _auto_title(sw)
    if title:
        fig.suptitle(str(title), fontsize="medium")
    ax.set_title(_note(sw, log_note), fontsize="small", color="0.35")


def _note(sw: _Sweep, log_note=False) -> str:
    """What the DEM data are: version, seeds, cases computed (the axes' small title)."""
    total = sw.values.size
    done = int(np.isfinite(sw.values).sum())
    version = sw.ds.attrs.get("pdamper_version")
    text = f"DEM (pdamper {version})" if version else "DEM"
    if sw.n_seeds > 1:
        text += f": line = mean of {sw.n_seeds} seeds, band = min-max, dots = single seeds"
    else:
        text += ": 1 seed per stroke"
    text += f"; {done}/{total} cases computed" if done < total else f"; {total} cases"
    if log_note and sw.nonpositive:
        text += f"\n{sw.nonpositive} single value(s) <= 0 not shown as dots (log axis)"
    return text


def _auto_title(sw: _Sweep) -> str:
    a = sw.ds.attrs
    parts = []
    shape = a.get("shape")
    parts.append(f"{shape} damper" if shape else "particle damper")
    n, nmax = a.get("particles"), a.get("max_particles")
    if n is not None:
        parts.append(f"$N_p$ = {_int_text(n)}" + (f" of {_int_text(nmax)}" if nmax is not None
                                                  else ""))
    hs = [h for h in sw.clearances() if h is not None]
    if hs and all(math.isclose(h, hs[0], rel_tol=1e-6) for h in hs):
        parts.append(f"h = {hs[0] * _MM:.3g} mm")
    f = _attr_float(sw.ds, "frequency_hz")
    if f is not None:
        parts.append(f"f = {f:g} Hz")
    return ", ".join(parts)


def _int_text(v) -> str:
    try:
        return f"{int(v)}"
    except (TypeError, ValueError):
        return str(v)


def _attr_float(ds, name: str):
    v = ds.attrs.get(name)
    if v is None:
        return None
    try:
        return _positive(float(v))
    except (TypeError, ValueError):
        return None


def _positive(v: float):
    return v if math.isfinite(v) and v > 0 else None
