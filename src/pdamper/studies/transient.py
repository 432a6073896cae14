"""The damper on a structure under a load in time (``[load]``): peaks and RMS at every dof with the
damper and without it, and the stepped sine.

- :func:`run_transient` -- the coupled DEM under the case's load in time (a force history, a
  ground acceleration, a random load, a stepped sine; or the structure's harmonic force from
  rest, :func:`in_time`) and the structure without the bed by its
  exact linear response (:mod:`pdamper.structure.linear`): every dof's peak and RMS and their
  ratios (damped / bare); for a random load the response PSD and the FRF estimate H1 (Welch,
  :func:`scipy.signal.csd`) against the exact FRF.
- :func:`run_stepped_sine` -- the stepped sine up or down (one DEM run, the state carried from one
  frequency to the next): the steady amplitude of each step at the damper and at every dof, with
  the bare structure's steady closed form and its stepped sine measured the same way.

See docs/structure.md ("Loads in time") for the model and measured numbers.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, shown
from ..params import Case
from ..structure.linear import dof_response, frequency_response, modal_response
from ..structure.loads import SteppedSine
from .structure_base import (STEADY_TOLERANCE, DampedRun, bare_resonance, damped_run, mode_table, parse_dofs,
                             response_codes, select_dofs, structure_numbers)

__all__ = ["TransientResult", "SweepResult", "run_transient", "in_time", "run_stepped_sine", "parse_dofs",
           "select_dofs", "fit_sine", "sweeps_apart", "SWEEPS", "APART", "structure_numbers", "code_numbers",
           "tmd_equivalent"]

#: The directions of a stepped sine.
SWEEPS = ("up", "down")
#: A stepped sine up and one down part where their amplitudes at a frequency differ by more than this fraction.
APART = 0.05


def in_time(case: Case) -> Case:
    """``case`` with its structure's load in time: its ``[load]``; or, a structure forced by its
    harmonic force (``force_amplitude``, ``force_frequency``) and no ``[load]``, that force from the
    start as a stepped sine of one step of ``[run] cycles`` periods (the same force and run length,
    as a load table: a case written by ``pdamper design --write-case`` runs so)."""
    if not case.drive.coupled:
        raise InputError("this study needs a [structure] section (the container riding on a structure) and a "
                         "[load]; see examples/frame_quake.toml")
    s = case.drive
    if s.load is None and s.force_amplitude > 0:
        force = SteppedSine(amplitude=float(s.force_amplitude), frequencies=(float(s.force_frequency),),
                            cycles=float(case.cycles))
        return dataclasses.replace(case, drive=dataclasses.replace(s, force_amplitude=0.0, load=force))
    if s.load is None:
        raise InputError("pdamper transient needs a load in time: a [load] section with kind = 'force_history', "
                         "'ground_acceleration', 'random' or 'stepped_sine', or the [structure]'s force_amplitude "
                         "and force_frequency (that force from rest)")
    return case


def _peak_rms(x: np.ndarray):
    return np.max(np.abs(x), axis=0), np.sqrt(np.mean(x * x, axis=0))


def _ratio(a, b):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(b > 0, a / b, np.nan)


def _bare(case: Case, s, t):
    """(every dof [samples, dofs], the damper points [samples, dampers]) without the dampers at ``t``:
    the exact linear response, or OpenSees' own run of a co-simulated model (:func:`pdamper.cosim.run_bare`)."""
    if case.drive.cosimulated:
        from ..cosim import run_bare

        run = run_bare(case)
        return run.displacements, run.damper_displacement
    _, bare_all = dof_response(s, t)
    q_bare, _ = modal_response(s, t)
    shapes = s.damper_shapes()[[case.damper_point(k) for k in range(case.damper_count)]]
    return bare_all, q_bare @ shapes.T


def _residual(t, x, s) -> np.ndarray:
    """The residual displacement [m] of each column of ``x`` after the load: its mean over the last two
    periods of the structure's first mode (a yielded structure's offset; about 0 for a linear one)."""
    keep = t >= t[-1] - 2.0 / float(np.min(s.mode_frequencies))
    return np.mean(x[keep], axis=0)


@dataclass(frozen=True, kw_only=True)
class TransientResult:
    """A structure under a load in time with the damper (DEM) and without (exact).

    Attributes: ``time`` [s] (the samples' ends); ``load`` f(t) there [N or m/s^2]; ``dofs`` the
    labels; ``damped`` / ``bare`` [samples, dofs] displacements [m] (relative to the ground
    under a ground acceleration); ``damper`` / ``damper_bare`` the damper point's; ``random``
    the PSDs and FRFs of a random load (None else); ``summary`` plain numbers for JSON;
    ``dissipated`` the bed's dissipated energy [J] from t = 0 on.
    """

    case: Case
    time: np.ndarray
    load: np.ndarray
    dofs: list
    damped: np.ndarray
    bare: np.ndarray
    damper: np.ndarray
    damper_bare: np.ndarray
    random: dict | None = None
    summary: dict = field(default_factory=dict)
    #: the energy the bed has dissipated (contact damping and friction) from t = 0 on [J], at ``time``
    dissipated: np.ndarray | None = None


def run_transient(case: Case, *, dofs=None, progress=None, limits=None) -> TransientResult:
    """The coupled DEM of ``case`` under its load in time and the bare structure's exact response:
    every dof's (or ``dofs``': labels) peak and RMS over the run with and without the damper, and
    their ratios (damped / bare: < 1 is a reduction); a random load's PSDs and H1 (module
    docstring). A structure forced harmonically without a ``[load]`` runs under that force from
    rest (:func:`in_time`). ``progress(fraction)`` is passed to the DEM run. The numbers codes ask
    for (summary ``codes``: :func:`code_numbers`, against ``limits``, a
    :class:`~pdamper.analysis.codes.Limits`) and the damper as an equivalent TMD (``tmd_equivalent``:
    :func:`tmd_equivalent`) with them."""
    case = in_time(case)
    s = case.running_drive
    labels, idx = select_dofs(s, dofs)
    run = damped_run(case, progress=progress)
    ground = bool(s.load.ground)
    t = run.time
    damped_all = run.dofs
    damped = damped_all[:, idx]
    bare_all, points_bare = _bare(case, s, t)
    bare = bare_all[:, idx]
    damper_bare = points_bare[:, 0]
    f = s.load.values(t)
    peak, rms = _peak_rms(damped)
    peak_b, rms_b = _peak_rms(bare)
    ppk, prms = _peak_rms(run.dampers)
    ppk_b, prms_b = _peak_rms(points_bare)
    beds = case.damper_beds()
    bed_mass = float(sum(d.bed_mass for d in beds))
    # the tight coupling's ledger is closed under every load (in the ground's frame, the ground's inertial
    # force on the bed included); the loop's coupled ledger is None where it is not closed
    err = run.energy_balance_error
    summary = {
        "load": s.load.describe(), "load_kind": s.load.kind, "ground": ground,
        "relative_to_ground": ground, "duration_s": case.duration, "particles": int(sum(d.n_particles for d in beds)),
        "bed_mass_kg": bed_mass, "mass_ratio": bed_mass / s.mass,
        "dofs": list(labels), "peak_m": peak.tolist(), "rms_m": rms.tolist(), "peak_bare_m": peak_b.tolist(),
        "rms_bare_m": rms_b.tolist(), "peak_reduction": _ratio(peak, peak_b).tolist(),
        "rms_reduction": _ratio(rms, rms_b).tolist(),
        "residual_m": _residual(t, damped, s).tolist(), "residual_bare_m": _residual(t, bare, s).tolist(),
        "damper_peak_m": float(ppk[0]), "damper_rms_m": float(prms[0]), "damper_peak_bare_m": float(ppk_b[0]),
        "damper_rms_bare_m": float(prms_b[0]), "damper_peak_reduction": float(_ratio(ppk, ppk_b)[0]),
        "damper_rms_reduction": float(_ratio(prms, prms_b)[0]),
        "load_peak": float(np.max(np.abs(f))), "load_rms": float(np.sqrt(np.mean(f * f))),
        "energy_balance_error": err,
        "steps": run.steps, "time_step_s": run.time_step_s, "wall_time_s": run.wall_time_s,
        "method": "dem", **structure_numbers(s),
    }
    if case.damper_count > 1:
        summary.update(dampers=case.damper_count, damper_points_peak_m=ppk.tolist(),
                       damper_points_peak_bare_m=ppk_b.tolist(), damper_points_rms_m=prms.tolist(),
                       damper_points_rms_bare_m=prms_b.tolist(), bed_masses_kg=[d.bed_mass for d in beds],
                       damper_particles=[d.n_particles for d in beds])
    if run.coupling:
        summary["coupling"] = run.coupling
    if err is None:
        summary["energy_balance_note"] = (
            "the coupling loop's coupled ledger is closed on pdamper's own structure under a force or a start; here "
            "the coupling's energy error is coupling.interface_energy_error (the work the walls did on the beds "
            "against the work their forces took from the structure)")
    random = _random_spectra(s, t, f, damped, bare, idx) if s.load.stationary else None
    if random is not None:
        summary["random"] = random
    summary["mode_table"] = mode_table(s)
    summary["codes"] = code_numbers(s, t, damped_all, labels, idx, limits=limits,
                                    bare=bare_all if case.drive.cosimulated else None)
    summary["tmd_equivalent"] = [tmd_equivalent(case, run, k) for k in range(case.damper_count)]
    return TransientResult(case=case, time=t, load=f, dofs=list(labels), damped=damped, bare=bare,
                           dissipated=run.dissipated, damper=run.displacement, damper_bare=damper_bare, random=random,
                           summary=summary)


def code_numbers(s, time, damped, labels, idx, *, limits=None, bare=None) -> dict:
    """The numbers codes ask for (:mod:`pdamper.analysis.codes`) of the structure ``s`` (as it runs)
    under its load in time, with the damper (``damped``: every dof's displacement [m] at the record's
    ``time`` [s], relative to the ground) and without (exact): the absolute floor accelerations of the
    dofs ``idx`` (``labels``), every storey's drift ratio (peak, RMS, and residual: the mean over the
    last two periods of the first mode), against ``limits``. The record starts from the structure's
    state at t = 0. ``bare``: every dof's displacement without the damper at ``time`` (a co-simulated
    structure's own run; default the exact linear response)."""
    from ..analysis.codes import code_summary, time_numbers

    _, shapes = s.dof_shapes()
    t = np.concatenate([[0.0], np.asarray(time, dtype=float)])
    x0 = np.asarray(shapes) @ np.asarray(s.initial_modal_state()[0], dtype=float)
    x = np.vstack([x0[None, :], np.asarray(damped, dtype=float)])
    if bare is None:
        _, xb = dof_response(s, t)
    else:
        xb = np.vstack([x0[None, :], np.asarray(bare, dtype=float)])
    ground = s.load.values(t) if s.load.ground else None
    storeys = s.storeys()
    window = 2.0 / float(s.natural_frequency)
    d, b = (time_numbers(t, y, storeys=storeys, ground=ground, residual_window=window) for y in (x, xb))
    for out in (d, b):
        for key in ("acceleration_peak_m_s2", "acceleration_rms_m_s2"):
            out[key] = [out[key][i] for i in idx]
    dt = float(t[1] - t[0])
    return code_summary(d, b, dofs=labels, storeys=storeys, limits=limits, ground=bool(s.load.ground),
                        method=f"the second difference of the displacements sampled every {dt * 1e3:.3g} ms")


def tmd_equivalent(case: Case, run, k: int = 0) -> dict:
    """Damper ``k`` of ``case`` as an equivalent TMD (:mod:`pdamper.analysis.tmd`) from its coupled run
    ``run`` (a :class:`~pdamper.studies.structure_base.DampedRun`, or the RunRecord of one bed): the mass and dashpot fitted to the
    bed's force over the whole record and what they mean for each mode of the structure (as it runs),
    seen at the damper's point."""
    from ..analysis.tmd import equivalent_damper, tmd_numbers

    s = case.running_drive
    if not isinstance(run, DampedRun):  # a RunRecord of the compiled tight coupling
        from ..analysis.tmd import bed_force
        from ..structure.linear import ground_velocity

        rec = run.structure
        edges = np.concatenate([[0.0], rec.time])
        vg = ground_velocity(s.load, edges) if s.load is not None and s.load.ground else None
        fw, a, v = bed_force(run.signals, rec, container_mass=case.container.mass, ground=vg)
        run = DampedRun(time=rec.time, displacement=rec.displacement, response_displacement=rec.displacement,
                        dofs=rec.displacement[:, None], dampers=rec.displacement[:, None], forces=fw[:, None],
                        accelerations=a[:, None], velocities=v[:, None], dissipated=rec.time * 0.0,
                        energy_balance_error=None, steps=0, time_step_s=0.0, wall_time_s=0.0)
    eq = equivalent_damper(run.forces[:, k], run.accelerations[:, k], run.velocities[:, k])
    mass, stiff, damp, _, pf, pr = s.modal_arrays()
    shapes = s.damper_shapes()[case.damper_point(k)]
    bed = case.damper_beds()[k].bed_mass
    out = {**tmd_numbers((mass, stiff, damp, shapes, pf, pr), bed_mass=bed, damper=eq), "fit": eq,
           "fit_over": "the whole record"}
    if case.damper_count > 1:
        out["damper"] = k + 1
    return out


def _random_spectra(s, t, f, damped, bare, idx) -> dict:
    """Welch PSDs of the load and of each dof, and the FRF estimate H1 = G_fx / G_ff with and
    without the damper against the exact FRF, over the load's band (segments of 2^k samples, a
    quarter of the record or less: 7 averages with half overlap, Hann window). The resolution
    fs / segment smears a resonance narrower than it (both H1 alike): a longer record narrows it."""
    from scipy.signal import coherence, csd, welch

    fs = 1.0 / (t[1] - t[0])
    n = t.size
    nper = int(2 ** math.floor(math.log2(max(n // 4, 16))))
    kw = dict(fs=fs, nperseg=nper, window="hann", noverlap=nper // 2, detrend="constant")
    fr, gff = welch(f, **kw)
    lo, hi = s.load.band
    keep = (fr >= lo) & (fr <= hi) & (fr > 0)
    _, gxx = welch(damped, axis=0, **kw)
    _, gbb = welch(bare, axis=0, **kw)
    _, gfx = csd(f[:, None], damped, axis=0, **kw)
    _, gfb = csd(f[:, None], bare, axis=0, **kw)
    _, coh = coherence(f[:, None], damped, axis=0, **kw)
    h1, h1b = gfx / gff[:, None], gfb / gff[:, None]
    exact = frequency_response(s, fr)[:, idx]
    ok = keep[:, None] & (np.abs(exact) > 0)
    err = np.abs(np.abs(h1b[ok]) / np.abs(exact[ok]) - 1.0)
    return {
        "frequencies_hz": fr[keep].tolist(), "segment_samples": nper, "frequency_resolution_hz": float(fs / nper),
        "load_psd": gff[keep].tolist(), "load_psd_target": s.load.psd(fr[keep]).tolist(),
        "response_psd_m2_per_hz": gxx[keep].T.tolist(), "response_psd_bare_m2_per_hz": gbb[keep].T.tolist(),
        "h1_abs": np.abs(h1[keep]).T.tolist(), "h1_phase_rad": np.angle(h1[keep]).T.tolist(),
        "h1_bare_abs": np.abs(h1b[keep]).T.tolist(), "frf_exact_abs": np.abs(exact[keep]).T.tolist(),
        "frf_exact_phase_rad": np.angle(exact[keep]).T.tolist(), "coherence": coh[keep].T.tolist(),
        "h1_bare_vs_exact_median_error": float(np.median(err)) if err.size else math.nan,
        "load_variance": float(np.var(f)), "load_variance_target": float(s.load.target_variance),
    }


# --------------------------------------------------------------------------- the stepped sine

def fit_sine(time, x, frequency: float) -> complex:
    """The complex amplitude x^ [m] of ``x(t) = Im(x^ e^{i Omega t}) + const`` fitted by least
    squares over ``time`` [s] (exact for a sinusoid on any window, whole periods or not)."""
    t = np.asarray(time, dtype=float)
    w = 2.0 * math.pi * frequency
    A = np.column_stack([np.sin(w * t), np.cos(w * t), np.ones_like(t)])
    (a, b, _), *_ = np.linalg.lstsq(A, np.asarray(x, dtype=float), rcond=None)
    return complex(a, b)  # a sin + b cos = Im((a + i b) e^{i w t})


@dataclass(frozen=True, kw_only=True)
class SweepResult:
    """A stepped sine with the damper (DEM) and without it, step by step in the sweep's order.

    ``frequencies`` [Hz]; ``damped`` the steady amplitude at the damper of each step [m] (fitted
    over its last ``measure_cycles``), ``phase`` its phase against the force [rad]; ``bare`` the
    closed form, ``bare_sweep`` the bare structure's stepped sine measured the same way, ``solid``
    the bed as a rigid mass; ``dof_amplitudes`` [steps, dofs]; ``time``/``displacement`` the run's
    damper record; ``summary`` for JSON (the keys of a response)."""

    case: Case
    force_amplitude: float
    direction: str
    frequencies: np.ndarray
    damped: np.ndarray
    phase: np.ndarray
    bare: np.ndarray
    bare_sweep: np.ndarray
    solid: np.ndarray
    dof_amplitudes: np.ndarray
    time: np.ndarray
    displacement: np.ndarray
    summary: dict = field(default_factory=dict)


def sweep_order(frequencies, direction: str) -> np.ndarray:
    """``frequencies`` [Hz] sorted for a sweep ``direction`` (``"up"``: rising, ``"down"``: falling)."""
    if direction not in SWEEPS:
        raise InputError(f"--sweep {shown(direction)}; choose one of {', '.join(SWEEPS)}")
    f = np.sort(np.unique(np.asarray(frequencies, dtype=float)))
    return f if direction == "up" else f[::-1]


def run_stepped_sine(case: Case, frequencies, *, force_amplitude: float, direction: str = "up",
                     measure_cycles: int = 8, dofs=None, progress=None, limits=None) -> SweepResult:
    """The stepped sine of ``force_amplitude`` [N] over ``frequencies`` [Hz] in ``direction`` (each
    step ``case.cycles`` periods, the last ``measure_cycles`` fitted; one DEM run, the state carried
    from step to step), with the bare structure's exact stepped sine and steady closed form; the
    numbers codes ask for over each step's measured periods (summary ``codes``:
    :func:`~pdamper.studies.structure_base.response_codes`, against ``limits``, a
    :class:`~pdamper.analysis.codes.Limits`; without the damper the steady harmonic response)."""
    from ..analysis.codes import time_numbers

    if not case.drive.coupled:
        raise InputError("the stepped sine needs a [structure] section (the container riding on a structure)")
    if not (force_amplitude > 0 and math.isfinite(force_amplitude)):
        raise InputError(f"--force = {shown(force_amplitude)} N; must be > 0, e.g. 0.4N")
    if case.cycles < measure_cycles + 2:
        raise InputError(f"run.cycles = {case.cycles:g} periods a step leave no transient to discard before the "
                         f"{measure_cycles} measured; give --cycles {measure_cycles + 2} or more")
    freqs = sweep_order(frequencies, direction)
    load = SteppedSine(amplitude=float(force_amplitude), frequencies=tuple(freqs), cycles=float(case.cycles))
    drive = dataclasses.replace(case.drive, force_amplitude=0.0, load=load, displacement=0.0, velocity=0.0)
    run = dataclasses.replace(case, drive=drive)
    s = run.running_drive
    labels, idx = select_dofs(s, dofs)
    rec = damped_run(run, progress=progress)
    X = rec.dofs[:, idx]
    t = rec.time
    starts = load.step_times()
    psi = load.force_phases()
    damped, phase, dof_amp, bare_sweep, steady, step_codes = [], [], [], [], [], []
    storeys = s.storeys()
    for j, fj in enumerate(freqs):
        end = starts[j + 1]
        sel = (t > end - measure_cycles / fj - 1e-12) & (t <= end + 1e-12)
        step_codes.append(time_numbers(t[sel], rec.dofs[sel], storeys=storeys))
        z = fit_sine(t[sel], rec.displacement[sel], fj)
        damped.append(abs(z))
        phase.append(float(np.angle(z * np.exp(-1j * psi[j]))))
        dof_amp.append([abs(fit_sine(t[sel], X[sel, i], fj)) for i in range(len(idx))])
        half = (t > end - measure_cycles / fj / 2.0 - 1e-12) & sel
        first = sel & ~half
        a1, a0 = abs(fit_sine(t[half], rec.displacement[half], fj)), abs(fit_sine(t[first], rec.displacement[first], fj))
        steady.append(abs(a1 / a0 - 1.0) if a0 > 0 else math.inf)
        # the bare structure's stepped sine, exactly, measured on the same window
        tb = np.linspace(end - measure_cycles / fj, end, 64 * measure_cycles + 1)
        qb, _ = modal_response(s, tb)
        bare_sweep.append(abs(fit_sine(tb, qb @ s.modal_arrays()[3], fj)))
    damped, bare_sweep = np.array(damped), np.array(bare_sweep)
    bare = s.steady_amplitude(freqs, force_amplitude)
    solid = s.steady_amplitude(freqs, force_amplitude, added_mass=case.bed_mass)
    k = int(np.argmax(damped))
    summary = {
        "method": "dem", "sweep": direction, "force_amplitude_N": float(force_amplitude),
        "particles": case.n_particles, "bed_mass_kg": case.bed_mass, "mass_ratio": case.bed_mass / s.mass,
        "cycles": case.cycles, "measure_cycles": measure_cycles, "frequencies_hz": freqs.tolist(),
        "damper_amplitude_m": damped.tolist(),
        "phase_damped_rad": phase, "dofs": list(labels),
        "response_amplitude_m": np.array(dof_amp).T.tolist(),
        "response_amplitude_bare_m": np.abs(s.dof_phasors(freqs, force_amplitude)[:, idx]).T.tolist(),
        "amplitude_bare_m": bare.tolist(), "amplitude_bare_sweep_m": bare_sweep.tolist(),
        "bare_sweep_vs_closed_form_max_error": float(np.max(np.abs(bare_sweep / bare - 1.0))),
        "amplitude_solid_mass_m": solid.tolist(), "steady_tolerance": STEADY_TOLERANCE,
        "window_change": [float(v) for v in steady], "steady": [bool(v <= STEADY_TOLERANCE) for v in steady],
        "peak_damped_m": float(damped[k]), "peak_damped_frequency_hz": float(freqs[k]),
        "peak_bare_m": float(np.max(bare)), **bare_resonance(s, force_amplitude, float(freqs[k])),
        "energy_balance_error": rec.energy_balance_error, "steps": rec.steps, "wall_time_s": rec.wall_time_s,
        "duration_s": load.duration, **structure_numbers(s),
    }
    summary["peak_reduction"] = summary["peak_damped_m"] / summary["resonance_bare_m"]
    summary["codes"] = response_codes(s, freqs, step_codes, float(force_amplitude), labels, idx, limits=limits)
    return SweepResult(case=case, force_amplitude=float(force_amplitude), direction=direction, frequencies=freqs,
                       damped=damped, phase=np.array(phase), bare=bare, bare_sweep=bare_sweep, solid=solid,
                       dof_amplitudes=np.array(dof_amp), time=t, displacement=rec.displacement, summary=summary)



def sweeps_apart(up: SweepResult, down: SweepResult, *, tolerance: float = APART) -> list:
    """Where the stepped sines ``up`` and ``down`` (:func:`run_stepped_sine`, the same frequencies)
    part: (f [Hz], amplitude up, amplitude down [m]) at each frequency, in the up sweep's order, where
    they differ by more than ``tolerance`` of the larger (there the two sweeps follow different
    branches, or one is a transient)."""
    x_down = dict(zip(down.frequencies.tolist(), down.damped.tolist()))
    return [(f, a, x_down[f]) for f, a in zip(up.frequencies.tolist(), up.damped.tolist())
            if abs(a - x_down[f]) > tolerance * max(a, x_down[f])]
