"""``pdamper calibrate``: the model parameters that make the DEM match a test campaign."""

from __future__ import annotations

from pathlib import Path

import click

from .codes import settings_line
from .common import device_option, echo_json, main, user_errors

__all__ = ["calibrate_command"]


@main.command("calibrate", short_help="Fit config keys (friction, tilt) so the DEM matches a campaign.")
@click.argument("campaign", metavar="CAMPAIGN")
@click.argument("config", metavar="CONFIG.toml")
@click.option("--fit", "fits", multiple=True, required=True, metavar="KEY=LOW:HIGH",
              help="A config key to fit over a range (repeatable), e.g. contact.friction=0.01:1 or "
                   "container.tilt=0deg:3deg; searched in log where the range spans a decade.")
@click.option("--seeds", type=click.IntRange(min=1), default=2, show_default=True, help="DEM seeds per point.")
@click.option("--cycles", type=click.FloatRange(min=0, min_open=True), help="Drive cycles per DEM case (default: the config's).")
@click.option("--points", type=click.IntRange(min=4), help="Grid points per key and round (default 7; 5 for two keys).")
@click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE", help="Override a config key (repeatable).")
@click.option("--out", type=click.Path(file_okay=False), help="Directory of the DEM rounds (default: <config name>_calibration); "
              "re-running resumes.")
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes (default: all cores).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run the DEM cases on an existing Dask cluster.")
@click.option("--plot", type=click.Path(dir_okay=False), help="Figure of the fit (.png, .svg, .pdf).")
@device_option
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (best, uncertainty, misfit, ...).")
@user_errors
def calibrate_command(campaign, config, fits, seeds, cycles, points, settings, out, workers, scheduler, plot, device,
                      as_json):
    """Fit model parameters (e.g. friction, tilt) so the DEM's eta*(X) matches a measured CAMPAIGN.

    CAMPAIGN is the output of 'pdamper campaign' (its directory or campaign.nc); CONFIG.toml the
    damper's model. The DEM runs at the campaign's strokes on parameter grids (two rounds, each a
    resumable sweep store); a smooth surrogate of eta* gives the best values, their uncertainty
    (profile Delta chi2 = 1) and the misfit.

    Example: pdamper calibrate rig/campaign my_damper.toml --fit contact.friction=0.01:1 --plot fit.png
    """
    from ..config import load_case
    from ..errors import InputError
    from ..studies import open_results
    from ..studies.calibrate import calibrate, parse_fit
    from .run import parse_set

    if workers and scheduler:
        raise InputError("--workers and --scheduler exclude each other: local processes, or a Dask cluster")
    params = [parse_fit(f) for f in fits]
    cpath = Path(campaign)
    camp = open_results(cpath / "campaign.nc" if cpath.is_dir() else cpath)
    if camp.attrs.get("kind") != "campaign":
        raise InputError(f"{campaign}: not a campaign dataset; make one with 'pdamper campaign RECORDS --bed-mass ...'")
    base = load_case(config, parse_set(settings))
    if device is not None:
        from ..run import check_device, on_device

        check_device(device)
        base = on_device(base, device)
    out = Path(out) if out else Path(f"{Path(config).stem}_calibration")
    cal = calibrate(camp, base, params, out=out, seeds=tuple(range(seeds)), cycles=cycles, points=points,
                    workers=workers, scheduler=scheduler, progress=False if as_json else None)
    if plot:
        from ..plotting.calibration import calibration_figure

        calibration_figure(cal, plot)
    if as_json:
        echo_json({**cal.to_dict(), "out": str(out), "plot": plot})
        return
    click.echo(f"pdamper calibrate: {len(cal.strokes_m)} strokes, {len(cal.points)} DEM points x {seeds} seed(s)")
    for line in settings_line(settings):
        click.echo(line)
    for k in cal.best:
        click.echo(f"  {k} = {cal.best[k]:.4g} ± {cal.uncertainty[k]:.2g}"
                   + ("" if cal.convex else "  (no clear minimum inside the range: widen it or add strokes)"))
    click.echo(f"  misfit chi2 = {cal.misfit:.3g} (reduced {cal.reduced_misfit:.3g}); rms eta* difference "
               f"{cal.rms_difference:.3f}")
    click.echo(f"  DEM rounds: {out}" + (f"; figure: {plot}" if plot else ""))
