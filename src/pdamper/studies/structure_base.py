"""What the structure's studies share: the dofs asked for, the structure's numbers for a summary,
the bare structure's resonance and the tolerance of a steady amplitude.

Below :mod:`pdamper.studies.structure` (free decay, frequency response) and
:mod:`pdamper.studies.transient` (loads in time, the stepped sine), which know nothing of each
other (an import-linter contract in pyproject.toml).
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError

__all__ = ["STEADY_TOLERANCE", "parse_dofs", "select_dofs", "structure_numbers", "mode_table", "bare_resonance",
           "bed_x_opt"]

#: A point is steady when its amplitude over the last forcing period differs from the one over
#: the period before, and the two halves of the measured periods from each other, by at most
#: this (relative); a bare run when it is this close to its exact steady amplitude.
STEADY_TOLERANCE = 0.02


def parse_dofs(text) -> list:
    """The dofs asked for: ``None`` (every one), or a text of comma-separated dof labels and ranges
    ``START:STOP[:STEP]`` (0-based, STOP excluded, as Python's), e.g. ``"0,18,38"``,
    ``"0:40:2"``, ``"damper,response"``.

    >>> parse_dofs("0:6:2,9")
    [0, 2, 4, 9]
    """
    if text is None:
        return None
    out = []
    for part in str(text).split(","):
        part = part.strip()
        if not part:
            continue
        if ":" in part:
            bits = part.split(":")
            try:
                nums = [int(b) for b in bits]
            except ValueError:
                nums = []
            if len(bits) not in (2, 3) or len(nums) != len(bits) or (len(nums) == 3 and nums[2] <= 0):
                raise InputError(f"--dofs {text!r}: {part!r} is not a range START:STOP[:STEP] of whole numbers, "
                                 "e.g. 0:40:2")
            out += list(range(*nums))
        else:
            out.append(int(part) if part.lstrip("-").isdigit() else part)
    if not out:
        raise InputError(f"--dofs {text!r}: name some dofs, e.g. 0,18,38 or 0:40:2")
    return out


def select_dofs(structure, wanted) -> tuple[list, np.ndarray]:
    """(labels, indices) of the dofs ``wanted`` (labels or 0-based indices, :func:`parse_dofs`;
    None: every dof) of ``structure`` (:meth:`~pdamper.structure.StructureBase.dof_shapes`; its
    ``dof_names`` where given)."""
    from ..structure.storeys import dof_index

    labels, _ = structure.dof_shapes()
    if wanted is None:
        return list(labels), np.arange(len(labels))
    idx = [dof_index(labels, w, what="--dofs") for w in wanted]
    return [labels[i] for i in idx], np.array(idx, dtype=int)


def structure_numbers(s) -> dict:
    """The structure's plain numbers for a summary (:meth:`~pdamper.structure.StructureBase.structure_summary`),
    its number of dofs as ``dof_count`` (``dofs`` is the list of the dofs reported)."""
    out = dict(s.structure_summary())
    if "dofs" in out:
        out["dof_count"] = out.pop("dofs")
    return out


def mode_table(s) -> dict:
    """The structure's modes as it runs (``s``: with the empty container's mass), lists over the modes:
    ``frequency_hz``, ``damping_ratio``, ``phi_damper`` (the shape at the damper, in the mode's own
    normalisation: 1 kg modal mass for FE modes) and ``mass_at_damper_kg`` (m_k / phi_k^2, physical)."""
    m, _, _, pd, _, _ = (np.asarray(a, dtype=float) for a in s.modal_arrays())
    with np.errstate(divide="ignore"):
        at = np.where(pd != 0, m / np.where(pd != 0, pd, 1.0) ** 2, math.inf)
    return {"frequency_hz": np.atleast_1d(s.mode_frequencies).tolist(),
            "damping_ratio": np.atleast_1d(s.mode_damping_ratios).tolist(), "phi_damper": pd.tolist(),
            "mass_at_damper_kg": at.tolist()}


def bare_resonance(s, force_amplitude: float, near: float) -> dict:
    """The bare structure's resonance at the damper for the mode nearest ``near`` [Hz]: its peak
    steady amplitude [m] (the largest of the closed form, found to 1e-9 of the frequency, not the
    grid's value) and frequency [Hz]."""
    from scipy.optimize import minimize_scalar

    fs, zs = s.mode_frequencies, s.mode_damping_ratios
    j = int(np.argmin(np.abs(fs - near)))
    fn, z = float(fs[j]), float(zs[j])
    if not z > 0:
        return {"resonance_bare_m": math.inf, "resonance_bare_frequency_hz": fn}
    span = fn * min(0.5, 4.0 * z + 1e-3)
    res = minimize_scalar(lambda f: -float(s.steady_amplitude([f], force_amplitude)[0]), method="bounded",
                          bounds=(fn - span, fn + span), options={"xatol": 1e-9 * fn})
    at = float(res.x)
    peak = float(s.steady_amplitude([at], force_amplitude)[0])
    return {"resonance_bare_m": peak, "resonance_bare_frequency_hz": at}


def bed_x_opt(case) -> float | None:
    """X_opt [m] of the case's bed (eqs. 6, 17: one species, one layer), else None (several species,
    or a filling of none or of the whole floor)."""
    from .. import theory as th

    if len(case.particles) != 1:
        return None
    g = case.container.geometry
    n, n_max = case.particles[0].count, g.clearance_capacity(case.particles[0].radius)
    if not 1 <= n < n_max:
        return None
    return th.optimal_stroke(th.clearance(g.drive_length, n, n_max))
