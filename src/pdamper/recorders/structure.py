"""What a run on a coupled structure records about the structure, and the coupled energy ledger.

The kernels write, at the end of each sample interval, the structure's displacement x_s [m],
velocity v_s [m/s], the work done on it by the external force [J] and the energy its own
damping dissipated [J] (both since the drive started). With the particles' ledger
(:class:`pdamper.recorders.energy.EnergyLedger`, whose ``work`` is the work the container
walls did on the bed, the same sum the structure lost to the bed) the whole system balances:

    E_struct + E_bed + D_struct + D_bed - W_ext = const,

``E_struct = 1/2 M v_s^2 + 1/2 K x_s^2`` (N modes: ``sum_k 1/2 m_k q_k'^2 + 1/2 k_k q_k^2``, written by
the kernels), ``E_bed`` the bed's mechanical energy (lab frame), ``D_bed`` its damping and friction
losses. The response point's displacement (N modes: ``sum_k phi_k(response) q_k``; one mode: x_s)
is recorded too.

Under a ground acceleration the ledger is kept in the ground's frame: ``W_ext`` is the work of the
ground's inertial force on the whole system, the bed's share included (which the bed's ``work`` holds
too), so the balance closes as under a force (docs/structure.md, "Energy ledger of the coupled
system").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._deprecated import renamed
from .._repr import short_repr

__all__ = ["StructureRecord", "StructureRecorder"]


@dataclass(frozen=True, kw_only=True)
class StructureRecord:
    """The structure's motion and energies at the sample ends ``time`` [s] (``x0_m``, ``v0_m_s``:
    at t = 0).

    Attributes: time [s], displacement [m], velocity [m/s], external_work [J], damping_loss [J]
    (arrays, named by quantity), and the structure's ``mass_kg``, ``stiffness_N_m`` [N/m], initial
    displacement ``x0_m`` and velocity ``v0_m_s`` (numbers, named with their unit). ``mass``,
    ``stiffness``, ``x0`` and ``v0`` are deprecated names of the last four.
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    external_work: np.ndarray
    damping_loss: np.ndarray
    mass_kg: float
    stiffness_N_m: float
    x0_m: float = 0.0
    v0_m_s: float = 0.0
    #: the response point's displacement [m] (None: not recorded)
    response_displacement: np.ndarray | None = None
    #: the structure's mechanical energy [J] as the kernels wrote it, and at t = 0 (N modes; None:
    #: one mode, whose energy is 1/2 M v^2 + 1/2 K x^2 of the recorded motion)
    mechanical_energy: np.ndarray | None = None
    initial_energy_J: float | None = None
    #: the modal coordinates q_k [m or the modes' normalisation], (samples, modes) (one mode: x_s;
    #: None: not recorded); every dof's motion is ``q @ shapes.T`` (:meth:`dof_displacements`)
    modal_coordinates: np.ndarray | None = None

    mass = renamed("mass_kg")
    stiffness = renamed("stiffness_N_m")
    x0 = renamed("x0_m")
    v0 = renamed("v0_m_s")

    @classmethod
    def from_channel(cls, case, data) -> "StructureRecord":
        """From the kernel channel ``"structure"`` of a run (:class:`~pdamper.recorders.base.Recorded`)."""
        out = data.channels["structure"]
        return cls.from_array(case.running_drive, (np.arange(out.shape[0]) + 1) * data.info.interval, out)

    @classmethod
    def from_array(cls, structure, time, out) -> "StructureRecord":
        """From the kernels' rows ``out`` (columns ``STRUCTURE_COLUMNS``) at ``time`` [s] of ``structure``
        (a structure of :mod:`pdamper.structure`)."""
        info = structure.record_info()
        energy = out[:, 4].copy() if info.get("initial_energy_J") is not None else None
        q = out[:, 6:].copy() if out.shape[1] > 6 else None
        return cls(time=time, displacement=out[:, 0].copy(), velocity=out[:, 1].copy(),
                   external_work=out[:, 2].copy(), damping_loss=out[:, 3].copy(),
                   response_displacement=out[:, 5].copy(), mechanical_energy=energy, modal_coordinates=q, **info)

    def dof_displacements(self, shapes) -> np.ndarray:
        """Every dof's displacement [m] (samples, dofs) from the recorded modal coordinates and the
        mode ``shapes`` (dofs, modes) of the structure as it ran (with the empty container's mass:
        :meth:`pdamper.structure.StructureBase.dof_shapes` of ``case.running_drive``)."""
        if self.modal_coordinates is None:
            raise ValueError("this record has no modal coordinates (a run before pdamper recorded them)")
        return self.modal_coordinates @ np.asarray(shapes, dtype=float).T

    def edges(self):
        """(x, v) at the n + 1 interval edges, t = 0 included."""
        return np.concatenate([[self.x0_m], self.displacement]), np.concatenate([[self.v0_m_s], self.velocity])

    @property
    def energy(self) -> np.ndarray:
        """Mechanical energy of the structure 1/2 M v^2 + 1/2 K x^2 [J] (N modes: the recorded sum)."""
        if self.mechanical_energy is not None:
            return self.mechanical_energy
        return 0.5 * self.mass_kg * self.velocity**2 + 0.5 * self.stiffness_N_m * self.displacement**2

    @property
    def initial_energy(self) -> float:
        """Mechanical energy of the structure at t = 0 [J]."""
        if self.initial_energy_J is not None:
            return self.initial_energy_J
        return 0.5 * self.mass_kg * self.v0_m_s**2 + 0.5 * self.stiffness_N_m * self.x0_m**2

    def residual(self, ledger=None) -> np.ndarray:
        """Balance of the whole system (structure + bed, see the module docstring) relative to
        the first sample [J]; without ``ledger`` the structure alone (a run without a bed)."""
        r = self.energy + self.damping_loss - self.external_work
        if ledger is not None:
            r = r + ledger.mechanical + ledger.damping + ledger.friction
        return r - r[0]

    def balance_error(self, ledger=None) -> float:
        """Largest |residual| relative to the energy put in (initial energy + external work) [-]."""
        scale = max(self.initial_energy + float(np.max(np.abs(self.external_work))), 1e-300)
        return float(np.max(np.abs(self.residual(ledger))) / scale)


class StructureRecorder:
    """The coupled structure's motion and energies (kernel channel ``"structure"``) as a
    :class:`StructureRecord`."""

    name = "structure"
    channels = frozenset({"structure"})
    every = 0

    def start(self, run) -> None:
        self.case = run.case

    def record(self, state) -> None:  # kernel channels only
        pass

    def finalize(self, data) -> StructureRecord:
        return StructureRecord.from_channel(self.case, data)


# short reprs: names, shapes and key numbers (a notebook shows a line, not a dump)
StructureRecord.__repr__ = short_repr
