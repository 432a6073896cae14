"""A stroke sweep: the base case at every stroke X for every seed (SPEC Sect. 1, 5, 7).

Every (stroke, seed) case is independent: it starts from rest with its own seeded jitter
(the paper's drive pauses between points), so the cases can run in any order, anywhere.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..excitation import HarmonicDrive
from ..params import Case, with_stroke
from ..units import parse_quantity

__all__ = ["SweepSpec", "stroke_grid", "parse_strokes", "case_key", "run_one", "run_sweep"]

#: The paper's sweep: 40 log-spaced strokes from 0.5 to 50 mm.
PAPER_STROKES = (0.5e-3, 50e-3, 40)


def stroke_grid(lo: float, hi: float, n: int) -> np.ndarray:
    """``n`` log-spaced strokes [m] from ``lo`` to ``hi`` (the paper: 0.5 mm, 50 mm, 40)."""
    if not (0 < lo <= hi) or not (isinstance(n, (int, np.integer)) and n >= 1):
        raise InputError(f"strokes: need 0 < first <= last and a count >= 1, got {lo!r}, {hi!r}, {n!r}")
    if n == 1:
        return np.array([lo])
    return np.geomspace(lo, hi, int(n))


def parse_strokes(text: str) -> np.ndarray:
    """Strokes from the CLI: ``"0.5mm:50mm:40"`` (log-spaced), or a list ``"5mm,12mm,13mm"``."""
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise InputError(f"--strokes {text!r}: write FIRST:LAST:COUNT, e.g. 0.5mm:50mm:40, or a list 5mm,12mm")
        lo = parse_quantity(parts[0], "length", name="--strokes (first)")
        hi = parse_quantity(parts[1], "length", name="--strokes (last)")
        try:
            n = int(parts[2])
        except ValueError:
            raise InputError(f"--strokes {text!r}: the count {parts[2]!r} is not a whole number") from None
        return stroke_grid(lo, hi, n)
    values = [parse_quantity(p, "length", name="--strokes") for p in text.split(",") if p.strip()]
    if not values or any(v <= 0 for v in values):
        raise InputError(f"--strokes {text!r}: give positive lengths, e.g. 5mm,12mm or 0.5mm:50mm:40")
    return np.array(sorted(set(values)))


def case_key(stroke: float, seed: int) -> str:
    """File-safe, exact key of one case: the stroke's full float repr and the seed."""
    return f"X{float(stroke)!r}_seed{int(seed)}"


@dataclass(frozen=True, kw_only=True)
class SweepSpec:
    """A base case, the strokes [m] and the seeds to run it at."""

    base: Case
    strokes: tuple
    seeds: tuple

    def __post_init__(self):
        if not isinstance(self.base.drive, HarmonicDrive):
            raise InputError("a stroke sweep needs a harmonic drive ([drive] stroke and frequency)")
        strokes = tuple(float(x) for x in np.atleast_1d(self.strokes))
        if not strokes or any(not (x > 0 and math.isfinite(x)) for x in strokes):
            raise InputError(f"sweep strokes must be positive lengths, got {self.strokes!r}")
        seeds = tuple(int(s) for s in np.atleast_1d(self.seeds))
        if not seeds or any(s < 0 for s in seeds):
            raise InputError(f"sweep seeds must be whole numbers >= 0, got {self.seeds!r}")
        object.__setattr__(self, "strokes", tuple(sorted(set(strokes))))
        object.__setattr__(self, "seeds", tuple(sorted(set(seeds))))

    def case(self, stroke: float, seed: int) -> Case:
        """The base case at ``stroke`` [m] with random seed ``seed``."""
        c = with_stroke(self.base, stroke)
        return dataclasses.replace(c, initial=dataclasses.replace(c.initial, seed=int(seed)))

    def items(self):
        """(key, stroke, seed) of every case, small strokes first."""
        return [(case_key(x, s), x, s) for x in self.strokes for s in self.seeds]


def run_one(case: Case) -> dict:
    """Run one case and return its summary (plain floats, the motion mode; what the store keeps).

    The mode is classified on a coarse trajectory the run records for it (50 frames/s,
    :data:`pdamper.run.MODE_FPS`; not stored).

    A numerically failed case is not an exception for the sweep: it returns ``failed`` with
    the message, so the other cases go on and the failure is reported.
    """
    from ..errors import SimulationError
    from ..run import run_case

    try:
        res = run_case(case)
    except SimulationError as exc:
        return {"failed": str(exc)}
    s = res.summary()
    return {
        "eta_star": s["eta_star"],
        "energy_per_cycle_J": s["energy_per_cycle_J"],
        "ledger_dissipated_per_cycle_J": s["ledger_dissipated_per_cycle_J"],
        "energy_balance_error": s["energy_balance_error"],
        "velocity_amplitude_m_s": float(res.analysis.velocity_amplitude_m_s) if res.analysis is not None else math.nan,
        "steps": int(s["steps"]),
        "wall_time_s": s["wall_time_s"],
        "mode": s.get("mode", "unknown"),
        "mode_features": s.get("mode_features", {}),
    }


def run_sweep(spec: SweepSpec, path, *, workers: int | None = None, scheduler: str | None = None,
              progress: bool | None = None):
    """Run every case of ``spec`` not yet in the store at ``path``; return the results dataset.

    Cases already in the store are not run again (resume after an interruption). Each case is
    written to the store as soon as it finishes. ``workers`` local processes (default: all
    cores) or an existing Dask cluster at ``scheduler``.
    """
    from .executor import execute
    from .store import ResultStore

    store = ResultStore.create_or_open(path, spec)
    todo = [(k, x, s, spec.case(x, s)) for k, x, s in spec.items() if not store.has(k)]
    if todo:
        execute(todo, run_one, store.save, workers=workers, scheduler=scheduler, progress=progress,
                total=len(spec.items()), done=len(spec.items()) - len(todo))
    return store.dataset()
