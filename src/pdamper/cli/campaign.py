"""``pdamper campaign``: measured records (one per stroke) as one eta*(X) dataset, beside the DEM."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import click

from .common import Quantity, column_options, echo_json, main, user_errors

__all__ = ["campaign_command"]


@main.command("campaign")
@click.argument("records", nargs=-1, required=True, metavar="RECORD...", type=click.Path(allow_dash=False))
@click.option("--bed-mass", type=Quantity("mass"), help="Mass of all particles, e.g. 149g (or bed_mass in campaign.toml).")
@click.option("--container-mass", type=Quantity("mass"), help="The container's own mass, e.g. 80g, removed from "
              "the bed's effective mass (or container_mass in campaign.toml; default 0).")
@click.option("--frequency", type=Quantity("frequency"), help="Drive frequency of every record (default: detected).")
@click.option("--drop-cycles", type=click.IntRange(min=0), help="Whole cycles dropped at the start (default 2).")
@click.option("--manifest", type=click.Path(dir_okay=False, exists=True),
              help="Campaign manifest (default: campaign.toml beside the records, if there is one).")
@column_options
@click.option("--out", type=click.Path(file_okay=False), help="Directory for campaign.nc and campaign.csv "
              "(default: campaign beside the first record).")
@click.option("--plot", type=click.Path(dir_okay=False), help="Figure of eta*(X) with error bars (.png, .svg, .pdf).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@user_errors
def campaign_command(records, bed_mass, container_mass, frequency, drop_cycles, manifest, columns, motion, out, plot,
                     as_json):
    """Analyse test-rig records (one per stroke) into an eta*(X) curve with error bars.

    Each RECORD (a file, a folder of files, or a 'pdamper run --out' directory) is read as its
    logger wrote it and analysed by the complex power method; its stroke and frequency come from
    the motion (or from campaign.toml). A broken record is reported and the rest go on.

    Example: pdamper campaign rig/*.csv --bed-mass 149g --plot campaign.png
    """
    from ..errors import InputError
    from ..io.files import atomic_write, write_dataset
    from ..studies.campaign import analyze_records, campaign_dataset

    points, failures = analyze_records(records, bed_mass=bed_mass, frequency=frequency, drop_cycles=drop_cycles,
                                       columns=columns, motion=motion, manifest=manifest, container_mass=container_mass)
    if not points:
        more = f" (and {len(failures) - 1} more record(s) that could not be analysed)" if len(failures) > 1 else ""
        raise InputError(f"{failures[0][1]}{more}")
    for f, why in failures:
        click.echo(f"skipped: {why}" if why.startswith(f) else f"skipped {f}: {why}", err=True)
    bed = bed_mass if bed_mass is not None else _from_manifest(manifest, points, "bed_mass", None)
    if container_mass is None:
        container_mass = _from_manifest(manifest, points, "container_mass", 0.0)
    ds = campaign_dataset(points, bed_mass=bed, history="pdamper " + " ".join(sys.argv[1:]),
                          container_mass=container_mass)
    out = Path(out) if out else Path(points[0].file).parent / "campaign"
    out.mkdir(parents=True, exist_ok=True)
    write_dataset(out / "campaign.nc", ds)
    atomic_write(out / "campaign.csv", ds[["eta_star", "eta_star_error", "energy_per_cycle", "velocity_amplitude",
                                           "effective_mass", "equivalent_damping", "cycles_used", "file"]]
                 .to_dataframe().dropna(subset=["eta_star"])
                 .to_csv(float_format=repr))
    if plot:
        from ..plotting.compare import compare_figure

        compare_figure(ds, [], plot)
    rows = sorted((p.to_dict() for p in points), key=lambda r: (round(r["frequency_hz"], 2), r["stroke_m"]))
    if as_json:
        echo_json({"records": rows, "failed": [{"file": f, "reason": w} for f, w in failures],
                   "dataset": str(out / "campaign.nc"), "csv": str(out / "campaign.csv"), "plot": plot})
        return
    click.echo(f"pdamper campaign: {len(points)} record(s) analysed, {len(failures)} skipped; "
               f"bed mass {bed * 1e3:.4g} g")
    click.echo(f"  {'X [mm]':>8}  {'f [Hz]':>7}  {'eta*':>7}  {'+-':>6}  {'E/cycle [mJ]':>12}  cycles  file")
    for r in rows:
        err = r["eta_star_error"]
        click.echo(f"  {r['stroke_m'] * 1e3:8.4g}  {r['frequency_hz']:7.4g}  {r['eta_star']:7.3f}  "
                   f"{'' if err is None or not math.isfinite(err) else f'{err:.3f}':>6}  "
                   f"{r['energy_per_cycle_J'] * 1e3:12.4g}  {r['cycles_used']:>6}  {Path(r['file']).name}")
    click.echo(f"  dataset: {out / 'campaign.nc'}, {out / 'campaign.csv'}" + (f"; figure: {plot}" if plot else ""))


def _from_manifest(manifest, points, key, default):
    """The manifest's ``key`` (the given manifest, else campaign.toml beside the first record)."""
    from ..studies.campaign import MANIFEST, read_manifest

    m = Path(manifest) if manifest else Path(points[0].file).parent / MANIFEST
    return read_manifest(m).get(key, default) if m.exists() else default
