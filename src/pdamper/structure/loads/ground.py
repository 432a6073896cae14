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
or drifting record is warned of) and, with ``baseline``, corrected (:mod:`.record_check`). A suite of
records (``files = [...]`` or a folder: ``pdamper transient`` runs one transient a record) is
checked record by record as it is read. A record is scaled by ``scale``, or to a target: a peak
ground acceleration (``pga``) or a 5 %-damped pseudo-spectral acceleration at the structure's first
period (``sa``; ``sa_period``, ``sa_damping``; :mod:`pdamper.structure.spectrum`), each record of a
suite by its own factor, after its baseline correction."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

import warnings
from pathlib import Path

from ...errors import InputError, shown
from ...schema import check_choice, param
from .base import SampledFields, SampledLoad, register_load
from .record_check import BASELINES, RecordCheck, RecordWarning, baseline_correct, check_record

__all__ = ["GroundAcceleration", "GroundMixin", "read_acceleration", "STANDARD_GRAVITY"]


def _warn(check: RecordCheck, source: str) -> None:
    """The record check's warning for ``source``, if it has one (a one-sided or drifting record)."""
    text = check.warning(source)
    if text:
        warnings.warn(text, RecordWarning, stacklevel=5)

#: The periods [s] a target spectral acceleration may be given at.
SA_PERIODS = (0.01, 100.0)
#: g_n [m/s^2], the unit "g" of a record's target ("0.3g").
STANDARD_GRAVITY = 9.80665


def read_acceleration(value, key: str) -> float:
    """An acceleration [m/s^2] as a record's target is written: ``"0.3g"`` (g the standard gravity,
    as strong-motion records count), a unit (``"2.9m/s^2"``) or a bare number (SI)."""
    from ...units import parse_quantity

    if isinstance(value, str):
        text = value.strip()
        if text.endswith("g") and not text.endswith("kg"):
            try:
                return float(text[:-1]) * STANDARD_GRAVITY
            except (ValueError, OverflowError):
                pass
        return parse_quantity(text, "acceleration", name=key)
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{key} = {shown(value)}; give an acceleration, e.g. '0.3g' or '2.94m/s^2'")
    try:
        return float(value)
    except OverflowError:
        raise InputError(f"{key} = {shown(value)}: too large a number; give an acceleration, e.g. '0.3g'") from None


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
    files : tuple
        A suite of records (:class:`~pdamper.structure.loads.base.Record`; config ``files =
        [...]`` or a folder): one transient each (:meth:`records`); its own samples the first's.
    pga : float or None
        Scale each record to this peak ground acceleration [m/s^2] (config ``"0.3g"``), instead of
        ``scale``.
    sa : float or None
        Scale each record so that its ``sa_damping`` (5 %) damped pseudo-spectral acceleration at
        ``sa_period`` is this [m/s^2]; ``sa_period`` [s] default the first period of the structure
        the load is given to (:meth:`for_structure`).
    """

    acceleration: tuple = param((), kind="list", dimension="acceleration")
    influence: tuple | None = param(None, kind="list")
    participation: tuple | None = param(None, kind="list")
    baseline: str = param("none", choices=tuple(BASELINES), write_default=False)
    pga: float | None = param(None, kind="custom")
    sa: float | None = param(None, kind="custom")
    sa_period: float | None = param(None, dimension="time")
    sa_damping: float = param(0.05, write_default=False)
    kind: str = param("ground_acceleration", kind="tag")
    ground = True
    signal_role = "acceleration"
    samples_field = "acceleration"
    unit = "m/s^2"
    size_keys = ("scale", "acceleration", "file", "files", "pga", "sa", "influence", "participation", "baseline")
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
        self._resolve_target()
        if self.files:  # a suite: each record checked as read (records() builds them without a word)
            for rec in self.records():
                _warn(rec.record_check, Path(rec.file).name)
        else:
            _warn(self.record_check, Path(self.file).name if self.file else "[load] acceleration")

    @property
    def record_check(self) -> RecordCheck:
        """The accelerogram's mean, and the drift of its velocity and displacement integrated from
        rest, after the baseline correction if any (:func:`~pdamper.structure.loads.record_check.check_record`;
        a one-sided or drifting record is warned of when the load is made)."""
        return check_record(self.time, self.acceleration)

    # ---- a target: the scale that puts the record at a PGA or a spectral acceleration
    def _resolve_target(self) -> None:
        """``scale`` from the target: ``pga`` over the record's peak, ``sa`` over its PSA at
        ``sa_period`` (pending until the period is known: :meth:`for_structure`)."""
        from ..spectrum import spectral_acceleration

        for key in ("pga", "sa", "sa_period"):
            v = getattr(self, key)
            if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float)) or not (v > 0 and math.isfinite(v))):
                unit = " s" if key == "sa_period" else " m/s^2" if isinstance(v, (int, float)) else ""
                raise InputError(f"load.{key} = {shown(v)}{unit}; must be > 0, e.g. " + ("'0.5s'" if key == "sa_period" else "'0.3g'"))
        if self.sa_period is not None and not SA_PERIODS[0] <= self.sa_period <= SA_PERIODS[1]:
            raise InputError(f"load.sa_period = {self.sa_period:g} s; give a period from {SA_PERIODS[0]:g} to "
                             f"{SA_PERIODS[1]:g} s, e.g. '0.5s' (a number without a unit is seconds)")
        z = self.sa_damping
        if isinstance(z, bool) or not isinstance(z, (int, float)) or not 0 < z < 1:
            raise InputError(f"load.sa_damping = {shown(z)}; give the spectrum's damping ratio between 0 and 1, e.g. 0.05")
        if self.pga is not None and self.sa is not None:
            raise InputError("load.pga and sa are both given; scale the records to one target")
        if self.sa is None and (self.sa_period is not None or z != 0.05):
            raise InputError("load.sa_period and sa_damping belong to a target spectral acceleration; give sa with "
                             "them (e.g. sa = '0.5g')")
        object.__setattr__(self, "_pending", False)
        raw = np.asarray(self.acceleration, dtype=float)
        where = f" ({self.file})" if self.file else ""
        if self.pga is not None:
            peak = float(np.max(np.abs(raw)))
            if not peak > 0:
                raise InputError(f"load.pga: the record{where} is zero everywhere; nothing to scale")
            object.__setattr__(self, "scale", self.pga / peak)
        elif self.sa is not None:
            if self.sa_period is None:
                object.__setattr__(self, "_pending", True)
                return
            got = spectral_acceleration(self.time, raw, self.sa_period, damping=z)
            if not got > 0:
                raise InputError(f"load.sa: the record{where} has no spectral acceleration at {self.sa_period:.4g} s")
            object.__setattr__(self, "scale", self.sa / got)

    def for_structure(self, structure):
        """The load with ``sa_period`` the structure's first period (1 / its lowest mode's frequency)
        where ``sa`` is given without it; else itself."""
        if self.sa is None or self.sa_period is not None:
            return self
        f1 = float(np.min(structure.mode_frequencies))
        if not SA_PERIODS[0] <= 1.0 / f1 <= SA_PERIODS[1]:
            raise InputError(f"the structure's first mode at {f1:.4g} Hz (structure.natural_frequency, or its mass and "
                             f"stiffness, modes or matrices) puts the target [load] sa at a period of {1.0 / f1:.4g} s, "
                             f"outside {SA_PERIODS[0]:g}-{SA_PERIODS[1]:g} s; check the structure, or give [load] sa_period")
        return dataclasses.replace(self, sa_period=1.0 / f1)

    @classmethod
    def config_read_extra(cls, table: dict, base_dir, read_signal) -> dict:
        """The file(s) (:class:`~pdamper.structure.loads.base.SampledLoad`) and the targets ``pga``,
        ``sa`` (``"0.3g"``), which set the scale (not both with ``scale``)."""
        out = super().config_read_extra(table, base_dir, read_signal)
        for key in ("pga", "sa"):
            if key in table:
                out[key] = read_acceleration(table[key], f"[load] {key}")
        target = [k for k in ("pga", "sa") if k in table]
        if target and "scale" in table:
            raise InputError(f"[load] scale and {target[0]} both set the records' scale; give one")
        return out

    def config_table(self) -> dict:
        """Its table (:meth:`~pdamper.structure.loads.base.SampledLoad.config_table`); with a target,
        the target instead of the scale it gives."""
        out = super().config_table()
        for key in ("pga", "sa"):
            if getattr(self, key) is not None:
                out.pop("scale", None)
                out[key] = float(getattr(self, key))
        return out

    def kernel_table(self):
        """The scaled samples (:meth:`~pdamper.structure.loads.base.SampledLoad.kernel_table`); a
        spectral target must know its period first."""
        if self.__dict__.get("_pending"):
            raise InputError("load.sa: the period of the target spectral acceleration is not known yet; give the load "
                             "to a [structure] (its first period is taken) or set load.sa_period")
        return super().kernel_table()

    def target_words(self) -> str:
        """The target in words ("scaled to PGA 0.3 g"), or ""."""
        if self.pga is not None:
            return f"scaled to PGA {self.pga / STANDARD_GRAVITY:.3g} g"
        if self.sa is not None:
            at = f"{self.sa_period:.3g} s" if self.sa_period is not None else "the structure's first period"
            return f"scaled to Sa({at}, {100 * self.sa_damping:g} %) = {self.sa / STANDARD_GRAVITY:.3g} g"
        return ""

    @property
    def peak(self) -> float:
        """The peak ground acceleration [m/s^2] (scaled)."""
        return float(np.max(np.abs(self.acceleration)) * abs(self.scale))

    def describe(self) -> str:
        target = self.target_words()
        if self.files:
            return f"ground acceleration, {self._source_words()}, {self._ground_words()}"
        return (f"ground acceleration ({self._source_words()}, peak {self.peak / 9.80665:.3g} g"
                + (f", {target}" if target else "") + f"), {self._ground_words()}, {self.duration:.4g} s")
