"""Measured force/motion records from delimited text files (CSV, semicolon or tab separated).

A record file has one header row and one row per sample. The columns that
matter are ``time``, ``force`` and one motion column, ``position``,
``velocity`` or ``acceleration``; other columns are ignored. A column name may
carry its unit in brackets or parentheses, e.g. ``time [ms]``, ``force [kN]``,
``position (mm)``, ``acceleration [m/s^2]``; without a unit the column is taken
as SI (s, N, m, m/s, m/s^2). Units are read with :mod:`pint` through
:func:`pdamper.units.unit_factor`, so any unit of the right dimension works
(``us``, ``lbf``, ``in``, ``g0`` ...). Names match case-insensitively, ignoring
surrounding whitespace; other names are mapped with ``columns``.

The delimiter is sniffed from the header (comma, semicolon or tab). Blank lines
and lines starting with ``#`` are skipped. In semicolon- and tab-separated files
a decimal comma (``0,25``) is accepted.

Everything is returned in SI as a :class:`Record`; every problem raises
:class:`pdamper.errors.InputError` naming the file, line and column.
"""

from __future__ import annotations

import csv
import re
import shlex
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..errors import InputError
from ..units import unit_factor

__all__ = ["Record", "read_record", "ROLES", "MOTIONS"]

#: The columns a record can have.
ROLES = ("time", "force", "position", "velocity", "acceleration")
#: The motion columns, of which a record uses exactly one.
MOTIONS = ("position", "velocity", "acceleration")
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
    """

    time: np.ndarray
    force: np.ndarray
    position: np.ndarray | None = None
    velocity: np.ndarray | None = None
    acceleration: np.ndarray | None = None
    source: str | None = None
    headers: dict = field(default_factory=dict)

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
                delimiter: str | None = None) -> Record:
    """Read a measured record (time, force, one motion column) from a delimited text file.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    columns : dict, optional
        Map of role (``"time"``, ``"force"``, ``"position"``, ``"velocity"``,
        ``"acceleration"``) to the column's name in the file, e.g.
        ``{"time": "t", "force": "F_x"}``. The name is matched without its unit
        (``"F_x"`` finds ``F_x [kN]``) or as the full header text.
    motion : str, optional
        Which motion column to use when the file has several. Mapping exactly one
        motion role in ``columns`` chooses it too.
    delimiter : str, optional
        Column delimiter; sniffed from the header if omitted.

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
    path = Path(path)
    columns = dict(columns or {})
    for role in columns:
        if role not in ROLES:
            raise InputError(f"unknown column role {role!r}; use one of {', '.join(ROLES)}")
    if motion is not None and motion not in MOTIONS:
        raise InputError(f"motion must be one of {', '.join(MOTIONS)}; got {motion!r}")
    mapped_motions = [m for m in MOTIONS if m in columns]
    if motion is not None and mapped_motions and mapped_motions != [motion]:
        raise InputError(f"motion={motion!r} but the column map names "
                         f"{', '.join(mapped_motions)}; choose one motion column")
    if motion is None and len(mapped_motions) > 1:
        raise InputError(f"the column map names several motion columns "
                         f"({', '.join(mapped_motions)}); choose one")

    lines = _read_lines(path)
    content = [(no, line) for no, line in lines
               if line.strip() and not line.lstrip().startswith("#")]
    if not content:
        raise InputError(f"{path}: the file is empty; expected a header row "
                         "(time, force, position|velocity|acceleration) and data rows")
    header_no, header_line = content[0]
    if delimiter is None:
        delimiter = _sniff(path, header_no, header_line)
    rows = list(csv.reader([line for _, line in content], delimiter=delimiter))
    header = [h.strip() for h in rows[0]]
    data = rows[1:]
    line_nos = [no for no, _ in content[1:]]
    names, units = zip(*(_split_header(h) for h in header))

    def find(role: str, required: bool) -> int | None:
        target = columns.get(role, role)
        key = target.strip().casefold()
        hits = [i for i, (h, n) in enumerate(zip(header, names))
                if n.casefold() == key or h.casefold() == key]
        if len(hits) > 1:
            raise InputError(f"{path}: {len(hits)} columns match {role} ({target!r}): "
                             f"{', '.join(repr(header[i]) for i in hits)}; rename one or "
                             f"map {role} to the full header text")
        if not hits:
            if required:
                hint = (f"map it with --{role}-column NAME (columns={{'{role}': NAME}})")
                raise InputError(f"{path}: no {role} column ({target!r}); the header has "
                                 f"{', '.join(repr(h) for h in header)}; rename the column or {hint}")
            return None
        return hits[0]

    i_time = find("time", True)
    i_force = find("force", True)
    chosen = motion or (mapped_motions[0] if mapped_motions else None)
    if chosen is not None:
        i_motion = find(chosen, True)
    else:
        present = {m: i for m in MOTIONS if (i := find(m, False)) is not None}
        if not present:
            raise InputError(
                f"{path}: no motion column; need one of position, velocity, acceleration "
                f"(the header has {', '.join(repr(h) for h in header)}); rename it or map it "
                "with --position-column/--velocity-column/--acceleration-column NAME")
        if len(present) > 1:
            listing = " and ".join(repr(header[i]) for i in present.values())
            first = next(iter(present))
            raise InputError(
                f"{path}: the record has {len(present)} motion columns, {listing}; choose the "
                f"one to use, e.g. --{first}-column {shlex.quote(names[present[first]])} "
                f"(motion={first!r})")
        chosen, i_motion = next(iter(present.items()))

    if not data:
        raise InputError(f"{path}: the file has a header but no data rows")
    used = {"time": i_time, "force": i_force, chosen: i_motion}
    width = max(used.values()) + 1
    for no, row in zip(line_nos, data):
        if len(row) < width:
            raise InputError(f"{path}, line {no}: {len(row)} field{'s' if len(row) != 1 else ''} "
                             f"but the header has {len(header)}; fix or remove the row")

    values = {}
    for role, i in used.items():
        col = _column(path, header[i], [row[i] for row in data], line_nos, delimiter)
        unit = units[i]
        if unit:
            col = col * _factor(path, header[i], unit, _DIMENSION[role])
        values[role] = col

    return Record(time=values["time"], force=values["force"],
                  **{chosen: values[chosen]}, source=str(path),
                  headers={role: header[i] for role, i in used.items()})


def _factor(path: Path, header: str, unit: str, dim: str) -> float:
    """SI factor of a column's unit; a dimensionless unit (``%``, ``fortnight/s``) is refused."""
    try:
        unit_factor(unit, "dimensionless")
    except InputError:
        pass
    else:
        raise InputError(f"{path}: column {header!r}: {unit!r} is not a unit of {dim}; "
                         f"use one such as {_UNIT_EXAMPLES[dim]}")
    try:
        return unit_factor(unit, dim, name=f"column {header!r}")
    except InputError:
        raise InputError(f"{path}: column {header!r}: {unit!r} is not a known unit of {dim}; "
                         f"use one such as {_UNIT_EXAMPLES[dim]}") from None


def _read_lines(path: Path) -> list[tuple[int, str]]:
    if not path.exists():
        raise InputError(f"record file not found: {path}")
    if path.is_dir():
        raise InputError(f"{path} is a directory; give the record file")
    raw = path.read_bytes()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        text = raw.decode("latin-1")
    return list(enumerate(text.splitlines(), start=1))


def _sniff(path: Path, no: int, header: str) -> str:
    counts = {d: header.count(d) for d in (",", ";", "\t")}
    best = max(counts, key=counts.get)
    if counts[best] == 0:
        raise InputError(
            f"{path}, line {no}: cannot find the column delimiter in the header {header.strip()!r}; "
            "separate the columns with commas, semicolons or tabs")
    return best


def _split_header(text: str) -> tuple[str, str]:
    """``"position [mm]"`` -> ``("position", "mm")``; ``"time"`` -> ``("time", "")``."""
    m = _HEADER.match(text)
    if not m:
        return text.strip(), ""
    unit = m.group("u1") if m.group("u1") is not None else m.group("u2")
    return m.group("name").strip(), unit.strip()


def _column(path: Path, header: str, cells: list[str], line_nos: list[int],
            delimiter: str) -> np.ndarray:
    """Cells of one column as floats; the first unreadable or non-finite cell is reported."""
    cells = [c.strip() for c in cells]
    try:
        col = np.array(cells, dtype=float)
    except ValueError:
        col = np.empty(len(cells))
        comma_ok = delimiter != ","
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
            what = "empty cell" if not cell else f"cannot read {cell!r} as a number"
            raise InputError(f"{path}, line {line_nos[k]}, column {header!r}: {what}; "
                             "fix the cell or remove the row") from None
    bad = np.flatnonzero(~np.isfinite(col))
    if bad.size:
        k = int(bad[0])
        raise InputError(f"{path}, line {line_nos[k]}, column {header!r}: {cells[k]!r} is not "
                         f"a finite number ({bad.size} such cell{'s' if bad.size > 1 else ''}); "
                         "fill the gap or remove the row")
    return col
