"""A stepped sine (``[load] kind = "stepped_sine"``): the force ``F0 sin`` at a sequence of
frequencies, ``cycles`` periods each, in the order given (up or down), the state carried from one
frequency to the next (one run: the structure and the bed go on as they are) and the phase
continuous. The steady amplitude of each step is measured over its last cycles (``pdamper
response --sweep up|down``): on a softening or jumping response the sweep up and the sweep down
follow different branches."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ...errors import InputError, shown
from ...schema import param
from .base import FORM_SINE, LoadBase, _positive, register_load

__all__ = ["SteppedSine"]


@register_load
@dataclass(frozen=True, kw_only=True)
class SteppedSine(LoadBase):
    """``amplitude sin`` at each of ``frequencies`` [Hz] in turn, ``cycles`` periods each.

    Parameters
    ----------
    amplitude : float
        F0 [N], > 0, at the force point.
    frequencies : tuple
        The steps' frequencies [Hz], in the sweep's order (rising: up; falling: down).
    cycles : float
        Periods of each step (the last ones measured: the transient after a step must have
        decayed).
    """

    amplitude: float = param(dimension="force")
    frequencies: tuple = param((), kind="list", dimension="frequency")
    cycles: float = param(40.0, kind="number")
    kind: str = param("stepped_sine", kind="tag")
    stepped = True
    size_keys = ("amplitude",)
    config_label = "a stepped sine"
    config_required = ("amplitude", "frequencies")
    config_hint = "give amplitude = '0.4N' and frequencies = ['1.9Hz', '1.95Hz', '2Hz']"

    def __post_init__(self):
        _positive(self.amplitude, "load.amplitude", "N", "'0.4N'")
        f = np.asarray(self.frequencies, dtype=float) if isinstance(self.frequencies, (list, tuple)) else np.zeros(0)
        if f.ndim != 1 or f.size == 0 or not np.all(np.isfinite(f)) or np.any(f <= 0):
            raise InputError(f"load.frequencies = {shown(self.frequencies)}; give one or more frequencies > 0 in the order "
                             "of the sweep, e.g. ['1.9Hz', '1.95Hz', '2Hz']")
        if f.size > 10_000:
            raise InputError(f"load.frequencies: {f.size} steps; give at most 10000")
        object.__setattr__(self, "frequencies", tuple(float(x) for x in f))
        _positive(self.cycles, "load.cycles", "", "40")
        if self.cycles * f.size > 10_000_000:
            raise InputError(f"load.cycles = {self.cycles:g} periods at {f.size} steps is too long a sweep")

    @property
    def direction(self) -> str:
        """``"up"``, ``"down"`` or ``"mixed"``: how the frequencies are ordered."""
        d = np.diff(self.frequencies)
        return "up" if np.all(d >= 0) else "down" if np.all(d <= 0) else "mixed"

    def step_times(self) -> np.ndarray:
        """The steps' start times [s] and the sweep's end (len(frequencies) + 1)."""
        return np.concatenate([[0.0], np.cumsum(self.cycles / np.asarray(self.frequencies))])

    @property
    def duration(self) -> float:
        return float(self.step_times()[-1])

    @property
    def highest_frequency(self) -> float:
        return float(max(self.frequencies))

    def force_phases(self) -> np.ndarray:
        """Each step's force ``F0 sin(Omega_j t + psi_j)`` in absolute time: psi_j [rad]."""
        form, rows = self.kernel_table()
        return rows[:-1, 3] - rows[:-1, 2] * rows[:-1, 0]

    def kernel_table(self):
        """``(FORM_SINE, rows)``: ``(t_j, F0, Omega_j, phi_j)`` a step, each phase continuing the last,
        then a closing row of zeros (no force after the sweep)."""
        f = np.asarray(self.frequencies)
        t = self.step_times()
        rows = np.zeros((f.size + 1, 4))
        rows[:, 0] = t
        rows[:-1, 1] = self.amplitude
        rows[:-1, 2] = 2.0 * math.pi * f
        phase = 0.0
        for j in range(f.size):
            rows[j, 3] = phase
            phase = math.fmod(phase + rows[j, 2] * (t[j + 1] - t[j]), 2.0 * math.pi)
        return FORM_SINE, rows

    def describe(self) -> str:
        f = self.frequencies
        if len(f) == 1:
            return f"sine {self.amplitude:g} N at {f[0]:.5g} Hz from rest, {self.cycles:g} cycles, {self.duration:.4g} s"
        return (f"stepped sine {self.amplitude:g} N, {len(f)} steps {f[0]:.5g} -> {f[-1]:.5g} Hz ({self.direction}), "
                f"{self.cycles:g} cycles each, {self.duration:.4g} s")
