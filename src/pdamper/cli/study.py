"""``pdamper study NAME``: one of the paper's studies with its dataset and figure."""

from __future__ import annotations

import math
from pathlib import Path

import click
import numpy as np

from .codes import settings_line
from .common import device_option, echo_json, main, until_steady_option, user_errors
from .run import parse_set

__all__ = ["study_command"]

#: --quick: 8 strokes from 0.5 to 50 mm, 6 cycles (2 dropped), one seed -- a first look.
QUICK = dict(strokes=(0.5e-3, 50e-3, 8), cycles=6, drop_cycles=2)


@main.command("study")
@click.argument("name", metavar="NAME|FILE.toml")
@click.option("--quick", is_flag=True, help="8 strokes, 6 cycles, 1 seed: a first look in 10 s to about a minute on 2 cores (docs/sweeps.md).")
@click.option("--strokes", help="FIRST:LAST:COUNT or a list, replacing the study's strokes (the paper's: "
              "0.5mm:50mm:40; --quick: 0.5mm:50mm:8).")
@click.option("--seeds", type=click.IntRange(min=1), default=1, show_default=True, help="Seeds per stroke.")
@click.option("--cycles", type=click.FloatRange(min=0, min_open=True), help="Drive cycles per case (default 20).")
@click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE",
              help="Override a config key in every setting, e.g. --set contact.tangential=spring (repeatable; "
                   "not a key the study varies or its settings set). Part of each store's configuration: "
                   "give the same --set to resume, another --out for other values.")
@click.option("--out", type=click.Path(), help="Study directory (default study_<NAME>[_quick]).")
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes (default: all cores).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on an existing Dask cluster.")
@click.option("--plot", type=click.Path(dir_okay=False), help="Figure file (default <out>/<NAME>.png).")
@until_steady_option
@device_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (no progress bar).")
@user_errors
def study_command(name, quick, strokes, seeds, cycles, settings, out, workers, scheduler, plot, until_steady, device,
                  as_json):
    """Run a study (one of the paper's, or your study file) and write its dataset and figure.

    NAME is one of: fig4, friction, modulus, density, restitution, radius, tilt, cylinder,
    cylinder-tilt (their study files ship with pdamper), or the path of a study file
    (docs/sweeps.md). Every setting is swept into its own resumable store under the study
    directory; study.nc holds them all with a 'setting' dimension; studies with two fillings
    draw two panels.

    Examples: pdamper study fig4 --quick; pdamper study fig4 --seeds 3 --set contact.tangential=spring
    --out study_fig4_spring
    """
    from ..errors import InputError
    from ..plotting.sweep import study_figure
    from ..studies.named import load_study, run_study
    from ..studies.sweep import parse_strokes, stroke_grid

    if workers and scheduler:
        raise InputError("--workers and --scheduler exclude each other: local processes, or a Dask cluster")
    study = load_study(name)  # unknown names fail here, with a suggestion
    overrides = parse_set(settings)
    name = study.name
    if strokes:
        xs = tuple(parse_strokes(strokes))
    elif quick:
        xs = tuple(stroke_grid(*QUICK["strokes"]))
    else:
        xs = None  # the study file's
    if cycles is None and quick:
        cycles = QUICK["cycles"]
    drop = QUICK["drop_cycles"] if quick else None
    out = Path(out) if out else Path(f"study_{name}{'_quick' if quick else ''}")
    ds = run_study(study.source, out, strokes=xs, seeds=tuple(range(seeds)), cycles=cycles, drop_cycles=drop,
                   workers=workers, scheduler=scheduler, progress=False if as_json else None, until_steady=until_steady,
                   device=device, overrides=overrides)
    plot = Path(plot) if plot else out / f"{name}.png"
    study_figure(ds, plot)
    mean = ds.eta_star.mean("seed", skipna=True)
    rows = []
    for k, label in enumerate(ds.setting.values.tolist()):
        m = mean.values[k]
        if np.all(np.isnan(m)):
            continue
        i = int(np.nanargmax(m))
        rows.append({"setting": label, "eta_star_peak": float(m[i]), "stroke_at_peak_m": float(ds.stroke.values[i]),
                     "x_opt_theory_m": float(ds.x_opt.values[k]), "clearance_m": float(ds.clearance.values[k])})
    summary = {"study": name, "title": ds.attrs.get("title", ""), "overrides": overrides, "dataset": str(out / "study.nc"),
               "plot": str(plot), "strokes_m": ds.stroke.values.tolist(), "seeds": ds.seed.values.tolist(),
               "settings": rows, "eta_star_mean": {r: mean.sel(setting=r).values.tolist()
                                                   for r in ds.setting.values.tolist()},
               "failed_cases": int(ds["failed"].sum())}
    if as_json:
        echo_json(summary)
        return
    click.echo(f"pdamper study {name}: {summary['title']}")
    for line in settings_line(settings):
        click.echo(line)
    click.echo(f"  {len(ds.stroke)} strokes x {len(ds.seed)} seeds per setting")
    for r in rows:
        click.echo(f"  {r['setting']:<32} peak eta* = {r['eta_star_peak']:.3f} at X = {r['stroke_at_peak_m'] * 1e3:.3g} mm"
                   f"   (theory X_opt = {r['x_opt_theory_m'] * 1e3:.3g} mm)" if math.isfinite(r['x_opt_theory_m'])
                   else f"  {r['setting']:<32} peak eta* = {r['eta_star_peak']:.3f} at X = {r['stroke_at_peak_m'] * 1e3:.3g} mm")
    if summary["failed_cases"]:
        click.echo(f"  {summary['failed_cases']} case(s) failed numerically (see the stores under {out})")
    click.echo(f"  dataset: {out / 'study.nc'}; figure: {plot}")
