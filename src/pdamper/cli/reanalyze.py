"""``pdamper reanalyze``: eta* of a stored sweep again from its kept signals, without simulating."""

from __future__ import annotations

import math
from pathlib import Path

import click

from .common import echo_json, main, user_errors

__all__ = ["reanalyze_command"]


@main.command("reanalyze")
@click.argument("store", metavar="STORE")
@click.option("--drop-cycles", "drop_cycles", type=click.IntRange(min=0),
              help="Drive cycles left out at the start of each case (default: the sweep's).")
@click.option("--out", "out", type=click.Path(dir_okay=False),
              help="Write the re-analysed results to this netCDF file (the store itself is not changed).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@user_errors
def reanalyze_command(store, drop_cycles, out, as_json):
    """Analyse a sweep's cases again from their kept signals (no simulation).

    With the sweep's own settings the numbers are the run's; with --drop-cycles N the first N
    cycles of each case are left out of the complex-power analysis. Cases stored without
    signals (a sweep run with --signals none) keep their numbers and are counted.

    Example: pdamper reanalyze cuboid_36_sweep --drop-cycles 5 --out drop5.nc
    """
    from ..io.files import write_dataset
    from ..studies.reanalyze import reanalyze

    ds = reanalyze(store, drop_cycles=drop_cycles)
    if out:
        write_dataset(Path(out), ds)
    eta = ds.eta_star.mean("seed", skipna=True)
    dims = [d for d in eta.dims]
    summary = {"store": str(store), "out": out, "drop_cycles": ds.attrs["drop_cycles"],
               "reanalysed": ds.attrs["reanalysed"], "not_reanalysed": ds.attrs["not_reanalysed"],
               "dims": {d: ds[d].values.tolist() for d in dims},
               "eta_star_mean": eta.values.tolist()}
    if as_json:
        echo_json(summary)
        return
    click.echo(f"pdamper reanalyze {store}: {summary['reanalysed']} case(s) re-analysed with drop_cycles = "
               f"{summary['drop_cycles']}" + (f", {summary['not_reanalysed']} without kept signals" if
                                              summary["not_reanalysed"] else ""))
    flat = eta.stack(point=dims) if len(dims) > 1 else eta
    for i in range(flat.size):
        v = float(flat.values.ravel()[i])
        if math.isnan(v):
            continue
        label = ", ".join(f"{d} = {flat[d].values.ravel()[i]:.4g}" for d in dims)
        click.echo(f"  {label}: eta* = {v:.3f}")
    if out:
        click.echo(f"  results: {out}")
