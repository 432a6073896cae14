"""The energy ledger of a run, and whether it balances.

Columns (all [J], lab frame, at the end of each sample interval): kinetic, rotational,
potential (gravity), elastic (Hertz springs, 2/5 k delta^5/2), the work done by the container
on the particles since the drive started (``int v_c d.F_walls dt``; on a structure under a ground
acceleration, kept in the ground's frame, also the ground's inertial force's, ``-int a_g P dt`` with
P the bed's momentum along the drive), and the energy dissipated since then by normal damping and by
friction. Balance:
``E_kin + E_rot + E_pot + E_el - W + D_n + D_f = const``.
"""

from __future__ import annotations

from .._repr import short_repr

from dataclasses import dataclass

import numpy as np

__all__ = ["EnergyLedger", "EnergyRecorder", "COLUMNS"]

#: The ledger's columns, as the kernel's ``"energy"`` channel holds them.
COLUMNS = ("kinetic", "rotational", "potential", "elastic", "work", "damping", "friction")


@dataclass(frozen=True, kw_only=True)
class EnergyLedger:
    """Energies [J] over time [s]; see the module docstring for the balance."""

    time: np.ndarray
    kinetic: np.ndarray
    rotational: np.ndarray
    potential: np.ndarray
    elastic: np.ndarray
    work: np.ndarray
    damping: np.ndarray
    friction: np.ndarray

    @classmethod
    def from_array(cls, time, eng) -> "EnergyLedger":
        return cls(time=np.asarray(time), **{c: eng[:, k].copy() for k, c in enumerate(COLUMNS)})

    @property
    def mechanical(self) -> np.ndarray:
        """Kinetic + rotational + potential + elastic [J]."""
        return self.kinetic + self.rotational + self.potential + self.elastic

    @property
    def residual(self) -> np.ndarray:
        """``mechanical - work + dissipated`` minus its first value [J]; zero for a closed balance."""
        r = self.mechanical - self.work + self.damping + self.friction
        return r - r[0]

    def balance_error(self) -> float:
        """Largest |residual| relative to the total work done and energy dissipated [-]."""
        scale = max(np.max(np.abs(self.work)), np.max(self.damping + self.friction), 1e-300)
        return float(np.max(np.abs(self.residual)) / scale)

    def dissipated_per_cycle(self, case) -> float:
        """Energy dissipated per drive cycle [J] over the analysed window (after ``drop_cycles``), from the ledger."""
        f = case.drive.frequency
        if not f:
            return float("nan")
        period = 1.0 / f
        t0 = case.drop_cycles * period
        n_cyc = int(np.floor((self.time[-1] - t0) / period + 1e-6))
        if n_cyc < 1:
            return float("nan")
        diss = self.damping + self.friction
        d0 = np.interp(t0, self.time, diss, left=0.0)
        d1 = np.interp(t0 + n_cyc * period, self.time, diss)
        return float((d1 - d0) / n_cyc)


class EnergyRecorder:
    """The energy ledger (kernel channel ``"energy"``) as an :class:`EnergyLedger`."""

    name = "energy"
    channels = frozenset({"energy"})
    every = 0

    def start(self, run) -> None:
        pass

    def record(self, state) -> None:  # kernel channels only
        pass

    def finalize(self, data) -> EnergyLedger:
        return EnergyLedger.from_array(data.time_end, data.channels["energy"])


# short reprs: names, shapes and key numbers (a notebook shows a line, not a dump)
EnergyLedger.__repr__ = short_repr
