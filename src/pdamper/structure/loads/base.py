"""What every load on a structure shares: its config table, what it can do, and its function of
time as the kernels take it.

A load kind is one class registered with :func:`register_load` (a frozen, keyword-only
dataclass whose fields are the keys of its ``[load]`` table, declared with
:func:`pdamper.schema.param`). Nobody outside these modules asks which kind a load is; callers
ask what it can do:

=====================  ==========================================================================
``in_time``            a function of time the structure runs under (``pdamper transient``); False
                       for the harmonic force, which the structure carries as its own fields
``ground``             a ground acceleration: every dof loaded through the mass matrix, the
                       displacements relative to the ground; else a force at the force dof
``stationary``         a stationary random process: its PSD and the FRF estimate are reported
``stepped``            a stepped sine: a steady amplitude per frequency step (``response --sweep``)
``signal_role``        the column a file of it holds beside the time (``"force"``,
                       ``"acceleration"``), or None: no file
=====================  ==========================================================================

and what it answers:

=============================  ==================================================================
``from_config(table, ...)``    the load of a ``[load]`` table (a file read by the reader the
                               config passes in: :func:`pdamper.io.records.read_signal`)
``config_table()``             the table it is written as (the inverse; also for a case written
                               by ``pdamper design --write-case``)
``structure_keys()``           the ``[structure]`` keys it stands for (the harmonic force:
                               ``force_amplitude``, ``force_frequency``; any other: ``load``)
``duration``                   the time it lasts [s] (the run's length under it)
``kernel_table()``             ``(form, rows)``: its function of time for the kernels
                               (:mod:`pdamper.kernels.structure`, ``LOAD_LINEAR`` / ``LOAD_SINE``)
``values(t)``                  f(t) at times t [s] (the kernels' function, in numpy)
``modal_coefficients(s)``      b_k of each mode of the structure ``s``: its generalised force is
                               ``b_k f(t)`` (a force: phi_k(force); the ground: -L_k)
``records()``                  the loads of a suite of records, one transient each (a load of
                               ``files = [...]``); a load alone: itself
``for_structure(s)``           the load as the structure ``s`` runs it (a record scaled to a
                               spectral acceleration at the structure's first period); else itself
``describe()``                 one line for people
=============================  ==================================================================
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...errors import InputError, resolved, shown
from ...schema import OwnTable, param, read_fields, register_tagged, write_fields

__all__ = ["LoadBase", "SampledLoad", "SampledFields", "Record", "LOADS", "register_load", "FORM_LINEAR", "FORM_SINE",
           "linear_rows", "table_values", "RECORD_SUFFIXES"]

#: Registered load kinds by tag (``[load] kind``).
LOADS: dict[str, type] = {}

#: The kernels' forms of a load table (:data:`pdamper.kernels.structure.LOAD_LINEAR`, ``LOAD_SINE``;
#: the same numbers: this layer does not import the kernels).
FORM_LINEAR = 0
FORM_SINE = 1


def register_load(cls):
    """Class decorator: register a load class under its ``kind`` tag; a load registered at any time
    is read from config files from then on (the reader asks :data:`LOADS` each time)."""
    return register_tagged(LOADS, cls, "kind", "load",
                           needs=("from_config", "config_table", "structure_keys", "kernel_table",
                                  "modal_coefficients"))


def linear_rows(time, values) -> np.ndarray:
    """The kernels' rows of a piecewise-linear load through the samples (``time`` [s] from 0,
    ``values``): ``(t_j, f_j, s_j, 0)`` for each interval, then ``(t_end, 0, 0, 0)``: zero from the
    last sample on."""
    t = np.asarray(time, dtype=float)
    f = np.asarray(values, dtype=float)
    rows = np.zeros((t.size, 4))
    rows[:, 0] = t
    rows[:-1, 1] = f[:-1]
    rows[:-1, 2] = np.diff(f) / np.diff(t)
    return rows


def table_values(form: int, rows: np.ndarray, t) -> np.ndarray:
    """f(t) of a load table at times ``t`` [s] (the kernels' :func:`~pdamper.kernels.structure.load_value`
    in numpy): the last row with ``t_j <= t``, 0 before the first."""
    t = np.asarray(t, dtype=float)
    j = np.searchsorted(rows[:, 0], t, side="right") - 1
    jj = np.clip(j, 0, rows.shape[0] - 1)
    s = t - rows[jj, 0]
    if form == FORM_SINE:
        f = rows[jj, 1] * np.sin(rows[jj, 2] * s + rows[jj, 3])
    else:
        f = rows[jj, 1] + rows[jj, 2] * s
    return np.where(j >= 0, f, 0.0)


def _positive(value, label: str, unit: str, example: str, *, allow_none: bool = False) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (value > 0 and math.isfinite(value)):
        raise InputError(f"{label} = {shown(value)}{' ' + unit if unit else ''}; must be > 0, e.g. {example}")


class LoadBase(OwnTable):
    """The answers of the load protocol that most loads share (see the module docstring)."""

    config_section = "load"
    #: what it can do (module docstring)
    in_time = True
    ground = False
    stationary = False
    stepped = False
    signal_role: str | None = None
    #: config keys beyond the dataclass fields; the kind in words; keys a table must give
    config_extra_keys: tuple = ()
    config_label = ""
    config_required: tuple = ()
    config_hint = ""
    #: the keys that set its size (named where a load swings a structure too far)
    size_keys: tuple = ("scale",)

    # ---- reading and writing its own table (label, table_keys: schema.OwnTable)
    @classmethod
    def from_config(cls, table: dict, *, base_dir=None, read_signal=None):
        """The load of the ``[load]`` ``table`` (``base_dir`` resolves a file named in it,
        ``read_signal(path, role, column=...)`` reads it: :func:`pdamper.io.records.read_signal`);
        keys of no field of this kind are refused."""
        t = {k: v for k, v in table.items() if k != "kind"}
        foreign = [k for k in t if k not in cls.table_keys()]
        if foreign:
            raise InputError(f"[load] {', '.join(foreign)} does not apply to {cls.label()} (give "
                             f"{', '.join(cls.table_keys())})")
        kw = read_fields(t, "load", cls)
        kw.update(cls.config_read_extra(t, base_dir, read_signal))
        missing = [k for k in cls.config_required if k not in kw]
        if missing:
            raise InputError(f"[load] {cls.label()} needs {', '.join(repr(k) for k in missing)}: {cls.config_hint}")
        return cls(**kw)

    @classmethod
    def config_read_extra(cls, table: dict, base_dir, read_signal) -> dict:
        """Keyword arguments from the table's keys that are not plain fields; none by default."""
        return {}

    def config_table(self) -> dict:
        """The ``[load]`` table of this load, every quantity in plain SI (read back by
        :meth:`from_config`); a load read from a file is written with its file, not its samples."""
        return {**write_fields(self), **self.config_extra()}

    def config_extra(self) -> dict:
        """Config keys beyond the plain fields; none by default."""
        return {}

    def structure_keys(self) -> dict:
        """The ``[structure]`` keys this load stands for: the load itself (``load``)."""
        return {"load": self}

    # ---- its function of time
    @property
    def highest_frequency(self) -> float:
        """The highest frequency of the load's content that a time step must follow [Hz]; 0: the
        samples themselves (a step follows them wherever it is)."""
        return 0.0

    def values(self, t) -> np.ndarray:
        """f(t) at times ``t`` [s]: the function the kernels integrate (:meth:`kernel_table`)."""
        form, rows = self.kernel_table()
        return table_values(form, rows, t)

    def modal_coefficients(self, structure) -> np.ndarray:
        """b_k of each mode of ``structure`` (its modal arrays as it runs): a force at the
        structure's force point, ``b_k = phi_k(force)``."""
        return np.asarray(structure.modal_arrays()[4], dtype=float)

    def records(self) -> tuple:
        """The loads to run one transient each: a load alone is itself (a suite of records,
        :class:`SampledLoad` with ``files``, one load a record)."""
        return (self,)

    def for_structure(self, structure):
        """The load as ``structure`` runs it (the structure asks when it is made); itself unless
        it depends on the structure (a record scaled at the structure's first period)."""
        return self

    def describe(self) -> str:
        return self.label()


#: The suffixes of the files a folder of records (``[load] files = "folder"``) is read from.
RECORD_SUFFIXES = (".at2", ".csv", ".txt", ".dat", ".tsv", ".h5", ".hdf5", ".hdf", ".mat", ".tdms")


@dataclass(frozen=True)
class Record:
    """One record of a suite: its file's ``name`` (a path), the samples' ``time`` [s] and
    ``values`` (in SI, as the load's samples: N or m/s^2), unscaled."""

    name: str
    time: tuple
    values: tuple


@dataclass(frozen=True, kw_only=True)
class SampledFields:
    """The fields a sampled load has beside its samples (listed last among its bases, so they come
    first): the file it was read from (custom: written by :meth:`SampledLoad.config_table`), the
    samples' column there, their times, a scale and the run's length (key ``duration``)."""

    file: str | None = param(None, kind="custom")
    #: a suite of records (:class:`Record`, config ``files = [...]`` or a folder): one transient each
    files: tuple = param((), kind="custom")
    column: str | None = param(None, kind="custom")
    time: tuple = param((), kind="list", dimension="time")
    scale: float = 1.0
    duration_s: float | None = param(None, dimension="time", key="duration")


class SampledLoad(LoadBase):
    """A load given as samples in time (a file or inline lists): piecewise linear through them,
    zero after the last; ``scale`` multiplies them; ``duration`` is the run's length (default: the
    record's). A kind has the fields of :class:`SampledFields` and its samples (:attr:`samples_field`)."""

    #: the dataclass field holding the samples (``force``, ``acceleration``)
    samples_field = ""
    #: the unit of the samples for messages
    unit = ""

    def _check_samples(self) -> None:
        """Times strictly increasing from 0 (a record starting later is moved to 0), values finite,
        at least 2; ``scale`` finite, ``duration`` > 0."""
        name = self.samples_field
        self._check_files()
        t = np.asarray(self.time, dtype=float)
        f = np.asarray(getattr(self, name), dtype=float)
        where = f" (file {self.file})" if self.file else ""
        if t.ndim != 1 or t.size < 2 or f.shape != t.shape:
            raise InputError(f"load.{name}: need at least 2 times and as many values{where}, got {t.size} times and "
                             f"{f.size} values; give time = [...] and {name} = [...] or file = '...'")
        if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f))):
            raise InputError(f"load.{name}: time and {name} must be finite numbers (found NaN or inf){where}")
        if np.any(np.diff(t) <= 0):
            k = int(np.argmax(np.diff(t) <= 0))
            raise InputError(f"load.time: must increase strictly; it does not at sample {k + 1} (t = {shown(float(t[k + 1]))} s)"
                             f"{where}")
        object.__setattr__(self, "time", tuple((t - t[0]).tolist()))
        object.__setattr__(self, name, tuple(f.tolist()))
        sc = self.scale
        if isinstance(sc, bool) or not isinstance(sc, (int, float)) or not math.isfinite(sc):
            raise InputError(f"load.scale = {shown(sc)}; must be a finite number (1: the samples as given)")
        _positive(self.duration_s, "load.duration", "s", "'10s'", allow_none=True)

    def _check_files(self) -> None:
        """A suite (``files``): records of a name and samples, its own samples the first record's
        (as the config reads it; given only ``files``, taken from it); every record a load of this
        kind (checked as it is made, :meth:`records`)."""
        files = self.files
        if not files:
            object.__setattr__(self, "files", ())
            return
        if isinstance(files, (str, bytes)) or not isinstance(files, (tuple, list)) or not all(
                isinstance(r, Record) for r in files):
            raise InputError("load.files: give the records' files in a config ([load] files = ['a.AT2', 'b.AT2'] "
                             "or a folder), or Record(name, time, values) objects")
        object.__setattr__(self, "files", tuple(files))
        if self.file is not None:
            raise InputError("[load] give either file = '...' (one record) or files = [...] (a suite), not both")
        first = files[0]
        if not self.time:
            object.__setattr__(self, "time", tuple(first.time))
            object.__setattr__(self, self.samples_field, tuple(first.values))

    def records(self) -> tuple:
        """One load a record of the suite (``files``; each checked as a load of this kind, with
        this load's other keys: its scale, duration, target), in the suite's order; a load of one
        record: itself."""
        if not self.files:
            return (self,)
        import warnings

        from .record_check import RecordWarning

        out = []
        for rec in self.files:
            try:
                with warnings.catch_warnings():  # the suite said each record's check when it was read
                    warnings.simplefilter("ignore", RecordWarning)
                    out.append(dataclasses.replace(self, files=(), file=rec.name, time=tuple(rec.time),
                                                   **{self.samples_field: tuple(rec.values)}))
            except InputError as exc:
                raise InputError(f"[load] files: {Path(rec.name).name}: {exc}") from None
        return tuple(out)

    @classmethod
    def config_read_extra(cls, table: dict, base_dir, read_signal) -> dict:
        """``file = "hammer.csv"`` (relative to the config file) and ``column`` (the samples'
        column where the file names it otherwise): the file's columns, read by ``read_signal``;
        or ``files = ["a.AT2", "b.AT2"]`` (or a folder: its record files, by name) for a suite."""
        if "files" in table:
            return cls._read_files(table, base_dir, read_signal)
        if "column" in table and "file" not in table:
            raise InputError("[load] column names a column of a file; give file = '...' with it")
        if "file" not in table:
            return {}
        inline = [k for k in ("time", cls.samples_field) if k in table]
        if inline:
            raise InputError(f"[load] give either file = '...' or inline {', '.join(inline)}, not both")
        value = table["file"]
        if not isinstance(value, str) or not value.strip():
            raise InputError(f"[load] file = {shown(value)} must be the path of a file of time and {cls.samples_field}")
        column = table.get("column")
        if column is not None and (not isinstance(column, str) or not column.strip()):
            raise InputError(f"[load] column = {shown(column)} must be the name of the {cls.samples_field} column")
        path = resolved(value, base_dir)  # a name the system refuses: the reader says so
        if read_signal is None:
            raise InputError(f"[load] file = {shown(value)}: no reader given (read the case with pdamper.config)")
        try:
            sig = read_signal(path, cls.signal_role, column=column)
        except InputError as exc:
            raise InputError(f"[load] file: {exc}") from None
        return {"file": str(path), "column": column, "time": tuple(sig.time.tolist()),
                cls.samples_field: tuple(sig.values.tolist())}

    @classmethod
    def _read_files(cls, table: dict, base_dir, read_signal) -> dict:
        """The suite of ``files``: a list of paths or one folder (relative to the config file),
        each read by ``read_signal`` (:func:`pdamper.io.records.read_signal`)."""
        given = [k for k in ("file", "time", cls.samples_field) if k in table]
        if given:
            raise InputError(f"[load] give either files = [...] (a suite of records) or {', '.join(given)}, not both")
        value = table["files"]
        root = Path(base_dir if base_dir is not None else Path.cwd())
        if isinstance(value, str) and value.strip():
            from ...errors import checked_file, unreadable_file

            try:
                folder = checked_file(Path(value) if Path(value).is_absolute() else root / value, "folder of records",
                                      directory_ok=True,
                                      missing=f"[load] files = {shown(value)}: not a folder; give the records as a "
                                              "list, files = ['a.AT2', 'b.AT2'], or a folder of them")
                if not folder.is_dir():
                    raise InputError(f"[load] files = {shown(value)}: not a folder; give the records as a list, files = "
                                     "['a.AT2', 'b.AT2'], or a folder of them")
                paths = sorted(p for p in folder.iterdir() if p.is_file() and not p.name.startswith(".")
                               and p.suffix.lower() in RECORD_SUFFIXES)
            except OSError as exc:
                raise unreadable_file(folder, exc, "folder of records") from None
            except InputError as exc:
                raise InputError(str(exc) if str(exc).startswith("[load]") else f"[load] files: {exc}") from None
            if not paths:
                raise InputError(f"[load] files = {shown(value)}: the folder holds no record file "
                                 f"({', '.join(RECORD_SUFFIXES)})")
        elif isinstance(value, list) and value and all(isinstance(v, str) and v.strip() for v in value):
            paths = [Path(v) if Path(v).is_absolute() else root / v for v in value]
        else:
            raise InputError(f"[load] files = {shown(value)}: give a list of record files, e.g. files = ['a.AT2', "
                             "'b.AT2'], or a folder of them, files = 'records'")
        column = table.get("column")
        if column is not None and (not isinstance(column, str) or not column.strip()):
            raise InputError(f"[load] column = {shown(column)} must be the name of the {cls.samples_field} column")
        if read_signal is None:
            raise InputError("[load] files: no reader given (read the case with pdamper.config)")
        records = []
        for path in paths:
            try:
                sig = read_signal(path.resolve(), cls.signal_role, column=column)
            except InputError as exc:
                raise InputError(f"[load] files: {exc}") from None
            records.append(Record(name=str(path.resolve()), time=tuple(sig.time.tolist()),
                                  values=tuple(sig.values.tolist())))
        first = records[0]
        return {"files": tuple(records), "column": column, "time": first.time, cls.samples_field: first.values}

    def config_table(self) -> dict:
        """Its table: the file (and column) it was read from, else the inline samples."""
        out = write_fields(self)
        if self.files:
            out.pop("time", None)
            out.pop(self.samples_field, None)
            out["files"] = [r.name for r in self.files]
            if self.column:
                out["column"] = str(self.column)
            return out
        if self.file:
            out.pop("time", None)
            out.pop(self.samples_field, None)
            out["file"] = str(self.file)
            if self.column:
                out["column"] = str(self.column)
        return out

    @property
    def record_length(self) -> float:
        """The time from the first sample to the last [s]."""
        return float(self.time[-1])

    @property
    def duration(self) -> float:
        """The run's length [s]: ``duration`` where given, else the record's."""
        return float(self.duration_s) if self.duration_s is not None else self.record_length

    def kernel_table(self):
        """``(FORM_LINEAR, rows)``: piecewise linear through the scaled samples, zero after the last."""
        return FORM_LINEAR, linear_rows(self.time, np.asarray(getattr(self, self.samples_field)) * self.scale)

    def target_words(self) -> str:
        """What the scale was set to reach, in words ("scaled to PGA 0.3 g"); "" for a plain scale."""
        return ""

    def _source_words(self) -> str:
        if self.files:
            names = [Path(r.name).name for r in self.files]
            shown = ", ".join(names if len(names) <= 4 else names[:3] + ["..."])
            target = self.target_words()
            each = f", each {target}" if target else f", each x {self.scale:g}" if self.scale != 1.0 else ""
            return f"a suite of {len(names)} records ({shown}; pdamper transient runs each, a single run the first){each}"
        src = Path(self.file).name if self.file else "inline samples"
        scaled = f" x {self.scale:g}" if self.scale != 1.0 else ""
        return f"{src}{scaled}, {len(self.time)} samples over {self.record_length:.4g} s"
