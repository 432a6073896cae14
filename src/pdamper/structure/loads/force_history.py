"""A force history at the force point (``[load] kind = "force_history"``): a force-time file
(``time [s]``, ``force [N]``, units in the header; any file the logger readers read,
:func:`pdamper.io.records.read_signal`) or inline lists, piecewise linear through the samples and
zero after the last (a hammer blow, a measured machine force)."""

from __future__ import annotations

from dataclasses import dataclass

from ...schema import param
from .base import SampledFields, SampledLoad, register_load

__all__ = ["ForceHistory"]


@register_load
@dataclass(frozen=True, kw_only=True)
class ForceHistory(SampledLoad, SampledFields):
    """A force F(t) [N] at the structure's force point (``force_dof``; one mode: the structure),
    the samples' time moved to start at 0.

    Parameters
    ----------
    file : str or None
        A file with columns ``time`` and ``force`` (units in brackets, e.g. ``time [ms]``,
        ``force [kN]``), relative to the config file; or give ``time`` and ``force``.
    column : str or None
        The force column's name where it is not ``force``.
    time : tuple
        Sample times [s], strictly increasing.
    force : tuple
        F [N] at those times.
    scale : float
        A factor on the force (1: as given).
    duration_s : float or None
        The run's length [s] (config key ``duration``; default: the record's), e.g. the ring-down
        after a short blow.
    """

    force: tuple = param((), kind="list", dimension="force")
    kind: str = param("force_history", kind="tag")
    signal_role = "force"
    samples_field = "force"
    unit = "N"
    size_keys = ("scale", "force", "file")
    config_label = "a force history"
    config_required = ("time", "force")
    config_hint = "give file = 'hammer.csv' (columns time [s], force [N]) or time = [...] and force = [...]"

    def __post_init__(self):
        self._check_samples()

    def describe(self) -> str:
        return f"force history ({self._source_words()}) at the force point, {self.duration:.4g} s"
