"""The harmonic force ``F0 sin(2 pi f t)`` at the force point (``[load] kind = "harmonic"``): the
structure's own ``force_amplitude`` and ``force_frequency`` (a ``[structure]`` with those keys and
a ``[load]`` of this kind are the same case, written the first way)."""

from __future__ import annotations

from dataclasses import dataclass

from ...errors import InputError
from ...schema import param
from .base import LoadBase, _positive, register_load

__all__ = ["HarmonicLoad"]


@register_load
@dataclass(frozen=True, kw_only=True)
class HarmonicLoad(LoadBase):
    """``F0 sin(2 pi f t)`` at the structure's force point, for as many cycles as ``[run]
    cycles`` (today's force of a structure, :class:`~pdamper.structure.base.StructureBase`).

    Parameters
    ----------
    amplitude : float
        F0 [N], > 0.
    frequency : float
        f [Hz], > 0.
    """

    amplitude: float = param(dimension="force")
    frequency: float = param(dimension="frequency")
    kind: str = param("harmonic", kind="tag")
    in_time = False
    size_keys = ("amplitude",)
    config_label = "a harmonic load"
    config_required = ("amplitude", "frequency")
    config_hint = "give amplitude = '0.4N' and frequency = '2Hz'"

    def __post_init__(self):
        _positive(self.amplitude, "load.amplitude", "N", "'0.4N'")
        _positive(self.frequency, "load.frequency", "Hz", "'2Hz'")

    def structure_keys(self) -> dict:
        """The structure's own harmonic force: ``force_amplitude``, ``force_frequency``."""
        return {"force_amplitude": float(self.amplitude), "force_frequency": float(self.frequency)}

    @property
    def highest_frequency(self) -> float:
        return float(self.frequency)

    @property
    def duration(self) -> float:
        raise InputError("a harmonic load lasts [run] cycles of its frequency; it has no duration of its own")

    def kernel_table(self):
        raise InputError("the harmonic load is the structure's own force (force_amplitude, force_frequency)")

    def describe(self) -> str:
        return f"harmonic force {self.amplitude:g} N at {self.frequency:g} Hz"
