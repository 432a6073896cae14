"""Analysis of force/motion records: the complex power method (paper Sect. 4.1).

Pure functions on arrays; they know nothing of the simulator, files or plots.

- :func:`complex_power` -- eqs. (3)-(5) from time, force and velocity samples:
  complex power ``P = 1/2 F* conj(V*)`` [W], energy dissipated per cycle
  ``E~_diss = (2 pi / Omega) Re(P)`` [J] and reduced loss factor
  ``eta* = E_diss / (1/2 m_bed |V*|^2)`` [-], over whole cycles after dropping the
  first two; with a time-domain cross-check and per-cycle energies.
- :func:`analyze_record` -- the same from any one motion signal (position,
  velocity or acceleration), e.g. a measured record read with
  :func:`pdamper.io.records.read_record`.
- :func:`detect_frequency` -- the drive frequency of a motion signal.
- :class:`PowerResult` -- the frozen result, with ``to_dict()`` for JSON.

Motion modes (:mod:`.modes`, docs/motion.md), from particle trajectories:

- :func:`classify_trajectory` -- the mode (:data:`MODES`: scattered, rolling collect-and-collide,
  swaying, single-sided, locked, lift-off for a bed moved along the floor; bouncing bed, bouncing
  collect-and-collide, fluidised for a vertical drive; compartment collect-and-collide for a
  baffled bed) and the measured features of a recorded trajectory of a case;
- :func:`mode_features`, :func:`classify_features` -- the same in two steps, on plain arrays
  (:func:`pdamper.analysis.modes.vertical_features`, ``compartment_features`` for the other
  families); :data:`THRESHOLDS` the thresholds.
- :func:`extrema`, :func:`decay_damping`, :func:`harmonic_amplitude` -- a structure's free
  decay (envelope, equivalent damping ratio against amplitude) and forced steady amplitude.
"""

from __future__ import annotations

from .complex_power import (
    DEFAULT_DROP_CYCLES,
    MOTIONS,
    TIME_TOLERANCE,
    PowerResult,
    Signals,
    analyze_record,
    complex_power,
    detect_frequency,
)
from .modes import MODES, THRESHOLDS, ModeFeatures, classify_features, classify_trajectory, mode_features
from .decay import decay_damping, extrema, harmonic_amplitude

__all__ = [
    "complex_power",
    "analyze_record",
    "detect_frequency",
    "PowerResult",
    "Signals",
    "DEFAULT_DROP_CYCLES",
    "TIME_TOLERANCE",
    "MOTIONS",
    "classify_trajectory",
    "mode_features",
    "classify_features",
    "ModeFeatures",
    "MODES",
    "THRESHOLDS",
    "extrema",
    "decay_damping",
    "harmonic_amplitude",
]
