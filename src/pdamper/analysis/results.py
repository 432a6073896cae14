"""The result types of the complex power method: :class:`PowerResult` and the :class:`Signals` it
keeps for plots (see :mod:`pdamper.analysis.complex_power` for the method)."""

from __future__ import annotations

from .._deprecated import renamed
from .._repr import short_repr

import functools
import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["PowerResult", "Signals"]


@dataclass(frozen=True, kw_only=True, eq=False)
class Signals:
    """The record's signals on its own time samples, in SI (used for plots).

    Attributes
    ----------
    time_s : numpy.ndarray
        Sample times [s].
    force_N : numpy.ndarray
        Driving force [N].
    velocity_m_s : numpy.ndarray
        Container velocity [m/s]: as given, or derived from position or
        acceleration as described in the module docstring.
    motion : str
        Which signal the record gave: ``"position"``, ``"velocity"`` or ``"acceleration"``.
    """

    time_s: np.ndarray
    force_N: np.ndarray
    velocity_m_s: np.ndarray
    motion: str


@dataclass(frozen=True, kw_only=True, eq=False)
class PowerResult:
    """Result of the complex power method on one record (paper eqs. 3-5).

    Attributes
    ----------
    frequency_hz : float
        Drive frequency f [Hz].
    frequency_detected : bool
        True if ``frequency_hz`` was detected from the motion, False if given.
    sample_rate_hz : float
        Sample rate of the record [Hz].
    resampled : bool
        False if the record has an integer number of samples per period and was
        used as sampled; True if it was resampled onto whole cycles.
    motion : str
        The motion signal the record gave (``"position"``, ``"velocity"``, ``"acceleration"``).
    cycles_dropped : int
        Whole cycles dropped at the start.
    cycles_used : int
        Whole cycles in the FFT window.
    window_s : tuple of float
        ``(t_start, t_end)`` of the FFT window [s]; ``t_end - t_start = cycles_used / f``.
    complex_power_W : complex
        ``P = 1/2 F* conj(V*)`` (3) [W]; the real part is the mean dissipated power.
    force_phasor_N : complex
        ``F*``, complex force amplitude at f [N], phase relative to the window start.
    velocity_phasor_m_s : complex
        ``V*``, complex velocity amplitude at f [m/s], phase relative to the window start.
    force_amplitude_N : float
        ``|F*|`` [N].
    velocity_amplitude_m_s : float
        ``|V*_Omega|`` [m/s].
    energy_per_cycle_J : float
        ``E~_diss = (2 pi / Omega) Re(P)`` (4), energy dissipated per cycle [J].
    dissipated_energy_J : float
        ``E_diss = E~_diss / (2 pi)`` [J], the numerator of (5).
    eta_star : float
        Reduced loss factor ``eta* = E_diss / (1/2 m_bed |V*|^2)`` (5) [-]; NaN
        if no bed mass was given.
    bed_mass_kg : float
        Mass of the particle bed [kg]; NaN if not given.
    mean_power_check_J : float
        ``<F v>`` over the window times the period [J]; equals
        ``energy_per_cycle_J`` for a periodic record with a sinusoidal velocity.
    drive_share : float
        Share of the motion signal's variance in the window carried by the drive
        frequency [-] (1 for a clean sinusoidal drive).
    cycle_energies_J : numpy.ndarray
        ``int F v dt`` over each whole cycle of the record [J], dropped cycles included.
    cycle_start_s : numpy.ndarray
        Start time of each of those cycles [s].
    cycle_used : numpy.ndarray
        Boolean per cycle: True if the cycle is in the FFT window, False if dropped.
    cycle_energy_spread : float
        Sample standard deviation of the used cycle energies divided by their
        mean magnitude [-] (NaN with fewer than two cycles); large values mean
        the record is not steady.
    signals : Signals or None
        The signals on the record's samples (for plotting); not part of :meth:`to_dict`.
    time_base : pdamper.analysis.nonuniform.TimeBase or None
        How the time stamps are spaced: jitter, gaps, effective rate, and whether the uniform
        (FFT) or the least-squares path at the true times was used.
    container_mass_kg : float
        The container's own mass m_c [kg] (its ``m_c x_c''`` is part of the measured force),
        removed from :attr:`effective_mass_kg`; 0 when not given (nothing removed).

    The effective (apparent) mass and the equivalent damping (:attr:`effective_mass_kg`,
    :attr:`equivalent_damping_N_s_per_m`) are the mass and the dashpot that, moved as the
    container is, would take the same complex power at f: with ``x(t) = Re(X* e^{i Omega t})``
    a force ``F = m x'' + c x' + k x`` has ``F* = (c + i (m Omega - k / Omega)) V*`` and so
    ``P = 1/2 |V*|^2 (c + i Omega (m - k / Omega^2))``.
    """

    frequency_hz: float
    frequency_detected: bool
    sample_rate_hz: float
    resampled: bool
    motion: str
    cycles_dropped: int
    cycles_used: int
    window_s: tuple[float, float]
    complex_power_W: complex
    force_phasor_N: complex
    velocity_phasor_m_s: complex
    force_amplitude_N: float
    velocity_amplitude_m_s: float
    energy_per_cycle_J: float
    dissipated_energy_J: float
    eta_star: float
    bed_mass_kg: float
    mean_power_check_J: float
    drive_share: float
    cycle_energies_J: np.ndarray
    cycle_start_s: np.ndarray
    cycle_used: np.ndarray
    cycle_energy_spread: float
    signals: Signals | None = field(default=None, repr=False)
    time_base: object = None
    container_mass_kg: float = 0.0

    @property
    def period_s(self) -> float:
        """Drive period ``T = 1/f`` [s]."""
        return 1.0 / self.frequency_hz

    @property
    def angular_frequency_rad_s(self) -> float:
        """``Omega = 2 pi f`` [rad/s]."""
        return 2.0 * math.pi * self.frequency_hz

    @functools.cached_property
    def statistics(self):
        """eta*'s standard error over the analysed cycles and the steady-state flag
        (:class:`~pdamper.analysis.steady.CycleStatistics`; computed once)."""
        from .steady import cycle_statistics

        return cycle_statistics(self.cycle_energies_J, self.cycle_used, self.eta_star)

    @property
    def eta_star_error(self) -> float:
        """Standard error of eta* over the analysed cycles [-] (:mod:`pdamper.analysis.steady`)."""
        return self.statistics.eta_star_error

    @property
    def steady(self) -> bool:
        """True when the analysed cycles show no drift (:mod:`pdamper.analysis.steady`)."""
        return self.statistics.steady

    angular_frequency = renamed("angular_frequency_rad_s")

    @property
    def total_effective_mass_kg(self) -> float:
        """``Im(P) / (1/2 Omega |V*|^2)`` [kg]: the effective mass of everything the force moves,
        the container's own mass included; ``m - k / Omega^2`` for ``F = m x'' + c x' + k x``.
        NaN if the velocity amplitude is zero."""
        v2 = self.velocity_amplitude_m_s ** 2
        if v2 == 0.0:
            return math.nan
        return self.complex_power_W.imag / (0.5 * self.angular_frequency_rad_s * v2)

    @property
    def effective_mass_kg(self) -> float:
        """The bed's effective (apparent) mass ``m_eff = Im(P) / (1/2 Omega |V*|^2) - m_c`` [kg]:
        :attr:`total_effective_mass_kg` with the container's own mass :attr:`container_mass_kg`
        removed. The whole bed moving with the container gives m_bed, a bed that takes no
        horizontal force 0; NaN if the velocity amplitude is zero."""
        return self.total_effective_mass_kg - self.container_mass_kg

    @property
    def equivalent_damping_N_s_per_m(self) -> float:
        """The equivalent viscous damping ``c_eq = 2 Re(P) / |V*|^2`` [N s/m]: the dashpot that
        dissipates the same energy per cycle at this velocity amplitude (``c`` for
        ``F = m x'' + c x' + k x``); NaN if the velocity amplitude is zero."""
        v2 = self.velocity_amplitude_m_s ** 2
        if v2 == 0.0:
            return math.nan
        return 2.0 * self.complex_power_W.real / v2

    @property
    def check_relative_difference(self) -> float:
        """``|mean_power_check_J - energy_per_cycle_J|`` relative to the apparent energy per cycle.

        The apparent energy ``pi |F*| |V*| / Omega`` is the scale of the
        exchanged energy; a dissipated energy of zero then still gives a finite number.
        """
        scale = math.pi * self.force_amplitude_N * self.velocity_amplitude_m_s / self.angular_frequency_rad_s
        diff = abs(self.mean_power_check_J - self.energy_per_cycle_J)
        if scale == 0.0:
            return 0.0 if diff == 0.0 else math.inf
        return diff / scale

    def to_dict(self) -> dict:
        """Plain JSON-ready dict: complex numbers as ``[re, im]``, arrays as lists, NaN as None."""

        def num(x):
            x = float(x)
            return x if math.isfinite(x) else None

        def cplx(z):
            return [num(z.real), num(z.imag)]

        return {
            "frequency_hz": num(self.frequency_hz),
            "frequency_detected": bool(self.frequency_detected),
            "sample_rate_hz": num(self.sample_rate_hz),
            "resampled": bool(self.resampled),
            "motion": self.motion,
            "cycles_dropped": int(self.cycles_dropped),
            "cycles_used": int(self.cycles_used),
            "window_s": [num(self.window_s[0]), num(self.window_s[1])],
            "complex_power_W": cplx(self.complex_power_W),
            "force_phasor_N": cplx(self.force_phasor_N),
            "velocity_phasor_m_s": cplx(self.velocity_phasor_m_s),
            "force_amplitude_N": num(self.force_amplitude_N),
            "velocity_amplitude_m_s": num(self.velocity_amplitude_m_s),
            "energy_per_cycle_J": num(self.energy_per_cycle_J),
            "dissipated_energy_J": num(self.dissipated_energy_J),
            "eta_star": num(self.eta_star),
            "bed_mass_kg": num(self.bed_mass_kg),
            "effective_mass_kg": num(self.effective_mass_kg),
            "equivalent_damping_N_s_per_m": num(self.equivalent_damping_N_s_per_m),
            "container_mass_kg": num(self.container_mass_kg),
            "mean_power_check_J": num(self.mean_power_check_J),
            "drive_share": num(self.drive_share),
            "cycle_energies_J": [num(e) for e in self.cycle_energies_J],
            "cycle_start_s": [num(t) for t in self.cycle_start_s],
            "cycle_used": [bool(u) for u in self.cycle_used],
            "cycle_energy_spread": num(self.cycle_energy_spread),
            "eta_star_error": num(self.eta_star_error),
            "steady": bool(self.steady),
            "time_base": self.time_base.to_dict() if self.time_base is not None else None,
        }


# short reprs: names, shapes and key numbers (a notebook shows a line, not a dump)
PowerResult.__repr__ = short_repr
Signals.__repr__ = short_repr
