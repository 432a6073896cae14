"""``pdamper fields``: the damper's effective fields (eta*, E, m_eff, c_eq over X x f) as a netCDF file."""

from __future__ import annotations

import math
import shlex

import click

from .common import echo_json, main, user_errors

__all__ = ["fields_command"]


@main.command("fields")
@click.argument("source", metavar="STORE_OR_CAMPAIGN")
@click.option("--out", "out", type=click.Path(dir_okay=False), required=True,
              help="The fields file to write (netCDF, .nc).")
@click.option("--sel", "sel", multiple=True, metavar="DIM=VALUE",
              help="Fix another dimension of the sweep at its value nearest VALUE (SI), e.g. --sel friction=0.1 "
                   "(repeatable).")
@click.option("--plot", "plot", type=click.Path(dir_okay=False), help="Also draw the fields (.png, .svg, .pdf).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
@user_errors
def fields_command(source, out, sel, plot, as_json):
    """The damper's fields over amplitude x frequency, from a sweep or a campaign.

    STORE_OR_CAMPAIGN is the --out of 'pdamper sweep' over drive.stroke and drive.frequency (or
    over the stroke only), its results.nc, or a 'pdamper campaign' output (its folder or
    campaign.nc). The file holds eta*, the energy per cycle, the bed's effective mass and the
    equivalent damping (mean, std, min and max over seeds), the motion mode per point and the
    provenance; 'pdamper plot fields F.nc' draws it (docs/fields.md).

    Example: pdamper fields cuboid_36_map --out fields_36.nc
    """
    from ..errors import InputError, shown
    from ..plotting.figure import check_path
    from ..studies.fields import build_fields, write_fields

    check_path(plot)
    chosen = {}
    for item in sel:
        dim, _, value = item.partition("=")
        if not value:
            raise InputError(f"--sel {shown(item)}: write DIM=VALUE, e.g. --sel friction=0.1")
        try:
            chosen[dim.strip()] = float(value)
        except ValueError:
            chosen[dim.strip()] = value
    # the command as given (from its parsed options, not sys.argv, which is the caller's when embedded)
    command = " ".join(["pdamper fields", shlex.quote(str(source)), "--out", shlex.quote(str(out)),
                        *[f"--sel {shlex.quote(item)}" for item in sel]])
    fields = build_fields(source, sel=chosen, command=command)
    write_fields(fields, out)
    if plot:
        from ..plotting.fields import fields_figure

        fields_figure(fields, plot)
    ds = fields.dataset
    jumps = fields.jumps()
    if as_json:
        echo_json({"fields": str(out), "source": ds.attrs["source"], "source_kind": ds.attrs["source_kind"],
                   "amplitudes_m": fields.amplitudes.tolist(), "frequencies_hz": fields.frequencies.tolist(),
                   "bed_mass_kg": fields.bed_mass, "seeds_max": int(ds["seeds"].max()),
                   "eta_star": ds["eta_star"].values.tolist(), "mode": ds["mode"].values.tolist(),
                   "jumps": jumps, "plot": plot})
        return
    click.echo(f"pdamper fields: {ds.attrs['source_kind']} {source} -> {out}")
    click.echo(f"  box: {fields.box()}; bed mass {fields.bed_mass * 1e3:.4g} g")
    click.echo(f"  {'X [mm]':>8}  {'f [Hz]':>7}  {'eta*':>7}  {'std':>6}  {'m_eff/m_bed':>11}  {'c_eq [N s/m]':>12}  "
               "seeds  mode")
    for i, x in enumerate(fields.amplitudes):
        for j, f in enumerate(fields.frequencies):
            p = ds.isel(amplitude=i, frequency=j)
            if not math.isfinite(float(p["eta_star"])):
                continue
            mode = str(p["mode"].values) + (" (seeds disagree)" if int(p["mode_mixed"]) else "")
            click.echo(f"  {x * 1e3:8.4g}  {f:7.4g}  {float(p['eta_star']):7.3f}  {float(p['eta_star_std']):6.3f}  "
                       f"{float(p['effective_mass']) / fields.bed_mass:11.3f}  {float(p['equivalent_damping']):12.4g}  "
                       f"{int(p['seeds']):>5}  {mode}")
    for jmp in jumps:
        click.echo(f"  mode change at {jmp['frequency_hz']:g} Hz between X = {jmp['below_m'] * 1e3:.4g} and "
                   f"{jmp['above_m'] * 1e3:.4g} mm ({jmp['family_below']} -> {jmp['family_above']})")
    if plot:
        click.echo(f"  figure: {plot}")
