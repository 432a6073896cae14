"""What the structure's studies share: the dofs asked for, the structure's numbers for a summary,
the bare structure's resonance and the tolerance of a steady amplitude.

Below :mod:`pdamper.studies.structure` (free decay, frequency response) and
:mod:`pdamper.studies.transient` (loads in time, the stepped sine), which know nothing of each
other (an import-linter contract in pyproject.toml).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, shown

__all__ = ["STEADY_TOLERANCE", "parse_dofs", "select_dofs", "structure_numbers", "mode_table", "bare_resonance",
           "DampedRun", "damped_run", "solid_amplitude",
           "bed_x_opt", "codes_over_frequencies", "response_codes"]

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
                raise InputError(f"--dofs {shown(text)}: {shown(part)} is not a range START:STOP[:STEP] of whole numbers, "
                                 "e.g. 0:40:2")
            out += list(range(*nums))
        else:
            out.append(int(part) if part.lstrip("-").isdigit() else part)
    if not out:
        raise InputError(f"--dofs {shown(text)}: name some dofs, e.g. 0,18,38 or 0:40:2")
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


@dataclass(frozen=True, kw_only=True)
class DampedRun:
    """A run of the structure with its dampers, as the studies read it: at the sample (or coupling
    step) ends ``time`` [s], the first damper point's ``displacement`` [m], the response point's
    ``response_displacement``, every dof's ``dofs`` [samples, dofs] (the labels of the structure's
    :meth:`~pdamper.structure.StructureBase.dof_shapes`), each damper point's ``dampers`` [samples,
    dampers]; each bed's wall force ``forces`` [N] and its container's absolute acceleration
    ``accelerations`` [m/s^2] and velocity ``velocities`` [m/s] (interval means, [samples, dampers]),
    the beds' energy ``dissipated`` from t = 0 [J]; the coupled ledger's error
    (``energy_balance_error``; None where it is not closed); the run's numbers; ``coupling`` the coupling
    loop's summary (empty for one bed in the compiled tight coupling)."""

    time: np.ndarray
    displacement: np.ndarray
    response_displacement: np.ndarray
    dofs: np.ndarray
    dampers: np.ndarray
    forces: np.ndarray
    accelerations: np.ndarray
    velocities: np.ndarray
    dissipated: np.ndarray
    energy_balance_error: float | None
    steps: int
    time_step_s: float
    wall_time_s: float
    coupling: dict = field(default_factory=dict)


def damped_run(case, *, progress=None) -> DampedRun:
    """Run ``case`` (a structure with its dampers): one bed by the compiled tight coupling
    (:class:`~pdamper.simulation.Simulation`), several or a co-simulated structure by the coupling loop
    (:func:`pdamper.cosim.run_coupled`). A :class:`~pdamper.errors.SimulationError` is the caller's."""
    s = case.running_drive
    if not case.in_loop:
        from ..analysis.tmd import bed_force
        from ..simulation import Simulation
        from ..structure.linear import ground_velocity

        res = Simulation(case).run(progress=progress)
        rec = res.structure
        edges = np.concatenate([[0.0], rec.time])
        vg = ground_velocity(s.load, edges) if s.load is not None and s.load.ground else None
        fw, a, v = bed_force(res.signals, rec, container_mass=case.container.mass, ground=vg)
        lost = res.energy.damping + res.energy.friction
        dissipated = np.interp(rec.time, res.energy.time, lost) - float(np.interp(0.0, res.energy.time, lost))
        return DampedRun(time=rec.time, displacement=rec.displacement, response_displacement=rec.response_displacement,
                         dofs=rec.dof_displacements(s.dof_shapes()[1]), dampers=rec.displacement[:, None],
                         forces=fw[:, None], accelerations=a[:, None], velocities=v[:, None], dissipated=dissipated,
                         energy_balance_error=rec.balance_error(res.energy), steps=res.steps,
                         time_step_s=res.time_step_s, wall_time_s=res.wall_time_s)
    from ..cosim import run_coupled

    run = run_coupled(case, progress=progress)
    c = dict(run.summary)
    steps, wall = c.pop("steps"), c.pop("wall_time_s")
    h = float(c["coupling_step_s"])
    x, v = run.container_displacement, run.container_velocity
    return DampedRun(time=run.time, displacement=run.displacement, response_displacement=run.response_displacement,
                     dofs=run.displacements, dampers=run.damper_displacement, forces=run.forces,
                     accelerations=np.diff(v, axis=0) / h, velocities=np.diff(x, axis=0) / h,
                     dissipated=sum(L.damping + L.friction for L in run.ledgers),
                     energy_balance_error=c["coupled_energy_balance_error"], steps=steps, time_step_s=math.nan,
                     wall_time_s=wall, coupling=c)


def solid_amplitude(case, s, frequencies, force_amplitude: float, point: str = "damper"):
    """The steady amplitude [m] at the damper (or the response point) of the structure ``s`` (as it
    runs) with each damper's bed as a rigid mass at its point, under ``force_amplitude`` [N] at each of
    ``frequencies`` [Hz] (closed form)."""
    if case.damper_count == 1:
        return s.steady_amplitude(frequencies, force_amplitude, added_mass=case.bed_mass, point=point)
    masses = np.zeros(s.damper_count)
    for k, d in enumerate(case.damper_beds()):
        masses[case.damper_point(k)] += d.bed_mass
    return s.carrying(masses if masses.size > 1 else float(masses[0])).steady_amplitude(
        frequencies, force_amplitude, point=point)


def codes_over_frequencies(s, frequencies, per: dict, force_amplitude: float, labels, idx, *, limits=None,
                           method: str = "") -> dict:
    """The JSON ``codes`` of a forced response (:func:`pdamper.analysis.codes.code_summary`): ``per``
    the numbers with the damper per dof (every dof of ``s``) or storey and frequency (key -> a list
    over the frequencies of lists over the dofs or storeys, None for a failed point), without it the
    structure's steady harmonic response (:func:`pdamper.analysis.codes.harmonic_numbers`); each dof's (``idx``, ``labels``) and storey's
    largest over the ``frequencies`` [Hz] and where (``_at_hz``), the lists per frequency in
    ``by_frequency`` (``by_frequency_bare``)."""
    from ..analysis.codes import code_summary, harmonic_numbers, worst

    storeys = s.storeys()
    freqs = np.asarray(frequencies, dtype=float)
    width = {"acceleration": len(s.dof_shapes()[0]), "drift": len(storeys.labels) if storeys else 0}

    def rows(key, table):  # [frequency][dof] -> [dof][frequency], the dofs asked for
        w = width[key.split("_")[0]]
        arr = np.array([r if r is not None else [math.nan] * w for r in table], dtype=float).reshape(freqs.size, w).T
        return (arr[idx] if key.startswith("acceleration") else arr).tolist()

    damped = {key: rows(key, per[key]) for key in per}
    bare_all = harmonic_numbers(freqs, s.dof_phasors(freqs, force_amplitude), storeys=storeys)
    bare = {key: (np.asarray(v)[idx].tolist() if key.startswith("acceleration") else v) for key, v in bare_all.items()}
    out = code_summary(worst(damped, freqs), worst(bare, freqs), dofs=labels, storeys=storeys, limits=limits,
                       method=method)
    out.update(frequencies_hz=freqs.tolist(), by_frequency=damped, by_frequency_bare=bare)
    return out


def response_codes(s, frequencies, point_codes: list, force_amplitude: float, labels, idx, *, limits=None) -> dict:
    """:func:`codes_over_frequencies` of a DEM response: ``point_codes`` each point's ``codes`` (over its
    measured periods, :func:`pdamper.studies.structure.response_point`, or a stepped sine's step;
    None: the point failed)."""
    keys = ["acceleration_peak_m_s2", "acceleration_rms_m_s2"]
    if s.storeys() is not None:
        keys += ["drift_ratio_peak", "drift_ratio_rms"]
    per = {key: [pc[key] if pc else None for pc in point_codes] for key in keys}
    return codes_over_frequencies(s, frequencies, per, force_amplitude, labels, idx, limits=limits,
                                  method="DEM: peak and RMS over the measured periods, the second difference of "
                                         "the sampled displacements; without the damper: the steady harmonic response")
