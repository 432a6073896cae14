r"""How well a run's eta* is known and whether the run has reached steady state, from the energy
dissipated in each analysed drive cycle.

The complex power gives one eta* over the analysed window (eq. 5); the energies of the single
cycles, ``E_k = int F v dt`` over cycle k, scatter around its energy per cycle because the bed
does not repeat itself exactly. Their spread says how well eta* is known:

* **Standard error.** The long-run variance of the cycle energies over n analysed cycles,
  estimated with Bartlett weights up to lag ``L = round(n^(1/3))`` (Newey & West 1987: the
  autocovariances ``g_k`` weighted by ``1 - k/(L+1)``; never negative), over n, square-rooted.
  Neighbouring cycles are correlated both ways: energy the bed stores at one cycle's end is
  given back in the next (negative lag-1 correlation, -0.2 to -0.55 at 14 mm), and a bed in a
  slowly changing state repeats itself (positive). eta*'s error is ``|eta*|`` times the relative
  standard error of the mean cycle energy. Measured against the spread of six seeds
  (CHANGELOG.md, "Performance history", "Steady state"): about twice that spread where the bed has one state,
  and blind to a choice between two states that a run never leaves.
* **Steady state.** The means of the first and the second half of the analysed cycles agree
  within two combined standard errors (a Geweke-style drift test; the long-run variance taken
  about each half's own mean), with at least
  :data:`MIN_CYCLES` analysed cycles. A run still settling into its motion mode fails it.

Statistics over a handful of cycles are rough: they tell a steady run from a drifting one and a
well-known eta* from a poorly known one, not more.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["CycleStatistics", "cycle_statistics", "MIN_CYCLES", "MIN_STEADY_CYCLES"]

#: Analysed cycles needed before a run is called steady.
MIN_CYCLES = 4

#: Analysed cycles a run with ``until_steady`` always drives (after the dropped ones) before it
#: may stop: fewer give too rough an error to stop on.
MIN_STEADY_CYCLES = 6


@dataclass(frozen=True, kw_only=True)
class CycleStatistics:
    """eta*'s statistical error and the steady-state flag of one analysed record.

    eta_star_error : standard error of eta* over the analysed cycles [-] (NaN below 2 cycles).
    relative_error : the same relative to the mean cycle energy [-].
    correlation : lag-1 autocorrelation of the cycle energies [-].
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


def _long_run_variance(d: np.ndarray) -> tuple[float, float]:
    """Bartlett-weighted long-run variance of the deviations ``d`` from their mean (lags up to
    round(n^(1/3))) and the lag-1 autocorrelation."""
    n = d.size
    g0 = float(np.dot(d, d)) / n
    lags = max(1, int(round(n ** (1.0 / 3.0))))
    lr = g0
    r1 = 0.0
    for k in range(1, min(lags, n - 1) + 1):
        gk = float(np.dot(d[:-k], d[k:])) / n
        if k == 1 and g0 > 0:
            r1 = gk / g0
        lr += 2.0 * (1.0 - k / (lags + 1.0)) * gk
    return max(lr, 0.0) * n / (n - 1), r1


def cycle_statistics(cycle_energies, used, eta_star: float) -> CycleStatistics:
    """Statistics of the analysed cycles: ``cycle_energies`` [J] of every whole cycle, ``used`` the
    mask of the analysed ones (as in :class:`~pdamper.analysis.PowerResult`), ``eta_star`` the
    record's eta*.

    >>> s = cycle_statistics([5.0, 1.0, 1.1, 0.9, 1.0, 1.05, 0.95, 1.0], [False] + [True] * 7, 0.5)
    >>> round(s.eta_star_error, 4), s.steady, s.cycles
    (0.0055, True, 7)
    >>> cycle_statistics([1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7], [True] * 8, 0.5).steady  # a drift
    False
    """
    e = np.asarray(cycle_energies, dtype=float)[np.asarray(used, dtype=bool)]
    n = int(e.size)
    mean = float(e.mean()) if n else math.nan
    if n < 2 or not (mean != 0.0 and math.isfinite(mean)):
        return CycleStatistics(eta_star_error=math.nan, relative_error=math.nan, correlation=math.nan,
                               drift=math.nan, steady=False, cycles=n)
    var, r1 = _long_run_variance(e - mean)
    rel = math.sqrt(var / n) / abs(mean)
    half = n // 2
    first, second = e[:half], e[n - half:]
    drift = (float(second.mean()) - float(first.mean())) / abs(mean) if half else math.nan
    steady = False
    if n >= MIN_CYCLES:
        # the two halves' means, with the long-run variance about each half's own mean (a drift
        # would otherwise widen the very error it is judged against)
        within, _ = _long_run_variance(np.concatenate([first - first.mean(), second - second.mean()]))
        steady = bool(abs(drift) <= 2.0 * math.sqrt(2.0 * within / half) / abs(mean))
    return CycleStatistics(eta_star_error=abs(float(eta_star)) * rel, relative_error=rel, correlation=r1, drift=drift,
                           steady=steady, cycles=n)
