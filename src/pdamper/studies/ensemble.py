"""Ensembles over the unknowns: a case at N Latin hypercube samples of a file of distributions
(:mod:`.unknowns`), run on any executor, stored case by case, summarised as what may happen.

- :class:`EnsembleSpec` -- the base case, the unknowns, N, the samples' seed and the study each
  sample runs (:data:`STUDIES`): ``"run"`` (the case as ``pdamper run`` runs it; with ``axes`` a
  sweep over them at every sample, on its rig), ``"transient"`` (the structure under its load in
  time with and without the damper, :func:`pdamper.studies.transient.run_transient`: peak and RMS
  ratios per dof) or ``"response"`` (the frequency response,
  :func:`pdamper.studies.structure.run_response`: the peak ratio per dof);
- :func:`run_ensemble` -- every sample not yet in the store at ``path`` run (local cores, a Dask
  ``scheduler``, or the GPU engine's batches for a bed on its rig with ``numerics.device =
  "cuda"``), each written the moment it finishes; returns the dataset: a ``sample`` dimension
  (and ``dof`` for the per-dof ratios, the sweep's axes for a sweep), the sampled values as data
  variables over ``sample``;
- :func:`summarize` -- percentiles 5/50/95 of eta*, the peak and RMS ratios per dof, the share of
  samples meeting a target with its Wilson interval, and which unknowns matter (Spearman):
  :mod:`pdamper.analysis.ensemble`.

**The store** (:class:`EnsembleStore`, a :class:`~pdamper.studies.store.ResultStore` of its own
format): ``store.json`` holds the base configuration, the unknowns, N, the seed, the study and its
options, and every sample's values; a sample's case file is keyed by its index and a digest of its
values (``sample0007-3f2a9c01be54``); killed with ``kill -9`` it resumes computing only the samples
not stored. Another configuration, other unknowns, another N or seed is refused with the first
difference named (a Latin hypercube of another N has other strata: it is another ensemble).

See docs/ensembles.md for the file, a worked example and its figures.
"""

from __future__ import annotations

import functools
import hashlib
import json
import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, shown
from ..params import Case
from .store import ResultStore, VARIABLES, _command_line, _first_difference, clear_unfinished, make_directories
from .unknowns import Samples, Unknown, Unknowns, key_kind, sample, sample_case, variable_name

__all__ = ["EnsembleSpec", "EnsembleStore", "run_ensemble", "open_ensemble", "summarize", "summary_lines", "damper_point",
           "Unknown", "Unknowns", "sample", "sample_case", "STUDIES", "FORMAT"]

FORMAT = "pdamper-ensemble-store/1"


# ----------------------------------------------------------------------------- the studies a sample runs

class _Timed:
    """Picklable ``case -> record`` of ``run`` (a one-sample function) with the CPU time [s] its
    process spent on the sample (``cpu_time_s``: beside the wall time, what a sample costs on a
    machine shared with other work)."""

    def __init__(self, run):
        self.run = run

    def __call__(self, case) -> dict:
        import time

        t0 = time.process_time()
        out = self.run(case)
        return {**out, "cpu_time_s": time.process_time() - t0}


def _one_run(case, until_steady=None):
    """A run study's sample: :func:`pdamper.studies.sweep.run_one` (no signals kept)."""
    from .sweep import run_one

    return run_one(case, keep="none", until_steady=until_steady, checked=True)


class _Transient:
    """Picklable ``case -> record`` of a transient sample (:func:`pdamper.studies.transient.run_transient`)."""

    def __init__(self, dofs):
        self.dofs = dofs

    def __call__(self, case) -> dict:
        from ..errors import SimulationError
        from .transient import run_transient

        try:
            s = run_transient(case, dofs=self.dofs).summary
        except SimulationError as exc:
            return {"failed": str(exc)}
        return {"peak_m": s["peak_m"], "rms_m": s["rms_m"], "peak_bare_m": s["peak_bare_m"],
                "rms_bare_m": s["rms_bare_m"], "peak_ratio": s["peak_reduction"], "rms_ratio": s["rms_reduction"],
                "damper_peak_ratio": s["damper_peak_reduction"], "damper_rms_ratio": s["damper_rms_reduction"],
                "energy_balance_error": s["energy_balance_error"], "steps": s["steps"],
                "wall_time_s": s["wall_time_s"]}


class _Response:
    """Picklable ``case -> record`` of a response sample (:func:`pdamper.studies.structure.run_response`
    over the frequencies, or each sample's own grid around its mode ``mode``)."""

    def __init__(self, dofs, frequencies, force_amplitude, measure_cycles, mode):
        self.dofs, self.frequencies, self.force = dofs, frequencies, force_amplitude
        self.measure_cycles, self.mode = measure_cycles, mode

    def __call__(self, case) -> dict:
        from ..errors import SimulationError
        from .structure import default_frequencies, run_response

        freqs = self.frequencies if self.frequencies is not None else default_frequencies(case, self.mode)
        force = self.force if self.force is not None else case.drive.force_amplitude
        try:
            s = run_response(case, freqs, force_amplitude=force, measure_cycles=self.measure_cycles, workers=1,
                             progress=False, dofs=self.dofs).summary
        except SimulationError as exc:
            return {"failed": str(exc)}
        if s["failed"]:
            return {"failed": "; ".join(f"{f} Hz: {m}" for f, m in s["failed"].items())}
        damped = np.max(np.asarray(s["response_amplitude_m"], dtype=float), axis=1)
        bare = np.max(np.asarray(s["response_amplitude_bare_m"], dtype=float), axis=1)
        ratio = (damped / bare).tolist()
        return {"peak_m": damped.tolist(), "peak_bare_m": bare.tolist(), "peak_ratio": ratio,
                # a steady sine's RMS is its amplitude over sqrt 2, with the damper and without: the same ratio
                "rms_ratio": ratio, "damper_peak_ratio": s["peak_reduction"],
                "peak_frequency_hz": s["peak_damped_frequency_hz"], "peak_steady": float(s["peak_steady"]),
                "energy_balance_error": s["energy_balance_error_max"], "wall_time_s": s["wall_time_s"]}


@dataclass(frozen=True)
class Study:
    """What a sample runs: ``variables`` ``{name: (record key, units, long name, per dof)}``, the
    one-sample function ``runner(spec)``, whether its cases may run on the GPU engine's batches
    (``batches``; a sweep's axes then too), ``analyze`` (its cases are checked as analysed by the
    complex power) and ``structure`` (it needs a structure and reports its dofs)."""

    name: str
    variables: dict
    runner: object
    batches: bool = False
    analyze: bool = False
    structure: bool = False


_RATIOS = {
    "peak": ("peak_m", "m", "peak displacement with the damper", True),
    "peak_bare": ("peak_bare_m", "m", "peak displacement without the damper (exact linear response)", True),
    "peak_ratio": ("peak_ratio", "1", "peak ratio, with / without the damper", True),
    "rms_ratio": ("rms_ratio", "1", "RMS ratio, with / without the damper", True),
    "damper_peak_ratio": ("damper_peak_ratio", "1", "peak ratio at the damper point", False),
    "energy_balance_error": ("energy_balance_error", "1", "energy ledger residual", False),
    "wall_time": ("wall_time_s", "s", "wall-clock time of the sample", False),
    "cpu_time": ("cpu_time_s", "s", "CPU time of the sample's process", False),
}

STUDIES = {
    "run": Study("run", {**{k: (*v, False) for k, v in VARIABLES.items()}, "cpu_time": _RATIOS["cpu_time"]},
                 lambda spec: functools.partial(_one_run, until_steady=spec.until_steady), batches=True, analyze=True),
    "transient": Study("transient", {
        **_RATIOS, "rms": ("rms_m", "m", "RMS displacement with the damper", True),
        "rms_bare": ("rms_bare_m", "m", "RMS displacement without the damper (exact linear response)", True),
        "damper_rms_ratio": ("damper_rms_ratio", "1", "RMS ratio at the damper point", False),
        "steps": ("steps", "1", "time steps taken", False)},
        lambda spec: _Transient(spec.dofs), structure=True),
    "response": Study("response", {
        **_RATIOS, "peak_frequency": ("peak_frequency_hz", "Hz", "frequency of the damper point's largest amplitude",
                                      False),
        "peak_steady": ("peak_steady", "1", "the damped peak is steady (1) or not (0)", False)},
        lambda spec: _Response(spec.dofs, spec.frequencies, spec.force_amplitude, spec.measure_cycles, spec.mode),
        structure=True),
}


def _digest(values: dict) -> str:
    """A short digest of a sample's values (its case key's second half): the values' JSON with every
    float's full repr."""
    text = json.dumps({k: (repr(v) if isinstance(v, float) else v) for k, v in values.items()}, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def sample_key(index: int, values: dict, prefix: str = "") -> str:
    """The case key of sample ``index`` with ``values`` (``prefix``: a sweep point's key)."""
    return f"{prefix}sample{int(index):04d}-{_digest(values)}"


@dataclass(frozen=True, kw_only=True)
class EnsembleSpec:
    """An ensemble: the ``base`` case at ``samples`` Latin hypercube samples (seeded by ``seed``) of
    ``unknowns`` (an :class:`~pdamper.studies.unknowns.Unknowns` or the path of its file), each
    running ``study`` (:data:`STUDIES`). A run study takes ``axes`` (a sweep over them at every
    sample, on the rig: :class:`~pdamper.studies.sweep.Axis`) and ``until_steady``; a transient or
    response study ``dofs`` (labels; None: every dof); a response study ``frequencies`` [Hz] (None:
    each sample's own grid around its mode ``mode``), ``force_amplitude`` [N] (None: the case's) and
    ``measure_cycles``. Every sample's case is made and checked when the spec is (an error names
    the sample and its values) and nothing has run."""

    base: Case
    unknowns: object
    samples: int
    seed: int = 0
    study: str = "run"
    axes: tuple = ()
    dofs: tuple | None = None
    frequencies: tuple | None = None
    force_amplitude: float | None = None
    measure_cycles: int = 8
    mode: int = 1
    until_steady: float | None = None

    def __post_init__(self):
        from ..plausible import check_case, check_memory

        u = self.unknowns
        if isinstance(u, (str, Path)):
            u = Unknowns.read(u)
        elif not isinstance(u, Unknowns):
            u = Unknowns(tuple(u))
        object.__setattr__(self, "unknowns", u)
        if self.study not in STUDIES:
            raise InputError(f"ensemble study {self.study!r}; choose one of {', '.join(map(repr, STUDIES))}")
        study = STUDIES[self.study]
        if self.axes and not study.batches:
            raise InputError(f"a {self.study} ensemble takes no sweep axes; a sweep's axes belong to a run ensemble")
        if self.dofs is not None:
            object.__setattr__(self, "dofs", tuple(self.dofs))
        if self.frequencies is not None:
            object.__setattr__(self, "frequencies", tuple(float(f) for f in np.atleast_1d(self.frequencies)))
        if study.structure:
            from .structure_base import select_dofs
            from .suite import is_suite

            if not self.base.drive.coupled:
                raise InputError(f"a {self.study} ensemble needs a structure ([structure] and its load); "
                                 "a damper on its rig takes a run ensemble (pdamper run --uncertain)")
            if is_suite(self.base):
                raise InputError("an ensemble over a suite of records: make the record an unknown instead, "
                                 "[[unknown]] key = \"load.file\", distribution = \"choice\", values = [the suite's "
                                 "files], and give [load] one file")
            labels, _ = select_dofs(self.base.running_drive, self.dofs)
            object.__setattr__(self, "_dofs", tuple(labels))
        else:
            object.__setattr__(self, "_dofs", ())
        drawn = sample(u, self.samples, self.seed)
        object.__setattr__(self, "_drawn", drawn)
        cases, grids, said = [], [], []
        for i, values in enumerate(drawn.points()):
            c = sample_case(self.base, values, label=f"sample {i}")
            if self.axes:
                from .sweep import SweepSpec

                grid = SweepSpec(base=c, axes=self.axes, seeds=(c.initial.seed,))
                said += [s for p in grid.points() for s in grid.cautions([p]) if s not in said]
                grids.append(grid)
            else:
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    check_case(c, analyze=study.analyze)
                check_memory(c)
                said += [(w.category, str(w.message)) for w in caught if (w.category, str(w.message)) not in said]
            cases.append(c)
        object.__setattr__(self, "_cases", tuple(cases))
        object.__setattr__(self, "_grids", tuple(grids))
        object.__setattr__(self, "_cautions", tuple(said))

    @property
    def drawn(self) -> Samples:
        """The samples (:class:`~pdamper.studies.unknowns.Samples`)."""
        return self._drawn

    @property
    def dof_labels(self) -> tuple:
        """The dofs a transient or response study reports (empty for a run study)."""
        return self._dofs

    def case(self, index: int) -> Case:
        """Sample ``index``'s case."""
        return self._cases[index]

    def cautions(self) -> tuple:
        """What the checks of the samples' cases warned of: (category, message), each once."""
        return self._cautions

    def items(self) -> list:
        """(key, point, seed, case) of every case: ``point`` is ``{"sample": i}`` (and the sweep
        point's keys)."""
        out = []
        for i, values in enumerate(self._drawn.points()):
            if self.axes:
                from .sweep import point_key

                grid = self._grids[i]
                s = grid.seeds[0]
                for p in grid.points():
                    out.append((sample_key(i, values, point_key(p, s).rsplit("_seed", 1)[0] + "_"),
                                {"sample": i, **p}, s, grid.case(p, s)))
            else:
                c = self._cases[i]
                out.append((sample_key(i, values), {"sample": i}, int(c.initial.seed), c))
        return out

    def describe(self) -> dict:
        """What the store keeps of the spec beside the base case (JSON)."""
        return {"study": self.study, "samples": int(self.samples), "seed": int(self.seed),
                "unknowns": self.unknowns.to_list(),
                "axes": [{"key": a.key, "values": list(a.values), "spacing": a.spacing} for a in self.axes],
                "dofs": list(self._dofs) if self.dofs is not None else None,
                "frequencies_hz": list(self.frequencies) if self.frequencies is not None else None,
                "force_amplitude_N": self.force_amplitude, "measure_cycles": int(self.measure_cycles),
                "mode": int(self.mode), "until_steady": self.until_steady,
                "sampling": "Latin hypercube (scipy.stats.qmc.LatinHypercube), inverse CDFs of scipy.stats"}


# ----------------------------------------------------------------------------- the store

def _number(v) -> bool:
    return v is None or isinstance(v, (int, float)) and not isinstance(v, bool)


def _ensemble_record(f: Path, variables: dict):
    """The sample record in file ``f`` (a dict), or why it is not one (a str)."""
    try:
        rec = json.loads(f.read_text())
    except (OSError, ValueError) as exc:
        return f"not readable JSON ({exc})"
    if not isinstance(rec, dict) or not isinstance(rec.get("point"), dict) \
            or not isinstance(rec["point"].get("sample"), int) or not isinstance(rec.get("values"), dict):
        return "no sample index and values of an ensemble's sample"
    if "failed" in rec:
        return rec
    for name, (key, _, _, per_dof) in variables.items():
        v = rec.get(key)
        if per_dof:
            if not isinstance(v, list) or not all(_number(x) for x in v):
                return f"{key} = {str(v)[:60]} is not a list of numbers"
        elif not _number(v) and not (key == "mode" and isinstance(v, str)):
            return f"{key} = {str(v)[:60]} is not a number"
    return rec


class EnsembleStore(ResultStore):
    """An ensemble's result directory (the module docstring): ``store.json`` and one file per
    finished sample (``cases/<key>.json``), ``results.nc`` and ``results.csv`` when it ends."""

    def __init__(self, path, meta: dict):
        super().__init__(path, {"axes": [], **meta})
        study = STUDIES.get(self.meta.get("ensemble", {}).get("study", "run"), STUDIES["run"])
        self.study = study
        self.record = functools.partial(_ensemble_record, variables=study.variables)

    @classmethod
    def create_or_open(cls, path, spec: EnsembleSpec, *, history: str | None = None, **_) -> "EnsembleStore":
        """Open the store at ``path`` for ``spec`` (creating it), refusing another ensemble."""
        from .._version import __version__
        from ..config import dumps_case
        from ..io.files import atomic_write, json_safe

        path = Path(path)
        text = dumps_case(spec.base, name="ensemble base")
        body = "\n".join(ln for ln in text.splitlines() if not ln.startswith("#"))
        described = json_safe(spec.describe())
        fp = hashlib.sha256((body + json.dumps(described, sort_keys=True)).encode()).hexdigest()
        meta_file = path / "store.json"
        old_history = []
        if meta_file.exists():
            try:
                old = json.loads(meta_file.read_text())
            except (OSError, ValueError) as exc:
                raise InputError(f"{meta_file}: not a readable pdamper result store ({exc}); use another --store") from None
            if old.get("format") != FORMAT:
                raise InputError(f"{path}: a result store of another kind (a sweep's?), not an ensemble's; use "
                                 "another --store")
            if old.get("fingerprint") != fp:
                raise InputError(f"{path}: this result store holds another ensemble "
                                 f"({_ensemble_difference(old, text, described)}); use another --store (a sweep's "
                                 "--out) or delete the store to start over")
            old_history = old.get("history", [])
        else:
            clear_unfinished(path)
            if path.exists() and (not path.is_dir() or any(path.iterdir())):
                raise InputError(f"{path}: exists and is not a pdamper ensemble store; choose another --store")
        make_directories(path)
        meta = {"format": FORMAT, "fingerprint": fp, "config": text, "pdamper_version": __version__,
                "ensemble": described, "axes": described["axes"], "seeds": [],
                "values": json_safe(spec.drawn.points()),
                "history": old_history + [f"pdamper {__version__}: {history or _command_line()}"]}
        store = cls(path, meta)
        with store._resumable("the store's description"):
            atomic_write(meta_file, json.dumps(meta, indent=2))
        return store

    @classmethod
    def open(cls, path) -> "EnsembleStore":
        """Open an existing ensemble store for reading (nothing is written)."""
        store = ResultStore.open(path)
        if store.meta.get("format") != FORMAT:
            raise InputError(f"{path}: a result store of another kind (a sweep's?), not an ensemble's")
        return cls(store.path, store.meta)

    def save_sample(self, key: str, point: dict, seed: int, result: dict) -> None:
        """Store one finished sample: its record with the sample's values."""
        values = self.meta["values"][point["sample"]]
        self.save(key, point, seed, {"values": values, **result})

    def dataset(self, records: list | None = None):
        """The stored samples as an ``xarray.Dataset`` (NaN where a sample has not finished): a
        ``sample`` dimension (and the sweep's axes; ``dof`` for the per-dof quantities), the
        sampled values as data variables over ``sample``. Writes nothing."""
        import xarray as xr

        from .._version import __version__
        from ..config import key_spec

        ens = self.meta["ensemble"]
        variables = self.study.variables
        n = int(ens["samples"])
        recs = self.records() if records is None else records
        axes = ens.get("axes", [])
        grid = [list(a["values"]) for a in axes]
        shape = tuple(len(v) for v in grid) + (n,)
        index = [{v: i for i, v in enumerate(vals)} for vals in grid]
        base = self.case()
        dof_labels = self._dof_labels(base)
        nd = len(dof_labels)
        data = {name: np.full(shape + ((nd,) if per else ()), np.nan)
                for name, (_, _, _, per) in variables.items()}
        failed = np.zeros(shape, dtype=np.int8)
        modes = np.full(shape, "", dtype=object)
        keys = np.full(shape, "", dtype=object)
        messages = np.full(shape, "", dtype=object)
        for r in recs:
            try:
                at = tuple(ix[r["point"][a["key"]]] for ix, a in zip(index, axes)) + (int(r["point"]["sample"]),)
                if at[-1] >= n:
                    continue
            except (KeyError, TypeError):
                continue
            keys[at] = r.get("key", "")
            if "failed" in r:
                failed[at] = 1
                modes[at] = "failed"
                messages[at] = str(r["failed"])[:300]
                continue
            modes[at] = str(r.get("mode") or "")
            for name, (key, _, _, per) in variables.items():
                v = r.get(key)
                if per:
                    data[name][at] = np.asarray([np.nan if x is None else x for x in (v or [np.nan] * nd)], float)
                else:
                    data[name][at] = np.nan if v is None else float(v)
        dims = tuple(a["key"].rsplit(".", 1)[-1] for a in axes) + ("sample",)
        coords = {"sample": ("sample", np.arange(n), {"long_name": "index of the Latin hypercube sample"})}
        for a, vals in zip(axes, grid):
            spec = key_spec(a["key"])
            kind = key_kind(a["key"])
            arr = np.array(vals, dtype=np.int64 if spec.kind == "whole" else float if spec.kind == "number" else str)
            coords[a["key"].rsplit(".", 1)[-1]] = (a["key"].rsplit(".", 1)[-1], arr,
                                                    {"config_key": a["key"], "units": kind.units,
                                                     "long_name": a["key"], "spacing": a.get("spacing", "list")})
        if nd:
            coords["dof"] = ("dof", np.array(dof_labels), {"long_name": "degree of freedom of the structure"})
        out = {}
        for name, (_, units, long_name, per) in variables.items():
            out[name] = (dims + (("dof",) if per else ()), data[name], {"units": units, "long_name": long_name})
        ds = xr.Dataset(out, coords=coords)
        ds["failed"] = (dims, failed, {"long_name": "1 where the sample failed numerically", "units": "1"})
        ds["failed_message"] = (dims, messages.astype(str), {"long_name": "why the sample failed"})
        if self.study.batches:
            ds["mode"] = (dims, modes.astype(str), {"long_name": "motion mode of the bed ('' not computed)"})
        ds["case_key"] = (dims, keys.astype(str), {"long_name": "key of the sample in the store's cases/ directory"})
        values = self.meta["values"]
        for u in ens["unknowns"]:
            kind = key_kind(u["key"])
            column = [v[u["key"]] for v in values]
            if kind.kind == "text":
                arr = np.array([Path(v).name if kind.file else str(v) for v in column], dtype=str)
            else:
                arr = np.array(column, dtype=np.int64 if kind.kind == "whole" else float)
            params = {k: v for k, v in u.items() if k not in ("key",)}
            ds[variable_name(u["key"])] = ("sample", arr, {
                "config_key": u["key"], "units": kind.units if kind.kind != "text" else "",
                "long_name": f"sampled {u['key']} ({u['distribution']})", "distribution": json.dumps(params),
                "role": "unknown"})
        ds.attrs.update({
            **self.provenance(f"pdamper {ens['study']} ensemble: {n} samples of {len(ens['unknowns'])} unknowns"),
            "pdamper_version": self.meta.get("pdamper_version", __version__),
            "study": ens["study"], "samples": n, "sampling_seed": int(ens["seed"]),
            "sampling": ens.get("sampling", "Latin hypercube"),
            "unknowns": json.dumps(ens["unknowns"]),
            "unknown_variables": " ".join(variable_name(u["key"]) for u in ens["unknowns"]),
            "particles": base.n_particles, "bed_mass_kg": float(base.bed_mass),
        })
        return ds

    def _dof_labels(self, base) -> list:
        ens = self.meta["ensemble"]
        if not self.study.structure:
            return []
        from .structure_base import select_dofs

        labels, _ = select_dofs(base.running_drive, ens.get("dofs"))
        return labels

    def write_outputs(self, ds) -> None:
        """Write ``results.nc`` and ``results.csv`` (one row per sample, the per-dof quantities one
        column per dof) atomically."""
        from ..io.files import atomic_write, write_dataset

        scalar = [v for v in ds.data_vars if "dof" not in ds[v].dims]
        table = ds[scalar].to_dataframe()
        for v in ds.data_vars:
            if "dof" in ds[v].dims:
                for k, d in enumerate(ds.dof.values):
                    table[f"{v}[{d}]"] = ds[v].isel(dof=k).values.ravel()
        table.columns = [f"{c} [{ds[c.split('[')[0]].attrs['units']}]" if ds[c.split('[')[0]].attrs.get("units")
                         not in (None, "", "1") else c for c in table.columns]
        with self._resumable("the results"):
            write_dataset(self.path / "results.nc", ds)
            atomic_write(self.path / "results.csv", table.to_csv(float_format=lambda v: repr(float(v))))


def _ensemble_difference(old: dict, text: str, described: dict) -> str:
    """Human words for the first thing two ensembles differ in."""
    from ..config import loads_case

    body = lambda t: [ln for ln in t.splitlines() if not ln.startswith("#")]  # noqa: E731
    if body(old.get("config", "")) != body(text):
        return _first_difference(old.get("config", ""), loads_case(text))
    was = old.get("ensemble", {})
    for k in ("study", "samples", "seed", "unknowns", "axes", "dofs", "frequencies_hz", "force_amplitude_N",
              "measure_cycles", "mode", "until_steady"):
        if was.get(k) != described.get(k):
            if k == "unknowns":
                return "other unknowns"
            if k == "samples":
                return (f"{was.get(k)} samples there, {described.get(k)} now: a Latin hypercube of another N has other "
                        "strata")
            return f"{k} = {shown(was.get(k))} there, {shown(described.get(k))} now"
    return "a setting differs"


# ----------------------------------------------------------------------------- running

def run_ensemble(base: Case, unknowns, n: int, path, *, seed: int = 0, study: str = "run", axes=(), dofs=None,
                 frequencies=None, force_amplitude: float | None = None, measure_cycles: int = 8, mode: int = 1,
                 until_steady: float | None = None, workers: int | None = None, scheduler: str | None = None,
                 progress: bool | None = None, history: str | None = None):
    """Run the ensemble of ``base`` over ``n`` samples of ``unknowns`` (an
    :class:`~pdamper.studies.unknowns.Unknowns` or the path of its file) seeded by ``seed``, each
    sample running ``study`` (:class:`EnsembleSpec` for the options); every sample not yet in the
    store at ``path`` runs (``workers`` local processes, default all cores, or the Dask cluster at
    ``scheduler``; a bed on its rig with ``numerics.device = "cuda"`` in the GPU engine's batches),
    each stored the moment it finishes. Returns the dataset (:meth:`EnsembleStore.dataset`): for a
    transient or response study ``peak_ratio`` and ``rms_ratio`` over (``sample``, ``dof``), for a
    run study ``eta_star`` over ``sample`` (and the axes), the sampled values over ``sample``.

    In a script, call it under ``if __name__ == "__main__":`` (the local cluster's processes
    import the script)."""
    from .sweep import run_cases_of

    spec = EnsembleSpec(base=base, unknowns=unknowns, samples=n, seed=seed, study=study, axes=tuple(axes),
                        dofs=dofs, frequencies=frequencies, force_amplitude=force_amplitude,
                        measure_cycles=measure_cycles, mode=mode, until_steady=until_steady)
    store = EnsembleStore.create_or_open(path, spec, history=history)
    for f, why in store.set_aside_bad():
        warnings.warn(f"{f}: not a sample record ({why}); set aside as {Path(f).name}.bad, the sample is computed "
                      "again", stacklevel=2)
    for category, message in spec.cautions():
        warnings.warn(message, category, stacklevel=2)
    items = spec.items()
    todo = [it for it in items if not store.has(it[0])]
    if todo:
        st = STUDIES[study]
        run = _Timed(st.runner(spec))
        kw = dict(workers=workers, scheduler=scheduler, progress=progress, total=len(items),
                  done=len(items) - len(todo))
        if st.batches:
            run_cases_of(todo, run, store.save_sample, keep="none", until_steady=until_steady, **kw)
        else:
            from ..run import on_gpu
            from .executor import execute

            if any(on_gpu(it[3]) for it in todo):
                raise InputError(f"the GPU engine runs beds on their rig; a {study} ensemble couples the bed to its "
                                 "structure and runs on the CPU: leave --device cuda out")
            execute(todo, run, store.save_sample, **kw)
    ds = store.dataset()
    store.write_outputs(ds)
    return ds


def open_ensemble(path):
    """An ensemble's dataset: ``path`` is its store or ``results.nc`` file (nothing written)."""
    p = Path(path)
    if p.is_dir():
        return EnsembleStore.open(p).dataset()
    if not p.exists():
        raise InputError(f"{p}: no such results file or ensemble store")
    import xarray as xr

    return xr.load_dataset(p, engine="h5netcdf")


# ----------------------------------------------------------------------------- what it says

def unknown_columns(ds) -> dict:
    """``{config key: values per sample}`` of the unknowns in an ensemble's dataset."""
    return {ds[v].attrs["config_key"]: ds[v].values.tolist() for v in ds.attrs.get("unknown_variables", "").split()
            if v in ds}


def _listed(ds) -> dict:
    """``{key: the listed values}`` of the unknowns that are choices (their order ranks them)."""
    out = {}
    for u in json.loads(ds.attrs.get("unknowns", "[]")):
        if u.get("distribution") == "choice":
            kind = key_kind(u["key"])
            out[u["key"]] = [Path(v).name if kind.file else v for v in u["values"]]
    return out


def damper_point(ds):
    """A transient ensemble's dataset ``ds`` judged at the damper point: its ``peak_ratio`` and
    ``rms_ratio`` those of the damper point (``damper_peak_ratio``, ``damper_rms_ratio``) over one
    dof labelled ``"damper"``, the other per-dof quantities left out (nothing recomputed), so that
    :func:`summarize` gives the damper point's percentiles, shares and ranking."""
    if "damper_rms_ratio" not in ds:
        raise InputError(f"a {ds.attrs.get('study', 'run')} ensemble has no damper point's peak and RMS ratios; "
                         "they belong to a transient ensemble")
    out = ds.drop_dims("dof") if "dof" in ds.dims else ds.copy()
    for q in ("peak_ratio", "rms_ratio"):
        v = ds[f"damper_{q}"]
        out[q] = v.expand_dims(dof=["damper"], axis=v.dims.index("sample") + 1).assign_attrs(v.attrs)
    out["dof"].attrs["long_name"] = "the damper point"
    return out


def summarize(ds, *, target_peak_ratio: float | None = None, target_rms_ratio: float | None = None,
              target_eta_star: float | None = None, confidence: float = 0.95) -> dict:
    """What an ensemble's dataset ``ds`` says (JSON-ready): ``samples``, ``finished``, ``failed``;
    ``eta_star``, ``peak_ratio``, ``rms_ratio`` each ``{"p05", "p50", "p95"}`` (lists per dof for the
    ratios, per sweep point for a sweep's eta*; None where the study has no such quantity); for each
    target given, the share of samples meeting it (every reported dof's ratio at most the target;
    eta* at least its target) with its Wilson interval, ``targets``; and ``ranking``: which
    unknowns matter for each quantity (Spearman, :func:`pdamper.analysis.ensemble.rank_importance`;
    a ratio by its largest over the dofs, a sweep's eta* by its best over the grid)."""
    from ..analysis.ensemble import percentiles, rank_importance, share_meeting

    n = int(ds.sizes["sample"])
    grid = [d for d in ds["failed"].dims if d != "sample"]
    finished = int((ds["case_key"] != "").all(grid).sum()) if grid else int((ds["case_key"] != "").sum())
    out = {"samples": n, "finished": finished, "failed": int(ds["failed"].any(grid).sum() if grid else
                                                              ds["failed"].sum()),
           "study": ds.attrs.get("study", "run"), "eta_star": None, "peak_ratio": None, "rms_ratio": None}
    inputs = unknown_columns(ds)
    order = _listed(ds)
    ranking, targets, decisive = {}, {}, {}
    if "dof" in ds.dims:
        out["dofs"] = ds.dof.values.tolist()
    for q in ("peak_ratio", "rms_ratio"):
        if q in ds:
            x = ds[q].transpose("sample", "dof").values
            out[q] = {k: v.tolist() for k, v in percentiles(x).items()}
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                worst = np.where(np.isfinite(x).all(axis=1), np.nanmax(x, axis=1), np.nan)
            decisive[q] = worst
            ranking[q] = rank_importance(inputs, worst, order=order)
    if "eta_star" in ds:
        eta = ds["eta_star"].transpose(*grid, "sample").values if grid else ds["eta_star"].values
        if grid:
            flat = eta.reshape(-1, n)
            out["eta_star"] = {k: v.tolist() for k, v in percentiles(flat, axis=1).items()}
            out["eta_star_points"] = [{d: ds[d].values[i].item() for d, i in zip(grid, idx)}
                                      for idx in np.ndindex(*eta.shape[:-1])]
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                best = np.nanmax(flat, axis=0)
        else:
            out["eta_star"] = {k: float(v) for k, v in percentiles(eta).items()}
            best = eta
        decisive["eta_star"] = best
        if np.isfinite(best).sum() >= 3:
            ranking["eta_star"] = rank_importance(inputs, best, order=order)
    for q, target in (("peak_ratio", target_peak_ratio), ("rms_ratio", target_rms_ratio)):
        if target is None:
            continue
        if q not in decisive:
            raise InputError(f"--target-{q.replace('_', '-')}: a {out['study']} ensemble has no {q}; targets on the "
                             "ratios belong to transient and response ensembles")
        targets[q] = share_meeting(decisive[q], target, confidence=confidence)
        x = ds[q].transpose("sample", "dof").values
        targets[q]["per_dof"] = [share_meeting(x[:, k], target, confidence=confidence)["share"]
                                 for k in range(x.shape[1])]
    if target_peak_ratio is not None and target_rms_ratio is not None:
        both = np.where((decisive["peak_ratio"] <= target_peak_ratio) & (decisive["rms_ratio"] <= target_rms_ratio),
                        0.0, 1.0)
        both[~(np.isfinite(decisive["peak_ratio"]) & np.isfinite(decisive["rms_ratio"]))] = np.nan
        targets["both"] = share_meeting(both, 0.5, confidence=confidence)
        targets["both"]["target"] = None
    if target_eta_star is not None:
        if "eta_star" not in decisive:
            raise InputError("--target-eta-star: this ensemble has no eta*")
        targets["eta_star"] = share_meeting(-decisive["eta_star"], -target_eta_star, confidence=confidence)
        targets["eta_star"]["target"] = float(target_eta_star)
    if "peak_steady" in ds:  # a response: the samples whose damped peak had not settled
        out["unsteady"] = int(((ds["peak_steady"] == 0) & (ds["failed"] == 0)).sum())
    out["targets"] = targets
    out["ranking"] = ranking
    out["unknowns"] = json.loads(ds.attrs.get("unknowns", "[]"))
    return out


def _pct(v) -> str:
    return "n/a" if v is None or (isinstance(v, float) and not math.isfinite(v)) else f"{v:.3g}"


def summary_lines(s: dict, *, top: int = 5) -> list:
    """The text of an ensemble's summary ``s`` (:func:`summarize`): percentiles, shares, ranking."""
    lines = [f"  ensemble              {s['samples']} samples (Latin hypercube) of {len(s['unknowns'])} unknowns, "
             f"{s['finished']} finished" + (f", {s['failed']} failed" if s["failed"] else "")]
    if s.get("eta_star") is not None:
        e = s["eta_star"]
        if isinstance(e["p50"], list):
            lines.append("  eta* over the samples at each point of the grid (percentiles 5, 50, 95):")
            for point, a, b, c in zip(s["eta_star_points"], e["p05"], e["p50"], e["p95"]):
                where = ", ".join(f"{k} {v * 1e3:.4g} mm" if k == "stroke" else f"{k} {v:.4g}"
                                  if isinstance(v, float) else f"{k} {v}" for k, v in point.items())
                lines.append(f"    {where:<30} p05 {_pct(a):>6}  p50 {_pct(b):>6}  p95 {_pct(c):>6}")
        else:
            lines.append(f"  eta*                  p05 {_pct(e['p05'])}  p50 {_pct(e['p50'])}  p95 {_pct(e['p95'])}")
    if s.get("peak_ratio") is not None:
        lines.append("  ratios with / without the damper over the samples (percentiles 5, 50, 95):")
        lines.append(f"  {'dof':>9}  {'peak p05':>8}  {'p50':>6}  {'p95':>6}  {'RMS p05':>8}  {'p50':>6}  {'p95':>6}")
        p, r = s["peak_ratio"], s["rms_ratio"] or {k: [None] * len(s["dofs"]) for k in ("p05", "p50", "p95")}
        for k, d in enumerate(s["dofs"]):
            lines.append(f"  {str(d):>9}  {_pct(p['p05'][k]):>8}  {_pct(p['p50'][k]):>6}  {_pct(p['p95'][k]):>6}  "
                         f"{_pct(r['p05'][k]):>8}  {_pct(r['p50'][k]):>6}  {_pct(r['p95'][k]):>6}")
    if s.get("unsteady"):
        lines.append(f"  not steady            the damped peak of {s['unsteady']} sample(s) had not settled by the end of "
                     "its run: give more --cycles")
    for q, t in s.get("targets", {}).items():
        words = {"peak_ratio": "peak ratio <= {:g}", "rms_ratio": "RMS ratio <= {:g}", "eta_star": "eta* >= {:g}"}
        what = words[q].format(t["target"]) if q in words else "both targets"
        label = f"meets {what}"
        lines.append(f"  {label:<21} {t['met']} of {t['samples']} samples: {100 * t['share']:.3g} % "
                     f"({100 * t['confidence']:.0f} % interval {100 * t['low']:.3g}-{100 * t['high']:.3g} %, Wilson)")
    for q, ranks in s.get("ranking", {}).items():
        shown = [f"{r['key']} {r['rho']:+.2f}" for r in ranks[:top] if math.isfinite(r["rho"])]
        if shown:
            lines.append(f"  what moves {q:<11}" + ", ".join(shown) + "  (Spearman rho)")
    return lines
