"""``pdamper sweep``: eta*(X) of a config over log-spaced strokes and several seeds, on all
local cores or a Dask cluster, resumable, with its plot."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import click
import numpy as np

from .common import device_option, echo_json, main, until_steady_option, user_errors
from .ensemble import uncertain_options
from .run import parse_set

__all__ = ["sweep_command"]


@main.command("sweep")
@click.argument("config", metavar="CONFIG.toml")
@click.option("--strokes", default=None,
              help="FIRST:LAST:COUNT, log-spaced, or a list such as 5mm,12mm,13mm; the shortcut for "
                   "--vary drive.stroke=... [default without --vary: 0.5mm:50mm:40, the paper's 40 points]")
@click.option("--vary", "vary", multiple=True, metavar="KEY=VALUES",
              help="Vary any config key (repeatable; one dimension each): a range FIRST:LAST:COUNT[:log|:linear] "
                   "(the stroke log-spaced, other keys linear unless said) or a list A,B,C, with units as in a "
                   "config file, e.g. --vary drive.frequency=1Hz:4Hz:4 --vary contact.friction=0.01,0.1,1.")
@click.option("--seeds", type=click.IntRange(min=1), default=1, show_default=True,
              help="Seeded initial states per stroke (0, 1, ...); the mean and spread are reported.")
@click.option("--cycles", type=click.FloatRange(min=0, min_open=True), help="Drive cycles per case (default: the config's).")
@click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE", help="Override any config key (repeatable).")
@click.option("--out", "out", type=click.Path(), help="Result store directory (default: <config name>_sweep). "
              "Re-running on the same store computes only the missing cases.")
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes (default: all cores).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on an existing Dask cluster instead of locally.")
@click.option("--plot", "plot", type=click.Path(dir_okay=False), help="Write the eta*(X) figure (png, svg or pdf).")
@click.option("--signals", "keep", type=click.Choice(["none", "signals", "full"]), default="signals",
              show_default=True, help="What the store keeps of each case: its 1 kHz force, motion and dissipated "
              "energy (about 0.25 MB per 20-cycle case; 'pdamper reanalyze' needs them), also every energy-ledger "
              "column ('full', about 0.7 MB), or nothing.")
@until_steady_option
@device_option
@click.option("--repair", is_flag=True, help="Rebuild a store whose store.json was lost from this config and its case files.")
@click.option("--measured", type=click.Path(exists=True), metavar="CAMPAIGN",
              help="Draw a measured campaign ('pdamper campaign') with error bars on the --plot figure.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (no progress bar).")
@uncertain_options(executor=False, store=False, eta=True)
@user_errors
def sweep_command(config, strokes, vary, seeds, cycles, settings, out, workers, scheduler, keep, until_steady, device,
                  plot, repair, measured, as_json, ensemble):
    """Run CONFIG.toml over a range of strokes (or any config keys) and report eta*.

    Every (point, seed) case is independent and written to the store as soon as it finishes;
    an interrupted sweep re-run with the same command resumes where it stopped.

    With --uncertain U.toml --samples N: the sweep at N samples of the unknowns (docs/ensembles.md), its
    store --out; eta*'s percentiles per point, which unknowns move the best eta* over the grid;
    --plot draws the CDF of the best eta*.

    Examples: pdamper sweep examples/cuboid_36.toml --seeds 3 --plot sweep_36.png;
    pdamper sweep examples/cuboid_36.toml --vary drive.stroke=5mm:30mm:6 --vary drive.frequency=1Hz:4Hz:4
    --plot map.png
    """
    from ..config import load_case
    from ..errors import InputError
    from ..analysis.modes import majority_mode
    from ..studies import SweepSpec, parse_axis, parse_strokes, run_sweep

    if workers and scheduler:
        raise InputError("--workers and --scheduler exclude each other: local processes, or a Dask cluster")
    overrides = parse_set(settings)
    if cycles is not None:
        overrides["run.cycles"] = cycles
    base = load_case(config, overrides)
    if device is not None:
        from ..run import check_device, on_device

        check_device(device)
        base = on_device(base, device)
    axes = tuple(parse_axis(v) for v in vary)
    if strokes is None and not axes:
        strokes = "0.5mm:50mm:40"
    if ensemble is not None:
        return _sweep_ensemble(ensemble, base, config, axes, strokes, seeds, out, workers, scheduler, until_steady,
                               keep, repair, measured, plot, as_json)
    spec = SweepSpec(base=base, axes=axes, strokes=parse_strokes(strokes) if strokes is not None else None,
                     seeds=tuple(range(seeds)))
    out = Path(out) if out else Path(f"{Path(config).stem}_sweep")
    if not as_json and axes:
        for a in spec.axes:
            how = {"log": "log-spaced", "linear": "linearly spaced", "list": "as listed"}[a.spacing]
            click.echo(f"  {a.key}: {len(a.values)} values, {how}")
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = run_sweep(spec, out, workers=workers, scheduler=scheduler, progress=None if not as_json else False,
                       keep=keep, history="pdamper " + " ".join(sys.argv[1:]), repair=repair,
                       until_steady=until_steady)
    for w in caught:
        if "set aside" in str(w.message):
            click.echo(f"warning: {w.message}", err=True)
    if plot and measured:
        from ..plotting.compare import compare_figure
        from ..studies import open_results

        m = Path(measured)
        compare_figure(open_results(m / "campaign.nc" if m.is_dir() else m), [ds], plot)
    elif plot:
        from ..plotting.map import results_figure

        results_figure(ds, plot)
    if [a.key for a in spec.axes] != ["drive.stroke"]:
        _grid_summary(ds, spec, out, plot, as_json, settings)
        return
    eta = ds.eta_star
    mean = eta.mean("seed", skipna=True)
    summary = {
        "store": str(out),
        "results_nc": str(out / "results.nc"),
        "results_csv": str(out / "results.csv"),
        "plot": plot,
        "particles": int(ds.attrs["particles"]),
        "clearance_m": ds.attrs["clearance_m"],
        "x_opt_theory_m": ds.attrs["x_opt_m"],
        "strokes_m": ds.stroke.values.tolist(),
        "seeds": ds.seed.values.tolist(),
        "eta_star_mean": mean.values.tolist(),
        "eta_star_min": eta.min("seed", skipna=True).values.tolist(),
        "eta_star_max": eta.max("seed", skipna=True).values.tolist(),
        "energy_per_cycle_J_mean": ds.energy_per_cycle.mean("seed", skipna=True).values.tolist(),
        "modes": [majority_mode(ds["mode"].values[i])[0] for i in range(len(ds.stroke))] if "mode" in ds else [],
        "failed_cases": int(ds["failed"].sum()),
        "wall_time_s_total": float(ds.wall_time.sum(skipna=True)),
    }
    if mean.notnull().any():
        k = int(np.argmax(mean.fillna(-1).values))
        summary["eta_star_peak"] = float(mean.values[k])
        summary["stroke_at_peak_m"] = float(ds.stroke.values[k])
    if as_json:
        echo_json(summary)
        return
    click.echo(f"pdamper sweep {config}: {len(ds.stroke)} strokes x {len(ds.seed)} seeds, {summary['particles']} "
               f"spheres, h = {summary['clearance_m'] * 1e3:.3g} mm, X_opt (theory) = {summary['x_opt_theory_m'] * 1e3:.3g} mm")
    _echo_settings(settings)
    click.echo(f"  {'X [mm]':>9}  {'eta* mean':>9}  {'min':>7}  {'max':>7}  {'E/cycle [mJ]':>12}  motion mode")
    for i, x in enumerate(ds.stroke.values):
        m = summary["eta_star_mean"][i]
        if m is None or (isinstance(m, float) and math.isnan(m)):
            continue
        click.echo(f"  {x * 1e3:9.3g}  {m:9.3f}  {summary['eta_star_min'][i]:7.3f}  {summary['eta_star_max'][i]:7.3f}  "
                   f"{summary['energy_per_cycle_J_mean'][i] * 1e3:12.4g}  {summary['modes'][i] if summary['modes'] else ''}")
    if "eta_star_peak" in summary:
        click.echo(f"  peak eta* = {summary['eta_star_peak']:.3f} at X = {summary['stroke_at_peak_m'] * 1e3:.3g} mm")
    if summary["failed_cases"]:
        click.echo(f"  {summary['failed_cases']} case(s) failed numerically; see {out / 'cases'}")
    click.echo(f"  results: {out / 'results.nc'} (xarray), {out / 'results.csv'}" + (f"; figure: {plot}" if plot else ""))


def _sweep_ensemble(ensemble, base, config, axes, strokes, seeds, out, workers, scheduler, until_steady, keep, repair,
                    measured, plot, as_json):
    """``sweep --uncertain``: the sweep at every sample (:func:`pdamper.cli.ensemble.run_uncertain`)."""
    from ..errors import InputError
    from ..studies import Axis, parse_strokes
    from .ensemble import run_uncertain

    for flag, given in (("--seeds", seeds > 1), ("--repair", repair), ("--measured", measured),
                        ("--signals", keep != "signals")):
        if given:
            raise InputError(f"{flag} does not apply to an ensemble" + (
                ": give the seed as an unknown in U.toml (key = \"initial.seed\", distribution = \"uniform\", "
                "low = 0, high = 999)" if flag == "--seeds" else ""))
    if strokes is not None:
        axes = (Axis(key="drive.stroke", values=tuple(parse_strokes(strokes)), spacing="list"),) + tuple(axes)
    run_uncertain(ensemble, base, config, study="run", command="sweep", as_json=as_json, plot=plot, out=out, axes=axes,
                  until_steady=until_steady, workers=workers, scheduler=scheduler)


def _grid_summary(ds, spec, out, plot, as_json, settings=()):
    """The report of a sweep over any keys: one row per point, mean/min/max over the seeds."""
    from ..analysis.modes import majority_mode

    eta = ds.eta_star
    mean, lo, hi = (eta.mean("seed", skipna=True), eta.min("seed", skipna=True), eta.max("seed", skipna=True))
    rows = []
    for p in spec.points():
        at = {a.name: p[a.key] for a in spec.axes}
        rows.append({"point": p, "eta_star_mean": float(mean.sel(at)), "eta_star_min": float(lo.sel(at)),
                     "eta_star_max": float(hi.sel(at)), "mode": majority_mode(ds["mode"].sel(at).values)[0]})
    summary = {"store": str(out), "results_nc": str(out / "results.nc"), "results_csv": str(out / "results.csv"),
               "plot": plot, "dims": {a.key: list(a.values) for a in spec.axes}, "seeds": ds.seed.values.tolist(),
               "points": rows, "failed_cases": int(ds["failed"].sum()),
               "wall_time_s_total": float(ds.wall_time.sum(skipna=True))}
    if as_json:
        echo_json(summary)
        return
    shape = " x ".join(f"{len(a.values)} {a.name}" for a in spec.axes)
    click.echo(f"pdamper sweep: {shape} x {len(ds.seed)} seeds, {int(ds.attrs['particles'])} spheres in a "
               f"{ds.attrs['shape']}")
    _echo_settings(settings)
    shown = {"m": (1e3, "mm"), "rad": (180 / math.pi, "deg"), "m s-1": (1.0, "m/s"), "1": (1.0, "")}
    scale = {}
    for a in spec.axes:
        units = ds[a.name].attrs.get("units", "1")
        scale[a.key] = shown.get(units, (1.0, units))
    head = "  ".join(f"{a.name + (' [' + scale[a.key][1] + ']' if scale[a.key][1] else ''):>14}" for a in spec.axes)
    click.echo(f"  {head}  {'eta* mean':>9}  {'min':>7}  {'max':>7}  motion mode")
    for r in rows:
        if math.isnan(r["eta_star_mean"]):
            continue
        vals = "  ".join(f"{v * scale[k][0]:>14.4g}" if isinstance(v, (int, float)) else f"{v:>14}"
                         for k, v in r["point"].items())
        click.echo(f"  {vals}  {r['eta_star_mean']:9.3f}  {r['eta_star_min']:7.3f}  {r['eta_star_max']:7.3f}  {r['mode']}")
    if summary["failed_cases"]:
        click.echo(f"  {summary['failed_cases']} case(s) failed numerically; see {out / 'cases'}")
    click.echo(f"  results: {out / 'results.nc'} (xarray), {out / 'results.csv'}" + (f"; figure: {plot}" if plot else ""))


def _echo_settings(settings) -> None:
    """The ``--set`` overrides as given, one line under the header (:func:`pdamper.cli.codes.settings_line`)."""
    from .codes import settings_line

    for line in settings_line(settings):
        click.echo(line)
