"""Helpers shared by the ensemble tests (tests/studies/test_ensemble.py, tests/plotting/test_ensemble_plots.py)."""

from __future__ import annotations

from dem_fixtures import locked_case
from pdamper.config import loads_case
from pdamper.studies.ensemble import EnsembleSpec, EnsembleStore
from pdamper.studies.unknowns import Unknown, Unknowns

#: One unknown: the structure's stiffness, 10 % off (as a U.toml file: :data:`STIFFNESS_TOML`).
STIFFNESS = Unknowns((Unknown(key="structure.stiffness_scale", distribution="normal", mean=1.0, std=0.1),))
STIFFNESS_TOML = '[[unknown]]\nkey = "structure.stiffness_scale"\ndistribution = "normal"\nmean = 1.0\nstd = 0.1\n'
#: The synthetic ensembles' case: a locked bed on a structure of one mode given as data (dofs damper,
#: force, response) under a force history.
SYNTHETIC_CASE = locked_case('kind = "force_history"\ntime = [0, 0.1]\nforce = [0, 1.0]\nduration = "0.5s"',
                             structure='modes = [{frequency = "3Hz", damping_ratio = 0.02, modal_mass = "2kg", '
                                       'damper = 1.0, force = 1.0, response = 0.5}]', text=True)


def synthetic_store(tmp_path, ratios, unknowns=STIFFNESS, samples: int | None = None):
    """A transient ensemble's store whose samples' records are written by hand (no DEM): sample i has
    peak ratios ``ratios[i]`` (or ``ratios(values)`` of its sampled values; None: failed) at the two
    dofs of a modal structure, RMS ratios 0.9 of them."""
    base = loads_case(SYNTHETIC_CASE)
    spec = EnsembleSpec(base=base, unknowns=unknowns, samples=samples or len(ratios), study="transient",
                        dofs=("damper", "response"))
    store = EnsembleStore.create_or_open(tmp_path / "store", spec)
    if callable(ratios):
        ratios = [ratios(v) for v in spec.drawn.points()]
    for (key, point, seed, _), r in zip(spec.items(), ratios):
        if r is None:
            store.save_sample(key, point, seed, {"failed": "a synthetic failure"})
            continue
        store.save_sample(key, point, seed, {
            "peak_m": [0.01 * x for x in r], "rms_m": [0.005 * x for x in r], "peak_bare_m": [0.01, 0.01],
            "rms_bare_m": [0.005, 0.005], "peak_ratio": list(r), "rms_ratio": [0.9 * x for x in r],
            "damper_peak_ratio": r[0], "damper_rms_ratio": 0.9 * r[0], "energy_balance_error": 1e-4,
            "steps": 10, "wall_time_s": 1.0})
    return spec, store
