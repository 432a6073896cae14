"""Run directories on disk: the files of one simulated run, with the config that re-creates it.

This module reads and writes the files from plain data (text, arrays, dicts);
:mod:`pdamper.rundir` turns a :class:`pdamper.run.RunResult` into them and back.

A run directory holds

- ``config.toml``  -- the full case (every parameter, plain SI numbers); ``pdamper run
  DIR/config.toml`` repeats the run bit for bit (:func:`pdamper.config.load_case`);
- ``signals.csv``  -- ``time [s],force [N],velocity [m/s],position [m]``: the driving force on the
  container and its motion, each sample the mean over its interval, stamped at its centre;
- ``energy.csv``   -- the energy ledger, ``time [s]`` (interval ends) and the energies [J];
- ``trajectory.npz`` -- decimated particle trajectories, only when they were recorded;
- ``result.json``  -- the summary (eta*, energy per cycle, steps, wall time ...), the complex-power
  analysis and the pdamper version; written last, so its presence marks a complete run.

Every file is written to a temporary file in the same directory and moved into place with
:func:`os.replace`, so a reader never sees a half-written file.

Overwriting: :func:`write_run` writes into a new or empty directory, or into an existing run
directory (one holding ``result.json`` written by pdamper, or a ``config.toml`` written by pdamper
without a result yet), replacing its files. It refuses any other non-empty directory rather than
mixing a run with unrelated files.
"""

from __future__ import annotations

import io
import json
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from ..errors import InputError, checked_file, shown, shown_path, unreadable_file
from .files import atomic_write, json_safe

__all__ = ["write_run_files", "read_run_files", "check_run_dir", "RUN_FORMAT", "FILES", "SIGNAL_COLUMNS",
           "ENERGY_COLUMNS"]

#: Marker and version of the run-directory layout, stored in ``result.json``.
RUN_FORMAT = {"name": "pdamper-run", "version": 1}
#: File names in a run directory.
FILES = {"config": "config.toml", "signals": "signals.csv", "energy": "energy.csv",
         "result": "result.json", "trajectory": "trajectory.npz"}
SIGNAL_COLUMNS = ("time [s]", "force [N]", "velocity [m/s]", "position [m]")
ENERGY_COLUMNS = ("time [s]", "kinetic [J]", "rotational [J]", "potential [J]", "elastic [J]", "work [J]",
                  "damping [J]", "friction [J]")


# --------------------------------------------------------------------------- writing

def check_run_dir(out_dir) -> Path:
    """Raise InputError unless ``out_dir`` can take a run (new, empty, or a pdamper run directory).

    Call it before a long run so a bad ``--out`` fails at once; :func:`write_run` calls it too.
    """
    path = Path(out_dir)
    try:
        path.exists()
    except (OSError, ValueError) as exc:  # a name the system refuses: too long, a NUL character
        raise unreadable_file(path, exc, "run directory") from None
    if path.exists() and not path.is_dir():
        raise InputError(f"run directory {path} is a file; give a directory (it is created if missing)")
    if path.is_dir() and any(path.iterdir()) and not _is_run_dir(path):
        raise InputError(f"run directory {path} is not empty and is not a pdamper run directory; "
                         "give a new or empty directory (an existing run directory is overwritten)")
    return path


def _is_run_dir(path: Path) -> bool:
    result = path / FILES["result"]
    if result.is_file():
        try:
            meta = json.loads(result.read_text(encoding="utf-8"))
            return isinstance(meta, dict) and meta.get("format", {}).get("name") == RUN_FORMAT["name"]
        except (OSError, ValueError, AttributeError):
            return False
    config = path / FILES["config"]
    if config.is_file():
        try:
            with config.open(encoding="utf-8") as fh:
                return "written by pdamper" in fh.readline()
        except (OSError, UnicodeDecodeError):
            return False
    return False


def _csv_bytes(columns, arrays) -> bytes:
    """CSV text; each number written as Python's shortest repr, which reads back to the same float."""
    data = np.column_stack([np.asarray(a, dtype=float) for a in arrays]).tolist()
    lines = [",".join(columns)] + [",".join(map(repr, row)) for row in data]
    return ("\n".join(lines) + "\n").encode("utf-8")


def write_run_files(out_dir, *, config_text: str, signals: list, energy: list, trajectory: dict | None,
                    meta: dict) -> Path:
    """Write a run directory from plain data: the config's TOML text, the columns of
    ``signals.csv`` and ``energy.csv`` (arrays in the order of :data:`SIGNAL_COLUMNS` and
    :data:`ENERGY_COLUMNS`), the trajectory arrays (or None) and the ``result.json`` content
    (``meta``, to which the format marker, version, time and file list are added; written last).
    See the module docstring for when an existing directory is overwritten. Returns the directory.
    """
    from .._version import __version__

    path = check_run_dir(out_dir)
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot create run directory {path}: {exc.strerror or exc}") from None
    # an old result.json would mark a half-rewritten directory as complete: remove it first
    for stale in (FILES["result"], FILES["trajectory"]):
        try:
            (path / stale).unlink()
        except FileNotFoundError:
            pass
    atomic_write(path / FILES["config"], config_text.encode("utf-8"))
    atomic_write(path / FILES["signals"], _csv_bytes(SIGNAL_COLUMNS, signals))
    atomic_write(path / FILES["energy"], _csv_bytes(ENERGY_COLUMNS, energy))
    files = [FILES["config"], FILES["signals"], FILES["energy"]]
    if trajectory is not None:
        buf = io.BytesIO()
        np.savez_compressed(buf, **{k: np.asarray(v) for k, v in trajectory.items()})
        atomic_write(path / FILES["trajectory"], buf.getvalue())
        files.append(FILES["trajectory"])
    meta = {"format": RUN_FORMAT, "pdamper_version": __version__,
            "written": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "files": files + [FILES["result"]], "units": "SI (keys name their unit where it is not obvious)", **meta}
    text = json.dumps(json_safe(meta), indent=2, allow_nan=False) + "\n"
    atomic_write(path / FILES["result"], text.encode("utf-8"))
    return path


# --------------------------------------------------------------------------- reading

def _read_csv(path: Path, columns) -> np.ndarray:
    """A CSV file of a run directory; a damaged one (truncated, binary, ragged, not finite) is an
    InputError naming the file and the line."""
    if not path.is_file():
        raise InputError(f"run directory {path.parent}: missing {path.name}")
    try:
        lines = path.read_bytes().decode("utf-8").splitlines()
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: damaged (byte {exc.start} is not text); re-run the case") from None
    except OSError as exc:
        raise InputError(f"cannot read {path}: {exc.strerror or exc}") from None
    header = lines[0].strip() if lines else ""
    if tuple(h.strip() for h in header.split(",")) != tuple(columns):
        raise InputError(f"{path}: unexpected header {shown(header[:200])}; expected {','.join(columns)}")
    try:
        data = np.loadtxt(lines[1:], delimiter=",", ndmin=2, dtype=float)
    except ValueError:
        data = None
    if data is None or data.size and (data.shape[1] != len(columns) or not np.isfinite(data).all()):
        for no, line in enumerate(lines[1:], start=2):
            cells = line.split(",")
            try:
                ok = len(cells) == len(columns) and all(np.isfinite(float(c)) for c in cells)
            except ValueError:
                ok = False
            if not ok:
                raise InputError(f"{path}, line {no}: damaged row {shown(line, 80)} (expected {len(columns)} finite "
                                 "numbers); the run directory was damaged after it was written, re-run the case")
        if data is None:
            raise InputError(f"{path}: damaged (not a table of {len(columns)} numbers); re-run the case")
    return data.reshape(-1, len(columns))


def read_run_files(out_dir) -> dict:
    """The plain content of a complete run directory: ``config_path``, ``signals`` and ``energy``
    (2-D arrays, columns as :data:`SIGNAL_COLUMNS` / :data:`ENERGY_COLUMNS`), ``trajectory``
    (dict or None) and ``meta`` (``result.json``)."""
    path = checked_file(out_dir, "run directory", directory_ok=True)
    if not path.is_dir():
        raise InputError(f"run directory not found: {shown_path(path)} is a file")
    result = path / FILES["result"]
    if not result.is_file():
        raise InputError(f"{path} is not a complete pdamper run directory (no {FILES['result']}); "
                         "the run may have been interrupted")
    try:
        meta = json.loads(result.read_text(encoding="utf-8"))
    except ValueError as exc:
        raise InputError(f"{result}: not valid JSON ({exc})") from None
    if not isinstance(meta, dict) or meta.get("format", {}).get("name") != RUN_FORMAT["name"]:
        raise InputError(f"{result} was not written by pdamper (no run format marker)")
    sig = _read_csv(path / FILES["signals"], SIGNAL_COLUMNS)
    eng = _read_csv(path / FILES["energy"], ENERGY_COLUMNS)
    if eng.shape[0] != sig.shape[0]:
        raise InputError(f"{path}: {FILES['signals']} has {sig.shape[0]} rows but {FILES['energy']} has "
                         f"{eng.shape[0]}; the run directory is inconsistent")
    trajectory = None
    tpath = path / FILES["trajectory"]
    if tpath.is_file():
        try:
            with np.load(tpath, allow_pickle=False) as z:
                trajectory = {k: z[k] for k in z.files}
        except Exception as exc:  # numpy/zipfile raise BadZipFile, EOFError, ValueError ... for a damaged file
            raise InputError(f"{tpath}: damaged trajectory file ({type(exc).__name__}: {exc}); delete it to read "
                             "the run without its trajectory, or re-run the case") from None
    return {"config_path": path / FILES["config"], "signals": sig, "energy": eng, "trajectory": trajectory,
            "meta": meta}
