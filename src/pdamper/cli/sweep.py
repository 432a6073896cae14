"""``pdamper sweep``: eta*(X) of a config over log-spaced strokes and several seeds, on all
local cores or a Dask cluster, resumable, with its plot."""

from __future__ import annotations

import math
from pathlib import Path

import click
import numpy as np

from .common import echo_json, main, user_errors
from .run import parse_set

__all__ = ["sweep_command"]


@main.command("sweep")
@click.argument("config", metavar="CONFIG.toml")
@click.option("--strokes", default="0.5mm:50mm:40", show_default=True,
              help="FIRST:LAST:COUNT, log-spaced (the paper's 40 points), or a list such as 5mm,12mm,13mm.")
@click.option("--seeds", type=click.IntRange(min=1), default=1, show_default=True,
              help="Seeded initial states per stroke (0, 1, ...); the mean and spread are reported.")
@click.option("--cycles", type=click.FloatRange(min=0, min_open=True), help="Drive cycles per case (default: the config's).")
@click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE", help="Override any config key (repeatable).")
@click.option("--out", "out", type=click.Path(), help="Result store directory (default: <config name>_sweep). "
              "Re-running on the same store computes only the missing cases.")
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes (default: all cores).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on an existing Dask cluster instead of locally.")
@click.option("--plot", "plot", type=click.Path(dir_okay=False), help="Write the eta*(X) figure (png, svg or pdf).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (no progress bar).")
@user_errors
def sweep_command(config, strokes, seeds, cycles, settings, out, workers, scheduler, plot, as_json):
    """Run CONFIG.toml over a range of strokes and report eta*(X) with the analytical laws.

    Every (stroke, seed) case is independent and written to the store as soon as it finishes;
    an interrupted sweep re-run with the same command resumes where it stopped.

    Example: pdamper sweep examples/cuboid_36.toml --seeds 3 --plot sweep_36.png
    """
    from ..config import load_case
    from ..errors import InputError
    from ..analysis.modes import majority_mode
    from ..studies import SweepSpec, parse_strokes, run_sweep

    if workers and scheduler:
        raise InputError("--workers and --scheduler exclude each other: local processes, or a Dask cluster")
    overrides = parse_set(settings)
    if cycles is not None:
        overrides["run.cycles"] = cycles
    base = load_case(config, overrides)
    spec = SweepSpec(base=base, strokes=parse_strokes(strokes), seeds=tuple(range(seeds)))
    out = Path(out) if out else Path(f"{Path(config).stem}_sweep")
    ds = run_sweep(spec, out, workers=workers, scheduler=scheduler, progress=None if not as_json else False)
    if plot:
        from ..plotting.sweep import sweep_figure

        sweep_figure(ds, plot)
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
