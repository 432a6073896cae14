"""The damper as an equivalent tuned mass damper: its force and motion fitted by a mass and a dashpot,
and what they mean for each mode of the structure, beside Den Hartog's optimal TMD of the same mass
ratio (:mod:`pdamper.theory.tmd`; docs/structure.md, "The damper as an equivalent TMD").

- :func:`bed_force` -- the force of the container's walls on the bed F_w [N], interval means, and
  the container's absolute acceleration and velocity over the same intervals, from a coupled run's
  records (the structure's motion and the driving force);
- :func:`equivalent_damper` -- the least-squares fit ``F_w = F_0 + m_a a + c_a v`` over a record:
  the damper's apparent mass m_a [kg] and its equivalent dashpot c_a [N s/m]. Over whole periods of
  a steady harmonic motion this is the bed's complex impedance (its effective mass and equivalent
  damping, as the damper's fields have them); over any record c_a takes the energy the bed took at
  the recorded velocity (a and v are nearly orthogonal: ``int a v dt = [v^2 / 2]``). ``r2`` says how
  much of F_w's variance a linear damper explains (an impacting bed: far from 1);
- :func:`tmd_numbers` -- per mode k (modal mass m_k, stiffness k_k, damping ratio zeta_k, shape
  phi_k at the damper): the bed's mass ratio ``mu_k = m_bed phi_k^2 / m_k``, the apparent one
  ``mu_a = m_a phi_k^2 / m_k``, the detuning ``1 / sqrt(1 + mu_a) - 1`` (the mode lowered by the
  apparent mass), the added damping ratio ``zeta_a = phi_k^2 c_a / (2 sqrt(k_k (m_k + phi_k^2
  m_a)))``, the host mode's Q = 1 / (2 zeta) without and with the damper, and Den Hartog's optimal
  TMD of mass ratio mu_k (tuning, damping, the equivalent damping it is worth) with the share of
  it the particle damper reaches.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from ..theory import tmd as th

__all__ = ["bed_force", "equivalent_damper", "tmd_numbers"]


def bed_force(signals, record, *, container_mass: float, ground=None):
    """(F_w [N], a [m/s^2], v [m/s]) over each sample interval of a coupled run: the walls' force
    on the bed, and the container's absolute acceleration and velocity (interval means).

    ``signals`` (:class:`pdamper.recorders.signals.Signals`: its ``force`` is ``m_c a + F_w``, the
    acceleration the structure record's velocity difference), ``record`` the
    :class:`~pdamper.recorders.structure.StructureRecord`, ``container_mass`` [kg] the empty
    container's; ``ground`` = (velocity [m/s] at the interval edges t = 0, dt, ..., the record's
    times) under a ground acceleration, else None."""
    x, v = record.edges()
    dt = float(record.time[1] - record.time[0]) if record.time.size > 1 else 1.0
    acc = np.diff(v) / dt
    force = np.asarray(signals.force, dtype=float) - container_mass * acc
    vel = np.diff(x) / dt
    if ground is not None:
        vg = np.asarray(ground, dtype=float)
        acc = acc + np.diff(vg) / dt
        vel = vel + 0.5 * (vg[1:] + vg[:-1])
    return force, acc, vel


def equivalent_damper(force, acceleration, velocity, *, window=None) -> dict:
    """The least-squares ``F_w = F_0 + m_a a + c_a v`` over the samples (``window``: a boolean mask or
    a slice of them): ``mass_kg`` m_a, ``damping_N_s_per_m`` c_a, ``offset_N`` F_0 (a tilt's static
    share), ``r2`` (the share of F_w's variance explained), ``samples``."""
    F, a, v = (np.asarray(z, dtype=float) for z in (force, acceleration, velocity))
    if window is not None:
        F, a, v = F[window], a[window], v[window]
    ok = np.isfinite(F) & np.isfinite(a) & np.isfinite(v)
    F, a, v = F[ok], a[ok], v[ok]
    if F.size < 4 or not (np.std(a) > 0 and np.std(v) > 0):
        return {"mass_kg": math.nan, "damping_N_s_per_m": math.nan, "offset_N": math.nan, "r2": math.nan,
                "samples": int(F.size)}
    A = np.column_stack([np.ones_like(a), a, v])
    # scale the columns so the fit is well conditioned whatever the units' sizes
    s = np.maximum(np.max(np.abs(A), axis=0), 1e-300)
    coef, *_ = np.linalg.lstsq(A / s, F, rcond=None)
    coef = coef / s
    resid = F - A @ coef
    var = float(np.var(F))
    return {"mass_kg": float(coef[1]), "damping_N_s_per_m": float(coef[2]), "offset_N": float(coef[0]),
            "r2": float(1.0 - np.var(resid) / var) if var > 0 else math.nan, "samples": int(F.size)}


def tmd_numbers(modal, *, bed_mass: float, damper: dict, phi=None, labels=None) -> dict:
    """The damper's TMD numbers per mode (module docstring): ``modal`` = (m_k, k_k, c_k, phi_k(damper),
    ...) of the structure as it runs (:meth:`~pdamper.structure.StructureBase.modal_arrays`),
    ``bed_mass`` [kg], ``damper`` an :func:`equivalent_damper` (its ``mass_kg``, ``damping_N_s_per_m``),
    ``phi`` the damper's shapes (default the structure's damper point's). Lists over the modes."""
    m, k, c = (np.asarray(z, dtype=float) for z in modal[:3])
    pd = np.asarray(modal[3] if phi is None else phi, dtype=float)
    if not bed_mass > 0:
        raise InputError("the TMD numbers need a bed (bed mass > 0)")
    w = np.sqrt(k / m)
    zeta = c / (2.0 * m * w)
    ma, ca = float(damper["mass_kg"]), float(damper["damping_N_s_per_m"])
    mu = bed_mass * pd**2 / m
    mu_a = ma * pd**2 / m
    m_with = m + pd**2 * ma
    with np.errstate(invalid="ignore", divide="ignore"):
        zeta_a = pd**2 * ca / (2.0 * np.sqrt(k * m_with))
        zeta_s = c / (2.0 * np.sqrt(k * m_with))  # the structure's own dashpot on the heavier mode
        zeta_with = zeta_s + zeta_a
        q = np.where(zeta > 0, 1.0 / (2.0 * zeta), math.inf)
        q_with = np.where(zeta_with > 0, 1.0 / (2.0 * zeta_with), math.inf)
        detune = 1.0 / np.sqrt(1.0 + mu_a) - 1.0
        dh_eq = th.den_hartog_equivalent_damping(mu)
        share = np.where(dh_eq > 0, zeta_a / dh_eq, math.nan)
    return {
        "modes": list(range(1, m.size + 1)) if labels is None else list(labels),
        "frequency_hz": (w / (2.0 * math.pi)).tolist(), "damping_ratio": zeta.tolist(), "q": q.tolist(),
        "phi_damper": pd.tolist(), "mass_at_damper_kg": (m / pd**2).tolist(),
        "mass_ratio": mu.tolist(), "effective_mass_ratio": mu_a.tolist(),
        "detuning": detune.tolist(), "frequency_with_damper_hz": (w / (2.0 * math.pi) * (1.0 + detune)).tolist(),
        "added_damping_ratio": zeta_a.tolist(), "damping_ratio_with_damper": zeta_with.tolist(),
        "q_with_damper": q_with.tolist(),
        "den_hartog_tuning": th.den_hartog_tuning(mu).tolist(),
        "den_hartog_damping_ratio": th.den_hartog_damping(mu).tolist(),
        "den_hartog_equivalent_damping_ratio": dh_eq.tolist(), "share_of_den_hartog": share.tolist(),
        "equivalent_mass_kg": ma, "equivalent_damping_N_s_per_m": ca,
        "fit_r2": damper.get("r2", math.nan), "bed_mass_kg": float(bed_mass),
    }
