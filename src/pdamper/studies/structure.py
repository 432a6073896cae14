"""The damper on a structure: free decay and frequency response, with and without the damper.

- :func:`run_decay` -- release the structure of a case (``[structure]``) from its initial
  displacement; the coupled run, the same structure without the bed (the compiled step alone)
  and its closed form; envelopes and the equivalent damping ratio against amplitude.
- :func:`run_response` -- a harmonic force ``F0 sin(2 pi f t)`` on the structure at each of a
  list of frequencies (independent cases: run on local processes with the sweep executor, or
  serially); the steady amplitude with the damper (Fourier amplitude over the last cycles of a
  run from rest), without it (closed form, and the bare structure run the same way) and with
  the bed as an equivalent solid mass (closed form, mass M + m_bed).

See docs/structure.md for the model, the measured numbers and the run times.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from ..analysis.decay import decay_damping, extrema, harmonic_amplitude
from ..errors import InputError
from ..excitation import CoupledStructure, ModalStructure
from ..params import Case
from ..units import quantities

__all__ = ["DecayResult", "ResponseResult", "run_decay", "run_response", "response_case", "parse_frequencies"]


def _structure(case: Case) -> CoupledStructure | ModalStructure:
    if not case.drive.coupled:
        raise InputError("this study needs a [structure] section in the config (the container riding on a "
                         "structure); see examples/structure_36.toml")
    return case.drive


@dataclass(frozen=True, kw_only=True)
class DecayResult:
    """A free decay with and without the damper.

    Attributes: ``time`` [s]; ``damped`` / ``bare`` displacement [m] with / without the bed
    (the bare one from the compiled step, ``closed_form`` the structure's own closed form, its
    ``motion``: :func:`pdamper.theory.oscillator_response`, summed over the modes of N modes);
    ``envelope_*`` = (times [s], amplitudes [m]) of the extremes; ``zeta_*`` = (times [s],
    amplitudes [m], damping ratios [-]); ``summary`` plain numbers for JSON.
    """

    case: Case
    time: np.ndarray
    damped: np.ndarray
    bare: np.ndarray
    closed_form: np.ndarray
    envelope_damped: tuple
    envelope_bare: tuple
    zeta_damped: tuple
    zeta_bare: tuple
    summary: dict = field(default_factory=dict)


def _zeta_at(zeta: tuple, lo: float, hi: float) -> float:
    """Mean equivalent damping ratio over the extremes with amplitude in [lo, hi] [m]."""
    _, a, z = zeta
    sel = (a >= lo) & (a <= hi) & np.isfinite(z)
    return float(np.mean(z[sel])) if np.any(sel) else math.nan


def run_decay(case: Case, *, progress=None) -> DecayResult:
    """Free decay of the structure of ``case`` with its bed and without (``case.cycles`` periods
    of the natural frequency). ``progress(fraction)`` is passed to the coupled run."""
    from ..simulation import Simulation, run_bare_structure

    s = _structure(case)
    if s.force_amplitude > 0:
        case = dataclasses.replace(case, drive=dataclasses.replace(s, force_amplitude=0.0))
        s = case.drive
    res = Simulation(case).run(progress=progress)
    rec = res.structure
    fs = case.recording.sample_rate
    bare = run_bare_structure(s, case.duration, sample_rate=fs)
    t = rec.time
    exact = np.asarray(s.motion(t)[0], dtype=float)  # closed form (N modes: their superposition)
    env_d, env_b = extrema(t, rec.displacement), extrema(t, bare.displacement)
    z_d, z_b = decay_damping(t, rec.displacement), decay_damping(t, bare.displacement)
    x0 = abs(s.displacement) if s.displacement else float(np.max(np.abs(rec.displacement)))
    scale = max(abs(s.displacement), float(np.max(np.abs(exact))), 1e-300)
    summary = {
        "mass_kg": s.mass, "stiffness_N_m": s.stiffness, "natural_frequency_hz": s.natural_frequency,
        "damping_ratio": s.modal_damping_ratio, "bed_mass_kg": case.bed_mass, "particles": case.n_particles,
        "mass_ratio": case.bed_mass / s.mass, "initial_displacement_m": s.displacement,
        "duration_s": case.duration,
        "final_amplitude_damped_m": float(env_d[1][-1]) if env_d[1].size else math.nan,
        "final_amplitude_bare_m": float(env_b[1][-1]) if env_b[1].size else math.nan,
        "zeta_damped_upper_half": _zeta_at(z_d, 0.5 * x0, x0),
        "zeta_damped_lower_half": _zeta_at(z_d, 0.0, 0.5 * x0),
        "zeta_damped_max": float(np.nanmax(z_d[2])) if z_d[2].size else math.nan,
        "amplitude_at_zeta_max_m": float(z_d[1][np.nanargmax(z_d[2])]) if z_d[2].size else math.nan,
        "zeta_bare_mean": float(np.mean(z_b[2])) if z_b[2].size else math.nan,
        "bare_vs_closed_form_max_error": float(np.max(np.abs(bare.displacement - exact)) / scale),
        "energy_balance_error": rec.balance_error(res.energy),
        "steps": res.steps, "time_step_s": res.time_step_s, "wall_time_s": res.wall_time_s,
        **s.structure_summary(),
    }
    return DecayResult(case=case, time=t, damped=rec.displacement, bare=bare.displacement, closed_form=exact,
                       envelope_damped=env_d, envelope_bare=env_b, zeta_damped=z_d, zeta_bare=z_b, summary=summary)


# --------------------------------------------------------------------------- frequency response

def parse_frequencies(text: str) -> np.ndarray:
    """``"1.5Hz:2.5Hz:11"`` (linear grid, both ends) or ``"1.8Hz,2Hz,2.2Hz"`` -> frequencies [Hz].

    >>> parse_frequencies("1.5Hz:2.5Hz:3").tolist()
    [1.5, 2.0, 2.5]
    """
    from ..units import parse_quantity

    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise InputError(f"--frequencies {text!r}: write LOW:HIGH:N, e.g. 1.5Hz:2.5Hz:11, or a list 1.8Hz,2Hz")
        lo, hi = (parse_quantity(p, "frequency", name="--frequencies") for p in parts[:2])
        try:
            n = int(parts[2])
        except ValueError:
            n = 0
        if n < 1 or not (0 < lo <= hi):
            raise InputError(f"--frequencies {text!r}: need 0 < LOW <= HIGH and a whole number N >= 1 of points, "
                             "e.g. 1.5Hz:2.5Hz:11")
        return np.linspace(lo, hi, n) if n > 1 else np.array([lo])
    out = np.array([parse_quantity(p, "frequency", name="--frequencies") for p in text.split(",") if p.strip()])
    if out.size == 0 or np.any(out <= 0):
        raise InputError(f"--frequencies {text!r}: give frequencies > 0, e.g. 1.8Hz,2Hz,2.2Hz or 1.5Hz:2.5Hz:11")
    return out


def response_case(case: Case, frequency: float, force_amplitude: float) -> Case:
    """The case forced at ``frequency`` [Hz] with ``force_amplitude`` [N], started from rest."""
    s = _structure(case)
    drive = dataclasses.replace(s, force_amplitude=force_amplitude, force_frequency=frequency,
                                displacement=0.0, velocity=0.0)
    return dataclasses.replace(case, drive=drive)


def response_point(case: Case, measure_cycles: int) -> dict:
    """Run one forced case; the steady amplitude [m] over its last ``measure_cycles`` cycles."""
    from ..errors import SimulationError
    from ..simulation import Simulation

    try:
        res = Simulation(case).run()
    except SimulationError as exc:
        return {"failed": str(exc)}
    rec = res.structure
    f = case.drive.force_frequency
    return {"amplitude_m": harmonic_amplitude(rec.time, rec.displacement, f, cycles=measure_cycles),
            "peak_m": float(np.max(np.abs(rec.displacement[-int(measure_cycles / f * case.recording.sample_rate):]))),
            "energy_balance_error": rec.balance_error(res.energy), "steps": res.steps,
            "wall_time_s": res.wall_time_s}


class _Point:
    """Picklable ``case -> response_point(case, measure_cycles)`` for the executor."""

    def __init__(self, measure_cycles):
        self.measure_cycles = measure_cycles

    def __call__(self, case):
        return response_point(case, self.measure_cycles)


@dataclass(frozen=True, kw_only=True)
class ResponseResult:
    """Steady amplitudes [m] against forcing frequency [Hz]: ``damped`` (DEM), ``bare_run`` (the
    structure alone run the same way), ``bare`` (closed form), ``solid`` (closed form with the
    bed as a rigid mass); ``points`` the per-frequency run summaries; ``summary`` for JSON."""

    case: Case
    force_amplitude: float
    frequencies: np.ndarray
    damped: np.ndarray
    bare_run: np.ndarray
    bare: np.ndarray
    solid: np.ndarray
    points: list
    summary: dict = field(default_factory=dict)


@quantities(frequencies="frequency", force_amplitude="force")
def run_response(case: Case, frequencies, *, force_amplitude: float, measure_cycles: int = 8,
                 workers: int | None = 1, scheduler: str | None = None, progress: bool | None = None) -> ResponseResult:
    """Frequency response of the structure of ``case`` under ``force_amplitude`` [N] at each of
    ``frequencies`` [Hz]; each point runs ``case.cycles`` forcing cycles from rest and measures
    the last ``measure_cycles``. ``workers`` > 1 or a ``scheduler`` run the points with the
    sweep executor (Dask); ``workers = 1`` runs them one after another."""
    from ..simulation import run_bare_structure

    s = _structure(case)
    freqs = np.asarray(frequencies, dtype=float)
    if freqs.ndim != 1 or freqs.size == 0 or np.any(~(freqs > 0)):
        raise InputError("frequencies: give one or more frequencies > 0 [Hz]")
    if not (force_amplitude > 0 and math.isfinite(force_amplitude)):
        raise InputError(f"--force = {force_amplitude!r} N; must be > 0, e.g. 0.4N")
    if case.cycles < measure_cycles + 2:
        fewer = int(math.floor(case.cycles + 1e-9)) - 2
        alt = (f", or measure at most {fewer} (--measure-cycles {fewer})" if fewer >= 1 else "")
        measured = f"{measure_cycles} measured cycle{'s' if measure_cycles != 1 else ''}"
        raise InputError(f"run.cycles = {case.cycles:g} leaves no transient to discard before the {measured}: "
                         f"{measured} need at least {measure_cycles + 2} cycles (2 of transient first); run "
                         f"--cycles {measure_cycles + 2} or more{alt}")
    cases = [response_case(case, float(f), force_amplitude) for f in freqs]
    results: dict = {}
    if (workers is not None and workers > 1) or scheduler or workers is None:
        from .executor import execute

        items = [(f"f{i:03d}", float(f), 0, c) for i, (f, c) in enumerate(zip(freqs, cases))]
        execute(items, _Point(measure_cycles), lambda key, f, seed, r: results.__setitem__(key, r),
                workers=workers, scheduler=scheduler, progress=progress)
        points = [results[f"f{i:03d}"] for i in range(freqs.size)]
    else:
        from ._progress import progress_bar, show_progress

        points = [response_point(c, measure_cycles)
                  for c in progress_bar(cases, desc="response", unit="freq", disable=not show_progress(progress))]
    damped = np.array([p.get("amplitude_m", math.nan) for p in points])
    bare_run = []
    for c in cases:
        rec = run_bare_structure(c.drive, c.duration, sample_rate=c.recording.sample_rate)
        bare_run.append(harmonic_amplitude(rec.time, rec.displacement, c.drive.force_frequency, cycles=measure_cycles))
    bare = s.steady_amplitude(freqs, force_amplitude)
    # the bed as a rigid mass at the damper: same stiffness and damping, the mass added
    solid = s.steady_amplitude(freqs, force_amplitude, added_mass=case.bed_mass)
    k = int(np.nanargmax(damped)) if np.any(np.isfinite(damped)) else 0
    summary = {
        "force_amplitude_N": force_amplitude, "particles": case.n_particles, "bed_mass_kg": case.bed_mass,
        "mass_ratio": case.bed_mass / s.mass, "cycles": case.cycles, "measure_cycles": measure_cycles,
        "frequencies_hz": freqs.tolist(), "amplitude_damped_m": damped.tolist(),
        "amplitude_bare_run_m": list(map(float, bare_run)), "amplitude_bare_m": bare.tolist(),
        "amplitude_solid_mass_m": solid.tolist(),
        "peak_damped_m": float(damped[k]), "peak_damped_frequency_hz": float(freqs[k]),
        "peak_bare_m": float(np.max(bare)),
        "resonance_bare_m": float(s.steady_amplitude([s.natural_frequency], force_amplitude)[0])
        if s.modal_damping_ratio > 0 else math.inf,
        "energy_balance_error_max": float(max((p.get("energy_balance_error", math.nan) for p in points),
                                              default=math.nan)),
        "failed": {f"{f:g}": p["failed"] for f, p in zip(freqs, points) if "failed" in p},
        "wall_time_s": float(sum(p.get("wall_time_s", 0.0) for p in points)),
        **s.structure_summary(),
    }
    summary["peak_reduction"] = summary["peak_damped_m"] / summary["peak_bare_m"]
    return ResponseResult(case=case, force_amplitude=force_amplitude, frequencies=freqs, damped=damped,
                          bare_run=np.asarray(bare_run), bare=bare, solid=solid, points=points, summary=summary)
