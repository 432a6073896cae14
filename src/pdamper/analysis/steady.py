r"""How well a run's eta* is known and whether the run has reached steady state, from the energy
dissipated in each analysed drive cycle.

The complex power gives one eta* over the analysed window (eq. 5); the energies of the single
cycles, ``E_k = int F v dt`` over cycle k, scatter around its energy per cycle because the bed
does not repeat itself exactly. Their spread says how well eta* is known:

* **Standard error.** ``s / sqrt(n)`` of the n analysed cycle energies, inflated for the
  correlation of neighbouring cycles (the bed carries its state from one cycle into the next) by
  the AR(1) factor ``sqrt((1 + r1) / (1 - r1))`` with ``r1`` the lag-1 autocorrelation, clipped to
  [0, 0.9] (with ~18 cycles a batch-means estimate would have 3-6 batches; the AR(1) factor is
  the usual large-sample correction, e.g. Bayley & Hammersley 1946, Flyvbjerg & Petersen 1989).
  eta*'s error is ``|eta*|`` times the relative standard error of the mean cycle energy.
* **Steady state.** The means of the first and the second half of the analysed cycles agree
  within two combined standard errors (a Geweke-style drift test), with at least
  :data:`MIN_CYCLES` analysed cycles. A run still settling into its motion mode fails it.

Statistics over a handful of cycles are rough: they tell a steady run from a drifting one and a
well-known eta* from a poorly known one, not more.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CycleStatistics", "cycle_statistics", "MIN_CYCLES"]

#: Analysed cycles needed before a run is called steady.
MIN_CYCLES = 4


@dataclass(frozen=True, kw_only=True)
class CycleStatistics:
    """eta*'s statistical error and the steady-state flag of one analysed record.

    eta_star_error : standard error of eta* over the analysed cycles [-] (NaN below 2 cycles).
    relative_error : the same relative to the mean cycle energy [-].
    correlation : lag-1 autocorrelation of the cycle energies used for the inflation (clipped).
    drift : second half's mean cycle energy minus the first's, relative to the mean [-].
    steady : True when at least MIN_CYCLES cycles were analysed and the drift is within two
        standard errors.
    cycles : analysed cycles.
    """

    eta_star_error: float
    relative_error: float
    correlation: float
    drift: float
    steady: bool
    cycles: int


def _inflation(e: np.ndarray) -> tuple[float, float]:
    """AR(1) inflation factor of the standard error and the clipped lag-1 autocorrelation."""
    if e.size < 3:
        return 1.0, 0.0
    d = e - e.mean()
    den = float(np.dot(d, d))
    r1 = float(np.dot(d[:-1], d[1:]) / den) if den > 0 else 0.0
    r1 = min(max(r1, 0.0), 0.9)
    return math.sqrt((1.0 + r1) / (1.0 - r1)), r1


def cycle_statistics(cycle_energies, used, eta_star: float) -> CycleStatistics:
    """Statistics of the analysed cycles: ``cycle_energies`` [J] of every whole cycle, ``used`` the
    mask of the analysed ones (as in :class:`~pdamper.analysis.PowerResult`), ``eta_star`` the
    record's eta*.

    >>> s = cycle_statistics([5.0, 1.0, 1.0, 1.1, 0.9, 1.0], [False, True, True, True, True, True], 0.5)
    >>> round(s.eta_star_error, 4), s.steady, s.cycles
    (0.0158, True, 5)
    """
    e = np.asarray(cycle_energies, dtype=float)[np.asarray(used, dtype=bool)]
    n = int(e.size)
    mean = float(e.mean()) if n else math.nan
    if n < 2 or not (mean != 0.0 and math.isfinite(mean)):
        return CycleStatistics(eta_star_error=math.nan, relative_error=math.nan, correlation=math.nan,
                               drift=math.nan, steady=False, cycles=n)
    inflate, r1 = _inflation(e)
    rel = float(np.std(e, ddof=1)) / math.sqrt(n) * inflate / abs(mean)
    half = n // 2
    first, second = e[:half], e[n - half:]
    drift = (float(second.mean()) - float(first.mean())) / abs(mean) if half else math.nan
    steady = False
    if n >= MIN_CYCLES:
        var = (np.var(first, ddof=1) / first.size + np.var(second, ddof=1) / second.size) if half >= 2 else 0.0
        spread = 2.0 * math.sqrt(var) * inflate / abs(mean)
        steady = bool(abs(drift) <= spread)
    return CycleStatistics(eta_star_error=abs(float(eta_star)) * rel, relative_error=rel, correlation=r1, drift=drift,
                           steady=steady, cycles=n)
