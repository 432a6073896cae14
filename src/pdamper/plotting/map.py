"""A design chart: η* of a sweep over two config keys as a coloured map.

The mean over seeds of ``eta_star`` is drawn as coloured cells over any two dimensions of the
results dataset (e.g. stroke x frequency), the motion mode of each cell (the seeds' majority) as
hatching, and where the stroke is an axis: the theory's optimal stroke X_opt (eq. (17) of the
paper; the dataset's ``x_opt`` variable or ``x_opt_m`` attribute) and the lift-off bound
A = X (2 pi f)^2 = g, above which the bed leaves the floor. A third dimension left in the
dataset (besides ``seed``) must be fixed by the caller with ``ds.sel(...)``. ``quantity`` colours
the map by another variable of :data:`QUANTITIES` instead: the bed's effective mass or the
equivalent damping (docs/analysis.md).

:func:`results_figure` picks the figure a sweep's dataset needs: η*(X) with the laws for a
stroke sweep (:func:`pdamper.plotting.sweep.sweep_figure`), this map for two dimensions, and η*
over the one key for a one-dimensional sweep over another key.
"""

from __future__ import annotations

import math

import numpy as np

from ..analysis.modes import majority_mode
from ..errors import InputError, shown
from .mode_looks import mode_rank, mode_style
from .figure import check_path, log_ticks, save

__all__ = ["map_figure", "line_figure", "results_figure", "QUANTITIES"]

_SCALES = {"m": (1e3, "mm"), "s": (1e3, "ms"), "rad": (180 / math.pi, "deg")}

#: What a map can be coloured by: dataset variable -> (colour-bar label, display scale).
QUANTITIES = {"eta_star": ("η*", 1.0), "effective_mass": ("effective mass of the bed m_eff [g]", 1e3),
              "equivalent_damping": ("equivalent damping c_eq [N s/m]", 1.0)}


def _dim_of(ds, key_or_dim: str) -> str:
    """A dataset dimension from its name (``stroke``) or its config key (``drive.stroke``)."""
    if key_or_dim in ds.dims:
        return key_or_dim
    for d in ds.dims:
        if ds[d].attrs.get("config_key") == key_or_dim:
            return d
    dims = [d for d in ds.dims if d != "seed"]
    raise InputError(f"{shown(key_or_dim)} is not a dimension of these results; they have "
                     + ", ".join(f"{d} ({ds[d].attrs.get('config_key', d)})" for d in dims))


def _axis_values(ds, dim):
    """(values scaled for display, axis label, log?)."""
    units = ds[dim].attrs.get("units", "")
    scale, unit_text = _SCALES.get(units, (1.0, units))
    label = ds[dim].attrs.get("long_name", dim)
    if unit_text and unit_text != "1":
        label += f" [{unit_text}]"
    vals = np.asarray(ds[dim].values, dtype=float) * scale
    log = ds[dim].attrs.get("spacing") == "log" and np.all(vals > 0)
    return vals, label, log, scale


def _edges(v, log):
    """Cell edges around sorted centres ``v`` (geometric midpoints on a log axis)."""
    v = np.asarray(v, dtype=float)
    if v.size == 1:
        return np.array([v[0] * 0.8, v[0] * 1.25]) if log else np.array([v[0] - 0.5, v[0] + 0.5])
    t = np.log(v) if log else v
    mid = (t[1:] + t[:-1]) / 2
    e = np.concatenate([[t[0] - (mid[0] - t[0])], mid, [t[-1] + (t[-1] - mid[-1])]])
    return np.exp(e) if log else e


def map_figure(ds, path=None, *, x=None, y=None, title=None, figsize=(7.2, 5.0), dpi: int = 150,
               quantity: str = "eta_star"):
    """η* (mean over seeds) as a coloured map over dimensions ``x`` and ``y`` (names or config
    keys; default: the first two), modes hatched, X_opt and the lift-off bound A = g drawn where
    the stroke is an axis; ``quantity`` (a name of :data:`QUANTITIES`) colours it by another
    variable. Returns the :class:`matplotlib.figure.Figure`; saved to ``path`` if given."""
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch, Rectangle

    target = check_path(path)
    dims = [d for d in ds["eta_star"].dims if d != "seed"]
    if len(dims) < 2:
        raise InputError(f"a map needs two dimensions; these results have {dims or 'none'} "
                         "(use the sweep figure for one)")
    xd = _dim_of(ds, x) if x else dims[0]
    yd = _dim_of(ds, y) if y else next(d for d in dims if d != xd)
    if xd == yd:
        raise InputError(f"--x and --y are both {shown(xd)}; choose two different dimensions")
    rest = [d for d in dims if d not in (xd, yd)]
    if rest:
        raise InputError(f"these results also vary {', '.join(rest)}; pick one value with ds.sel({rest[0]}=...) "
                         "before drawing a map")
    if quantity not in QUANTITIES:
        raise InputError(f"quantity {shown(quantity)}: choose one of {', '.join(QUANTITIES)}")
    if quantity not in ds or quantity != "eta_star" and not np.isfinite(ds[quantity].values).any():
        raise InputError(f"these results have no {quantity} values (a store of an older pdamper keeps none); "
                         "re-analyse the kept signals with 'pdamper reanalyze STORE --out new.nc' and map new.nc, "
                         "or map eta_star")
    label, qscale = QUANTITIES[quantity]
    eta = ds[quantity].mean("seed", skipna=True).transpose(yd, xd) * qscale
    xv, xlabel, xlog, xscale = _axis_values(ds, xd)
    yv, ylabel, ylog, yscale = _axis_values(ds, yd)
    fig = Figure(figsize=figsize, layout="constrained")
    ax = fig.add_subplot()
    finite = np.isfinite(eta.values).any()
    if quantity == "eta_star":
        vmin, vmax = 0.0, max(1.0, float(np.nanmax(eta.values)) if finite else 1.0)
    else:
        vmin, vmax = (float(np.nanmin(eta.values)), float(np.nanmax(eta.values))) if finite else (0.0, 1.0)
    mesh = ax.pcolormesh(_edges(xv, xlog), _edges(yv, ylog), eta.values, cmap="viridis", vmin=vmin, vmax=vmax)
    fig.colorbar(mesh, ax=ax, label=f"{label} (mean over seeds)")
    # motion modes, hatched cell by cell
    modes = ds["mode"].transpose(yd, xd, "seed").values if "mode" in ds else None
    marked = set()
    if modes is not None:
        xe, ye = _edges(xv, xlog), _edges(yv, ylog)
        for i in range(len(yv)):
            for j in range(len(xv)):
                m, _ = majority_mode(modes[i, j])
                hatch = mode_style(m)["hatch"] if m else ""
                if hatch:
                    ax.add_patch(Rectangle((xe[j], ye[i]), xe[j + 1] - xe[j], ye[i + 1] - ye[i],
                                           fill=False, hatch=hatch, edgecolor="white", linewidth=0, alpha=0.7))
                if m:
                    marked.add(m)
    handles = []
    # theory: X_opt and the lift-off bound where the stroke is an axis
    cfg = {d: ds[d].attrs.get("config_key") for d in (xd, yd)}
    stroke_dim = next((d for d in (xd, yd) if cfg[d] == "drive.stroke"), None)
    freq_dim = next((d for d in (xd, yd) if cfg[d] == "drive.frequency"), None)
    if stroke_dim is not None:
        other = yd if stroke_dim == xd else xd
        oth_vals, oth_log = (yv, ylog) if stroke_dim == xd else (xv, xlog)
        oth_edges = _edges(oth_vals, oth_log)
        sscale = xscale if stroke_dim == xd else yscale

        def draw(stroke_pts, other_pts, **kw):
            return ax.plot(stroke_pts, other_pts, **kw) if stroke_dim == xd else ax.plot(other_pts, stroke_pts, **kw)

        if "x_opt" in ds and other in ds["x_opt"].dims:  # X_opt moves along the other axis: a step per cell
            xo = np.repeat(np.asarray(ds["x_opt"].transpose(other).values, dtype=float) * sscale, 2)
            span = np.repeat(oth_edges, 2)[1:-1]
        else:
            xo = np.full(2, float(ds.attrs.get("x_opt_m", math.nan)) * sscale)
            span = oth_edges[[0, -1]]
        if np.isfinite(xo).any():
            handles += draw(xo, span, color="black", lw=2, ls="--", label="X_opt (theory)")
        g = float(ds.attrs.get("gravity_m_s2", 9.81))
        if freq_dim is not None:
            fscale = yscale if freq_dim == yd else xscale
            f = np.geomspace(max(oth_edges[0], 1e-9), oth_edges[-1], 200) / fscale
            pts = (g / (2 * math.pi * f) ** 2 * sscale, f * fscale)
        else:
            fr = float(ds.attrs.get("frequency_hz", math.nan))
            pts = (np.full(2, g / (2 * math.pi * fr) ** 2 * sscale if math.isfinite(fr) else math.nan), oth_edges[[0, -1]])
        if np.isfinite(pts[0]).any():
            handles += draw(*pts, color="tab:red", lw=1.8, label="lift-off bound A = g")
    ax.set_xscale("log" if xlog else "linear")
    ax.set_yscale("log" if ylog else "linear")
    ax.set_xlim(_edges(xv, xlog)[[0, -1]])
    ax.set_ylim(_edges(yv, ylog)[[0, -1]])
    for axis, log, v in ((ax.xaxis, xlog, xv), (ax.yaxis, ylog, yv)):
        if log:  # at least 3 labelled ticks, none on top of another (1-2-5 or 1..9 x 10^n)
            log_ticks(axis, *_edges(v, True)[[0, -1]])
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    for m in sorted(marked, key=mode_rank):
        hatch = mode_style(m)["hatch"]
        handles.append(Patch(facecolor="grey", hatch=hatch, edgecolor="white", label=m if hatch else f"{m} (plain)"))
    if handles:
        ax.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3, fontsize=8, frameon=False)
    ax.set_title(title or _title(ds, quantity), fontsize=10)
    if target is not None:
        save(fig, target, dpi)
    return fig


def line_figure(ds, path=None, *, title=None, figsize=(7.0, 4.5), dpi: int = 150):
    """η* over the one dimension of a sweep over a key other than the stroke: the mean over
    seeds (line with markers) and the single seeds (dots)."""
    from matplotlib.figure import Figure

    target = check_path(path)
    dims = [d for d in ds["eta_star"].dims if d != "seed"]
    if len(dims) != 1:
        raise InputError(f"a line figure needs one dimension besides seed; these results have {dims}")
    d = dims[0]
    xv, xlabel, xlog, _ = _axis_values(ds, d)
    fig = Figure(figsize=figsize, layout="constrained")
    ax = fig.add_subplot()
    eta = ds["eta_star"].transpose(d, "seed").values
    for k in range(eta.shape[1]):
        ax.plot(xv, eta[:, k], "o", color="tab:blue", alpha=0.35, ms=4, label="single seeds" if k == 0 else None)
    ax.plot(xv, np.nanmean(np.where(np.isfinite(eta), eta, np.nan), axis=1) if np.isfinite(eta).any() else eta[:, 0],
            "-o", color="tab:blue", label="mean over seeds")
    ax.set_xscale("log" if xlog else "linear")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("η*")
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title or _title(ds), fontsize=10)
    if target is not None:
        save(fig, target, dpi)
    return fig


def results_figure(ds, path=None, **kw):
    """The figure a sweep's results need: η*(X) with the laws for a stroke sweep, a map for two
    dimensions, η* over the key for one other dimension."""
    from .sweep import sweep_figure

    dims = [d for d in ds["eta_star"].dims if d not in ("seed", "setting")]
    if dims == ["stroke"]:
        return sweep_figure(ds, path, **kw)
    if len(dims) == 1:
        return line_figure(ds, path, **kw)
    return map_figure(ds, path, **kw)


def _title(ds, quantity: str = "eta_star") -> str:
    n, shape = ds.attrs.get("particles"), ds.attrs.get("shape", "container")
    varied = ds.attrs.get("varied_keys", "")
    what = QUANTITIES[quantity][0].split(" [")[0]
    return f"{what} over {varied}: {n} spheres in a {shape}" if n else f"{what} over {varied}"
