"""A stationary random load (``[load] kind = "random"``): a force at the force point or a ground
acceleration (``excitation``), a Gaussian process of a given power spectral density, seeded,
lasting ``duration``.

The spectrum is one-sided per hertz, G(f) [N^2/Hz or (m/s^2)^2/Hz] (the variance is the integral
of G over f > 0; the two-sided density per rad/s of random-vibration texts is S0 = G / (4 pi)):

- ``spectrum = "white"``: band-limited white noise, ``G = level`` inside ``band = [f_lo, f_hi]``;
- ``spectrum = "kanai_tajimi"``: the Kanai-Tajimi ground filter on white noise of ``level``,
  ``G = level (1 + 4 zeta_g^2 r^2) / ((1 - r^2)^2 + 4 zeta_g^2 r^2)``, ``r = f / f_g``
  (``ground_frequency`` f_g, ``ground_damping`` zeta_g; Kanai 1957, Tajimi 1960; Clough &
  Penzien, Dynamics of Structures, Sect. 24-4), inside ``band`` (default 0 to 10 f_g).

A realisation is drawn by the spectral representation (FFT of Gaussian coefficients, Shinozuka &
Deodatis, Appl. Mech. Rev. 44, 1991): on N = duration / time_step samples the Fourier
coefficient at f_j = j / duration is complex Gaussian with ``E|X_j|^2 = G(f_j) / duration`` (the
record is periodic over ``duration``; its mean square is ``sum_j G(f_j) / duration`` on average,
the variance of G's integral); ``seed`` fixes it (numpy's ``default_rng``). The kernels follow it
piecewise linearly (``time_step`` default ``1 / (20 f_hi)``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, shown
from ...schema import param
from .base import FORM_LINEAR, LoadBase, _positive, linear_rows, register_load
from .ground import GroundMixin

__all__ = ["RandomLoad", "SPECTRA", "EXCITATIONS"]

#: The spectra a random load has.
SPECTRA = ("white", "kanai_tajimi")
#: What it excites: a force at the force point, or the ground.
EXCITATIONS = ("force", "ground")


@register_load
@dataclass(frozen=True, kw_only=True)
class RandomLoad(GroundMixin, LoadBase):
    """A stationary Gaussian force or ground acceleration of a given PSD (module docstring).

    Parameters
    ----------
    excitation : str
        ``"force"`` (at the force point) or ``"ground"`` (every dof through the mass matrix).
    spectrum : str
        ``"white"`` or ``"kanai_tajimi"``.
    level : float
        G0, the one-sided PSD [N^2/Hz or (m/s^2)^2/Hz], > 0.
    band : (f_lo, f_hi) or None
        The band [Hz] the PSD fills (needed for white noise; Kanai-Tajimi: 0 to 10 f_g).
    ground_frequency, ground_damping : float or None
        f_g [Hz] and zeta_g of the Kanai-Tajimi filter.
    duration_s : float
        The record's and the run's length [s] (config key ``duration``).
    seed : int
        The realisation.
    time_step : float or None
        The samples' interval [s] (default 1 / (20 f_hi)).
    influence, participation : tuple or None
        A ground excitation's influence vector or modes' participation
        (:class:`~pdamper.structure.loads.ground.GroundAcceleration`).
    """

    excitation: str = param("force", choices=EXCITATIONS)
    spectrum: str = param("white", choices=SPECTRA)
    level: float | None = param(None, kind="number")
    band: tuple | None = param(None, kind="list", dimension="frequency")
    ground_frequency: float | None = param(None, dimension="frequency")
    ground_damping: float | None = param(None, kind="number")
    duration_s: float | None = param(None, dimension="time", key="duration")
    seed: int = 0
    time_step: float | None = param(None, dimension="time")
    influence: tuple | None = param(None, kind="list")
    participation: tuple | None = param(None, kind="list")
    kind: str = param("random", kind="tag")
    stationary = True
    size_keys = ("level", "band")
    config_label = "a random load"
    config_required = ("level", "duration_s")
    config_hint = "give level (the one-sided PSD, e.g. 0.01 for 0.01 N^2/Hz), band = ['0.5Hz', '10Hz'] and duration"

    def __post_init__(self):
        for key, choices in (("excitation", EXCITATIONS), ("spectrum", SPECTRA)):
            if getattr(self, key) not in choices:
                raise InputError(f"load.{key} = {shown(getattr(self, key))}; choose one of "
                                 + ", ".join(repr(c) for c in choices))
        _positive(self.level, "load.level", "(one-sided PSD per Hz)", "0.01")
        _positive(self.duration_s, "load.duration", "s", "'60s'")
        seed = self.seed
        if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
            raise InputError(f"load.seed = {shown(seed)}; must be a whole number >= 0")
        kt = self.spectrum == "kanai_tajimi"
        for key in ("ground_frequency", "ground_damping"):
            if getattr(self, key) is not None and not kt:
                raise InputError(f"load.{key} belongs to spectrum = 'kanai_tajimi'")
        if kt:
            _positive(self.ground_frequency, "load.ground_frequency", "Hz", "'2.5Hz'")
            _positive(self.ground_damping, "load.ground_damping", "", "0.6")
            if self.ground_damping > 10.0:  # a soil's damping ratio is below 1 (its square would overflow)
                raise InputError(f"load.ground_damping = {shown(self.ground_damping)}; a ground's damping ratio is "
                                 "below 1, at most 10, e.g. 0.6 (firm soil)")
        if self.band is None:
            if not kt:
                raise InputError("load.band is missing: white noise fills a band, e.g. band = ['0.5Hz', '10Hz']")
            object.__setattr__(self, "band", (0.0, 10.0 * self.ground_frequency))
        b = self.band
        if not (isinstance(b, (tuple, list)) and len(b) == 2 and all(isinstance(x, (int, float)) and
                                                                    not isinstance(x, bool) for x in b)
                and 0.0 <= b[0] < b[1] and math.isfinite(b[1])):
            raise InputError(f"load.band = {shown(b)}; give [f_lo, f_hi] with 0 <= f_lo < f_hi, e.g. ['0.5Hz', '10Hz']")
        object.__setattr__(self, "band", (float(b[0]), float(b[1])))
        _positive(self.time_step, "load.time_step", "s", "'5ms'", allow_none=True)
        if self.time_step is not None and not self.band[1] <= 0.5 / self.time_step:
            raise InputError(f"load.time_step = {self.time_step:g} s samples up to {0.5 / self.time_step:g} Hz, below "
                             f"the band's top {self.band[1]:g} Hz; give a time_step of at most "
                             f"{0.5 / self.band[1]:.3g} s (or leave it out)")
        if self.samples_count < 4:
            raise InputError(f"load.duration = {self.duration_s:g} s is shorter than 4 samples of {self.step:g} s; give "
                             "a longer duration, e.g. '60s'")
        if self.samples_count > 20_000_000:
            n = self.samples_count
            why = "" if self.time_step is not None else (
                f" (20 samples a period of the band's top {self.band[1]:g} Hz, "
                + ("10 ground_frequency" if kt and self.band == (0.0, 10.0 * self.ground_frequency) else "band")
                + ")")
            count = f"{n:,}" if n < 1e15 else f"{n:.3g}"
            raise InputError(f"load.duration = {self.duration_s:g} s at a time_step of {self.step:g} s{why} is "
                             f"{count} samples, more than 20,000,000; shorten it or sample coarser")
        if self.excitation != "ground":
            for key in ("influence", "participation"):
                if getattr(self, key) is not None:
                    raise InputError(f"load.{key} belongs to excitation = 'ground' (a force acts at the force point)")
        self._check_ground()

    # ---- what it can do
    @property
    def ground(self) -> bool:
        """True for a ground acceleration."""
        return self.excitation == "ground"

    def modal_coefficients(self, structure) -> np.ndarray:
        if self.ground:
            return GroundMixin.modal_coefficients(self, structure)
        return LoadBase.modal_coefficients(self, structure)

    # ---- the spectrum
    def psd(self, frequencies) -> np.ndarray:
        """The target one-sided PSD G(f) at ``frequencies`` [Hz] (0 outside the band)."""
        f = np.asarray(frequencies, dtype=float)
        g = np.full(f.shape, float(self.level))
        if self.spectrum == "kanai_tajimi":
            r2 = (f / self.ground_frequency) ** 2
            z2 = 4.0 * self.ground_damping ** 2 * r2
            g = g * (1.0 + z2) / ((1.0 - r2) ** 2 + z2)
        return np.where((f >= self.band[0]) & (f <= self.band[1]), g, 0.0)

    @property
    def step(self) -> float:
        """The samples' interval [s]."""
        return float(self.time_step) if self.time_step is not None else 1.0 / (20.0 * self.band[1])

    @property
    def samples_count(self) -> int:
        return int(round(self.duration_s / self.step))

    @property
    def duration(self) -> float:
        return float(self.samples_count * self.step)

    @property
    def highest_frequency(self) -> float:
        return float(self.band[1])

    def samples(self) -> tuple[np.ndarray, np.ndarray]:
        """(t [s], f) of the realisation: N + 1 samples over ``duration`` (the last = the first)."""
        cached = self.__dict__.get("_samples")
        if cached is not None:
            return cached
        n = self.samples_count
        dt = self.step
        freqs = np.fft.rfftfreq(n, dt)
        rng = np.random.default_rng(int(self.seed))
        coef = rng.standard_normal(freqs.size) + 1j * rng.standard_normal(freqs.size)
        # irfft: x_t = (1/n) sum_j (2 Re C_j e^{2 pi i j t/n}); with C_j = (n/2) sqrt(G(f_j) df) (a + ib),
        # a, b standard normal, the component's mean square is G(f_j) df, df = 1/(n dt)
        amp = 0.5 * n * np.sqrt(self.psd(freqs) / (n * dt))
        amp[0] = 0.0
        if n % 2 == 0:
            amp[-1] = 0.0
        x = np.fft.irfft(coef * amp, n)
        t = dt * np.arange(n + 1)
        out = (t, np.append(x, x[0]))
        object.__setattr__(self, "_samples", out)
        return out

    @property
    def target_variance(self) -> float:
        """The integral of the target PSD over the band [N^2 or (m/s^2)^2] (quadrature)."""
        f = np.linspace(self.band[0], self.band[1], 20001)
        return float(np.trapezoid(self.psd(f), f))

    def kernel_table(self):
        t, x = self.samples()
        return FORM_LINEAR, linear_rows(t, x)

    def describe(self) -> str:
        what = "force at the force point" if not self.ground else f"ground acceleration, {self._ground_words()}"
        shape = ("white noise" if self.spectrum == "white" else
                 f"Kanai-Tajimi f_g = {self.ground_frequency:g} Hz, zeta_g = {self.ground_damping:g}")
        return (f"random {what}: {shape}, G0 = {self.level:g} per Hz over {self.band[0]:g}-{self.band[1]:g} Hz, "
                f"rms {math.sqrt(self.target_variance):.3g}, {self.duration:g} s, seed {self.seed}")
