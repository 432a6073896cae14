"""What a recorder is: one small protocol for everything a run records.

A recorder says what it needs and how often, receives it during the run, and returns its result
at the end (after OpenMM's reporters and HOOMD's writers)::

    class Recorder(Protocol):
        name: str                  # key of its result in RunRecord.outputs
        channels: frozenset[str]   # kernel channels it reads at the end (see below)
        every: int                 # call record() every `every` samples; 0: never
        def start(self, run: RunInfo) -> None: ...
        def record(self, state: State) -> None: ...
        def finalize(self, data: Recorded) -> object: ...   # arrays, a dataclass or an xarray.Dataset

Time is counted in **samples** of ``recording.sample_rate`` (1 kHz by default); sample ``k``
ends at ``(k + 1) / sample_rate`` after the drive starts.

**Kernel channels** are what the compiled time loop writes at the end of every sample interval
(:func:`pdamper.kernels.record.record_sample`), for the recorders that ask for them: the mean
wall force along the drive (``"wall_force"``, impulse over the interval, so impacts are not
aliased), the seven energies of the ledger (``"energy"``), frames of all spheres every
``frame_every`` samples (``"frames"``; the recorder sets ``frame_every``), the coupled
structure's state (``"structure"``), the ledger's dissipation by contact type (``"energy_by_contact"``:
normal damping and friction of sphere pairs, the floor, the other walls and the baffles,
:class:`~pdamper.recorders.contacts.ContactEnergyRecorder`). A channel nobody asks for is not
computed: without ``"energy_by_contact"`` the kernels are compiled without the split. The built-in
recorders (:class:`~pdamper.recorders.signals.SignalsRecorder`,
:class:`~pdamper.recorders.energy.EnergyRecorder`,
:class:`~pdamper.recorders.trajectory.TrajectoryRecorder`,
:class:`~pdamper.recorders.structure.StructureRecorder`) read only channels.

**Python recorders** set ``every > 0``: the simulation stops its compiled loop at the end of
every ``every``-th sample and calls ``record(state)`` with a read-only :class:`State` (positions,
velocities, spins, the container's motion, the running energy sums). That costs a return to
Python per call (tens of microseconds), so choose ``every`` accordingly; no kernel changes. A
Python recorder that asks for the ``"contacts"`` channel finds in ``state.contacts`` the contacts
touching at that sample and their normal forces (:class:`~pdamper.recorders.contacts.Contacts`,
listed then and only for the samples such a recorder is due at;
:class:`~pdamper.recorders.contacts.ContactsRecorder` keeps them, with the coordination number).

Example -- the bed's kinetic energy in the lab frame, every 10 samples (``examples/
kinetic_energy_recorder.py`` runs it; ``docs/engine.md`` explains it)::

    import numpy as np
    import xarray as xr

    class BedKineticEnergy:
        name = "bed_kinetic_energy"
        channels = frozenset()

        def __init__(self, every=10):
            self.every = every

        def start(self, run):
            self.mass, self.time, self.energy = run.mass, [], []

        def record(self, state):
            v = state.velocity + state.container_velocity * state.direction   # lab frame
            self.time.append(state.time)
            self.energy.append(0.5 * float(np.sum(self.mass * np.sum(v * v, axis=1))))

        def finalize(self, data):
            return xr.Dataset({"kinetic_energy": ("time", np.array(self.energy), {"units": "J"})},
                              coords={"time": ("time", np.array(self.time), {"units": "s"})})

    result = pdamper.run_case(case, recorders=[BedKineticEnergy()])
    result.recorded["bed_kinetic_energy"]
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Protocol, runtime_checkable

import numpy as np

from ..errors import shown

__all__ = ["Recorder", "RunInfo", "State", "Recorded", "CHANNELS", "check_recorders"]

#: The channels a recorder may ask for: the kernel channels, and ``"contacts"`` (a Python recorder's
#: ``state.contacts``).
CHANNELS = ("wall_force", "energy", "frames", "structure", "energy_by_contact", "contacts")


@runtime_checkable
class Recorder(Protocol):
    """The recorder protocol (see the module docstring)."""

    name: str
    channels: frozenset
    every: int

    def start(self, run: "RunInfo") -> None: ...

    def record(self, state: "State") -> None: ...

    def finalize(self, data: "Recorded") -> Any: ...


@dataclass(frozen=True, kw_only=True)
class RunInfo:
    """What a recorder learns when the run starts.

    Attributes: ``case``; ``interval`` [s] between samples; ``n_samples`` of the driven phase;
    ``radius`` [m] and ``mass`` [kg] of each sphere (N,); ``direction`` (3,) the drive direction and
    ``gravity`` (3,) [m/s^2] in the container frame; ``frame_every`` samples per frame of the
    ``"frames"`` channel (0: none).
    """

    case: Any
    interval: float
    n_samples: int
    radius: np.ndarray
    mass: np.ndarray
    direction: np.ndarray
    gravity: np.ndarray
    frame_every: int = 0


@dataclass(frozen=True, kw_only=True)
class State:
    """The state at the end of sample ``sample`` (time ``time`` [s] after the drive started), as
    a Python recorder sees it: read-only views, valid during the call (copy what you keep).

    Attributes: ``position`` [m], ``velocity`` [m/s] (relative to the container), ``spin``
    [rad/s], each (N, 3) in the container frame; the container's ``container_position`` [m],
    ``container_velocity`` [m/s], ``container_acceleration`` [m/s^2] along ``direction`` (3,);
    the running sums since the drive started: ``work`` done by the container on the spheres,
    energy dissipated by normal ``damping`` and by ``friction`` [J]; ``contacts`` the contacts
    touching now (:class:`~pdamper.recorders.contacts.Contacts`) when a due recorder asks for the
    ``"contacts"`` channel, else None.
    """

    sample: int
    time: float
    position: np.ndarray
    velocity: np.ndarray
    spin: np.ndarray
    container_position: float
    container_velocity: float
    container_acceleration: float
    direction: np.ndarray
    work: float
    damping: float
    friction: float
    contacts: Any = None


@dataclass(frozen=True, kw_only=True)
class Recorded:
    """The kernel channels at the end of the run, for :meth:`Recorder.finalize`.

    Attributes: ``info`` (:class:`RunInfo`); ``time_end`` [s] the end of each sample interval;
    ``channels``: name -> array of each channel the run recorded (``wall_force`` (n,) [N],
    ``energy`` (n, 7) [J], ``frames`` (F, N, 9), ``structure`` (n, 6 + modes), ``energy_by_contact``
    (n, 4, 2) [J]: damping and friction by contact type, :data:`pdamper.kernels.bundles.CONTACT_TYPES`).
    """

    info: RunInfo
    time_end: np.ndarray
    channels: dict = field(default_factory=dict)


def check_recorders(recorders) -> list:
    """The recorders as a list, each checked against the protocol: a clear error instead of an
    AttributeError in the middle of a run."""
    out = list(recorders)
    names = set()
    for r in out:
        missing = [a for a in ("name", "channels", "every", "start", "record", "finalize") if not hasattr(r, a)]
        if missing:
            raise TypeError(f"{shown(r)} is not a recorder: it lacks {', '.join(missing)} "
                            "(see pdamper.recorders.base for the protocol and an example)")
        unknown = set(r.channels) - set(CHANNELS)
        if unknown:
            raise ValueError(f"recorder {shown(r.name)} asks for unknown channels {sorted(unknown)}; "
                             f"the kernel channels are {', '.join(CHANNELS)}")
        if not (isinstance(r.every, (int, np.integer)) and r.every >= 0):
            raise ValueError(f"recorder {shown(r.name)}: every = {shown(r.every)}; give a whole number of samples >= 0")
        if "contacts" in r.channels and r.every == 0:
            raise ValueError(f"recorder {shown(r.name)} asks for the contacts channel with every = 0; the contacts are "
                             "listed at the samples a recorder is due at: give every >= 1")
        if r.name in names:
            raise ValueError(f"two recorders are named {shown(r.name)}; give each its own name")
        names.add(r.name)
    return out
