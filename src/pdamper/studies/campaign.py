"""A test campaign: many measured records (one per stroke, or per stroke and frequency) as one
η*(X[, f]) dataset, with the schema of a sweep's results so the two can be drawn and fitted together.

Each record is read as a logger writes it (:func:`pdamper.io.records.read_record`) and analysed by
the complex power method (:func:`pdamper.analysis.analyze_record`); its stroke is the amplitude of
the container motion at the drive frequency (|V*| / Omega) and its frequency the detected (or
given) drive frequency. A manifest ``campaign.toml`` beside the records may give the bed mass and,
per file, the stroke, the frequency and the columns::

    bed_mass = "149g"
    container_mass = "80g"      # optional: the container's own mass, removed from m_eff
    frequency = "2Hz"           # optional, for every record
    drop_cycles = 2

    [[record]]
    file = "x12.csv"
    stroke = "12mm"             # optional: else measured from the motion
    columns = { force = "F_x" } # optional channel map

Records whose strokes agree within 0.5 % (and frequencies within 0.5 %) are repeats of one point:
the dataset has dimensions ``stroke`` and ``seed`` (the repeat) like a sweep, plus ``frequency``
when the records were taken at more than one. The variables are the sweep's (``eta_star``,
``energy_per_cycle``, ``velocity_amplitude``, ``effective_mass``, ``equivalent_damping``; the
container mass removed is the attribute ``container_mass_kg``) plus ``eta_star_error`` (the standard error of eta*
from the spread of the used cycles' energies, corrected for their correlation (:mod:`pdamper.analysis.steady`): the error bar), ``cycles_used`` and ``file``.

A record that cannot be read or analysed is reported (its file and the reason) and the others go on.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .._deprecated import renamed_function
from ..errors import InputError, checked_file, shown, shown_path, unreadable_file

__all__ = ["MeasuredPoint", "analyze_records", "analyse_records", "campaign_dataset", "read_manifest", "MANIFEST"]

MANIFEST = "campaign.toml"
_SAME = 5e-3  # strokes/frequencies closer than this (relative) are repeats of one point
#: Files in a folder of records that are not records (configs, manifests, figures, results).
_NOT_RECORDS = (".toml", ".json", ".nc", ".png", ".svg", ".pdf", ".md", ".zip", ".py")


@dataclass(frozen=True)
class MeasuredPoint:
    """One analysed record of a campaign (SI units)."""

    file: str
    stroke_m: float
    frequency_hz: float
    eta_star: float
    eta_star_error: float
    energy_per_cycle_J: float
    velocity_amplitude_m_s: float
    cycles_used: int
    effective_mass_kg: float = math.nan
    equivalent_damping_N_s_per_m: float = math.nan

    def to_dict(self) -> dict:
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in self.__dict__.items()}


def read_manifest(path) -> dict:
    """The manifest ``path`` (see the module docstring) as ``{"bed_mass", "container_mass", "frequency",
    "drop_cycles", "records": {file name: {"stroke", "frequency", "columns"}}}`` in SI."""
    from ..units import parse_quantity

    from ..config import parse_toml

    path = checked_file(path, "campaign manifest")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeError) as exc:
        raise unreadable_file(path, exc, "campaign manifest") from None
    data = parse_toml(text, source=f"{shown_path(path)} (the campaign manifest)")
    allowed = ("bed_mass", "container_mass", "frequency", "drop_cycles", "record")
    for key in data:
        if key not in allowed:
            raise InputError(f"{path}: unknown key {shown(key)}; allowed: {', '.join(allowed)}")
    out = {"records": {}}
    if "bed_mass" in data:
        out["bed_mass"] = parse_quantity(data["bed_mass"], "mass", name=f"{path}: bed_mass")
    if "container_mass" in data:
        out["container_mass"] = parse_quantity(data["container_mass"], "mass", name=f"{path}: container_mass")
    if "frequency" in data:
        out["frequency"] = parse_quantity(data["frequency"], "frequency", name=f"{path}: frequency")
    if "drop_cycles" in data:
        if isinstance(data["drop_cycles"], bool) or not isinstance(data["drop_cycles"], int):
            raise InputError(f"{path}: drop_cycles = {shown(data['drop_cycles'])} must be a whole number")
        out["drop_cycles"] = data["drop_cycles"]
    for k, rec in enumerate(data.get("record", [])):
        where = f"{path}, record #{k + 1}"
        if not isinstance(rec, dict) or not isinstance(rec.get("file"), str):
            raise InputError(f"{where}: give file = 'name.csv'")
        for key in rec:
            if key not in ("file", "stroke", "frequency", "columns"):
                raise InputError(f"{where}: unknown key {shown(key)}; allowed: file, stroke, frequency, columns")
        entry = {}
        if "stroke" in rec:
            entry["stroke"] = parse_quantity(rec["stroke"], "length", name=f"{where}: stroke")
        if "frequency" in rec:
            entry["frequency"] = parse_quantity(rec["frequency"], "frequency", name=f"{where}: frequency")
        if "columns" in rec:
            if not isinstance(rec["columns"], dict):
                raise InputError(f"{where}: columns = {shown(rec['columns'])} must be a table such as {{ force = 'F_x' }}")
            entry["columns"] = {str(a): str(b) for a, b in rec["columns"].items()}
        out["records"][rec["file"]] = entry
    return out


def _expand(paths) -> list[Path]:
    """Files from the arguments: a directory stands for its records (not the manifest)."""
    out = []
    for p in map(Path, paths):
        try:
            folder = p.is_dir() and not (p / "signals.csv").exists()
        except (OSError, ValueError):  # a name the system refuses: the record reader names it
            folder = False
        if folder:
            out += sorted(q for q in p.iterdir() if q.is_file() and not q.name.startswith(".")
                          and q.suffix.lower() not in _NOT_RECORDS)
        else:
            out.append(p)
    return out


def analyze_records(paths, *, bed_mass=None, frequency=None, drop_cycles=None, columns=None, motion=None,
                    manifest=None, container_mass=None) -> tuple[list[MeasuredPoint], list[tuple[str, str]]]:
    """Analyse every record; returns (the points, the failures as ``(file, reason)``).

    ``manifest``: a manifest file; by default a ``campaign.toml`` beside the first record is read
    if there is one. Arguments given here win over the manifest's.
    ``container_mass``: the container's own mass [kg] (its ``m_c x''`` is in the force), removed
    from each record's effective mass; default the manifest's, else 0.
    """
    from ..analysis import DEFAULT_DROP_CYCLES, analyze_record
    from ..io.records import read_record

    files = _expand(paths)
    if not files:
        raise InputError("no record files given; give files or a folder of records")
    if manifest is None:
        near = files[0].parent / MANIFEST
        manifest = near if near.exists() else None
    man = read_manifest(manifest) if manifest is not None else {"records": {}}
    m_c = container_mass if container_mass is not None else man.get("container_mass", 0.0)
    if not (isinstance(m_c, (int, float)) and math.isfinite(m_c) and m_c >= 0):
        raise InputError(f"container mass = {shown(m_c)} kg; give the empty container's own mass, >= 0 (e.g. 80g), or 0")
    bed = bed_mass if bed_mass is not None else man.get("bed_mass")
    if bed is None:
        raise InputError("the bed mass is needed for eta*: give --bed-mass 149g (or bed_mass in campaign.toml)")
    drop = drop_cycles if drop_cycles is not None else man.get("drop_cycles", DEFAULT_DROP_CYCLES)
    points, failures = [], []
    for f in files:
        entry = man["records"].get(f.name, {})
        try:
            rec = read_record(f, columns={**entry.get("columns", {}), **(columns or {})}, motion=motion)
            freq = frequency if frequency is not None else entry.get("frequency", man.get("frequency"))
            r = analyze_record(rec.time, rec.force, **{rec.motion_kind: rec.motion}, frequency=freq,
                               drop_cycles=drop, bed_mass=bed, keep_signals=False, container_mass=m_c)
        except InputError as exc:
            failures.append((str(f), str(exc)))
            continue
        err = r.eta_star_error
        stroke = entry.get("stroke", r.velocity_amplitude_m_s / r.angular_frequency_rad_s)
        points.append(MeasuredPoint(file=str(f), stroke_m=float(stroke), frequency_hz=float(r.frequency_hz),
                                    eta_star=float(r.eta_star), eta_star_error=float(err),
                                    energy_per_cycle_J=float(r.energy_per_cycle_J),
                                    velocity_amplitude_m_s=float(r.velocity_amplitude_m_s),
                                    cycles_used=int(r.cycles_used), effective_mass_kg=float(r.effective_mass_kg),
                                    equivalent_damping_N_s_per_m=float(r.equivalent_damping_N_s_per_m)))
    return points, failures


analyse_records = renamed_function(analyze_records, "analyse_records")


def _groups(values) -> list[float]:
    """Representative values of clusters closer than _SAME (relative), sorted."""
    reps: list[list[float]] = []
    for v in sorted(values):
        if reps and abs(v - reps[-1][0]) <= _SAME * abs(reps[-1][0]):
            reps[-1].append(v)
        else:
            reps.append([v])
    return [float(np.mean(r)) for r in reps]


def campaign_dataset(points: list[MeasuredPoint], *, bed_mass: float, title: str = "test campaign",
                     history: str = "", container_mass: float = 0.0):
    """The points as a dataset with the schema of a sweep's results (module docstring);
    ``container_mass`` [kg]: the one removed from the effective masses (an attribute)."""
    import xarray as xr

    from .._version import __version__

    if not points:
        raise InputError("no record could be analysed; see the reasons above")
    strokes = _groups([p.stroke_m for p in points])
    freqs = _groups([p.frequency_hz for p in points])
    two_d = len(freqs) > 1

    def at(v, reps):
        return int(np.argmin([abs(v - r) for r in reps]))

    slots: dict[tuple, list[MeasuredPoint]] = {}
    for p in points:
        key = (at(p.stroke_m, strokes),) + ((at(p.frequency_hz, freqs),) if two_d else ())
        slots.setdefault(key, []).append(p)
    n_rep = max(len(v) for v in slots.values())
    shape = (len(strokes),) + ((len(freqs),) if two_d else ()) + (n_rep,)
    dims = ("stroke",) + (("frequency",) if two_d else ()) + ("seed",)
    names = {"eta_star": ("1", "reduced loss factor eta* (measured)"),
             "eta_star_error": ("1", "standard error of eta* from the spread of the used cycles"),
             "energy_per_cycle": ("J", "energy dissipated per cycle (complex power)"),
             "velocity_amplitude": ("m s-1", "container velocity amplitude at the drive frequency"),
             "cycles_used": ("1", "whole cycles analysed"),
             "effective_mass": ("kg", "effective mass of the bed, Im(P) / (1/2 Omega |V*|^2), "
                                      "the container's own mass (attribute container_mass_kg) removed"),
             "equivalent_damping": ("N s m-1", "equivalent viscous damping, 2 Re(P) / |V*|^2")}
    arrays = {k: np.full(shape, np.nan) for k in names}
    files = np.full(shape, "", dtype=object)
    for key, group in slots.items():
        for j, p in enumerate(group):
            idx = key + (j,)
            arrays["eta_star"][idx] = p.eta_star
            arrays["eta_star_error"][idx] = p.eta_star_error
            arrays["energy_per_cycle"][idx] = p.energy_per_cycle_J
            arrays["velocity_amplitude"][idx] = p.velocity_amplitude_m_s
            arrays["cycles_used"][idx] = p.cycles_used
            arrays["effective_mass"][idx] = p.effective_mass_kg
            arrays["equivalent_damping"][idx] = p.equivalent_damping_N_s_per_m
            files[idx] = p.file
    coords = {"stroke": ("stroke", np.array(strokes), {"units": "m", "long_name": "stroke X (measured)",
                                                       "config_key": "drive.stroke"}),
              "seed": ("seed", np.arange(n_rep), {"long_name": "repeat of the measurement"})}
    if two_d:
        coords["frequency"] = ("frequency", np.array(freqs), {"units": "Hz", "long_name": "drive frequency f",
                                                              "config_key": "drive.frequency"})
    ds = xr.Dataset({k: (dims, arrays[k], {"units": u, "long_name": d}) for k, (u, d) in names.items()}, coords=coords)
    ds["file"] = (dims, files.astype(str), {"long_name": "record file"})
    ds.attrs.update({"Conventions": "CF-1.10", "title": title, "source": "measured records",
                     "history": history or f"pdamper {__version__} campaign", "pdamper_version": __version__,
                     "bed_mass_kg": float(bed_mass), "container_mass_kg": float(container_mass), "kind": "campaign",
                     "frequency_hz": float(np.mean([p.frequency_hz for p in points]))})
    return ds
