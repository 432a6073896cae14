"""A single-degree-of-freedom structure the container rides on, two-way coupled (``[structure]``
with ``mass`` and ``stiffness`` or ``natural_frequency``)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..excitation import register_drive
from ..schema import param, read_fields, read_quantity
from .base import StructureBase

__all__ = ["CoupledStructure"]


@dataclass(frozen=True, kw_only=True)
class _OneMode:
    """The single mode's own fields (first in the written config: see :mod:`.base`)."""

    mass: float = param(dimension="mass")
    stiffness: float = param(kind="number", unit="N/m")
    damping_ratio: float = 0.005


@register_drive
@dataclass(frozen=True, kw_only=True)
class CoupledStructure(StructureBase, _OneMode):
    """The container rides rigidly on a single-degree-of-freedom structure, two-way coupled.

    ``M x_s'' + c x_s' + K x_s = F0 sin(2 pi f_F t) - F_w`` with ``c = 2 zeta sqrt(K M)`` and F_w
    the force of the walls on the particles along the drive; the structure's motion is the
    container's (see :mod:`pdamper.kernels.structure` and docs/structure.md). Both integrators
    advance it with the same structure step (Gear and Verlet, docs/structure.md).

    Parameters
    ----------
    mass : float
        M [kg], > 0: the structure's modal mass without the damper. The empty container's mass
        (``[container] mass``) moves with it: a run adds it (:meth:`carrying`).
    stiffness : float
        K [N/m], > 0.
    damping_ratio : float
        zeta [-], in [0, 1): the structure's own damping.
    force_amplitude, force_frequency, displacement, velocity, angle, direction
        What moves it and along which direction (:class:`~pdamper.structure.base.StructureBase`).

    Examples
    --------
    >>> s = CoupledStructure(mass=7.0, stiffness=1105.0, damping_ratio=0.005, displacement=0.01)
    >>> round(s.natural_frequency, 3)
    2.0
    """

    kind: str = param("structure", kind="tag")
    config_default = True
    config_extra_keys = ("natural_frequency",)
    config_label = "the single-mode structure"
    config_summary = "mass with stiffness or natural_frequency (one mode)"

    def __post_init__(self):
        self._prepare()
        self._check_scales()
        for name, unit, ex in (("mass", "kg", "'7kg'"), ("stiffness", "N/m", "1105 (N/m)")):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (v > 0 and math.isfinite(v)):
                raise InputError(f"structure.{name} = {shown(v)} {unit}; must be > 0, e.g. {ex}")
        z = self.damping_ratio
        if isinstance(z, bool) or not isinstance(z, (int, float)) or not (0.0 <= z < 1.0):
            raise InputError(f"structure.damping_ratio = {shown(z)}; must be in [0, 1), e.g. 0.005 (0.5 %)")
        if not math.isfinite(self._k * self._m):
            raise InputError(f"structure.mass = {self.mass:g} kg with stiffness {self.stiffness:g} N/m is beyond what "
                             "a number holds (their product overflows); give the mode's mass, e.g. '7kg'")
        self._check_motion()
        self._check_dofs()

    @classmethod
    def config_read_extra(cls, table: dict, base_dir) -> dict:
        """``mass`` is needed, and exactly one of ``stiffness`` and ``natural_frequency`` (which
        gives the stiffness ``K = M (2 pi f_n)^2``)."""
        extra = super().config_read_extra(table, base_dir)
        if "mass" not in table:
            raise InputError("[structure] mass is missing: give the structure's modal mass (without the damper; the "
                             "empty container is [container] mass), e.g. mass = '7kg'")
        if ("stiffness" in table) == ("natural_frequency" in table):
            raise InputError("[structure] give exactly one of stiffness (N/m, e.g. 1105) or natural_frequency "
                             "(e.g. '2Hz')")
        if "natural_frequency" not in table:
            return extra
        mass = read_fields({"mass": table["mass"]}, "structure", cls)["mass"]
        fn = read_quantity(table["natural_frequency"], "[structure] natural_frequency", "frequency")
        if not (fn > 0 and math.isfinite(fn)):
            raise InputError(f"[structure] natural_frequency = {shown(table['natural_frequency'])}; must be > 0, e.g. '2Hz'")
        if not (mass > 0 and math.isfinite(mass)):
            raise InputError(f"[structure] mass = {shown(table['mass'])}; must be > 0, e.g. '7kg'")
        w = 2.0 * math.pi * fn
        stiffness = mass * w * w
        if not (0 < stiffness < math.inf):
            raise InputError(f"[structure] natural_frequency = {shown(table['natural_frequency'])} gives a stiffness of "
                             f"{stiffness:g} N/m with mass = {mass:g} kg; give a natural frequency a damper test can "
                             "have, e.g. '2Hz'")
        return {**extra, "stiffness": stiffness}

    # ---- the one mode
    @property
    def _m(self) -> float:
        """M of the model: ``mass`` times ``mass_scale`` [kg]."""
        return self.mass * self.mass_scale

    @property
    def _k(self) -> float:
        """K of the model: ``stiffness`` times ``stiffness_scale`` [N/m]."""
        return self.stiffness * self.stiffness_scale

    @property
    def damping(self) -> float:
        """c = 2 zeta sqrt(K M) [N s/m]."""
        return 2.0 * self.damping_ratio * math.sqrt(self._k * self._m)

    @property
    def natural_frequency(self) -> float:
        """f_n = sqrt(K/M) / 2 pi [Hz] (without the bed)."""
        return math.sqrt(self._k / self._m) / (2.0 * math.pi)

    @property
    def mode_frequencies(self) -> np.ndarray:
        """The one mode's natural frequency f_n [Hz], as an array of one."""
        return np.array([self.natural_frequency])

    @property
    def mode_damping_ratios(self) -> np.ndarray:
        """The one mode's damping ratio zeta, as an array of one."""
        return np.array([float(self.damping_ratio)])

    @property
    def velocity_bound(self) -> float:
        """An upper estimate [m/s] of |v_s| without the bed (for the time step)."""
        from ..theory.oscillator import steady_amplitude

        w = 2.0 * math.pi * self.natural_frequency
        free = abs(self.velocity) + w * abs(self.displacement)
        forced = 0.0
        if self.force_amplitude > 0:
            wf = 2.0 * math.pi * self.force_frequency
            res = self.force_amplitude / self._k / max(2.0 * self.damping_ratio, 0.02)
            forced = max(wf, w) * max(res, steady_amplitude(self.force_frequency, mass=self._m,
                                                            stiffness=self._k, damping_ratio=self.damping_ratio,
                                                            force_amplitude=self.force_amplitude))
        return free + 2.0 * forced

    def motion(self, t):
        """(x, v, a) at times t [s] of the structure *without* the bed (closed form; under a load in
        time its exact linear response, :mod:`pdamper.structure.linear`); the coupled motion is
        recorded by the run."""
        from ..theory.oscillator import oscillator_response

        if self.load is not None:
            from .linear import damper_motion

            return damper_motion(self, t)

        return oscillator_response(t, mass=self._m, stiffness=self._k, damping_ratio=self.damping_ratio,
                                   force_amplitude=self.force_amplitude, force_frequency=self.force_frequency or 0.0,
                                   displacement=self.displacement, velocity=self.velocity)

    def modal_motion(self, t):
        """(q, q', q'') [each (1, len(t))] of its one mode (shape 1) without the bed: :meth:`motion`."""
        return tuple(np.atleast_1d(np.asarray(z, dtype=float))[None, :] for z in self.motion(t))

    def kernel_drive(self):
        """(kernel kind, par, table, state) for the kernels (:mod:`pdamper.kernels.structure`);
        the state starts at rest at the initial displacement (held during settling). Under a load
        in time: the structure as a modal structure of one mode (:meth:`load_kernel_drive`)."""
        if self.load is not None:
            return self.load_kernel_drive()
        om = 2.0 * math.pi * (self.force_frequency or 0.0)
        par = np.array([self._m, self._k, self.damping, self.force_amplitude, om])
        st = np.zeros((2, 5))
        st[0, 0] = self.displacement
        return "structure", par, np.zeros((1, 5)), st

    def carrying(self, mass):
        """The structure with the empty container's ``mass`` [kg] on it (several containers: their
        masses' sum): M + m_c, the same K and the same dashpot c (its damping ratio falls as
        1/sqrt(M + m_c)), the scales taken into M and K (what runs:
        :attr:`pdamper.params.Case.running_drive`); itself for no mass and no scale."""
        if not isinstance(mass, (int, float)):
            mass = float(np.sum(mass))
        if mass == 0.0 and self.stiffness_scale == 1.0 and self.mass_scale == 1.0:
            return self
        m2 = self._m + mass
        return dataclasses.replace(self, mass=m2, stiffness=self._k, stiffness_scale=1.0, mass_scale=1.0,
                                   damping_ratio=self.damping / (2.0 * math.sqrt(self._k * m2)))

    def describe(self) -> str:
        return f"structure M = {self._m:g} kg, f_n = {self.natural_frequency:.4g} Hz, {self._forced_words()}"

    def response_motion(self, t):
        """Displacement [m] of the response point (the structure itself) without the bed."""
        return self.motion(t)[0]

    def steady_amplitude(self, frequencies, force_amplitude: float, added_mass: float = 0.0, point: str = "damper"):
        """Steady amplitude [m] under ``force_amplitude`` sin(2 pi f t) at ``frequencies`` [Hz]
        without the bed, with ``added_mass`` [kg] rigidly on the structure (the same K and c)."""
        from ..theory.oscillator import steady_amplitude

        if added_mass == 0.0:
            return np.asarray(steady_amplitude(frequencies, mass=self._m, stiffness=self._k,
                                               damping_ratio=self.damping_ratio, force_amplitude=force_amplitude))
        m2 = self._m + added_mass
        zeta2 = self.damping / (2.0 * math.sqrt(self._k * m2))
        return np.asarray(steady_amplitude(frequencies, mass=m2, stiffness=self._k, damping_ratio=zeta2,
                                           force_amplitude=force_amplitude))

    def modal_arrays(self):
        """(modal masses [kg], stiffnesses [N/m], dampings [N s/m], mode shape at the damper, at the
        force, at the response point): the structure as its one mode, every shape 1."""
        one = np.ones(1)
        return (np.array([self._m]), np.array([self._k]), np.array([self.damping]), one, one.copy(),
                one.copy())

    def record_info(self) -> dict:
        """What :class:`pdamper.recorders.structure.StructureRecord` keeps of the structure."""
        return {"mass_kg": self._m, "stiffness_N_m": self._k, "x0_m": self.displacement,
                "v0_m_s": self.velocity}

    def structure_summary(self) -> dict:
        """Plain numbers about the structure for a run's summary."""
        return {"modes_kept": 1, "mode_frequencies_hz": [self.natural_frequency],
                "mode_damping_ratios": [float(self.damping_ratio)]}

    def start_state(self, st, wall_force: float = 0.0) -> float:
        """Release the structure at t = 0: set (x0, v0, a0) in the kernel state ``st``, with
        ``wall_force`` [N] the bed's wall force along the drive at that moment; returns a0."""
        if self.load is not None:
            return self.load_start_state(st, wall_force)
        a0 = (-self.damping * self.velocity - self._k * self.displacement - wall_force) / self._m
        st[0, 0:4] = (self.displacement, self.velocity, a0, 0.0)
        st[1, :] = 0.0
        return a0
