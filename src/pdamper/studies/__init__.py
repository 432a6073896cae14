"""Parameter studies: stroke sweeps over seeds, run on all local cores or a Dask cluster,
written case by case to a resumable result store.

- :mod:`.sweep` -- what a sweep is (strokes x seeds over a base case) and how one case runs.
- :mod:`.store` -- the result store: one atomically written file per finished case.
- :mod:`.executor` -- where the cases run: an embedded local Dask cluster or a scheduler address.
- :mod:`.unknowns`, :mod:`.ensemble` -- ensembles over the unknowns: a file of distributions over
  case keys, its Latin hypercube samples, every sample run and stored with a ``sample`` dimension.
"""

from .store import ResultStore
from .sweep import Axis, SweepSpec, open_results, parse_axis, parse_strokes, run_sweep, stroke_grid

__all__ = ["Axis", "parse_axis", "SweepSpec", "parse_strokes", "stroke_grid", "run_sweep", "ResultStore", "open_results"]
