"""A ground acceleration (``[load] kind = "ground_acceleration"``): an accelerogram moves the
structure's supports, every dof loaded through the mass matrix, ``M x'' + C x' + K x = -M r a_g(t)``
with x relative to the ground (as engineers read a storey drift) and r the influence vector (1
where a dof moves with the ground along the drive direction). The modes' participation ``L_k =
phi_k^T M r`` comes from the FE matrices (``influence``, default 1 at every dof) or is given per
mode (``participation``: Gamma_k, ``L_k = Gamma_k m_k``); one mode: the whole mass, L = M. The
container moves with the damper point, so the bed feels the ground's and the structure's
acceleration together.

The file: a CSV with ``time [s]`` and ``acceleration [m/s^2]`` (or ``[g]``, the standard
gravity), or a PEER NGA ``.AT2`` file (:func:`pdamper.io.records.read_at2`). Every record is
checked as it is read (its mean, the drift of its integrated velocity and displacement: a one-sided
or drifting record is warned of) and, with ``baseline``, corrected (:mod:`.record_check`)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

import warnings
from pathlib import Path

from ...errors import InputError, shown
from ...schema import check_choice, param
from .base import SampledFields, SampledLoad, register_load
from .record_check import BASELINES, RecordCheck, RecordWarning, baseline_correct, check_record

__all__ = ["GroundAcceleration", "GroundMixin"]


class GroundMixin:
    """A ground acceleration's answers: every dof through the mass matrix (``influence``,
    ``participation``)."""

    def _check_ground(self) -> None:
        for key in ("influence", "participation"):
            v = getattr(self, key)
            if v is None:
                continue
            arr = np.asarray(v, dtype=float) if isinstance(v, (list, tuple)) else np.zeros(0)
            if arr.ndim != 1 or arr.size == 0 or not np.all(np.isfinite(arr)):
                raise InputError(f"load.{key} = {shown(v)}; give a list of finite numbers, e.g. "
                                 + ("[1, 0] (per dof, or the pattern of one node's dofs)" if key == "influence"
                                    else "[1.2, -0.3] (one per mode)"))
            object.__setattr__(self, key, tuple(float(x) for x in arr))
        if self.influence is not None and self.participation is not None:
            raise InputError("load.influence and load.participation are both given; give the influence vector (the "
                             "participation then comes from the mass matrix) or each mode's participation, not both")

    def modal_coefficients(self, structure) -> np.ndarray:
        """b_k = -L_k, the modes' participation in the ground's inertial force
        (:meth:`pdamper.structure.StructureBase.ground_participation`)."""
        return -structure.ground_participation(influence=self.influence, participation=self.participation)

    def _ground_words(self) -> str:
        if self.participation is not None:
            return "participation " + ", ".join(f"{g:.3g}" for g in self.participation)
        return "every dof through the mass matrix"


@register_load
@dataclass(frozen=True, kw_only=True)
class GroundAcceleration(GroundMixin, SampledLoad, SampledFields):
    """A ground acceleration a_g(t) [m/s^2] along the drive direction (module docstring).

    Parameters
    ----------
    file : str or None
        A CSV with columns ``time`` and ``acceleration`` (units in brackets: ``[m/s^2]``, ``[g]``,
        ``[cm/s^2]``) or a PEER ``.AT2`` file, relative to the config file; or give ``time`` and
        ``acceleration``.
    column : str or None
        The acceleration column's name where it is not ``acceleration``.
    time : tuple
        Sample times [s], strictly increasing.
    acceleration : tuple
        a_g [m/s^2] at those times.
    scale : float
        A factor on the accelerations (e.g. to a target peak ground acceleration).
    duration_s : float or None
        The run's length [s] (config key ``duration``; default: the record's).
    influence : tuple or None
        r: per dof of FE matrices 1 where it moves with the ground (0: a rotation), or the pattern of
        one node's dofs repeated over the nodes (``[1, 0]``); default 1 at every dof.
    participation : tuple or None
        Gamma_k of each mode, instead of ``influence`` (needed for modes given as data).
    baseline : str
        ``"none"`` (default: the samples as given), or the order of a least-squares polynomial
        baseline fitted to the velocity and taken off (``"constant"``, ``"linear"``,
        ``"quadratic"``, ``"cubic"``; :func:`~pdamper.structure.loads.record_check.baseline_correct`).
        Every record is checked when the load is made (:attr:`record_check`): a one-sided or
        drifting one is warned of (:class:`~pdamper.structure.loads.record_check.RecordWarning`).
    """

    acceleration: tuple = param((), kind="list", dimension="acceleration")
    influence: tuple | None = param(None, kind="list")
    participation: tuple | None = param(None, kind="list")
    baseline: str = param("none", choices=tuple(BASELINES), write_default=False)
    kind: str = param("ground_acceleration", kind="tag")
    ground = True
    signal_role = "acceleration"
    samples_field = "acceleration"
    unit = "m/s^2"
    size_keys = ("scale", "acceleration", "file", "influence", "participation", "baseline")
    config_label = "a ground acceleration"
    config_required = ("time", "acceleration")
    config_hint = ("give file = 'quake.csv' (columns time [s], acceleration [m/s^2] or [g]) or a PEER .AT2 file, "
                   "or time = [...] and acceleration = [...]")

    def __post_init__(self):
        self._check_samples()
        self._check_ground()
        check_choice(self, "baseline", "load")
        order = BASELINES[self.baseline]
        if order is not None:
            object.__setattr__(self, "acceleration",
                               tuple(baseline_correct(self.time, self.acceleration, order).tolist()))
        text = self.record_check.warning(Path(self.file).name if self.file else "[load] acceleration")
        if text:
            warnings.warn(text, RecordWarning, stacklevel=4)

    @property
    def record_check(self) -> RecordCheck:
        """The accelerogram's mean, and the drift of its velocity and displacement integrated from
        rest, after the baseline correction if any (:func:`~pdamper.structure.loads.record_check.check_record`;
        a one-sided or drifting record is warned of when the load is made)."""
        return check_record(self.time, self.acceleration)

    @property
    def peak(self) -> float:
        """The peak ground acceleration [m/s^2] (scaled)."""
        return float(np.max(np.abs(self.acceleration)) * abs(self.scale))

    def describe(self) -> str:
        return (f"ground acceleration ({self._source_words()}, peak {self.peak / 9.80665:.3g} g), "
                f"{self._ground_words()}, {self.duration:.4g} s")
