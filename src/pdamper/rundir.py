"""A run's directory: a :class:`pdamper.run.RunResult` written as files, and read back.

``pdamper run --out DIR`` writes it: ``config.toml`` (the full case; ``pdamper run
DIR/config.toml`` repeats the run bit for bit), ``signals.csv``, ``energy.csv``, the trajectory
if recorded, and ``result.json`` last (its presence marks a complete run). The file format is
:mod:`pdamper.io.runs`'s; this module maps the recorders' results onto it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from .io.runs import FILES, check_run_dir, read_run_files, write_run_files

__all__ = ["write_run", "read_run", "check_run_dir", "StoredRun", "FILES"]


@dataclass(frozen=True, kw_only=True, eq=False)
class StoredRun:
    """A run read back from its directory (see :func:`read_run`).

    Attributes
    ----------
    path : the run directory.
    case : :class:`pdamper.params.Case` from ``config.toml``.
    signals : :class:`pdamper.recorders.signals.Signals` (SI).
    energy : :class:`pdamper.recorders.energy.EnergyLedger` [J].
    summary : dict, as :meth:`pdamper.run.RunResult.summary` (NaN stored as null -> NaN).
    analysis : dict of the complex-power result (``PowerResult.to_dict()``) or None.
    version : the pdamper version that wrote the run.
    trajectory : dict of arrays or None.
    """

    path: Path
    case: object
    signals: object
    energy: object
    summary: dict
    analysis: dict | None
    version: str
    trajectory: dict | None = None


def write_run(result, out_dir) -> Path:
    """Write the run ``result`` (a :class:`pdamper.run.RunResult`) to the directory ``out_dir``.

    Creates the directory (and its parents); an existing run directory is overwritten, any other
    non-empty directory refused (:func:`pdamper.io.runs.check_run_dir`). Returns the directory.
    """
    from .config import dumps_case
    from .recorders.energy import COLUMNS

    s, e = result.signals, result.energy
    return write_run_files(
        out_dir, config_text=dumps_case(result.case, name=FILES["config"]),
        signals=[s.time, s.force, s.velocity, s.position], energy=[e.time] + [getattr(e, c) for c in COLUMNS],
        trajectory=result.trajectory,
        meta={"summary": result.summary(),
              "analysis": result.analysis.to_dict() if result.analysis is not None else None})


def read_run(out_dir) -> StoredRun:
    """Read a run directory written by :func:`write_run`."""
    from .config import load_case
    from .recorders.energy import COLUMNS, EnergyLedger
    from .recorders.signals import Signals

    raw = read_run_files(out_dir)
    sig, eng, meta = raw["signals"], raw["energy"], raw["meta"]
    signals = Signals(time=sig[:, 0], time_end=eng[:, 0].copy(), force=sig[:, 1], velocity=sig[:, 2],
                      position=sig[:, 3])
    energy = EnergyLedger(time=eng[:, 0], **{c: eng[:, k + 1] for k, c in enumerate(COLUMNS)})
    summary = {k: (math.nan if v is None else v) for k, v in (meta.get("summary") or {}).items()}
    return StoredRun(path=Path(out_dir), case=load_case(raw["config_path"]), signals=signals, energy=energy,
                     summary=summary, analysis=meta.get("analysis"), version=str(meta.get("pdamper_version", "")),
                     trajectory=raw["trajectory"])
