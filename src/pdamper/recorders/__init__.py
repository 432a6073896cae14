"""What a run records, in memory, through one protocol (:mod:`.base`): the driving force and
container motion (:mod:`.signals`), the energy ledger (:mod:`.energy`), decimated trajectories
(:mod:`.trajectory`), the coupled structure (:mod:`.structure`), the contacts and the ledger by
contact type (:mod:`.contacts`). A new recorder needs no kernel
change (see :mod:`.base` for the protocol and an example). File formats are :mod:`pdamper.io`'s
business."""

from .base import CHANNELS, Recorded, Recorder, RunInfo, State
from .contacts import (ContactEnergyRecorder, ContactLedger, ContactRecord, Contacts, ContactsRecorder,
                       coordination_number)
from .energy import EnergyLedger, EnergyRecorder
from .signals import Signals, SignalsRecorder
from .structure import StructureRecord, StructureRecorder
from .trajectory import TrajectoryRecorder

__all__ = ["Recorder", "RunInfo", "State", "Recorded", "CHANNELS", "Signals", "SignalsRecorder", "EnergyLedger",
           "EnergyRecorder", "StructureRecord", "StructureRecorder", "TrajectoryRecorder", "ContactEnergyRecorder",
           "ContactLedger", "ContactsRecorder", "ContactRecord", "Contacts", "coordination_number"]
