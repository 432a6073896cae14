"""What a run records, in memory: the driving force and container motion (:mod:`.signals`),
the energy ledger (:mod:`.energy`), and decimated trajectories (arrays in ``RunResult``).
File formats are :mod:`pdamper.io`'s business."""

from .energy import EnergyLedger
from .signals import Signals

__all__ = ["Signals", "EnergyLedger"]
