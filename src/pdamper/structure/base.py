"""What every structure model shares: the fields that move it (a harmonic force, a start), its
direction, and the answers of the drive protocol that follow from its modes.

A structure is a drive (:class:`pdamper.excitation.DriveBase`) of the ``[structure]`` section
whose motion the bed's force changes (``coupled``). A model (:mod:`.sdof`, :mod:`.modal`) is a
frozen dataclass made of two parts: its own fields, in a small dataclass listed *last* among its
bases, and :class:`StructureBase`'s shared ones. Python collects a dataclass's fields from the
last base to the first, so the model's own fields come first and the shared ones after: the
order of the keys a config file is written in, which a result store's fingerprint is taken of
(``tests/structure/test_base.py`` checks the written text is the one pdamper wrote before the
shared base).

What a model adds to the drive protocol (:class:`StructureBase` derives the rest from it):

=============================  ==================================================================
``modal_arrays()``             (m_k, k_k, c_k, phi_k(damper), phi_k(force), phi_k(response))
``mode_frequencies``           f_k [Hz], the lowest first; ``mode_damping_ratios`` zeta_k [-]
``natural_frequency``          f_1 [Hz]; ``mass``, ``stiffness``, ``damping``: the first mode's at the
                               damper [kg, N/m, N s/m]
``steady_amplitude(f, F0)``    the steady amplitude without the bed (closed form)
``start_state(st, F_w)``       releases it at t = 0 in the kernels' state
``carrying(mass)``             the structure with the empty container's mass at the damper
``record_info()``              what the run's structure record keeps
``structure_summary()``        plain numbers for a run's summary
=============================  ==================================================================
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..excitation import DriveBase
from ..schema import param
from ..units import thousandth_hint

__all__ = ["StructureBase", "MAX_STRUCTURE_HZ"]

#: Highest natural or forcing frequency of a structure [Hz].
MAX_STRUCTURE_HZ = 1000.0


@dataclass(frozen=True, kw_only=True)
class StructureBase(DriveBase):
    """The fields every structure has, and the drive protocol's answers shared by the models.

    Parameters
    ----------
    force_amplitude : float
        F0 [N], >= 0 (0: free motion), of the harmonic force ``F0 sin(2 pi f_F t)``.
    displacement, velocity : float
        The damper point's x [m] and v [m/s] when the drive starts (t = 0).
    angle : float
        Direction of the motion in the horizontal plane [rad], as for
        :class:`~pdamper.excitation.HarmonicDrive`.
    force_frequency : float or None
        f_F [Hz], > 0, needed when F0 > 0.
    direction : (x, y, z) or None
        Direction of the motion in the lab frame (y up), instead of ``angle``.
    """

    force_amplitude: float = param(0.0, dimension="force")
    displacement: float = param(0.0, dimension="length")
    velocity: float = param(0.0, dimension="velocity")
    angle: float = param(0.0, dimension="angle")
    force_frequency: float | None = param(None, dimension="frequency")
    direction: tuple | None = param(None, kind="list")

    config_section = "structure"
    coupled = True
    counts_cycles = True
    config_writes_kind = False  # a [structure] tells its model by its keys
    config_after = "run"        # [structure] last

    # ---- checks
    def _check_motion(self) -> None:
        """Validate what moves it (``force_amplitude``, ``force_frequency``, ``displacement``,
        ``velocity``) and its direction; something must move it."""
        f0 = self.force_amplitude
        if isinstance(f0, bool) or not isinstance(f0, (int, float)) or not (f0 >= 0 and math.isfinite(f0)):
            raise InputError(f"structure.force_amplitude = {f0!r} N; must be >= 0 (0: free motion)")
        ff = self.force_frequency
        if ff is not None and not (isinstance(ff, (int, float)) and ff > 0 and math.isfinite(ff)):
            raise InputError(f"structure.force_frequency = {ff!r} Hz; must be > 0, e.g. '2Hz'")
        if f0 > 0 and ff is None:
            raise InputError("structure.force_frequency is missing: a force_amplitude > 0 needs its "
                             "frequency, e.g. force_frequency = '2Hz'")
        for name in ("displacement", "velocity"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise InputError(f"structure.{name} = {v!r}; must be a finite number")
        self._check_direction()
        if f0 == 0 and self.displacement == 0 and self.velocity == 0:
            raise InputError("structure: nothing moves it; give a displacement (free decay, e.g. '10mm') "
                             "or a force_amplitude with force_frequency (forced response)")

    def check_scale(self, length: float) -> None:
        """A start (``displacement``, ``velocity``) or resonant swing (F0 / K / 2 zeta of the first
        mode) beyond twice the container's ``length`` [m], or a frequency beyond 1 kHz (no damper
        test; the time step would vanish): an InputError with the fix."""
        if not self.natural_frequency <= MAX_STRUCTURE_HZ:
            raise InputError(f"structure: a natural frequency of {self.natural_frequency:.3g} Hz (structure.mass = "
                             f"{self.mass:g} kg, stiffness {self.stiffness:.3g} N/m) is beyond {MAX_STRUCTURE_HZ:g} Hz; "
                             "check structure.mass and structure.stiffness / natural_frequency (a number without a "
                             "unit is SI)")
        ff = self.force_frequency
        if ff is not None and not ff <= MAX_STRUCTURE_HZ:
            raise InputError(f"structure.force_frequency = {ff:g} Hz is beyond {MAX_STRUCTURE_HZ:g} Hz, no damper test; "
                             "give the forcing frequency, e.g. '2Hz'")
        for key in ("displacement", "velocity"):
            v = abs(getattr(self, key))
            limit = 2 * length if key == "displacement" else 2 * length * 2 * math.pi * self.natural_frequency
            if v > limit:
                unit = "m" if key == "displacement" else "m/s"
                raise InputError(f"structure.{key} = {getattr(self, key):g} {unit} moves the container {v / limit:.3g} "
                                 f"times further than twice its length {length:g} m (a number without a unit is SI)"
                                 f"{thousandth_hint(v, limit, 'mm' if key == 'displacement' else 'mm/s')}")
        resonant = self.force_amplitude / self.stiffness / max(2.0 * self.modal_damping_ratio, 0.02)
        if resonant > 2 * length:
            raise InputError(f"structure.force_amplitude = {self.force_amplitude:g} N would swing the structure "
                             f"(structure.mass = {self.mass:g} kg, stiffness {self.stiffness:.3g} N/m) by about "
                             f"{resonant:.3g} m at resonance (F0 / K / 2 zeta), beyond twice the container's length "
                             f"{length:g} m; give a smaller force or check the mass (a number without a unit is SI)")

    # ---- what follows from the modes
    @property
    def frequency(self) -> float:
        """The frequency [Hz] that counts the run's cycles: f_F when forced, else f_1."""
        return self.force_frequency if self.force_amplitude > 0 else self.natural_frequency

    @property
    def n_modes(self) -> int:
        """Number of modes carried."""
        return int(np.size(self.mode_frequencies))

    @property
    def highest_frequency(self) -> float:
        """The highest frequency of the structure's motion without the bed [Hz] (for time steps)."""
        return float(max(np.max(self.mode_frequencies), self.force_frequency or 0.0))

    @property
    def modal_damping_ratio(self) -> float:
        """zeta_1 [-] of the first mode."""
        return float(self.mode_damping_ratios[0])

    def duration(self, cycles: float) -> float:
        """Time [s] of ``cycles`` periods of :attr:`frequency`."""
        return cycles / self.frequency

    def speed_bound(self) -> float:
        """An upper estimate [m/s] of the container's speed (``velocity_bound``)."""
        return self.velocity_bound

    def container_motion(self, t: float, state):
        """The damper point's ``(x, v, a)`` now, from the kernels' state."""
        return state[0, 0], state[0, 1], state[0, 2]

    def steady_phasor(self, frequencies, force_amplitude: float, added_mass: float = 0.0, point: str = "damper"):
        """Complex steady amplitude x^ [m] at the damper (or ``point = "response"``) under
        ``force_amplitude`` sin(2 pi f t) at each of ``frequencies`` [Hz] without the bed
        (``x(t) = Im(x^ e^{i 2 pi f t})``: its angle is the phase against the force), with
        ``added_mass`` [kg] rigidly at the damper: ``(-W^2 (diag m + m_a phi_d phi_d^T) + i W diag c +
        diag k) q = phi_f F0``; ``|x^|`` is :meth:`steady_amplitude`."""
        mass, k, c, pd, pf, pr = self.modal_arrays()
        out = []
        for f in np.atleast_1d(np.asarray(frequencies, dtype=float)):
            w = 2.0 * math.pi * f
            A = np.diag(k - w * w * mass + 1j * w * c) - w * w * added_mass * np.outer(pd, pd)
            q = np.linalg.solve(A, pf * force_amplitude)
            out.append(complex(np.dot(pr if point == "response" else pd, q)))
        return np.array(out)

    def _forced_words(self) -> str:
        return (f"F0 = {self.force_amplitude:g} N at {self.force_frequency:g} Hz" if self.force_amplitude > 0
                else f"free decay from {self.displacement * 1e3:g} mm")
