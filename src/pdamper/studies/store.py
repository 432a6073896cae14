"""The result store of a sweep: a directory that never loses a finished case.

Layout of ``PATH/``:

- ``store.json`` -- what the store is for: the base configuration (TOML text, with the varied keys
  and the seed at canonical values), its fingerprint, the axes (config keys and their values) and
  seeds asked for so far, the package version, the theory's numbers for the base case;
- ``cases/<key>.json`` -- one file per finished case (its point on the grid, the seed, its results
  and its motion mode with the measured features of :mod:`pdamper.analysis.modes`), written
  atomically (temporary file, fsync, rename) the moment the case finishes, so Ctrl-C, ``kill -9``
  or a power cut lose at most the cases that were running;
- ``cases/<key>.signals.nc`` -- the case's recorded signals (1 kHz driving force, container
  motion, the energy ledger's dissipated energy; with ``keep="full"`` every ledger column),
  compressed netCDF written before the case's ``.json``, so :func:`pdamper.studies.reanalyze`
  can recompute eta* without simulating;
- ``results.nc`` (CF-style netCDF) and ``results.csv`` -- the labelled dataset, written by a
  sweep when it ends (:meth:`ResultStore.write_outputs`). Opening a store never writes.

The dataset's dimensions are the sweep's axes (``stroke``, ``frequency``, ``friction``, ...) and
``seed``. Its ``mode`` variable (text) holds each case's motion mode: one of
:data:`pdamper.analysis.modes.MODES`, ``"failed"`` for a numerically failed case, ``""`` for one
not computed yet and ``"unknown"`` for a case stored without mode classification.

Re-running the same sweep on the same ``PATH`` computes only the missing cases. A store made
with another configuration is refused with the first difference named, never mixed. A store of
an earlier pdamper (a stroke sweep, ``pdamper-sweep-store/1``) opens and resumes as before.

This module stores and reads; it computes no physics (the sweep passes the theory's numbers in).
"""

from __future__ import annotations

import contextlib
import dataclasses
import hashlib
import json
import math
import os
import sys
from pathlib import Path

import numpy as np

from ..errors import InputError, checked_file, shown
from ..io.files import atomic_write, json_safe, remove_stale_temporaries, write_dataset

__all__ = ["ResultStore", "VARIABLES", "NO_MODE", "UNKNOWN_MODE", "KEEP", "signal_arrays", "FORMAT"]

FORMAT = "pdamper-sweep-store/2"
_OLD_FORMAT = "pdamper-sweep-store/1"
STROKE = "drive.stroke"

#: ``mode`` of a case not computed yet, and of a case stored without a mode (an older store).
NO_MODE, UNKNOWN_MODE = "", "unknown"

#: What a sweep keeps of each case's signals: nothing; the signals (force, velocity, position at
#: the sample rate, and the ledger's dissipated energy: what re-analysis needs); or also every
#: ledger column.
KEEP = ("none", "signals", "full")

#: Data variables of a sweep dataset: name -> (summary key, units, long name).
VARIABLES = {
    "eta_star": ("eta_star", "1", "reduced loss factor eta*"),
    "energy_per_cycle": ("energy_per_cycle_J", "J", "energy dissipated per cycle (complex power)"),
    "ledger_energy_per_cycle": ("ledger_dissipated_per_cycle_J", "J",
                                "energy dissipated per cycle (energy ledger)"),
    "energy_balance_error": ("energy_balance_error", "1", "energy ledger residual relative to energy exchanged"),
    "velocity_amplitude": ("velocity_amplitude_m_s", "m s-1", "container velocity amplitude at the drive frequency"),
    "effective_mass": ("effective_mass_kg", "kg",
                       "effective mass of the bed, Im(P) / (1/2 Omega |V*|^2), the container's own mass removed"),
    "equivalent_damping": ("equivalent_damping_N_s_per_m", "N s m-1", "equivalent viscous damping, 2 Re(P) / |V*|^2"),
    "container_mass": ("container_mass_kg", "kg", "the container's own mass (not in effective_mass)"),
    "eta_star_error": ("eta_star_error", "1", "standard error of eta* over the analysed cycles"),
    "steady": ("steady", "1", "steady state reached over the analysed cycles (1) or not (0)"),
    "cycles_run": ("cycles_run", "1", "drive cycles simulated"),
    "steps": ("steps", "1", "time steps taken"),
    "wall_time": ("wall_time_s", "s", "wall-clock time of the case"),
}

#: Units of each dimension the config schema knows, written CF-style.
_CF_UNITS = {"length": "m", "time": "s", "frequency": "Hz", "mass": "kg", "angle": "rad", "force": "N",
             "velocity": "m s-1", "acceleration": "m s-2", "pressure": "Pa", "density": "kg m-3"}
_LONG_NAMES = {"drive.stroke": "stroke X", "drive.frequency": "drive frequency f", "contact.friction": "friction mu",
               "particles.count": "number of spheres N_p", "particles.radius": "sphere radius r",
               "contact.restitution": "coefficient of restitution"}


def signal_arrays(signals, energy, keep: str = "signals") -> dict:
    """The arrays of a run a store keeps (see :data:`KEEP`), as ``{name: 1-D array}``."""
    if keep not in KEEP:
        raise InputError(f"keep = {shown(keep)}; choose one of {', '.join(map(repr, KEEP))}")
    if keep == "none":
        return {}
    out = {"time": signals.time, "time_end": signals.time_end, "force": signals.force,
           "velocity": signals.velocity, "position": signals.position,
           "ledger_time": energy.time, "ledger_dissipated": energy.damping + energy.friction}
    if keep == "full":
        from ..recorders.energy import COLUMNS

        out.update({f"ledger_{c}": getattr(energy, c) for c in COLUMNS})
    return {k: np.ascontiguousarray(v, dtype=float) for k, v in out.items()}


_SIGNAL_ATTRS = {
    "time": ("s", "centre of the sample interval"), "time_end": ("s", "end of the sample interval"),
    "force": ("N", "driving force on the container along the drive, interval mean"),
    "velocity": ("m s-1", "container velocity along the drive, interval mean"),
    "position": ("m", "container position along the drive at the interval centre"),
    "ledger_time": ("s", "time of the energy ledger"),
    "ledger_dissipated": ("J", "energy dissipated so far (normal damping + friction)"),
}


def _canonical(spec):
    """The base case with the fields a sweep sets (its axes' keys, the seed) at fixed values: a
    stroke sweep at a stroke of 1 m (as pdamper-sweep-store/1 did, so those stores keep their
    fingerprint), any other grid at its first values."""
    from ..schema import replace

    keys = [a.key for a in spec.axes]
    point = {STROKE: 1.0} if keys == [STROKE] else {a.key: a.values[0] for a in spec.axes}
    return replace(spec.base, {**point, "initial.seed": 0})


def _fingerprint(text: str, keys) -> str:
    body = "\n".join(line for line in text.splitlines() if not line.startswith("#"))
    if list(keys) != [STROKE]:
        body += "\n# varied: " + ", ".join(keys)
    return hashlib.sha256(body.encode()).hexdigest()


def _flat(d, prefix=""):
    out = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flat(v, key + "."))
        else:
            out[key] = v
    return out


#: Two axis values closer than this (relative) are one value: a number typed on the command line is
#: read to 15 significant digits (:data:`pdamper.units.SIGNIFICANT_DIGITS`), so a stroke of a
#: log-spaced grid typed back from a table differs from the stored one in its last digits; no two
#: strokes a user means to differ are this close.
SAME_VALUE = 1e-13


def _is_number(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _known(v, old: list):
    """``v``, or the value of ``old`` that is the same number read to 15 digits (:data:`SAME_VALUE`)."""
    if _is_number(v):
        for o in old:
            if _is_number(o) and math.isclose(float(v), float(o), rel_tol=SAME_VALUE, abs_tol=0.0):
                return o
    return v


def _merge(old: list, new) -> list:
    """Values of an axis asked for so far: numbers sorted, text in the order first given; a new
    number that is an old one read to 15 digits is the old one (no near-duplicate points)."""
    new = [_known(v, list(old)) for v in new]
    vals = list(old) + [v for v in new if v not in old]
    if all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in vals):
        return sorted(set(vals))
    return vals



def _shortest(v) -> str:
    """A number as the CSV holds it: the shortest text that reads back to the same float
    (``repr`` of a numpy scalar says ``np.float64(...)`` under numpy 2)."""
    return repr(float(v))

class ResultStore:
    """A sweep's result directory (see the module docstring)."""

    #: ``record(file)``: the case record of a case file (a dict), or why it is not one (a str)
    record = staticmethod(lambda f: _valid_record(f))

    def __init__(self, path, meta: dict):
        self.path = Path(path)
        self.meta = _upgrade(meta)

    # ---------------------------------------------------------------- opening
    @classmethod
    def create_or_open(cls, path, spec, *, attrs: dict | None = None, history: str | None = None,
                       repair: bool = False, until_steady: float | None = None) -> "ResultStore":
        """Open the store at ``path`` for ``spec`` (creating it), refusing another configuration.

        ``attrs``: numbers the sweep computed for the base case (the theory's N_p,max, h, X_opt),
        kept in ``store.json`` and put on the dataset. ``until_steady``: the runs stop early at this
        error of eta* (:func:`pdamper.run.run_case`); a store's cases all share one setting, so
        another one is refused. ``history``: the command line. ``repair``:
        a store whose ``store.json`` was lost is rebuilt from ``spec`` and its case files (the
        cases are taken to be of this configuration: the caller vouches for it).
        """
        from .._version import __version__
        from ..config import case_to_dict, dumps_case

        path = Path(path)
        base = _canonical(spec)
        keys = [a.key for a in spec.axes]
        text = dumps_case(base, name="sweep base")
        fp = _fingerprint(text, keys)
        meta_file = path / "store.json"
        axes = [{"key": a.key, "values": list(a.values), "spacing": a.spacing} for a in spec.axes]
        seeds = list(spec.seeds)
        old_history = []
        if meta_file.exists():
            try:
                old = _upgrade(json.loads(meta_file.read_text()))
            except (OSError, ValueError) as exc:
                raise InputError(f"{meta_file}: not a readable pdamper result store ({exc}); use another --out") from None
            old_keys = [a["key"] for a in old["axes"]]
            if old_keys != keys:
                raise InputError(f"{path}: this result store varies {', '.join(old_keys)}, this sweep "
                                 f"{', '.join(keys)}; use another --out")
            if old.get("fingerprint") != fp:
                raise InputError(f"{path}: this result store was made with a different configuration "
                                 f"({_first_difference(old.get('config', ''), base)}); use another --out "
                                 "or delete the store to start over")
            if old.get("until_steady") != until_steady:
                def said(v):
                    return f"--until-steady {v:g}" if v is not None else "the full cycles (no --until-steady)"

                raise InputError(f"{path}: this result store's cases ran {said(old.get('until_steady'))}, this sweep "
                                 f"asks for {said(until_steady)}; use the same setting or another --out")
            for a, o in zip(axes, old["axes"]):
                a["values"] = _merge(o["values"], a["values"])
                if o.get("spacing") != a["spacing"]:
                    a["spacing"] = "list"
            seeds = sorted(set(old["seeds"]) | set(seeds))
            old_history = old.get("history", [])
            attrs = {**old.get("attrs", {}), **(attrs or {})}
        elif repair and (path / "cases").is_dir():
            found = cls(path, {"axes": axes, "seeds": seeds, "config": text}).records()
            for a in axes:
                a["values"] = _merge(a["values"], [r["point"][a["key"]] for r in found if a["key"] in r["point"]])
            seeds = sorted(set(seeds) | {int(r["seed"]) for r in found})
            old_history = [f"store.json rebuilt from {len(found)} case files ({_command_line()})"]
        else:
            clear_unfinished(path)
            if path.exists() and (not path.is_dir() or any(path.iterdir())):
                hint = (" It has case files but no store.json: re-run the same command with --repair to rebuild it"
                        if (path / "cases").is_dir() and any((path / "cases").glob("*.json")) else "")
                raise InputError(f"{path}: exists and is not a pdamper result store; choose another --out.{hint}")
        make_directories(path)
        meta = {"format": FORMAT, "fingerprint": fp, "config": text, "axes": axes, "seeds": seeds,
                "pdamper_version": __version__, "base": json_safe(case_to_dict(base)),
                "attrs": json_safe(attrs or {}),
                "history": old_history + [f"pdamper {__version__}: {history or _command_line()}"]}
        if until_steady is not None:
            meta["until_steady"] = float(until_steady)
        if keys == [STROKE]:  # readable by an earlier pdamper too
            meta["strokes"] = axes[0]["values"]
        store = cls(path, meta)
        with store._resumable("the store's description"):
            atomic_write(meta_file, json.dumps(meta, indent=2))
        return store

    def on_grid(self, spec):
        """``spec`` with each axis value that is a stored one read to 15 digits replaced by the stored
        value, so that its cases are the stored ones (no near-duplicate points; nothing re-checked)."""
        import copy

        stored = {a["key"]: a["values"] for a in self.axes}
        axes = tuple(dataclasses.replace(a, values=tuple(_known(v, stored.get(a.key, [])) for v in a.values))
                     for a in spec.axes)
        if axes == spec.axes:
            return spec
        out = copy.copy(spec)
        object.__setattr__(out, "axes", axes)
        object.__setattr__(out, "strokes", out.axis(STROKE).values if spec.strokes is not None else None)
        return out

    @classmethod
    def open(cls, path) -> "ResultStore":
        """Open an existing store for reading (nothing is written)."""
        path = checked_file(path, "result store", directory_ok=True,
                            missing="{path}: no pdamper result store here (no store.json); give the --out of a sweep")
        meta_file = path / "store.json"
        if not meta_file.exists():
            raise InputError(f"{path}: no pdamper result store here (no store.json); give the --out of a sweep")
        try:
            meta = json.loads(meta_file.read_text())
        except (OSError, ValueError) as exc:
            raise InputError(f"{meta_file}: not a readable pdamper result store ({exc})") from None
        return cls(path, meta)

    @property
    def axes(self) -> list[dict]:
        """The axes: ``[{"key", "values", "spacing"}, ...]``."""
        return self.meta["axes"]

    @property
    def dims(self) -> tuple[str, ...]:
        return tuple(a["key"].rsplit(".", 1)[-1] for a in self.axes) + ("seed",)

    # ---------------------------------------------------------------- cases
    def _case_file(self, key: str) -> Path:
        return self.path / "cases" / f"{key}.json"

    def _signals_file(self, key: str) -> Path:
        return self.path / "cases" / f"{key}.signals.nc"

    def has(self, key: str) -> bool:
        """True if the case ``key`` has finished and is stored."""
        return self._case_file(key).exists()

    def save(self, key: str, point, seed: int, summary: dict) -> None:
        """Store one finished case atomically: its signals first (if any), then its record."""
        summary = dict(summary)
        signals = summary.pop("signals", None)
        if not isinstance(point, dict):
            point = {STROKE: float(point)}
        rec = {"key": key, "point": point, "seed": int(seed), **summary}
        if STROKE in point:
            rec["stroke"] = float(point[STROKE])
        with self._resumable(f"case {key}"):
            if signals:
                named = {"case_key": key, "seed": int(seed), "point": json.dumps(json_safe(point))}
                if STROKE in point:
                    named["stroke_m"] = float(point[STROKE])
                atomic_write(self._signals_file(key), _signals_bytes(signals, named))
            atomic_write(self._case_file(key), json.dumps(json_safe(rec)))

    def records(self) -> list:
        """All stored cases (dicts), in no particular order; a file that is not a case record is
        skipped (:meth:`set_aside_bad` moves such files out of the way)."""
        out = []
        for f in sorted((self.path / "cases").glob("*.json")):
            rec = self.record(f)
            if isinstance(rec, dict):
                out.append(rec)
        return out

    def set_aside_bad(self) -> list[tuple[str, str]]:
        """Rename every case file that is not a valid case record to ``<name>.bad`` (so its case is
        computed again) and return ``(file, reason)`` of each."""
        bad = []
        for f in sorted((self.path / "cases").glob("*.json")):
            why = self.record(f)
            if isinstance(why, str):
                target = f.with_name(f.name + ".bad")
                k = 1
                while target.exists():
                    target = f.with_name(f"{f.name}.bad{k}")
                    k += 1
                f.rename(target)
                bad.append((str(f), why))
        return bad

    def signals(self, key: str):
        """The kept signals of case ``key`` as an ``xarray.Dataset`` (None if none were kept)."""
        from ..io.files import read_dataset

        f = self._signals_file(key)
        if not f.exists():
            return None
        return read_dataset(f, "a case's kept signals")

    # ---------------------------------------------------------------- dataset
    def case(self):
        """The base case of the store (the varied keys and the seed at their canonical values)."""
        from ..config import loads_case

        return loads_case(self.meta["config"], source=str(self.path / "store.json"))

    def dataset(self, records: list | None = None):
        """The stored results as an ``xarray.Dataset`` with one dimension per axis and ``seed``;
        NaN where a case has not finished. Writes nothing. ``records``: use these case records
        instead of the stored ones (e.g. re-analysed)."""
        import xarray as xr

        from .._version import __version__
        from ..config import key_spec

        recs = self.records() if records is None else records
        values = [list(a["values"]) for a in self.axes]
        for rec in recs:  # a case stored beyond the values asked for (e.g. by an older pdamper)
            for vals, a in zip(values, self.axes):
                v = rec["point"].get(a["key"])
                if v is not None and v not in vals:
                    vals.append(v)
        values = [_merge([], v) for v in values]
        seeds = sorted(set(self.meta["seeds"]) | {r["seed"] for r in recs})
        index = [{v: i for i, v in enumerate(vals)} for vals in values]
        shape = tuple(len(v) for v in values) + (len(seeds),)
        js = {s: j for j, s in enumerate(seeds)}
        data = {name: np.full(shape, np.nan) for name in VARIABLES}
        failed = np.zeros(shape, dtype=np.int8)
        modes = np.full(shape, NO_MODE, dtype=object)
        keys = np.full(shape, "", dtype=object)
        for r in recs:
            try:
                at = tuple(ix[r["point"][a["key"]]] for ix, a in zip(index, self.axes)) + (js[r["seed"]],)
            except KeyError:
                continue  # a record of another grid: not part of this store's dataset
            keys[at] = r.get("key", "")
            if "failed" in r:
                failed[at] = 1
                modes[at] = "failed"
                continue
            modes[at] = str(r.get("mode") or UNKNOWN_MODE)
            for name, (key, _, _) in VARIABLES.items():
                v = r.get(key)
                data[name][at] = np.nan if v is None else float(v)
        dims = self.dims
        coords = {}
        for a, vals in zip(self.axes, values):
            spec = key_spec(a["key"])
            attrs = {"long_name": _LONG_NAMES.get(a["key"], a["key"]), "config_key": a["key"],
                     "spacing": a.get("spacing", "list")}
            if spec.dimension in _CF_UNITS:
                attrs["units"] = _CF_UNITS[spec.dimension]
            elif spec.kind in ("number", "whole"):
                attrs["units"] = spec.unit.replace("/", " ") + "-1" if spec.unit and "/" in spec.unit else "1"
            arr = np.array(vals, dtype=np.int64 if spec.kind == "whole" else float if spec.kind == "number" else str)
            coords[a["key"].rsplit(".", 1)[-1]] = (a["key"].rsplit(".", 1)[-1], arr, attrs)
        coords["seed"] = ("seed", np.array(seeds, dtype=np.int64), {"long_name": "random seed of the initial jitter"})
        ds = xr.Dataset({name: (dims, data[name], {"units": u, "long_name": d}) for name, (_, u, d) in VARIABLES.items()},
                        coords=coords)
        ds["failed"] = (dims, failed, {"long_name": "1 where the case failed numerically", "units": "1"})
        ds["mode"] = (dims, modes.astype(str), {
            "long_name": "motion mode of the bed ('' not computed, 'unknown' stored without a mode)"})
        ds["case_key"] = (dims, keys.astype(str), {"long_name": "key of the case in the store's cases/ directory"})
        base = self.case()
        geo = base.container.geometry
        varied = ", ".join(a["key"] for a in self.axes)
        ds.attrs.update({
            **self.provenance(f"pdamper sweep over {varied}: {base.n_particles} spheres in a {geo.shape}"),
            "varied_keys": varied,
            "pdamper_version": self.meta.get("pdamper_version", __version__),
            "shape": geo.shape,
            "particles": base.n_particles,
            "frequency_hz": float(base.drive.frequency or float("nan")),
            "bed_mass_kg": float(base.bed_mass),
            "gravity_m_s2": float(base.gravity),
            "cycles": float(base.cycles),
            "drop_cycles": int(base.drop_cycles),
            # a number the JSON could not hold (NaN: no clearance law for this case) comes back None
            **{k: (float("nan") if v is None else v) for k, v in self.meta.get("attrs", {}).items()},
        })
        return ds

    def provenance(self, title: str) -> dict:
        """The dataset attributes that say where it comes from: CF conventions, ``title``, the
        source (pdamper's version), the history of commands and the configuration."""
        from .._version import __version__

        return {"Conventions": "CF-1.10", "title": title,
                "source": f"pdamper {self.meta.get('pdamper_version', __version__)} DEM simulation",
                "history": "\n".join(self.meta.get("history", [])), "config": self.meta["config"]}

    def write_outputs(self, ds) -> None:
        """Write ``results.nc`` (CF-style netCDF) and ``results.csv`` (one row per case) atomically."""
        table = ds[list(VARIABLES) + ["failed", "mode"]].to_dataframe()
        table.columns = [f"{c} [{ds[c].attrs['units']}]" if c in VARIABLES else c for c in table.columns]
        table.index.names = [f"{n} [{ds[n].attrs['units']}]" if "units" in ds[n].attrs else n
                             for n in table.index.names]
        with self._resumable("the results"):
            write_dataset(self.path / "results.nc", ds)
            atomic_write(self.path / "results.csv", table.to_csv(float_format=_shortest))

    @contextlib.contextmanager
    def _resumable(self, what: str):
        """A write that fails (a full disk, a read-only directory: InputError from atomic_write) says
        what the store still holds and how to go on."""
        try:
            yield
        except InputError as exc:
            try:
                n = sum(1 for _ in (self.path / "cases").glob("*.json"))
            except OSError:
                n = 0
            raise InputError(f"{exc}. Writing {what} failed; the result store {self.path} keeps its {n} finished "
                             "case(s), each written whole: once it can be written (space freed, or the store copied to a "
                             "writable place), re-run the same command on it to resume (nothing finished is computed "
                             "again)") from None


def clear_unfinished(path: Path) -> None:
    """What a store whose ``store.json`` could not be written (a full disk, ``kill -9``) left at
    ``path``: its temporary files and an empty ``cases/`` folder, removed."""
    if path.is_dir():
        remove_stale_temporaries(path)
        empty = path / "cases"
        if empty.is_dir() and not any(empty.iterdir()):
            empty.rmdir()


def make_directories(path: Path) -> None:
    """A store's folder and its ``cases/`` made, the temporary files of a writer killed between
    writing and renaming removed."""
    try:
        (path / "cases").mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create the result store {path}: {exc.strerror or exc}; give an --out where "
                         "you can write") from None
    for d in (path, path / "cases"):
        remove_stale_temporaries(d)


def _valid_record(f: Path):
    """The case record in file ``f`` (a dict), or why it is not one (a str)."""
    try:
        rec = json.loads(f.read_text())
    except (OSError, ValueError) as exc:
        return f"not readable JSON ({exc})"
    if not isinstance(rec, dict):
        return "not a JSON object"
    if "point" not in rec and "stroke" in rec:  # pdamper-sweep-store/1
        rec["point"] = {STROKE: rec["stroke"]}
    if not isinstance(rec.get("point"), dict) or not isinstance(rec.get("seed"), int):
        return "no point and seed of a case"
    if "failed" in rec:
        return rec
    for name, (key, _, _) in VARIABLES.items():
        v = rec.get(key)
        if v is not None and not isinstance(v, (int, float)):
            return f"{key} = {shown(v)} is not a number"
    if "eta_star" not in rec:
        return "no eta_star"
    return rec


def _upgrade(meta: dict) -> dict:
    """A ``store.json`` of any format as the current one reads it (in memory; nothing written)."""
    meta = dict(meta)
    if "axes" not in meta:
        if meta.get("format", _OLD_FORMAT) != _OLD_FORMAT or "strokes" not in meta:
            raise InputError(f"store.json: format {shown(meta.get('format'))} is not one this pdamper reads; "
                             "update pdamper or re-run the sweep into a new --out")
        meta["axes"] = [{"key": STROKE, "values": list(meta["strokes"]), "spacing": "list"}]
        meta.setdefault("attrs", {})
    meta.setdefault("seeds", [])
    return meta


def _signals_bytes(arrays: dict, attrs: dict | None = None) -> bytes:
    """The arrays as compressed netCDF (zlib with shuffle) in memory: the signals along the
    dimension ``time`` (the interval centres, its coordinate [s]), the ledger's along ``ledger_time``;
    ``attrs`` name the case (``case_key``, ``seed``, ``stroke_m``, ``point``: its axes' values as JSON).

    Written with h5netcdf directly, not xarray: the store writes while the sweep's Dask client is
    active, and xarray would then ask that client for a distributed write lock."""
    import io

    import h5netcdf

    n_ledger = len(arrays.get("ledger_time", ()))
    buf = io.BytesIO()
    with h5netcdf.File(buf, "w") as f:
        f.dimensions = {"time": len(arrays["time"]), "ledger_time": n_ledger}
        for k, v in arrays.items():
            dim = "ledger_time" if k.startswith("ledger_") else "time"
            var = f.create_variable(k, (dim,), data=v, compression="gzip", compression_opts=4, shuffle=True)
            units, long_name = _SIGNAL_ATTRS.get(k, ("J", k.replace("_", " ")))
            var.attrs["units"] = units
            var.attrs["long_name"] = long_name
        for k, v in (attrs or {}).items():
            f.attrs[k] = v
    return buf.getvalue()


def _command_line() -> str:
    return " ".join([os.path.basename(sys.argv[0])] + sys.argv[1:]) if sys.argv and sys.argv[0] else "python API"


def _first_difference(old_text: str, new_case) -> str:
    """Human words for the first setting that differs between a stored config and a case."""
    from ..config import case_to_dict, loads_case

    try:
        old = _flat(case_to_dict(loads_case(old_text)))
    except Exception:  # an older or damaged store: say so instead of guessing
        return "its stored configuration cannot be read"
    new = _flat(case_to_dict(new_case))

    absent = object()  # a key a config leaves out is at its default

    def said(d, k):
        return repr(d[k]) if k in d else "the default"

    for k in sorted(set(old) | set(new)):
        if old.get(k, absent) != new.get(k, absent):
            return f"{k} = {said(old, k)} there, {said(new, k)} now"
    return "a setting differs"
