"""The contacts of a run: the ledger's dissipation by contact type, and the contacts themselves.

**By contact type** (:class:`ContactEnergyRecorder`, kernel channel ``"energy_by_contact"``): the
energy dissipated by normal damping and by friction since the drive started, at the end of each
sample, for each contact type of :data:`CONTACT_TYPES` -- sphere-sphere pairs, the floor, the
container's other walls, the baffles -- as a :class:`ContactLedger`. The kernels integrate each
type's powers as they integrate the totals (:func:`pdamper.kernels.record.integrate_split`), so the
parts sum to the ledger's ``damping`` and ``friction`` to rounding. Asked for, the split is compiled
into the kernels; not asked for, it is not there (the kernels are a run's without it).

**The contacts** (:class:`ContactsRecorder`, channel ``"contacts"``): every ``every`` samples, the
contacts touching then -- sphere pairs ``(i, j)`` and sphere-wall contacts -- with each one's normal
force (:class:`Contacts`), listed only at those samples; :meth:`ContactRecord.coordination_number`
(and :func:`coordination_number` on one :class:`Contacts`) is the mean number of contacts a sphere
has, counted from them, with no overlap tolerance of one's own.

Example::

    from pdamper import run_case
    from pdamper.recorders.contacts import ContactEnergyRecorder, ContactsRecorder

    res = run_case(case, recorders=[ContactEnergyRecorder(), ContactsRecorder(every=10)])
    split = res.recorded["energy_by_contact"]     # ContactLedger
    split.damping[-1], split.friction[-1]         # [J] per type (sphere, floor, wall, baffle)
    z = res.recorded["contacts"].coordination_number()   # per recorded sample
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._repr import short_repr
from ..errors import shown
from ..kernels.bundles import CONTACT_TYPES

__all__ = ["CONTACT_TYPES", "ContactLedger", "ContactEnergyRecorder", "Contacts", "ContactRecord", "ContactsRecorder",
           "coordination_number"]


@dataclass(frozen=True, kw_only=True)
class ContactLedger:
    """The energy dissipated since the drive started by contact type, at the end of each sample.

    Attributes: ``time`` (n,) [s]; ``damping`` and ``friction`` (n, 4) [J], by normal damping and by
    friction, columns :attr:`types` (:data:`CONTACT_TYPES`: ``sphere``, ``floor``, ``wall``, ``baffle``).
    Each type's sum over the columns is the run's :class:`~pdamper.recorders.energy.EnergyLedger`
    ``damping`` and ``friction`` to rounding (:attr:`total_damping`, :attr:`total_friction`).
    """

    time: np.ndarray
    damping: np.ndarray
    friction: np.ndarray
    types: tuple = CONTACT_TYPES

    def of(self, kind: str) -> tuple[np.ndarray, np.ndarray]:
        """(damping, friction) [J] over time of one contact type (``"sphere"``, ``"floor"``, ...)."""
        if kind not in self.types:
            raise ValueError(f"contact type {shown(kind)}: choose one of {', '.join(self.types)}")
        k = self.types.index(kind)
        return self.damping[:, k], self.friction[:, k]

    @property
    def total_damping(self) -> np.ndarray:
        """The types' damping summed [J] (the ledger's ``damping``)."""
        return self.damping.sum(axis=1)

    @property
    def total_friction(self) -> np.ndarray:
        """The types' friction summed [J] (the ledger's ``friction``)."""
        return self.friction.sum(axis=1)

    def to_dataset(self):
        """An :class:`xarray.Dataset` with ``damping`` and ``friction`` over (``time``, ``contact``)."""
        import xarray as xr

        coords = {"time": ("time", self.time, {"units": "s"}), "contact": ("contact", list(self.types))}
        return xr.Dataset({"damping": (("time", "contact"), self.damping, {"units": "J"}),
                           "friction": (("time", "contact"), self.friction, {"units": "J"})}, coords=coords)


class ContactEnergyRecorder:
    """The ledger's dissipation by contact type (kernel channel ``"energy_by_contact"``) as a
    :class:`ContactLedger` (module docstring)."""

    channels = frozenset({"energy_by_contact"})
    every = 0

    def __init__(self, *, name: str = "energy_by_contact"):
        self.name = name

    def start(self, run) -> None:
        pass

    def record(self, state) -> None:  # kernel channels only
        pass

    def finalize(self, data) -> ContactLedger:
        split = data.channels["energy_by_contact"]
        return ContactLedger(time=data.time_end, damping=split[:, :, 0].copy(), friction=split[:, :, 1].copy())


@dataclass(frozen=True, kw_only=True)
class Contacts:
    """The contacts touching at one time (:meth:`pdamper.simulation.Simulation.contacts`).

    Attributes: ``time`` [s]; ``ends`` (M, 2) int, a row per contact: spheres ``(i, j)``, ``i < j``, or
    sphere ``i`` on wall ``w`` as ``j = -1 - w`` (``wall_names[w]``); ``normal_force`` (M,) [N], the
    contact law's, pushing when positive; ``kind`` (M,) int, the row of :data:`CONTACT_TYPES`;
    ``n_spheres`` the spheres of the bed. Touching: the bodies overlap (the force loops' test).
    """

    time: float
    ends: np.ndarray
    normal_force: np.ndarray
    kind: np.ndarray
    wall_names: tuple = ()
    n_spheres: int = 0

    @property
    def pairs(self) -> np.ndarray:
        """(P, 2) the sphere pairs in contact."""
        return self.ends[self.kind == CONTACT_TYPES.index("sphere")]

    def per_sphere(self, walls: bool = False) -> np.ndarray:
        """(N,) the contacts of each sphere: its sphere partners, with ``walls`` its walls too."""
        out = np.zeros(self.n_spheres, dtype=np.int64)
        pairs = self.pairs
        np.add.at(out, pairs[:, 0], 1)
        np.add.at(out, pairs[:, 1], 1)
        if walls:
            np.add.at(out, self.ends[self.ends[:, 1] < 0, 0], 1)
        return out


def coordination_number(contacts: Contacts, *, walls: bool = False, rattlers: bool = True) -> float:
    """The mean number of contacts of a sphere, ``Z = 2 P / N`` for P sphere pairs in contact among N
    spheres (``walls``: each sphere-wall contact counts one for its sphere too; ``rattlers = False``:
    the mean over the spheres with at least two contacts, the mechanical coordination number of
    granular packings). NaN for no sphere (or no sphere left)."""
    per = contacts.per_sphere(walls)
    if not rattlers:
        per = per[per >= 2]
    return float(per.mean()) if per.size else float("nan")


@dataclass(frozen=True, kw_only=True)
class ContactRecord:
    """The contacts at each recorded sample (:class:`ContactsRecorder`): ``time`` (k,) [s] and
    ``contacts`` (a :class:`Contacts` per time)."""

    time: np.ndarray
    contacts: tuple

    def coordination_number(self, *, walls: bool = False, rattlers: bool = True) -> np.ndarray:
        """(k,) :func:`coordination_number` at each recorded time."""
        return np.array([coordination_number(c, walls=walls, rattlers=rattlers) for c in self.contacts])


class ContactsRecorder:
    """The contacts touching every ``every`` samples and their normal forces (channel
    ``"contacts"``; module docstring) as a :class:`ContactRecord`."""

    channels = frozenset({"contacts"})

    def __init__(self, every: int = 10, *, name: str = "contacts"):
        if isinstance(every, bool) or not isinstance(every, (int, np.integer)) or every < 1:
            raise ValueError(f"ContactsRecorder: every = {shown(every)}; give a whole number of samples >= 1")
        self.every = int(every)
        self.name = name

    def start(self, run) -> None:
        self.seen = []

    def record(self, state) -> None:
        self.seen.append(state.contacts)

    def finalize(self, data) -> ContactRecord:
        return ContactRecord(time=np.array([c.time for c in self.seen]), contacts=tuple(self.seen))


# short reprs: names, shapes and key numbers (a notebook shows a line, not a dump)
for _cls in (ContactLedger, Contacts, ContactRecord):
    _cls.__repr__ = short_repr
