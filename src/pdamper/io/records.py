"""Measured force/motion records as loggers write them: text files, HDF5, MATLAB, NI TDMS, and
pdamper's own run output.

A record has the columns (channels) ``time``, ``force`` and one motion channel, ``position``,
``velocity`` or ``acceleration``; other columns are ignored. Names match case-insensitively;
other names are mapped with ``columns`` (``{"force": "F_x"}``). Units are read with :mod:`pint`
through :func:`pdamper.units.unit_factor`, so any unit of the right dimension works (``ms``,
``kN``, ``mm``, ``lbf``, ``in``); for an acceleration ``g`` is the standard gravity (not the gram).
Everything is returned in SI as a :class:`Record`; every problem raises
:class:`pdamper.errors.InputError` naming the file, the line or channel, and the fix.

**Text files** (CSV, ``;`` or tab separated; ``-`` reads standard input):

- a logger's preamble before the header (``Device: NI-9234``, ``Rate: 1000 Hz`` ...) is skipped:
  the header is the first line naming the time and force columns; ``key: value`` preamble lines
  are kept in :attr:`Record.meta`;
- a unit may be in the header (``time [ms]``, ``force (kN)``) or in a second header row of units
  (``s;N;mm``); without one the column is SI;
- the delimiter is sniffed from the header; with ``;`` or tab a decimal comma (``0,25``) is read;
  quoted fields are read; blank lines and lines starting with ``#`` are skipped;
- the data are read by :func:`pandas.read_csv` (C parser): 5 million rows in a few seconds
  (docs/analysis.md); a cell that is not a number is reported with its line and column.

**Binary files** (by extension): HDF5 (``.h5``, ``.hdf5``; datasets found by name in any group,
units from a ``units`` attribute), MATLAB (``.mat``; variables by name), NI TDMS (``.tdms``;
channels by name, ``group/channel`` if ambiguous; the time from the waveform's increment when
there is no time channel; units from ``unit_string``).

**pdamper's own run output** (a ``pdamper run --out`` directory or its ``signals.csv``) is read
with its velocity (each sample the interval mean, what the run analysed).

**One signal in time** (:func:`read_signal`: a structure's load, :mod:`pdamper.structure.loads`):
the columns ``time`` and one other (``force``, ``acceleration``), from the same text and binary
files, or a PEER NGA strong-motion file (``.AT2``: a four-line header naming the units (``G``) and
``NPTS``, ``DT``, then the accelerations, several a line, separated by blanks or in fixed-width
fields that touch), returned as a :class:`Signal` in SI. COSMOS V2 / ``.V2A`` files are not read
(docs/structure.md says why and how to convert one).
"""

from __future__ import annotations

import csv
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError, checked_file, shown, shown_path, unreadable_file
from ..units import unit_factor

__all__ = ["Record", "read_record", "ROLES", "MOTIONS", "Signal", "read_signal", "read_at2", "SIGNAL_ROLES"]

#: The columns a record can have.
ROLES = ("time", "force", "position", "velocity", "acceleration")
#: The motion columns, of which a record uses exactly one.
MOTIONS = ("position", "velocity", "acceleration")
#: The signals :func:`read_signal` reads beside the time.
SIGNAL_ROLES = ("force", "acceleration")
_DIMENSION = {"time": "time", "force": "force", "position": "length",
              "velocity": "velocity", "acceleration": "acceleration"}
_UNIT_EXAMPLES = {"time": "s, ms", "force": "N, kN", "length": "m, mm",
                  "velocity": "m/s, mm/s", "acceleration": "m/s^2, mm/s^2"}
_HEADER = re.compile(r"^(?P<name>.*?)\s*(?:\[(?P<u1>[^\]]*)\]|\((?P<u2>[^)]*)\))\s*$")


@dataclass(frozen=True, kw_only=True, eq=False)
class Record:
    """A force/motion record in SI units, with exactly one motion signal.

    Attributes
    ----------
    time : numpy.ndarray
        Sample times [s].
    force : numpy.ndarray
        Driving force on the container [N].
    position, velocity, acceleration : numpy.ndarray or None
        The container motion [m], [m/s] or [m/s^2]; exactly one is set.
    source : str or None
        Where the record came from (the file path).
    headers : dict
        The file's header text of each column used, by role (for messages and plots).
    meta : dict
        ``key: value`` lines of a logger's preamble, if any.
    """

    time: np.ndarray
    force: np.ndarray
    position: np.ndarray | None = None
    velocity: np.ndarray | None = None
    acceleration: np.ndarray | None = None
    source: str | None = None
    headers: dict = field(default_factory=dict)
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        given = [m for m in MOTIONS if getattr(self, m) is not None]
        if len(given) != 1:
            raise InputError("a record needs exactly one motion signal (position, velocity "
                             f"or acceleration); got {', '.join(given) or 'none'}")

    @property
    def motion_kind(self) -> str:
        """Which motion signal the record carries: ``"position"``, ``"velocity"`` or ``"acceleration"``."""
        return next(m for m in MOTIONS if getattr(self, m) is not None)

    @property
    def motion(self) -> np.ndarray:
        """The motion samples in SI ([m], [m/s] or [m/s^2], see :attr:`motion_kind`)."""
        return getattr(self, self.motion_kind)

    def __len__(self) -> int:
        return int(self.time.size)


def read_record(path, *, columns: dict | None = None, motion: str | None = None,
                delimiter: str | None = None, decimal: str | None = None) -> Record:
    """Read a measured record (time, force, one motion channel) from a file (see the module docstring).

    Parameters
    ----------
    path : str or os.PathLike
        The file (text, ``.h5``/``.hdf5``, ``.mat``, ``.tdms``), a ``pdamper run --out`` directory,
        or ``"-"`` for text on standard input.
    columns : dict, optional
        Map of role (``"time"``, ``"force"``, ``"position"``, ``"velocity"``,
        ``"acceleration"``) to the column's (channel's) name in the file, e.g.
        ``{"time": "t", "force": "F_x"}``. The name is matched without its unit
        (``"F_x"`` finds ``F_x [kN]``) or as the full header text.
    motion : str, optional
        Which motion column to use when the file has several. Mapping exactly one
        motion role in ``columns`` chooses it too.
    delimiter, decimal : str, optional
        Column delimiter and decimal mark of a text file; detected if omitted.

    Returns
    -------
    Record
        All signals converted to SI.

    Raises
    ------
    InputError
        Missing file or column, ambiguous motion, unknown unit, unreadable or
        non-finite cell (with line and column), empty file.
    """
    columns = dict(columns or {})
    for role in columns:
        if role not in ROLES:
            raise InputError(f"unknown column role {shown(role)}; use one of {', '.join(ROLES)}")
    if motion is not None and motion not in MOTIONS:
        raise InputError(f"motion must be one of {', '.join(MOTIONS)}; got {shown(motion)}")
    mapped_motions = [m for m in MOTIONS if m in columns]
    if motion is not None and mapped_motions and mapped_motions != [motion]:
        raise InputError(f"motion={shown(motion)} but the column map names "
                         f"{', '.join(mapped_motions)}; choose one motion column")
    if motion is None and len(mapped_motions) > 1:
        raise InputError(f"the column map names several motion columns "
                         f"({', '.join(mapped_motions)}); choose one")
    if str(path) == "-":
        import sys

        return _read_text(_lines_of(sys.stdin.read()), "<stdin>", columns, motion, delimiter, decimal, None)
    path = checked_file(path, "record file", directory_ok=True)
    if path.is_dir():
        if not (path / "signals.csv").exists():
            raise InputError(f"{shown_path(path)} is a directory without a run's signals.csv; give the record file")
        path = path / "signals.csv"
    suffix = path.suffix.lower()
    if suffix in (".h5", ".hdf5", ".hdf"):
        return _read_channels(path, _hdf5_channels(path), columns, motion)
    if suffix == ".mat":
        return _read_channels(path, _mat_channels(path), columns, motion)
    if suffix == ".tdms":
        return _read_channels(path, _tdms_channels(path), columns, motion)
    return _read_text(_read_lines(path, head=600), shown_path(path), columns, motion, delimiter, decimal, path)


#: The header of a pdamper run's signals.csv: read with its velocity (the analysed signal).
_RUN_HEADER = ["time [s]", "force [N]", "velocity [m/s]", "position [m]"]


def _choose(source, header, names, columns, motion) -> dict:
    """Role -> index of the column used, from the header texts and names (without units)."""
    mapped_motions = [m for m in MOTIONS if m in columns]

    def find(role: str, required: bool) -> int | None:
        target = columns.get(role, role)
        key = target.strip().casefold()
        hits = [i for i, (h, n) in enumerate(zip(header, names))
                if n.casefold() == key or h.casefold() == key]
        if len(hits) > 1:
            raise InputError(f"{source}: {len(hits)} columns match {role} ({shown(target)}): "
                             f"{', '.join(_short(header[i]) for i in hits)}; rename one or "
                             f"map {role} to the full header text")
        if not hits:
            if required:
                hint = (f"map it with --{role}-column NAME (columns={{'{role}': NAME}})")
                raise InputError(f"{source}: no {role} column ({shown(target)}); the header has "
                                 f"{', '.join(_short(h) for h in header)}; rename the column or {hint}")
            return None
        return hits[0]

    used = {"time": find("time", True), "force": find("force", True)}
    chosen = motion or (mapped_motions[0] if mapped_motions else None)
    if chosen is None and [h.strip() for h in header] == _RUN_HEADER:
        chosen = "velocity"  # pdamper's own run output: the signal its analysis used
    if chosen is not None:
        used[chosen] = find(chosen, True)
        return used
    present = {m: i for m in MOTIONS if (i := find(m, False)) is not None}
    if not present:
        raise InputError(
            f"{source}: no motion column; need one of position, velocity, acceleration "
            f"(the header has {', '.join(_short(h) for h in header)}); rename it or map it "
            "with --position-column/--velocity-column/--acceleration-column NAME")
    if len(present) > 1:
        listing = " and ".join(_short(header[i]) for i in present.values())
        first = next(iter(present))
        raise InputError(
            f"{source}: the record has {len(present)} motion columns, {listing}; choose the "
            f"one to use, e.g. --{first}-column {shlex.quote(names[present[first]])} "
            f"(motion={shown(first)})")
    used.update(present)
    return used


def _lines_of(text: str) -> list[tuple[int, str]]:
    return list(enumerate(text.lstrip("\ufeff").splitlines(), start=1))


def _fields(line: str, delimiter: str) -> list[str]:
    try:
        return next(csv.reader([line], delimiter=delimiter), [])
    except csv.Error:  # a field over the csv module's limit (128 kB): a binary dump pasted into the file
        return line.split(delimiter)


def _short(text: str, limit: int = 60) -> str:
    """``repr(text)``, cut to ``limit`` characters with its length said (a message never quotes a 100 kB cell)."""
    return shown(text, limit)


def _written(text: str) -> str:
    """A number's text as the file writes it (``-.0050``), quoted and cut only when it is long."""
    return text if len(text) <= 30 else _short(text)


def _is_number(cell: str, decimal: str = ".") -> bool:
    cell = cell.strip()
    if decimal == ",":
        cell = cell.replace(",", ".")
    try:
        float(cell)
    except ValueError:
        return False
    return True


def _find_header(source, content, columns, roles=("time", "force")):
    """(position in content, delimiter) of the header: the first line naming the ``roles`` (time
    and force)."""
    wanted = [columns.get(r, r).strip().casefold() for r in roles]
    for pos, (no, line) in enumerate(content[:500]):
        for d in (",", ";", "\t"):
            if d not in line:
                continue
            cells = [c.strip() for c in _fields(line, d)]
            names = {_split_header(c)[0].casefold() for c in cells} | {c.casefold() for c in cells}
            if all(w in names for w in wanted):
                return pos, d
    # no line names both: the first line with a delimiter that is not data is the header, and the
    # missing column is named from it
    for pos, (no, line) in enumerate(content[:500]):
        counts = {d: line.count(d) for d in (",", ";", "\t")}
        d = max(counts, key=counts.get)
        if counts[d] and not all(_is_number(c, ",") for c in _fields(line, d)):
            return pos, d
    no, header = content[0]
    raise InputError(
        f"{source}, line {no}: cannot find the column delimiter in the header {_short(header.strip())}; "
        "separate the columns with commas, semicolons or tabs")


def _read_text(lines, source, columns, motion, delimiter, decimal, path) -> Record:
    """A record from text: ``lines`` are the first lines of the file (all of it for standard
    input); the data are read by pandas from ``path`` (or from the lines) after the header."""
    content = [(no, line) for no, line in lines if line.strip() and not line.lstrip().startswith("#")]
    if not content:
        raise InputError(f"{source}: the file is empty; expected a header row "
                         "(time, force, position|velocity|acceleration) and data rows")
    if delimiter is None:
        pos, delimiter = _find_header(source, content, columns)
    else:
        pos = next((k for k, (_, ln) in enumerate(content) if delimiter in ln), 0)
    meta = {}
    for _, line in content[:pos]:  # a logger's preamble: keep its "key: value" lines
        key, sep, value = line.partition(":")
        if sep and key.strip():
            meta[key.strip()] = value.strip()
    header, names, units, data, last_header = _header(content, pos, delimiter)
    used = _choose(source, header, names, columns, motion)
    if not data:
        raise InputError(f"{source}: the file has a header but no data rows")
    if decimal is None:
        sample = [c for _, ln in data[:50] for c in _fields(ln, delimiter)]
        decimal = "," if delimiter != "," and any("," in c for c in sample) else "."
    values = _parse_columns(source, lines, last_header, header, used, delimiter, decimal, path)
    for role, i in used.items():
        if units[i]:
            values[role] = values[role] * _factor(source, header[i], units[i], _DIMENSION[role])
    motion_role = next(r for r in used if r in MOTIONS)
    return Record(time=values["time"], force=values["force"], **{motion_role: values[motion_role]}, source=source,
                  headers={role: header[i] for role, i in used.items()}, meta=meta)


def _header(content, pos: int, delimiter: str):
    """(header texts, names, units, data lines, line number of the last header row) of a text file
    whose header is ``content[pos]``; a second header row of units (``s;N;mm`` or ``[s];[N];[mm]``)
    fills the units the first leaves out."""
    header_no, header_line = content[pos]
    header = [h.strip() for h in _fields(header_line, delimiter)]
    names, units = (list(x) for x in zip(*(_split_header(h) for h in header)))
    data = content[pos + 1:]
    last_header = header_no
    if data and not any(_is_number(c, ",") for c in _fields(data[0][1], delimiter)):
        row = [c.strip().strip("[]()").strip() for c in _fields(data[0][1], delimiter)]
        for i, u in enumerate(row[:len(units)]):
            if u and not units[i]:
                units[i] = u
        header = [f"{n} [{u}]" if u else n for n, u in zip(names, units)]
        last_header = data[0][0]
        data = data[1:]
    return header, names, units, data, last_header


def _parse_columns(source, lines, last_header, header, used, delimiter, decimal, path) -> dict:
    """The used columns as float arrays, read by pandas' C parser after line ``last_header``;
    where it fails (or a cell is empty), the file is scanned for the wrong row or cell."""
    import io

    import pandas as pd

    cols = sorted(set(used.values()))
    target = path if path is not None else io.StringIO("\n".join(ln for _, ln in lines))
    try:
        frame = pd.read_csv(target, sep=delimiter, decimal=decimal, header=None, skiprows=last_header, usecols=cols,
                            dtype=float, engine="c", quotechar='"', comment="#", skip_blank_lines=True,
                            encoding="utf-8-sig" if path is not None else None, encoding_errors="replace")
        out = {role: frame[i].to_numpy(dtype=float) for role, i in used.items()}
        if all(np.isfinite(c).all() for c in out.values()) and len(frame):
            return out
    except (ValueError, pd.errors.ParserError, UnicodeDecodeError):
        pass
    # the slow path: every data line, to name the line and cell that is wrong
    if path is not None:
        lines = _read_lines(path)
    data = [(no, ln) for no, ln in lines if no > last_header and ln.strip() and not ln.lstrip().startswith("#")]
    if not data:
        raise InputError(f"{source}: the file has a header but no data rows")
    width = max(used.values()) + 1
    rows = [_fields(ln, delimiter) for _, ln in data]
    line_nos = np.array([no for no, _ in data])
    for no, row in zip(line_nos, rows):
        if len(row) < width:
            raise InputError(f"{source}, line {no}: {len(row)} field{'s' if len(row) != 1 else ''} "
                             f"but the header has {len(header)}; fix or remove the row")
    return {role: _column(source, header[i], [row[i] for row in rows], line_nos, decimal) for role, i in used.items()}


# ----------------------------------------------------------------------------- binary files

def _read_channels(path: Path, channels: dict, columns, motion) -> Record:
    """A record from named 1-D channels ``{name: (array, unit)}`` of a binary file."""
    if not channels:
        raise InputError(f"{shown_path(path)}: no 1-D numeric channels found; is this a record file?")
    header = list(channels)
    names = [h.rsplit("/", 1)[-1] for h in header]
    used = _choose(shown_path(path), header, names, columns, motion)
    values = {}
    n = None
    for role, i in used.items():
        arr, unit = channels[header[i]]
        arr = np.asarray(arr, dtype=float).ravel()
        if n is not None and arr.size != n:
            raise InputError(f"{shown_path(path)}: channel {_short(header[i])} has {arr.size} samples, the time {n}; give channels of "
                             "one length")
        n = arr.size
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise InputError(f"{shown_path(path)}: channel {_short(header[i])}, sample {int(bad[0])}: not a finite number "
                             f"({bad.size} such samples); fill the gaps")
        values[role] = arr * (_factor(shown_path(path), header[i], unit, _DIMENSION[role]) if unit else 1.0)
    motion_role = next(r for r in used if r in MOTIONS)
    return Record(time=values["time"], force=values["force"], **{motion_role: values[motion_role]}, source=str(path),
                  headers={role: header[i] for role, i in used.items()})


def _hdf5_channels(path: Path) -> dict:
    import h5py

    out = {}
    try:
        with h5py.File(path, "r") as f:
            def visit(name, obj):
                if isinstance(obj, h5py.Dataset) and obj.ndim <= 2 and obj.dtype.kind in "fiu" and max(obj.shape, default=0) > 1:
                    unit = obj.attrs.get("units", obj.attrs.get("unit", ""))
                    unit = unit.decode() if isinstance(unit, bytes) else str(unit)
                    out[name] = (obj[()], unit)
            f.visititems(visit)
    except Exception as exc:  # h5py raises OSError, KeyError, RuntimeError ... for a damaged file
        raise InputError(f"{shown_path(path)}: cannot read as HDF5 ({type(exc).__name__}: {exc})") from None
    return out


def _mat_channels(path: Path) -> dict:
    import scipy.io

    try:
        data = scipy.io.loadmat(path, squeeze_me=True)
    except Exception as exc:  # scipy raises MatReadError, TypeError, ValueError ... for a damaged file
        raise InputError(f"{shown_path(path)}: cannot read as a MATLAB file ({exc}); save it with -v7 or read it as HDF5 "
                         "(a -v7.3 file is HDF5: rename it to .h5)") from None
    return {k: (v, "") for k, v in data.items() if not k.startswith("__") and isinstance(v, np.ndarray)
            and v.dtype.kind in "fiu" and v.ndim == 1 and v.size > 1}


def _tdms_channels(path: Path) -> dict:
    from nptdms import TdmsFile

    try:
        tdms = TdmsFile.read(path)
    except Exception as exc:  # npTDMS raises plain exceptions for a damaged file
        raise InputError(f"{shown_path(path)}: cannot read as an NI TDMS file ({exc})") from None
    out = {}
    for group in tdms.groups():
        for ch in group.channels():
            data = ch[:]
            if data.dtype.kind not in "fiu" or data.size < 2:
                continue
            out[f"{group.name}/{ch.name}"] = (data, str(ch.properties.get("unit_string", "")))
            if "time" not in {h.rsplit("/", 1)[-1].casefold() for h in out} and "wf_increment" in ch.properties:
                inc = float(ch.properties["wf_increment"])
                out[f"{group.name}/time"] = (float(ch.properties.get("wf_start_offset", 0.0)) + inc * np.arange(data.size),
                                             "s")
    return out


def _factor(path, header: str, unit: str, dim: str) -> float:
    """SI factor of a column's unit; a dimensionless unit (``%``, ``fortnight/s``) is refused.
    For an acceleration ``g`` is the standard gravity (pint's ``g`` is the gram)."""
    if dim == "acceleration" and unit.strip() in ("g", "G", "g0", "gn"):
        return 9.80665
    try:
        unit_factor(unit, "dimensionless")
    except InputError:
        pass
    else:
        raise InputError(f"{shown_path(path)}: column {_short(header)}: {_short(unit)} is not a unit of {dim}; "
                         f"use one such as {_UNIT_EXAMPLES[dim]}")
    try:
        return unit_factor(unit, dim, name=f"column {_short(header)}")
    except InputError:
        raise InputError(f"{shown_path(path)}: column {_short(header)}: {_short(unit)} is not a known unit of {dim}; "
                         f"use one such as {_UNIT_EXAMPLES[dim]}") from None


def _read_lines(path: Path, head: int | None = None) -> list[tuple[int, str]]:
    """(line number, text) of the file's lines (only the first ``head`` with ``head``)."""
    path = checked_file(path, "record file")
    try:
        with open(path, "rb") as f:
            raw = b"".join(f.readline() for _ in range(head)) if head else f.read()
    except OSError as exc:
        raise unreadable_file(path, exc, "record file") from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return list(enumerate(text.splitlines(), start=1))


def _split_header(text: str) -> tuple[str, str]:
    """``"position [mm]"`` -> ``("position", "mm")``; ``"time"`` -> ``("time", "")``."""
    m = _HEADER.match(text)
    if not m:
        return text.strip(), ""
    unit = m.group("u1") if m.group("u1") is not None else m.group("u2")
    return m.group("name").strip(), unit.strip()


def _column(path, header: str, cells: list[str], line_nos, decimal: str) -> np.ndarray:
    """Cells of one column as floats; the first unreadable or non-finite cell is reported."""
    cells = [c.strip() for c in cells]
    try:
        col = np.array(cells, dtype=float)
    except ValueError:
        col = np.empty(len(cells))
        comma_ok = decimal == ","
        for k, cell in enumerate(cells):
            try:
                col[k] = float(cell)
                continue
            except ValueError:
                pass
            if comma_ok and "," in cell:
                try:
                    col[k] = float(cell.replace(",", "."))
                    continue
                except ValueError:
                    pass
            what = "empty cell" if not cell else f"cannot read {_short(cell)} as a number"
            raise InputError(f"{shown_path(path)}, line {line_nos[k]}, column {_short(header)}: {what}; "
                             "fix the cell or remove the row") from None
    bad = np.flatnonzero(~np.isfinite(col))
    if bad.size:
        k = int(bad[0])
        raise InputError(f"{shown_path(path)}, line {line_nos[k]}, column {_short(header)}: {_short(cells[k])} is not "
                         f"a finite number ({bad.size} such cell{'s' if bad.size > 1 else ''}); "
                         "fill the gap or remove the row")
    return col


# ----------------------------------------------------------------------------- one signal in time

@dataclass(frozen=True, kw_only=True, eq=False)
class Signal:
    """One signal in time, in SI: ``time`` [s], ``values`` (a force [N] or an acceleration
    [m/s^2], :attr:`role`), where it came from (``source``) and the header of its column."""

    time: np.ndarray
    values: np.ndarray
    role: str
    source: str = ""
    header: str = ""

    def __len__(self) -> int:
        return int(self.time.size)


def read_signal(path, role: str, *, column: str | None = None) -> Signal:
    """Read one signal in time from a file: the ``time`` column and the ``role`` column (``"force"``
    or ``"acceleration"``; ``column`` names it where the file calls it otherwise), units in the
    header (``time [s]``, ``force [N]``, ``acceleration [g]``: ``g`` the standard gravity) or a row
    of units, from a text file, HDF5, MATLAB or TDMS (as :func:`read_record`), or a PEER NGA
    ``.AT2`` file (accelerations in g, :func:`read_at2`). Every problem raises
    :class:`~pdamper.errors.InputError` naming the file and the line or column."""
    if role not in SIGNAL_ROLES:
        raise InputError(f"role {shown(role)}; read one of {', '.join(SIGNAL_ROLES)}")
    path = checked_file(path, f"{role} file")
    suffix = path.suffix.lower()
    if suffix == ".at2":
        if role != "acceleration":
            raise InputError(f"{shown_path(path)}: a PEER .AT2 file holds a ground acceleration, not a {role}")
        return read_at2(path)
    columns = {role: column} if column else {}
    if suffix in (".h5", ".hdf5", ".hdf", ".mat", ".tdms"):
        channels = (_hdf5_channels if suffix in (".h5", ".hdf5", ".hdf") else
                    _mat_channels if suffix == ".mat" else _tdms_channels)(path)
        return _signal_of_channels(path, channels, role, columns)
    return _signal_of_text(_read_lines(path, head=600), path, role, columns)


def _signal_of_text(lines, path: Path, role: str, columns: dict) -> Signal:
    source = shown_path(path)
    content = [(no, line) for no, line in lines if line.strip() and not line.lstrip().startswith("#")]
    if not content:
        raise InputError(f"{source}: the file is empty; expected a header row (time, {role}) and data rows, e.g. "
                         f"'time [s],{role} [{'N' if role == 'force' else 'm/s^2'}]'")
    pos, delimiter = _find_header(source, content, columns, ("time", role))
    header, names, units, data, last_header = _header(content, pos, delimiter)
    used = {r: _find_column(source, header, names, r, columns.get(r, r), role) for r in ("time", role)}
    if not data:
        raise InputError(f"{source}: the file has a header but no data rows")
    sample = [c for _, ln in data[:50] for c in _fields(ln, delimiter)]
    decimal = "," if delimiter != "," and any("," in c for c in sample) else "."
    values = _parse_columns(source, lines, last_header, header, used, delimiter, decimal, path)
    dims = {"time": "time", role: _DIMENSION[role]}
    for r, i in used.items():
        if units[i]:
            values[r] = values[r] * _factor(source, header[i], units[i], dims[r])
    return _checked_signal(source, values["time"], values[role], role, header[used[role]])


def _find_column(source, header, names, role, target, signal) -> int:
    """The index of the column of ``role`` (named ``target``) of a file of time and ``signal``."""
    key = target.strip().casefold()
    hits = [i for i, (h, n) in enumerate(zip(header, names)) if n.casefold() == key or h.casefold() == key]
    if len(hits) > 1:
        raise InputError(f"{source}: {len(hits)} columns match {role} ({shown(target)}): "
                         f"{', '.join(_short(header[i]) for i in hits)}; rename one")
    if not hits:
        raise InputError(f"{source}: no {role} column ({shown(target)}); the header has "
                         f"{', '.join(_short(h) for h in header)}; name the columns 'time [s]' and "
                         f"'{signal} [unit]'" + (" (or name the column with column = ...)" if role != "time" else ""))
    return hits[0]


def _signal_of_channels(path: Path, channels: dict, role: str, columns: dict) -> Signal:
    if not channels:
        raise InputError(f"{shown_path(path)}: no 1-D numeric channels found; is this a {role} file?")
    header = list(channels)
    names = [h.rsplit("/", 1)[-1] for h in header]
    out = {}
    for r in ("time", role):
        i = _find_column(shown_path(path), header, names, r, columns.get(r, r), role)
        arr, unit = channels[header[i]]
        arr = np.asarray(arr, dtype=float).ravel()
        out[r] = arr * (_factor(shown_path(path), header[i], unit, _DIMENSION[r]) if unit else 1.0)
        out[r + "_header"] = header[i]
    if out["time"].size != out[role].size:
        raise InputError(f"{shown_path(path)}: channel {_short(out[role + '_header'])} has {out[role].size} samples, the time "
                         f"{out['time'].size}; give channels of one length")
    return _checked_signal(shown_path(path), out["time"], out[role], role, out[role + "_header"])


def _checked_signal(source: str, time, values, role: str, header: str) -> Signal:
    """A :class:`Signal` once its samples are finite, at least two, at strictly increasing times."""
    time = np.asarray(time, dtype=float)
    values = np.asarray(values, dtype=float)
    if time.size < 2:
        raise InputError(f"{source}: {time.size} sample{'s' if time.size != 1 else ''}; a {role} in time needs at "
                         "least 2")
    for what, arr in (("time", time), (role, values)):
        bad = np.flatnonzero(~np.isfinite(arr))
        if bad.size:
            raise InputError(f"{source}: {what} sample {int(bad[0])} is not a finite number ({bad.size} such); fill "
                             "the gaps")
    steps = np.diff(time)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0))
        raise InputError(f"{source}: the time must increase strictly; it does not at sample {k + 1} "
                         f"(t = {time[k + 1]:.10g} s after {time[k]:.10g} s)")
    return Signal(time=time, values=values, role=role, source=source, header=header)


_AT2_NPTS = re.compile(r"NPTS\s*=\s*([^\s,]+)", re.IGNORECASE)
_AT2_DT = re.compile(r"DT\s*=\s*([^\s,]+)", re.IGNORECASE)
_AT2_OLD = re.compile(r"^\s*(\S+)\s+(\S+)\s+NPTS\s*,\s*DT", re.IGNORECASE)
#: Units of the third header line of an .AT2 file -> factor to m/s^2.
_AT2_UNITS = {"G": 9.80665, "CM/S/S": 0.01, "CM/SEC/SEC": 0.01, "CM/S^2": 0.01, "CM/S2": 0.01, "M/S/S": 1.0,
              "M/SEC/SEC": 1.0, "M/S^2": 1.0, "M/S2": 1.0}


def _at2_cells(line: str, width: int | None) -> list[str]:
    """The fields of a data line: split at blanks, or every ``width`` characters (fixed width)."""
    if width is None:
        return line.split()
    text = line.rstrip()
    return [text[k:k + width] for k in range(0, len(text), width)]


def _at2_number(cell: str) -> float:
    return float(cell.strip().replace("D", "E").replace("d", "e"))


def _at2_width(lines, npts: int) -> int | None:
    """The field width of fixed-width data lines whose fields touch (``  .1000000E-01-.2000000E-01``):
    ``k = ceil(NPTS / lines)`` fields a full line, every full line ``k w`` characters long, the last
    one its remaining fields; None where the lines do not have one width."""
    n = len(lines)
    k = -(-npts // n) if n else 0
    if not n or not (n - 1) * k < npts <= n * k:
        return None
    full = lines if npts == n * k else lines[:-1]
    lengths = {len(ln.rstrip()) for _, ln in full}
    if len(lengths) != 1:
        return None
    length = lengths.pop()
    if length % k or not length:
        return None
    width = length // k
    last = npts - k * (n - 1)
    return width if len(lines[-1][1].rstrip()) == last * width else None


def _at2_values(source: str, lines, npts: int) -> np.ndarray:
    """The accelerations of an .AT2 file's data ``lines``: fields separated by blanks, or, where
    they touch (older PEER and COSMOS files write Fortran ``E`` fields without a blank between a
    negative number and the one before it), split by the field width that the header's NPTS and the
    lines' length give (:func:`_at2_width`). A cell that is not a number is named by its line."""
    width = None
    try:
        values = [_at2_number(c) for _, ln in lines for c in ln.split()]
        if len(values) != npts:
            raise ValueError
    except ValueError:
        width = _at2_width(lines, npts)
    if width is not None:
        values = []
        for no, ln in lines:
            for j, cell in enumerate(_at2_cells(ln, width)):
                try:
                    values.append(_at2_number(cell))
                except ValueError:
                    raise InputError(f"{source}, line {no}, field {j + 1} (columns {j * width + 1}-{(j + 1) * width}"
                                     f" of fixed width {width}): cannot read {_short(cell)} as an acceleration") from None
    else:
        values = []
        for no, ln in lines:
            for cell in ln.split():
                try:
                    values.append(_at2_number(cell))
                except ValueError:
                    raise InputError(f"{source}, line {no}: cannot read {_short(cell)} as an acceleration (nor "
                                     "fields of one fixed width: the lines' lengths do not match NPTS)") from None
    arr = np.asarray(values, dtype=float)
    if arr.size != npts:
        raise InputError(f"{source}: the header says NPTS = {npts} but the file has {arr.size} accelerations; "
                         "fix NPTS or the data")
    bad = np.flatnonzero(~np.isfinite(arr))
    if bad.size:
        k = int(bad[0])
        raise InputError(f"{source}: acceleration {k + 1} ({_at2_line(lines, k, width)}) is not a finite number "
                         f"({bad.size} such); fill the gaps")
    return arr


def _at2_line(lines, k: int, width: int | None) -> str:
    """``line N`` of the ``k``-th value (0-based) of an .AT2 file's data lines."""
    seen = 0
    for no, ln in lines:
        n = len(_at2_cells(ln, width))
        if k < seen + n:
            return f"line {no}"
        seen += n
    return "past the last line"


def read_at2(path) -> Signal:
    """A ground acceleration [m/s^2] from a PEER NGA strong-motion file (``.AT2``): line 1 the
    database, line 2 the event and station, line 3 ``ACCELERATION TIME SERIES IN UNITS OF G``,
    line 4 ``NPTS= 4000, DT= .0100 SEC`` (or the older ``4000 .0100 NPTS, DT``), then the NPTS
    accelerations, several a line; the samples at ``k DT``, k = 0 .. NPTS - 1. Fields written in a
    fixed width that touch (``  .1000000E-01-.2000000E-01``, as older PEER and COSMOS files have)
    are split by that width, which the header's NPTS and the lines' length give; a Fortran ``D``
    exponent reads as ``E``."""
    path = Path(path)
    source = shown_path(path)
    lines = _read_lines(path)
    if len(lines) < 5:
        raise InputError(f"{source}: {len(lines)} lines; a PEER .AT2 file has 4 header lines (database, event, "
                         "'ACCELERATION TIME SERIES IN UNITS OF G', 'NPTS= n, DT= dt SEC') and the accelerations")
    units_line = lines[2][1]
    m = re.search(r"UNITS\s+OF\s+(\S+)", units_line, re.IGNORECASE)
    unit = m.group(1).strip(".,").upper() if m else ""
    if unit not in _AT2_UNITS:
        raise InputError(f"{source}, line 3: {_short(units_line.strip())} does not name the units (expected "
                         f"'... IN UNITS OF G'; known: {', '.join(_AT2_UNITS)})")
    head = lines[3][1]
    old = _AT2_OLD.match(head)
    n_text, dt_text = (old.group(1), old.group(2)) if old else (
        (_AT2_NPTS.search(head) or [None, None])[1], (_AT2_DT.search(head) or [None, None])[1])
    if n_text is None or dt_text is None:
        raise InputError(f"{source}, line 4: {_short(head.strip())}; expected 'NPTS= 4000, DT= .0100 SEC'")
    try:
        npts = int(float(n_text))
        dt = float(dt_text)
    except (ValueError, OverflowError):  # OverflowError: NPTS = 1e999, an infinite float made whole
        raise InputError(f"{source}, line 4: cannot read NPTS = {_short(n_text)} and DT = {_short(dt_text)} as "
                         "numbers (NPTS a whole number of samples, DT a time step in seconds)") from None
    if not (2 <= npts <= 10_000_000 and float(n_text) == npts):
        raise InputError(f"{source}, line 4: NPTS = {_written(n_text)}; must be a whole number of samples from 2 to "
                         "10,000,000")
    if not (dt > 0 and np.isfinite(dt) and dt <= 10.0):
        raise InputError(f"{source}, line 4: DT = {_written(dt_text)} s; must be a time step > 0 (and at most 10 s)")
    values = _at2_values(source, [(no, ln) for no, ln in lines[4:] if ln.strip()], npts)
    return _checked_signal(source, dt * np.arange(npts), np.asarray(values) * _AT2_UNITS[unit], "acceleration",
                           f"acceleration [{unit.lower()}]")
