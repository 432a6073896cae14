"""``pdamper analyze``: the complex power method on a measured (or exported) record file."""

from __future__ import annotations

import math

import click

from .._version import __version__
from ..analysis import DEFAULT_DROP_CYCLES, analyze_record
from ..errors import InputError, shown
from ..io.records import read_record
from .common import Quantity, column_options, echo_json, main, user_errors

__all__ = ["analyze_command", "STEADY_SPREAD"]

#: Relative standard deviation of the used per-cycle energies above which the
#: record is reported as possibly not steady.
STEADY_SPREAD = 0.10


@main.command("analyze")
@click.argument("record", type=click.Path(dir_okay=True, allow_dash=True))
@click.option("--bed-mass", type=Quantity("mass"),
              help="Mass of all particles m_bed, e.g. 149g; needed for eta* (eq. 5).")
@click.option("--container-mass", type=Quantity("mass"), default=0.0,
              help="The container's own mass m_c (its m_c x'' is in the force), e.g. 80g; removed from "
                   "the bed's effective mass. Default 0.")
@click.option("--frequency", type=Quantity("frequency"),
              help="Drive frequency, e.g. 2Hz; detected from the motion if omitted.")
@click.option("--drop-cycles", type=int, default=DEFAULT_DROP_CYCLES, show_default=True,
              help="Whole cycles dropped at the start (the transient).")
@column_options
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units).")
@click.option("--plot", type=click.Path(dir_okay=False),
              help="Write a figure of the signals and per-cycle energies (.png, .svg, .pdf).")
@user_errors
def analyze_command(record, bed_mass, container_mass, frequency, drop_cycles, columns, motion, as_json, plot):
    """Energy dissipated per cycle and eta* of a force/motion RECORD (paper Sect. 4.1).

    RECORD is a text file (comma, semicolon or tab separated; a logger's preamble, a
    units row and decimal commas are read; '-' reads standard input), an HDF5, MATLAB
    or NI TDMS file, or a 'pdamper run --out' directory, with the columns (channels)
    time, force and one of position, velocity, acceleration; units are honoured, e.g.
    "time [ms]", "force [kN]", "accel [g]" (without a unit: SI). Time stamps with
    jitter, rounding or a dropped sample are analysed at their true times.

    Example: pdamper analyze run.csv --bed-mass 149g --plot run.png
    """
    if plot is not None:
        from ..plotting.analysis import FORMATS

        if not str(plot).lower().endswith(FORMATS):
            raise InputError(f"--plot {shown(plot)}: unknown format; use a file ending in "
                             f"{', '.join(FORMATS)}")

    rec = read_record(record, columns=columns, motion=motion)
    result = analyze_record(rec.time, rec.force, **{rec.motion_kind: rec.motion},
                            frequency=frequency, drop_cycles=drop_cycles, bed_mass=bed_mass,
                            container_mass=container_mass)

    if plot is not None:
        from ..plotting.analysis import plot_analysis

        plot_analysis(result, plot, title=f"{click.format_filename(record)}")

    steady = (not math.isfinite(result.cycle_energy_spread)
              or result.cycle_energy_spread <= STEADY_SPREAD)
    if as_json:
        out = {"version": __version__, "record": str(record), "columns": rec.headers,
               "samples": len(rec)}
        out.update(result.to_dict())
        out["steady"] = steady
        out["check_relative_difference"] = result.check_relative_difference
        out["plot"] = str(plot) if plot is not None else None
        echo_json(out)
        return
    click.echo(_table(record, rec, result))
    if not math.isfinite(result.eta_star):
        click.echo("\neta* not reported: give the bed mass, e.g. --bed-mass 149g.")
    if not steady:
        click.echo(f"\nnote: the energies of the used cycles spread by "
                   f"{100 * result.cycle_energy_spread:.0f} % (relative standard deviation, "
                   f"more than {100 * STEADY_SPREAD:.0f} %); the record may not be steady: drop "
                   "more cycles (--drop-cycles) or record longer.")
    if plot is not None:
        click.echo(f"\nplot written to {plot}")


def _table(path, rec, r) -> str:
    fs = r.sample_rate_hz
    rate = f"{fs / 1e3:.6g} kHz" if fs >= 1e3 else f"{fs:.6g} Hz"
    motion_note = {"velocity": "as measured",
                   "position": "V* = i Omega X*",
                   "acceleration": "V* = A* / (i Omega)"}[r.motion]
    p = r.complex_power_W
    rows = [
        ("record", str(path), f"{len(rec)} samples at {rate}"),
        ("columns", ", ".join(rec.headers.values()), f"motion: {r.motion}"),
        *([("time stamps", "not uniform: phasors at the true times (least squares)",
            f"jitter {100 * r.time_base.jitter:.2g} % of an interval, {r.time_base.gaps} gap(s), "
            f"longest interval {r.time_base.max_gap_s:.4g} s")]
          if r.time_base is not None and not r.time_base.uniform else []),
        ("drive frequency f", f"{r.frequency_hz:.7g} Hz",
         "detected from the motion" if r.frequency_detected else "given"),
        ("FFT window", f"{r.window_s[0]:.6g} s .. {r.window_s[1]:.6g} s",
         f"{r.cycles_used} whole cycles, first {r.cycles_dropped} dropped"
         + (", resampled to whole cycles" if r.resampled else "")),
        ("complex power P", f"{p.real:.6g} {'+' if p.imag >= 0 else '-'} {abs(p.imag):.6g}i W",
         "eq. (3), 1/2 F* conj(V*)"),
        ("force amplitude |F*|", f"{r.force_amplitude_N:.6g} N", ""),
        ("velocity amplitude |V*|", f"{r.velocity_amplitude_m_s:.6g} m/s", motion_note),
        ("energy per cycle E~_diss", f"{r.energy_per_cycle_J:.6g} J", "eq. (4), (2 pi/Omega) Re(P)"),
        ("mean-power check <F v> T", f"{r.mean_power_check_J:.6g} J", _check_note(r)),
        ("E_diss = E~_diss / 2 pi", f"{r.dissipated_energy_J:.6g} J", ""),
    ]
    if math.isfinite(r.eta_star):
        rows.append(("reduced loss factor eta*", f"{r.eta_star:.5g}",
                     f"eq. (5), m_bed = {r.bed_mass_kg * 1e3:.6g} g"))
    rows.append(("effective mass m_eff", f"{r.effective_mass_kg * 1e3:.6g} g",
                 "Im(P) / (1/2 Omega |V*|^2)"
                 + (f" - m_c, container m_c = {r.container_mass_kg * 1e3:.6g} g" if r.container_mass_kg
                    else ", container mass included (--container-mass)")))
    rows.append(("equivalent damping c_eq", f"{r.equivalent_damping_N_s_per_m:.6g} N s/m", "2 Re(P) / |V*|^2"))
    w0 = max(len(a) for a, _, _ in rows)
    w1 = max(len(b) for _, b, _ in rows)
    lines = [f"{a:<{w0}}  {b:<{w1}}  {c}".rstrip() for a, b, c in rows]
    lines += ["", "energy put in per cycle, int F v dt:",
              f"{'cycle':>5}  {'start [s]':>10}  {'energy [J]':>12}"]
    for k, (t0, e, used) in enumerate(zip(r.cycle_start_s, r.cycle_energies_J, r.cycle_used)):
        lines.append(f"{k + 1:>5}  {t0:>10.5g}  {e:>12.6g}" + ("" if used else "  dropped"))
    if math.isfinite(r.cycle_energy_spread):
        lines.append(f"spread of the used cycles: {100 * r.cycle_energy_spread:.2g} % "
                     "(relative standard deviation)")
    return "\n".join(lines)


def _check_note(r) -> str:
    diff = abs(r.mean_power_check_J - r.energy_per_cycle_J)
    if r.energy_per_cycle_J != 0.0 and diff <= abs(r.energy_per_cycle_J):
        return f"time domain; differs by {100 * diff / abs(r.energy_per_cycle_J):.2g} %"
    return (f"time domain; differs by {r.check_relative_difference:.2g} of the apparent "
            "energy pi |F*| |V*| / Omega")
