"""The result store of a sweep: a directory that never loses a finished case.

Layout of ``PATH/``:

- ``store.json`` -- what the store is for: the base configuration (TOML text, with the stroke
  and the seed left out since the sweep sets them), its fingerprint, the strokes and seeds
  asked for so far, the package version;
- ``cases/<key>.json`` -- one file per finished case (stroke, seed, its results and its motion
  mode with the measured features of :mod:`pdamper.analysis.modes`), each
  written atomically (temporary file, fsync, rename) the moment the case finishes, so
  Ctrl-C, ``kill -9`` or a power cut lose at most the cases that were running;
- ``results.nc`` -- the labelled dataset (netCDF via h5netcdf), rewritten after every run,
  and ``results.csv`` for spreadsheets.

The dataset's ``mode`` variable (text) holds each case's motion mode: one of
:data:`pdamper.analysis.modes.MODES`, ``"failed"`` for a numerically failed case, ``""`` for one
not computed yet and ``"unknown"`` for a case stored by a pdamper without mode classification (an
older store opens as before; re-run it into a new ``--out`` to get the modes).

Re-running the same sweep on the same ``PATH`` computes only the missing cases. A store made
with another configuration is refused with the first difference named, never mixed.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..io.files import atomic_write, json_safe

__all__ = ["ResultStore", "open_results", "VARIABLES", "NO_MODE", "UNKNOWN_MODE"]

#: ``mode`` of a case not computed yet, and of a case stored without a mode (an older store).
NO_MODE, UNKNOWN_MODE = "", "unknown"

#: Data variables of a sweep dataset: name -> (summary key, units, description).
VARIABLES = {
    "eta_star": ("eta_star", "1", "reduced loss factor eta*, eq. (5)"),
    "energy_per_cycle": ("energy_per_cycle_J", "J", "dissipated energy per cycle, complex power, eq. (4)"),
    "ledger_energy_per_cycle": ("ledger_dissipated_per_cycle_J", "J",
                                "dissipated energy per cycle from the energy ledger (cross-check)"),
    "energy_balance_error": ("energy_balance_error", "1", "largest energy-ledger residual / energy exchanged"),
    "velocity_amplitude": ("velocity_amplitude_m_s", "m/s", "|V*| of the container at the drive frequency"),
    "steps": ("steps", "1", "time steps taken"),
    "wall_time": ("wall_time_s", "s", "wall-clock time of the case"),
}


def _canonical(case):
    """The base case with the fields a sweep sets (stroke, seed) at fixed values."""
    from ..params import with_stroke

    c = with_stroke(case, 1.0)
    return dataclasses.replace(c, initial=dataclasses.replace(c.initial, seed=0))


def _flat(d, prefix=""):
    out = {}
    for k, v in d.items():
        key = f"{prefix}{k}"
        if isinstance(v, dict):
            out.update(_flat(v, key + "."))
        else:
            out[key] = v
    return out


class ResultStore:
    """A sweep's result directory (see the module docstring)."""

    def __init__(self, path, meta: dict):
        self.path = Path(path)
        self.meta = meta

    # ---------------------------------------------------------------- opening
    @classmethod
    def create_or_open(cls, path, spec) -> "ResultStore":
        """Open the store at ``path`` for ``spec`` (creating it), refusing another configuration."""
        from .. import __version__
        from ..config import case_to_dict, dumps_case

        path = Path(path)
        base = _canonical(spec.base)
        text = dumps_case(base, name="sweep base")
        body = "\n".join(line for line in text.splitlines() if not line.startswith("#"))
        fp = hashlib.sha256(body.encode()).hexdigest()
        meta_file = path / "store.json"
        if meta_file.exists():
            try:
                meta = json.loads(meta_file.read_text())
            except (OSError, ValueError) as exc:
                raise InputError(f"{meta_file}: not a readable pdamper result store ({exc}); use another --out") from None
            if meta.get("fingerprint") != fp:
                raise InputError(f"{path}: this result store was made with a different configuration "
                                 f"({_first_difference(meta.get('config', ''), base)}); use another --out "
                                 "or delete the store to start over")
            strokes = sorted(set(meta.get("strokes", [])) | set(spec.strokes))
            seeds = sorted(set(meta.get("seeds", [])) | set(spec.seeds))
        else:
            if path.exists() and (not path.is_dir() or any(path.iterdir())):
                raise InputError(f"{path}: exists and is not a pdamper result store; choose another --out")
            strokes, seeds = list(spec.strokes), list(spec.seeds)
        (path / "cases").mkdir(parents=True, exist_ok=True)
        meta = {"format": "pdamper-sweep-store/1", "fingerprint": fp, "config": text, "strokes": strokes,
                "seeds": seeds, "pdamper_version": __version__,
                "base": json_safe(case_to_dict(base))}
        atomic_write(meta_file, json.dumps(meta, indent=2))
        return cls(path, meta)

    @classmethod
    def open(cls, path) -> "ResultStore":
        """Open an existing store for reading."""
        path = Path(path)
        meta_file = path / "store.json"
        if not meta_file.exists():
            raise InputError(f"{path}: no pdamper result store here (no store.json); give the --out of a sweep")
        return cls(path, json.loads(meta_file.read_text()))

    # ---------------------------------------------------------------- cases
    def _case_file(self, key: str) -> Path:
        return self.path / "cases" / f"{key}.json"

    def has(self, key: str) -> bool:
        """True if the case ``key`` has finished and is stored."""
        return self._case_file(key).exists()

    def save(self, key: str, stroke: float, seed: int, summary: dict) -> None:
        """Store one finished case atomically."""
        rec = {"key": key, "stroke": float(stroke), "seed": int(seed), **summary}
        atomic_write(self._case_file(key), json.dumps(json_safe(rec)))

    def records(self) -> list:
        """All stored cases (dicts), in no particular order; unreadable files are skipped."""
        out = []
        for f in sorted((self.path / "cases").glob("*.json")):
            try:
                out.append(json.loads(f.read_text()))
            except (OSError, ValueError):
                continue
        return out

    # ---------------------------------------------------------------- dataset
    def case(self):
        """The base case of the store (stroke and seed at their canonical values)."""
        from ..config import loads_case

        return loads_case(self.meta["config"], source=str(self.path / "store.json"))

    def dataset(self):
        """The stored results as an ``xarray.Dataset`` with dims (stroke, seed); NaN where a case
        has not finished. Also rewrites ``results.nc`` and ``results.csv``."""
        import xarray as xr

        from .. import __version__
        from .. import theory
        from ..analysis.modes import case_clearance, floor_capacity

        recs = self.records()
        strokes = sorted(set(self.meta.get("strokes", [])) | {r["stroke"] for r in recs})
        seeds = sorted(set(self.meta.get("seeds", [])) | {r["seed"] for r in recs})
        ix = {x: i for i, x in enumerate(strokes)}
        js = {s: j for j, s in enumerate(seeds)}
        data = {name: np.full((len(strokes), len(seeds)), np.nan) for name in VARIABLES}
        failed = np.zeros((len(strokes), len(seeds)), dtype=bool)
        modes = np.full((len(strokes), len(seeds)), NO_MODE, dtype=object)
        for r in recs:
            i, j = ix[r["stroke"]], js[r["seed"]]
            if "failed" in r:
                failed[i, j] = True
                modes[i, j] = "failed"
                continue
            modes[i, j] = str(r.get("mode") or UNKNOWN_MODE)
            for name, (key, _, _) in VARIABLES.items():
                v = r.get(key)
                data[name][i, j] = np.nan if v is None else float(v)
        base = self.case()
        geo = base.container.geometry
        n_max = floor_capacity(base)
        n = base.n_particles
        _, h = case_clearance(base)
        ds = xr.Dataset(
            {name: (("stroke", "seed"), data[name], {"units": u, "long_name": d})
             for name, (_, u, d) in VARIABLES.items()},
            coords={"stroke": ("stroke", np.array(strokes), {"units": "m", "long_name": "stroke X"}),
                    "seed": ("seed", np.array(seeds, dtype=np.int64), {"long_name": "random seed of the initial jitter"})},
        )
        ds["failed"] = (("stroke", "seed"), failed.astype(np.int8), {"long_name": "1 where the case failed numerically"})
        ds["mode"] = (("stroke", "seed"), modes.astype(str), {
            "long_name": "motion mode of the bed (pdamper.analysis.modes; '' not computed, 'unknown' stored "
                         "without a mode)"})
        ds.attrs.update({
            "title": f"pdamper stroke sweep: {n} spheres in a {geo.shape}",
            "config": self.meta["config"],
            "pdamper_version": self.meta.get("pdamper_version", __version__),
            "shape": geo.shape,
            "particles": n,
            "max_particles": n_max,
            "clearance_m": h,
            "x_opt_m": float(theory.optimal_stroke(h)) if math.isfinite(h) and h > 0 else float("nan"),
            "frequency_hz": float(base.drive.frequency),
            "bed_mass_kg": float(base.bed_mass),
            "cycles": float(base.cycles),
            "drop_cycles": int(base.drop_cycles),
        })
        self._write_outputs(ds)
        return ds

    def _write_outputs(self, ds):
        import io

        buf = ds.to_netcdf(engine="h5netcdf")
        atomic_write(self.path / "results.nc", bytes(buf))
        out = io.StringIO()
        cols = ["stroke [m]", "seed"] + [f"{name} [{VARIABLES[name][1]}]" for name in VARIABLES] + ["failed", "mode"]
        out.write(",".join(cols) + "\n")
        for i, x in enumerate(ds.stroke.values):
            for j, s in enumerate(ds.seed.values):
                vals = [repr(float(x)), str(int(s))] + [repr(float(ds[name].values[i, j])) for name in VARIABLES]
                vals.append(str(int(ds["failed"].values[i, j])))
                vals.append(str(ds["mode"].values[i, j]))
                out.write(",".join(vals) + "\n")
        atomic_write(self.path / "results.csv", out.getvalue())


def _first_difference(old_text: str, new_case) -> str:
    """Human words for the first setting that differs between a stored config and a case."""
    from ..config import case_to_dict, loads_case

    try:
        old = _flat(case_to_dict(loads_case(old_text)))
    except Exception:  # an older or damaged store: say so instead of guessing
        return "its stored configuration cannot be read"
    new = _flat(case_to_dict(new_case))
    for k in sorted(set(old) | set(new)):
        if old.get(k) != new.get(k):
            return f"{k} = {old.get(k)!r} there, {new.get(k)!r} now"
    return "a setting differs"


def open_results(path):
    """The results of a sweep as an ``xarray.Dataset``: ``path`` is a store directory or a
    ``results.nc`` file."""
    import xarray as xr

    p = Path(path)
    if p.is_dir():
        return ResultStore.open(p).dataset()
    if not p.exists():
        raise InputError(f"{p}: no such results file or store directory")
    return xr.load_dataset(p, engine="h5netcdf")
