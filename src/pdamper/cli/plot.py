"""``pdamper plot ...``: figures from stored results (``pdamper plot modes RESULTS...``)."""

from __future__ import annotations

from pathlib import Path

import click

from .common import echo_json, main, user_errors

__all__ = ["plot_group", "modes_command", "map_command", "compare_command", "fields_command"]


@main.group("plot", cls=type(main))
def plot_group():
    """Figures from stored results: 'pdamper plot modes RESULTS', 'pdamper plot map STORE'."""


@plot_group.command("modes")
@click.argument("results", nargs=-1, required=True, metavar="RESULTS...")
@click.option("--out", "out", type=click.Path(dir_okay=False), default="modes.png", show_default=True,
              help="Figure file (.png, .svg or .pdf).")
@click.option("--title", help="Figure title.")
@click.option("--label", "labels", multiple=True, help="Row label, one per row in order (repeatable), "
              "e.g. --label 'N_p = 44, 3 deg tilt'.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (the map as data).")
@user_errors
def modes_command(results, out, title, labels, as_json):
    """Mode map of sweeps or studies: stroke x filling (or study setting), beside eta*.

    RESULTS are sweep stores (the --out of pdamper sweep), their results.nc, or a study's
    study.nc (one row per setting, e.g. the fig4 study's N_p = 36 and 44). Each cell is
    coloured by the motion mode most seeds are in (docs/motion.md).

    Example: pdamper plot modes cuboid_36_sweep cuboid_44_sweep --out modes.png
    """
    from ..analysis.modes import majority_mode
    from ..plotting.modes import mode_map_figure, mode_rows
    from ..studies import open_results

    datasets = [open_results(p) for p in results]
    names = [Path(p).name if Path(p).is_dir() else Path(p).stem for p in results]
    mode_map_figure(datasets, out, names=names, labels=labels or None, title=title)
    rows = mode_rows(datasets, names, labels or None)
    if as_json:
        echo_json({"plot": out, "rows": [{"label": r["label"], "strokes_m": r["stroke"].tolist(),
                                          "modes": [majority_mode(c)[0] for c in r["modes"]],
                                          "x_opt_m": r["x_opt"]} for r in rows]})
        return
    click.echo(f"pdamper plot modes: {len(rows)} row(s) -> {out}")
    for r in rows:
        click.echo(f"  {r['label']}")
        for x, cell in zip(r["stroke"], r["modes"]):
            mode, mixed = majority_mode(cell)
            if mode:
                click.echo(f"    X = {x * 1e3:8.3g} mm  {mode}" + ("  (seeds disagree)" if mixed else ""))


@plot_group.command("map")
@click.argument("results", metavar="STORE")
@click.option("--x", "x", help="Dimension on the x axis: a name (stroke) or config key (drive.stroke); default the first.")
@click.option("--y", "y", help="Dimension on the y axis; default the second.")
@click.option("--sel", "sel", multiple=True, metavar="DIM=VALUE",
              help="Fix a third dimension at its value nearest VALUE (SI), e.g. --sel friction=0.1 (repeatable).")
@click.option("--out", "out", type=click.Path(dir_okay=False), default="map.png", show_default=True,
              help="Figure file (.png, .svg or .pdf).")
@click.option("--title", help="Figure title.")
@click.option("--quantity", type=click.Choice(["eta_star", "effective_mass", "equivalent_damping"]),
              default="eta_star", show_default=True, metavar="NAME",
              help="What colours the cells: eta_star, effective_mass (the bed's) or equivalent_damping.")
@user_errors
def map_command(results, x, y, sel, out, title, quantity):
    """Design chart: eta* of a sweep over two keys as a coloured map, with X_opt and the lift-off bound.

    STORE is the --out of a sweep with two or more --vary dimensions (or its results.nc). Cells are
    coloured by eta* (mean over seeds) and hatched by the motion mode most seeds are in.

    Example: pdamper plot map cuboid_36_sweep --x drive.stroke --y drive.frequency --out map.png
    """
    from ..errors import InputError, shown
    from ..plotting.map import _dim_of, map_figure
    from ..studies import open_results

    ds = open_results(results)
    for item in sel:
        dim, _, value = item.partition("=")
        try:
            v = float(value)
        except ValueError:
            v = value
        d = _dim_of(ds, dim.strip())
        if not value:
            raise InputError(f"--sel {shown(item)}: write DIM=VALUE, e.g. --sel friction=0.1")
        ds = ds.sel({d: v}, method="nearest" if isinstance(v, float) else None)
    map_figure(ds, out, x=x, y=y, title=title, quantity=quantity)
    click.echo(f"pdamper plot map: {out}")


@plot_group.command("compare")
@click.argument("campaign", metavar="CAMPAIGN")
@click.argument("sweeps", nargs=-1, metavar="SWEEP...")
@click.option("--out", "out", type=click.Path(dir_okay=False), default="compare.png", show_default=True,
              help="Figure file (.png, .svg or .pdf).")
@click.option("--title", help="Figure title.")
@user_errors
def compare_command(campaign, sweeps, out, title):
    """Measured eta*(X) (a 'pdamper campaign' dataset) with error bars over the DEM of SWEEP stores.

    Example: pdamper plot compare rig/campaign/campaign.nc cuboid_36_sweep --out fig4_measured.png
    """
    from ..plotting.compare import compare_figure
    from ..studies import open_results

    camp = open_results(Path(campaign) / "campaign.nc" if Path(campaign).is_dir() else campaign)
    compare_figure(camp, [open_results(s) for s in sweeps], out, title=title)
    click.echo(f"pdamper plot compare: {out}")


@plot_group.command("fields")
@click.argument("fields_file", metavar="F.nc")
@click.option("--out", "out", type=click.Path(dir_okay=False), default="fields.png", show_default=True,
              help="Figure file (.png, .svg or .pdf).")
@click.option("--title", help="Figure title.")
@user_errors
def fields_command(fields_file, out, title):
    """The damper's fields: eta*(X) and m_eff/m_bed(X) per frequency, seed spread, mode changes.

    F.nc is the --out of 'pdamper fields'. Lines are the fields' interpolation, drawn within a
    motion-mode family only; bands the min-max over seeds; dotted lines where the fields jump.

    Example: pdamper plot fields fields_36.nc --out fields_36.png
    """
    from ..plotting.fields import fields_figure
    from ..studies.fields import load_fields

    fields_figure(load_fields(fields_file), out, title=title)
    click.echo(f"pdamper plot fields: {out}")
