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

from ..analysis.decay import decay_damping, extrema, harmonic_amplitude, harmonic_phasor
from ..errors import InputError, shown
from ..structure import CoupledStructure, ModalStructure
from ..params import Case
from ..units import quantities
from .structure_base import (STEADY_TOLERANCE, bare_resonance, codes_over_frequencies, damped_run, response_codes,
                             select_dofs, solid_amplitude, structure_numbers)

__all__ = ["DecayResult", "ResponseResult", "FieldsResponseResult", "load_forced", "run_decay", "run_response",
           "run_response_fields", "fields_decay", "response_case", "parse_frequencies", "default_frequencies",
           "grid_warnings", "start_phasors", "steadiness", "frequency_format", "STARTS", "STEADY_TOLERANCE"]


def load_forced(path, overrides: dict | None = None, *, force: float | None = None) -> Case:
    """The case of the config file ``path`` (:func:`pdamper.config.load_case` with ``overrides``),
    its structure forced by ``force`` [N] (its ``force_amplitude``, unless ``overrides`` set it) at
    its ``force_frequency`` or, where the file gives none, at its first mode's natural frequency.
    A file whose structure nothing moves (``force_amplitude = 0``, no start) or that has a
    ``[load]`` in time is read with a nominal start and forced (each forced run sets its own start:
    :func:`response_case`); ``force`` None: the file as it is."""
    from ..config import load_case

    overrides = dict(overrides or {})
    if force is not None and force > 0 and "structure.force_amplitude" not in overrides:
        probe = load_case(path, {**overrides, "structure.displacement": "1mm", "structure.force_amplitude": 0.0})
        if not probe.drive.coupled:
            return probe  # not a structure: the study says so
        drive = dataclasses.replace(probe.drive, load=None, force_amplitude=force,
                                    force_frequency=probe.drive.force_frequency or probe.drive.natural_frequency)
        return dataclasses.replace(probe, drive=drive)
    return load_case(path, overrides)


def _structure(case: Case) -> CoupledStructure | ModalStructure:
    """The case's structure as its runs move it: with the empty container's mass at the damper
    (:attr:`pdamper.params.Case.running_drive`)."""
    if not case.drive.coupled:
        raise InputError("this study needs a [structure] section in the config (the container riding on a "
                         "structure); see examples/structure_36.toml")
    return case.running_drive


@dataclass(frozen=True, kw_only=True)
class DecayResult:
    """A free decay with and without the damper.

    Attributes: ``time`` [s]; ``damped`` / ``bare`` displacement [m] with / without the bed
    (the bare one from the compiled step, ``closed_form`` the structure's own closed form, its
    ``motion``: :func:`pdamper.theory.oscillator_response`, summed over the modes of N modes);
    ``envelope_*`` = (times [s], amplitudes [m]) of the extremes; ``zeta_*`` = (times [s],
    amplitudes [m], damping ratios [-]); ``summary`` plain numbers for JSON; ``envelope_fields``
    (times [s], amplitudes [m]) the envelope from the damper's fields by averaging, if asked.
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
    envelope_fields: tuple | None = None


def _several(case: Case, rec) -> dict:
    """What a run of several dampers (or in the coupling loop) adds to a summary: the dampers, their
    beds, the coupling's numbers."""
    if not rec.coupling:
        return {}
    beds = case.damper_beds()
    return {"dampers": case.damper_count, "bed_masses_kg": [d.bed_mass for d in beds],
            "damper_particles": [d.n_particles for d in beds], "coupling": rec.coupling}


def _zeta_at(zeta: tuple, lo: float, hi: float) -> float:
    """Mean equivalent damping ratio over the extremes with amplitude in [lo, hi] [m]."""
    _, a, z = zeta
    sel = (a >= lo) & (a <= hi) & np.isfinite(z)
    return float(np.mean(z[sel])) if np.any(sel) else math.nan


def run_decay(case: Case, *, progress=None, fields=None, extrapolate: bool = False) -> DecayResult:
    """Free decay of the structure of ``case`` with its bed and without (``case.cycles`` periods
    of the natural frequency). ``progress(fraction)`` is passed to the coupled run. ``fields``:
    also the envelope from the damper's fields (:func:`fields_decay`)."""
    from ..simulation import run_bare_structure

    s = _structure(case)
    if s.force_amplitude > 0 or s.load is not None:  # a free decay: no force, no load in time
        case = dataclasses.replace(case, drive=dataclasses.replace(case.drive, force_amplitude=0.0, load=None))
        s = _structure(case)
    rec = damped_run(case, progress=progress)
    fs = case.recording.sample_rate
    bare = run_bare_structure(s, case.duration, sample_rate=fs)
    t = rec.time
    exact = np.asarray(s.motion(t)[0], dtype=float)  # closed form (N modes: their superposition)
    env_d, env_b = extrema(t, rec.displacement), extrema(t, bare.displacement)
    z_d, z_b = decay_damping(t, rec.displacement), decay_damping(t, bare.displacement)
    x0 = abs(s.displacement) if s.displacement else float(np.max(np.abs(rec.displacement)))
    scale = max(abs(s.displacement), float(np.max(np.abs(exact))), 1e-300)
    beds = case.damper_beds()
    bed_mass = float(sum(d.bed_mass for d in beds))
    summary = {
        "mass_kg": s.mass, "stiffness_N_m": s.stiffness, "natural_frequency_hz": s.natural_frequency,
        "damping_ratio": s.modal_damping_ratio, "bed_mass_kg": bed_mass,
        "particles": int(sum(d.n_particles for d in beds)),
        "mass_ratio": bed_mass / s.mass, "initial_displacement_m": s.displacement,
        "duration_s": case.duration,
        "final_amplitude_damped_m": float(env_d[1][-1]) if env_d[1].size else math.nan,
        "final_amplitude_bare_m": float(env_b[1][-1]) if env_b[1].size else math.nan,
        "zeta_damped_upper_half": _zeta_at(z_d, 0.5 * x0, x0),
        "zeta_damped_lower_half": _zeta_at(z_d, 0.0, 0.5 * x0),
        "zeta_damped_max": float(np.nanmax(z_d[2])) if z_d[2].size else math.nan,
        "amplitude_at_zeta_max_m": float(z_d[1][np.nanargmax(z_d[2])]) if z_d[2].size else math.nan,
        "zeta_bare_mean": float(np.mean(z_b[2])) if z_b[2].size else math.nan,
        "bare_vs_closed_form_max_error": float(np.max(np.abs(bare.displacement - exact)) / scale),
        "energy_balance_error": rec.energy_balance_error,
        "steps": rec.steps, "time_step_s": rec.time_step_s, "wall_time_s": rec.wall_time_s,
        **s.structure_summary(), **_several(case, rec),
    }
    env_f = None
    if fields is not None:
        tf, af, _ = fields_decay(case, fields, extrapolate=extrapolate)
        env_f = (tf, af)
        summary["final_amplitude_fields_m"] = float(af[-1])
        summary["fields_decay_end_s"] = float(tf[-1])
        if np.any(env_d[0] <= tf[-1]):  # the direct envelope against the fields' at the direct extremes' times
            inside = env_d[0] <= tf[-1]
            ref = np.interp(env_d[0][inside], tf, af)
            summary["fields_vs_direct_envelope_max_error"] = float(np.max(np.abs(ref / env_d[1][inside] - 1.0)))
    return DecayResult(case=case, time=t, damped=rec.displacement, bare=bare.displacement, closed_form=exact,
                       envelope_damped=env_d, envelope_bare=env_b, zeta_damped=z_d, zeta_bare=z_b, summary=summary,
                       envelope_fields=env_f)


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
            raise InputError(f"--frequencies {shown(text)}: write LOW:HIGH:N, e.g. 1.5Hz:2.5Hz:11, or a list 1.8Hz,2Hz")
        lo, hi = (parse_quantity(p, "frequency", name="--frequencies") for p in parts[:2])
        try:
            n = int(parts[2])
        except ValueError:
            n = 0
        if n < 1 or not (0 < lo <= hi):
            raise InputError(f"--frequencies {shown(text)}: need 0 < LOW <= HIGH and a whole number N >= 1 of points, "
                             "e.g. 1.5Hz:2.5Hz:11")
        return np.linspace(lo, hi, n) if n > 1 else np.array([lo])
    out = np.array([parse_quantity(p, "frequency", name="--frequencies") for p in text.split(",") if p.strip()])
    if out.size == 0 or np.any(out <= 0):
        raise InputError(f"--frequencies {shown(text)}: give frequencies > 0, e.g. 1.8Hz,2Hz,2.2Hz or 1.5Hz:2.5Hz:11")
    return out


#: What ``start=`` takes: from rest, on the bare structure's steady orbit, on the fields' orbit.
STARTS = ("rest", "bare", "fields")
def response_case(case: Case, frequency: float, force_amplitude: float, phasor: complex = 0j) -> Case:
    """The case forced at ``frequency`` [Hz] with ``force_amplitude`` [N], started from rest, or
    with ``phasor`` x^ [m] (complex amplitude of the damper point, ``x(t) = Im(x^ e^{i Omega t})``
    against the force ``F0 sin(Omega t)``) on that orbit: x(0) = Im x^, v(0) = Omega Re x^ (a
    modal structure takes them in its static shape of a load at the damper)."""
    _structure(case)
    x0, v0 = (0.0, 0.0) if phasor == 0 else (float(phasor.imag), float(2.0 * math.pi * frequency * phasor.real))
    drive = dataclasses.replace(case.drive, force_amplitude=force_amplitude, force_frequency=frequency,
                                displacement=x0, velocity=v0, load=None)
    return dataclasses.replace(case, drive=drive)


def start_phasors(case: Case, frequencies, force_amplitude: float, start: str = "rest", fields=None,
                  extrapolate: bool = False) -> list[complex]:
    """The damper point's complex amplitude to start each frequency on (``start``: ``"rest"`` 0,
    ``"bare"`` the bare structure's steady state H_df F0, ``"fields"`` the fields' prediction: the
    stable solution of smallest amplitude)."""
    from ..analysis.harmonic import receptances, solve_frequency

    if start not in STARTS:
        raise InputError(f"--start {shown(start)}; choose one of {', '.join(STARTS)}")
    s = _structure(case)
    modal = s.modal_arrays()
    out = []
    for f in np.asarray(frequencies, dtype=float):
        if start == "rest":
            out.append(0j)
        elif start == "bare":
            out.append(receptances(modal, f)[1] * force_amplitude)
        else:
            if fields is None:
                raise InputError("--start fields needs the damper's fields: --fields F.nc")
            sols = [x for x in solve_frequency(modal, fields, f, force_amplitude, extrapolate=extrapolate) if x.stable]
            out.append(sols[0].damper_phasor if sols else 0j)
    return out


def default_frequencies(case: Case, mode: int = 1, *, points: int = 9, spread: float = 0.1) -> np.ndarray:
    """``points`` frequencies [Hz] from (1 - spread) to (1 + spread) times the natural frequency of
    mode ``mode`` (1-based) of the case's structure, the ends rounded to 3 significant digits.

    >>> from pdamper.config import load_case
    >>> print(*default_frequencies(load_case("examples/structure_36.toml"))[::4])
    1.8 2.0 2.2
    """
    fn = mode_frequency(case, mode)
    lo, hi = (float(f"{(1.0 + sign * spread) * fn:.3g}") for sign in (-1, 1))
    return np.linspace(lo, hi, points)


def mode_frequency(case: Case, mode: int = 1) -> float:
    """The natural frequency [Hz] of mode ``mode`` (1-based) of the case's structure (without the bed)."""
    s = _structure(case)
    fs = np.atleast_1d(s.mode_frequencies)
    if isinstance(mode, bool) or not isinstance(mode, (int, np.integer)) or not 1 <= mode <= fs.size:
        raise InputError(f"--mode {shown(mode)}; the structure has {fs.size} mode{'s' if fs.size > 1 else ''}: "
                         f"give 1{f' to {fs.size}' if fs.size > 1 else ''}")
    return float(fs[mode - 1])


def frequency_format(frequencies):
    """A formatter of frequencies [Hz] with the fewest decimals (2 to 6) that show every value of
    ``frequencies`` as it is (a grid 2.2955 Hz apart is not printed as 2.296).

    >>> f = frequency_format([2.29, 2.2955, 2.301])
    >>> f(2.2955), f(2.29)
    ('2.2955', '2.2900')
    """
    f = np.atleast_1d(np.asarray(frequencies, dtype=float))
    d = next((d for d in range(2, 7) if np.all(np.abs(np.round(f, d) - f) <= 1e-9 * np.maximum(np.abs(f), 1.0))), 6)
    return lambda x: f"{x:.{d}f}"


def grid_warnings(case: Case, frequencies, mode: int = 1) -> list[str]:
    """A warning when ``frequencies`` [Hz] miss the resonance of mode ``mode``: the damped peak
    lies between the mode's frequency with the bed as a solid mass and without the bed, so a grid
    that reaches into that band has it (its end points included); one wholly below or above it
    does not."""
    fn = mode_frequency(case, mode)
    s = _structure(case)
    _, _, _, pd, _, _ = s.modal_arrays()
    # the bed as a rigid mass at the damper: the mode's frequency falls as its mass at the damper grows
    m_mode = s.modal_arrays()[0][mode - 1] / pd[mode - 1] ** 2
    f_solid = fn * math.sqrt(m_mode / (m_mode + case.bed_mass))
    f = np.asarray(frequencies, dtype=float)
    lo, hi = float(f.min()), float(f.max())
    if hi >= f_solid and lo <= fn:
        return []
    fmt = frequency_format(f)
    side = "below" if hi < f_solid else "above"
    return [f"the frequencies {fmt(lo)}-{fmt(hi)} Hz lie {side} the resonance of mode {mode} (between "
            f"{f_solid:.5g} Hz, the bed as a solid mass, and {fn:.5g} Hz, without the bed): the peak is not on "
            "this grid; leave --frequencies out (a grid around the mode) or reach into that band"]


def response_point(case: Case, measure_cycles: int) -> dict:
    """Run one forced case; the steady amplitude [m] over its last ``measure_cycles`` cycles."""
    from ..errors import SimulationError

    try:
        rec = damped_run(case)
    except SimulationError as exc:
        return {"failed": str(exc)}
    f = case.drive.force_frequency
    dofs = rec.dofs
    return {**_point_codes(case, rec, dofs, measure_cycles),
            "amplitude_m": harmonic_amplitude(rec.time, rec.displacement, f, cycles=measure_cycles),
            "dof_amplitudes_m": [harmonic_amplitude(rec.time, dofs[:, i], f, cycles=measure_cycles)
                                 for i in range(dofs.shape[1])],
            "response_point_amplitude_m": harmonic_amplitude(rec.time, rec.response_displacement, f,
                                                             cycles=measure_cycles),
            "phase_rad": float(np.angle(harmonic_phasor(rec.time, rec.displacement, f, cycles=measure_cycles))),
            "peak_m": float(np.max(np.abs(rec.displacement[-int(measure_cycles / f * case.recording.sample_rate):]))),
            "energy_balance_error": rec.energy_balance_error, "steps": rec.steps,
            "wall_time_s": rec.wall_time_s, **steadiness(rec.time, rec.displacement, f, measure_cycles),
            **({"damper_points_amplitude_m": [harmonic_amplitude(rec.time, rec.dampers[:, j], f, cycles=measure_cycles)
                                             for j in range(rec.dampers.shape[1])]} if rec.coupling else {})}


def _point_codes(case: Case, rec, dofs, measure_cycles: int) -> dict:
    """Over the measured periods of a forced run ``rec`` (a
    :class:`~pdamper.studies.structure_base.DampedRun`; every dof's displacement ``dofs``): the
    numbers codes ask for (``codes``: :func:`pdamper.analysis.codes.time_numbers`, no residual) and
    the (first) damper's equivalent mass and dashpot (``damper_fit``:
    :func:`pdamper.analysis.tmd.equivalent_damper`)."""
    from ..analysis.codes import time_numbers
    from ..analysis.tmd import equivalent_damper

    n = int(round(measure_cycles / case.drive.force_frequency / float(rec.time[1] - rec.time[0])))
    n = max(3, min(n, rec.time.size))
    codes = time_numbers(rec.time[-n:], dofs[-n:], storeys=case.running_drive.storeys())
    for key in ("drift_ratio_residual", "residual_window_s"):  # a steady oscillation has none
        codes.pop(key, None)
    fw, a, v = rec.forces[:, 0], rec.accelerations[:, 0], rec.velocities[:, 0]
    return {"codes": codes, "damper_fit": equivalent_damper(fw[-n:], a[-n:], v[-n:])}


def steadiness(time, x, frequency: float, measure_cycles: int = 2) -> dict:
    """Is the record's amplitude at ``frequency`` steady? ``last_period_change``: |A_last / A_before
    - 1| of the amplitudes [m] over the last forcing period and the one before; ``window_change``:
    the same between the two halves of the last ``measure_cycles`` periods (a slow beat of a
    lightly damped transient moves little from one period to the next); ``steady``: both within
    :data:`STEADY_TOLERANCE`."""
    def change(cycles):
        n = int(round(cycles / frequency / (time[1] - time[0])))
        if time.size < 2 * n + 1:
            return math.inf
        a1 = harmonic_amplitude(time, x, frequency, cycles=cycles)
        a0 = harmonic_amplitude(time[:-n], x[:-n], frequency, cycles=cycles)
        return abs(a1 / a0 - 1.0) if a0 > 0 else math.inf

    last = change(1)
    window = change(max(1, int(measure_cycles) // 2))
    return {"steady": bool(last <= STEADY_TOLERANCE and window <= STEADY_TOLERANCE),
            "last_period_change": float(last), "window_change": float(window)}


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


def _forced(case: Case, frequencies, force_amplitude: float):
    """(the structure, the frequencies [Hz] as an array) of a forced response, checked."""
    s = _structure(case)
    freqs = np.asarray(frequencies, dtype=float)
    if freqs.ndim != 1 or freqs.size == 0 or np.any(~(freqs > 0)):
        raise InputError("frequencies: give one or more frequencies > 0 [Hz]")
    if not (force_amplitude > 0 and math.isfinite(force_amplitude)):
        raise InputError(f"--force = {shown(force_amplitude)} N; must be > 0, e.g. 0.4N")
    return s, freqs


@quantities(frequencies="frequency", force_amplitude="force")
def run_response(case: Case, frequencies, *, force_amplitude: float, measure_cycles: int = 8,
                 workers: int | None = 1, scheduler: str | None = None, progress: bool | None = None,
                 start: str = "rest", fields=None, extrapolate: bool = False, dofs=None,
                 limits=None) -> ResponseResult:
    """Frequency response of the structure of ``case`` under ``force_amplitude`` [N] at each of
    ``frequencies`` [Hz]; each point runs ``case.cycles`` forcing cycles and measures the last
    ``measure_cycles``, started from rest or on an orbit (``start``, :func:`start_phasors`; the
    fields for ``"fields"``); each point says whether it is steady (:func:`steadiness`).
    ``workers`` > 1 or a ``scheduler`` run the points with the sweep executor (Dask);
    ``workers = 1`` runs them one after another. Every dof's amplitude (or ``dofs``': labels,
    :func:`pdamper.studies.transient.parse_dofs`) is measured too (``response_amplitude_m``), and
    the numbers codes ask for over the measured periods (``codes``, :func:`response_codes`, against
    ``limits``) with the damper as an equivalent TMD at the damped peak (``tmd_equivalent``,
    :func:`response_tmd`; the fit at every frequency ``damper_fits``)."""
    from ..simulation import run_bare_structure

    s, freqs = _forced(case, frequencies, force_amplitude)
    labels, idx = select_dofs(s, dofs)
    if case.cycles < measure_cycles + 2:
        fewer = int(math.floor(case.cycles + 1e-9)) - 2
        alt = (f", or measure at most {fewer} (--measure-cycles {fewer})" if fewer >= 1 else "")
        measured = f"{measure_cycles} measured cycle{'s' if measure_cycles != 1 else ''}"
        raise InputError(f"run.cycles = {case.cycles:g} leaves no transient to discard before the {measured}: "
                         f"{measured} need at least {measure_cycles + 2} cycles (2 of transient first); run "
                         f"--cycles {measure_cycles + 2} or more{alt}")
    phasors = start_phasors(case, freqs, force_amplitude, start, fields, extrapolate)
    cases = [response_case(case, float(f), force_amplitude, z) for f, z in zip(freqs, phasors)]
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
    bare_run, bare_steady = [], []
    for c in cases:
        rec = run_bare_structure(c.running_drive, c.duration, sample_rate=c.recording.sample_rate)
        bare_run.append(harmonic_amplitude(rec.time, rec.displacement, c.drive.force_frequency, cycles=measure_cycles))
        bare_steady.append(bool(abs(bare_run[-1] / float(s.steady_amplitude([c.drive.force_frequency],
                                                                             force_amplitude)[0]) - 1.0)
                                <= STEADY_TOLERANCE))  # against its exact steady amplitude
    bare = s.steady_amplitude(freqs, force_amplitude)
    # the bed as a rigid mass at the damper: same stiffness and damping, the mass added
    solid = solid_amplitude(case, s, freqs, force_amplitude)
    k = int(np.nanargmax(damped)) if np.any(np.isfinite(damped)) else 0
    nan_dofs = [math.nan] * len(s.dof_shapes()[0])
    dof_amp = np.array([p.get("dof_amplitudes_m", nan_dofs) for p in points], dtype=float)[:, idx]
    summary = {
        **structure_numbers(s),
        "force_amplitude_N": force_amplitude, "particles": case.n_particles, "bed_mass_kg": case.bed_mass,
        "mass_ratio": case.bed_mass / s.mass, "cycles": case.cycles, "measure_cycles": measure_cycles,
        "frequencies_hz": freqs.tolist(), "damper_amplitude_m": damped.tolist(),
        "dofs": list(labels), "response_amplitude_m": dof_amp.T.tolist(),
        "response_amplitude_bare_m": np.abs(s.dof_phasors(freqs, force_amplitude)[:, idx]).T.tolist(),
        "response_point_amplitude_m": [float(p.get("response_point_amplitude_m", math.nan)) for p in points],
        "amplitude_damped_m": damped.tolist(),  # the old name of damper_amplitude_m (one release)
        "phase_damped_rad": [float(p.get("phase_rad", math.nan)) for p in points],
        "amplitude_bare_run_m": list(map(float, bare_run)), "amplitude_bare_m": bare.tolist(),
        "amplitude_solid_mass_m": solid.tolist(),
        "peak_damped_m": float(damped[k]), "peak_damped_frequency_hz": float(freqs[k]),
        "peak_bare_m": float(np.max(bare)),
        "method": "dem", "start": start, "steady_tolerance": STEADY_TOLERANCE,
        "steady": [bool(p.get("steady", False)) for p in points],
        "last_period_change": [float(p.get("last_period_change", math.nan)) for p in points],
        "window_change": [float(p.get("window_change", math.nan)) for p in points],
        "bare_run_steady": bare_steady,
        "peak_steady": bool(points[k].get("steady", False)),
        **bare_resonance(s, force_amplitude, float(freqs[k])),
        "energy_balance_error_max": float(max((p.get("energy_balance_error", math.nan) for p in points),
                                              default=math.nan)),
        "failed": {f"{f:g}": p["failed"] for f, p in zip(freqs, points) if "failed" in p},
        "wall_time_s": float(sum(p.get("wall_time_s", 0.0) for p in points)),
    }
    summary["peak_reduction"] = summary["peak_damped_m"] / summary["resonance_bare_m"]
    summary["peak_reduction_on_grid"] = summary["peak_damped_m"] / summary["peak_bare_m"]
    summary["codes"] = response_codes(s, freqs, [p.get("codes") for p in points], force_amplitude, labels, idx,
                                      limits=limits)
    fits = [p.get("damper_fit") for p in points]
    summary["damper_fits"] = {key: [float(f[key]) if f else math.nan for f in fits]
                              for key in ("mass_kg", "damping_N_s_per_m", "r2")}
    summary["tmd_equivalent"] = [response_tmd(s, case.bed_mass, summary, fits[k])]
    return ResponseResult(case=case, force_amplitude=force_amplitude, frequencies=freqs, damped=damped,
                          bare_run=np.asarray(bare_run), bare=bare, solid=solid, points=points, summary=summary)


_NO_FIT = {"mass_kg": math.nan, "damping_N_s_per_m": math.nan, "offset_N": math.nan, "r2": math.nan, "samples": 0}


def response_tmd(s, bed_mass: float, summary: dict, fit: dict | None, *, over: str = "") -> dict:
    """The damper as an equivalent TMD (:func:`pdamper.analysis.tmd.tmd_numbers`) at the damped peak of
    a forced response (``summary``): ``fit`` its mass and dashpot there; and, from the ratio of the
    resonant amplitudes R (damped peak over the bare resonance), the added damping ratio of the mode
    nearest the peak, zeta (1 / R - 1) (a mode's resonant amplitude is F / (2 zeta k)), and its
    detuning, the damped peak's frequency over the bare resonance's, minus 1 (to the grid's step);
    ``steady`` False where the damped peak is a transient (then R, and these, are not the steady ones)."""
    from ..analysis.tmd import tmd_numbers

    fit = fit or _NO_FIT
    out = tmd_numbers(s.modal_arrays(), bed_mass=bed_mass, damper=fit)
    f_peak, f_res, ratio = (summary.get(k, math.nan) for k in ("peak_damped_frequency_hz",
                                                               "resonance_bare_frequency_hz", "peak_reduction"))
    fs = np.atleast_1d(s.mode_frequencies)
    j = int(np.argmin(np.abs(fs - f_res))) if math.isfinite(f_res) else 0
    z = float(np.atleast_1d(s.mode_damping_ratios)[j])
    grid = np.diff(np.sort(np.asarray(summary.get("frequencies_hz", []), dtype=float)))
    out.update(at_frequency_hz=float(f_peak), fit=fit,
               fit_over=over or "the measured periods at the damped peak's frequency",
               from_peak_ratio={"mode": j + 1, "peak_ratio": float(ratio),
                                "steady": bool(summary.get("peak_steady", True)),
                                "added_damping_ratio": z * (1.0 / ratio - 1.0) if ratio > 0 else math.nan,
                                "detuning": f_peak / f_res - 1.0 if f_res > 0 else math.nan,
                                "grid_step_hz": float(np.min(grid)) if grid.size else math.nan})
    return out


# --------------------------------------------------------------------------- from the fields

@dataclass(frozen=True, kw_only=True)
class FieldsResponseResult:
    """The forced response from the damper's fields (harmonic balance,
    :mod:`pdamper.analysis.harmonic`): ``solution`` the
    :class:`~pdamper.analysis.harmonic.FrequencyResponse` (every fixed point per frequency, its
    stability, the jumps); ``bare`` / ``solid`` the damper point's amplitude [m] without the bed
    and with it as a rigid mass (``bare_response`` / ``solid_response`` at the response point);
    ``summary`` for JSON."""

    case: Case
    force_amplitude: float
    frequencies: np.ndarray
    solution: object
    bare: np.ndarray
    solid: np.ndarray
    bare_response: np.ndarray
    solid_response: np.ndarray
    summary: dict = field(default_factory=dict)


def _one_or_list(values: list):
    """A frequency's stable values: the value when there is one, the list when several (or none)."""
    return values[0] if len(values) == 1 else list(values)


@quantities(frequencies="frequency", force_amplitude="force")
def run_response_fields(case: Case, frequencies, fields, *, force_amplitude: float, extrapolate: bool = False,
                        points: int = 48, dofs=None, limits=None) -> FieldsResponseResult:
    """Frequency response of the structure of ``case`` with the damper as its ``fields`` (a
    :class:`~pdamper.analysis.fields.DamperFields`) at the damper node: every solution per
    frequency, stable or not, the jump frequencies, and the curves without the bed and with it
    as a solid mass; every dof's amplitude (or ``dofs``') on each stable solution, the numbers codes
    ask for (``codes``: the largest stable solution's at each frequency, against ``limits``) and the
    fields at the peak as an equivalent TMD (``tmd_equivalent``). Refuses (InputError) where the
    fields do not hold the solution, unless ``extrapolate``."""
    from ..analysis.harmonic import solve_response

    s, freqs = _forced(case, frequencies, force_amplitude)
    labels, idx = select_dofs(s, dofs)
    if case.damper_count > 1:
        return _response_fields_several(case, s, freqs, fields, force_amplitude, extrapolate, labels, idx)
    if isinstance(fields, (list, tuple)):
        if len(fields) != 1:
            raise InputError(f"{len(fields)} fields files for one damper; give one")
        fields = fields[0]
    _check_bed(fields, case.bed_mass, "")
    sol = solve_response(s.modal_arrays(), fields, freqs, force_amplitude, extrapolate=extrapolate, points=points)
    bare = s.steady_amplitude(freqs, force_amplitude)
    solid = s.steady_amplitude(freqs, force_amplitude, added_mass=case.bed_mass)
    bare_r = s.steady_amplitude(freqs, force_amplitude, point="response")
    solid_r = s.steady_amplitude(freqs, force_amplitude, added_mass=case.bed_mass, point="response")
    xd, xr = sol.stable("damper_amplitude_m"), sol.stable("response_amplitude_m")
    phasors = _dof_phasors(s, sol, force_amplitude, idx)
    dof_amp = [[_one_or_list([float(abs(z[i])) for z in zs]) for zs in phasors] for i in range(len(idx))]
    summary = {
        **structure_numbers(s),
        "method": "fields", "force_amplitude_N": force_amplitude, "particles": case.n_particles,
        "bed_mass_kg": case.bed_mass, "mass_ratio": case.bed_mass / s.mass,
        "frequencies_hz": freqs.tolist(),
        "damper_amplitude_m": [_one_or_list(v) for v in xd],
        **_amplitudes(s, sol, freqs, force_amplitude, labels, idx, dof_amp, xd, xr, (bare, solid, bare_r, solid_r)),
        "jump_frequencies_hz": [j["frequency_hz"] for j in sol.jumps], "jumps": sol.jumps,
        "stability": "slope criterion: stable where d(ln X - ln G(X))/d ln X > 0, G(X) = F0 |H_df| / "
                     "|1 + H_dd Z(X, f)| (the fold where a branch ends; phase instabilities not seen)",
        "fields_box": fields.box(), "fields_source": str(fields.dataset.attrs.get("source", "")),
        "solve_time_per_frequency_s": sol.time_s.tolist(),
        "solve_time_median_s": float(np.median(sol.time_s)),
    }
    summary["codes"], summary["tmd_equivalent"] = _fields_codes(s, sol, freqs, force_amplitude, labels, idx,
                                                                case.bed_mass, summary, limits)
    return FieldsResponseResult(case=case, force_amplitude=force_amplitude, frequencies=freqs, solution=sol,
                                bare=bare, solid=solid, bare_response=bare_r, solid_response=solid_r, summary=summary)


def _check_bed(fields, bed_mass: float, which: str) -> None:
    bed = fields.bed_mass
    if math.isfinite(bed) and abs(bed - bed_mass) > 0.02 * bed_mass:
        raise InputError(f"the fields{which} were built for a bed of {bed * 1e3:.4g} g, the config's bed is "
                         f"{bed_mass * 1e3:.4g} g; build the fields from a sweep of this damper")


def _response_fields_several(case: Case, s, freqs, fields, force_amplitude: float, extrapolate: bool, labels,
                             idx) -> FieldsResponseResult:
    """:func:`run_response_fields` with several dampers: one fields a damper (one for all of them),
    the harmonic balance in as many amplitudes (:func:`pdamper.analysis.harmonic.solve_several`)."""
    from ..analysis.harmonic import solve_response_several

    beds = case.damper_beds()
    fl = list(fields) if isinstance(fields, (list, tuple)) else [fields]
    if len(fl) == 1:
        fl = fl * len(beds)
    if len(fl) != len(beds):
        raise InputError(f"{len(fl)} fields files for {len(beds)} dampers; give one a damper, in the dampers' order, "
                         "or one for all")
    for j, (f_, d) in enumerate(zip(fl, beds)):
        _check_bed(f_, d.bed_mass, f" of damper {j + 1}")
    P = s.damper_shapes()[[case.damper_point(k) for k in range(len(beds))]]
    modal = s.modal_arrays()
    sol = solve_response_several(modal, P, fl, freqs, force_amplitude, extrapolate=extrapolate)
    bare = s.steady_amplitude(freqs, force_amplitude)
    solid = solid_amplitude(case, s, freqs, force_amplitude)
    bare_r = s.steady_amplitude(freqs, force_amplitude, point="response")
    solid_r = solid_amplitude(case, s, freqs, force_amplitude, point="response")
    xd = sol.stable("damper_amplitude_m")
    xr = sol.stable("response_amplitude_m")
    mass, k, c, pd, pf, pr = modal
    _, shapes = s.dof_shapes()
    dof_amp = [[] for _ in idx]
    for f, sols in zip(freqs, sol.solutions):
        w = 2.0 * math.pi * float(f)
        den = k - mass * w * w + 1j * c * w
        per = []
        for x in sols:
            if not x.stable:
                continue
            Z = np.array([complex(-w * w * m_, w * c_) for m_, c_ in zip(x.effective_masses_kg,
                                                                          x.equivalent_dampings_N_s_per_m)])
            per.append(shapes[idx] @ ((pf * force_amplitude - P.T @ (Z * np.array(x.damper_phasors))) / den))
        for i in range(len(idx)):
            dof_amp[i].append(_one_or_list([float(abs(z[i])) for z in per]))
    bed_mass = float(sum(d.bed_mass for d in beds))
    summary = {
        **structure_numbers(s),
        "method": "fields", "dampers": len(beds), "force_amplitude_N": force_amplitude,
        "particles": int(sum(d.n_particles for d in beds)), "bed_mass_kg": bed_mass, "mass_ratio": bed_mass / s.mass,
        "bed_masses_kg": [d.bed_mass for d in beds], "frequencies_hz": freqs.tolist(),
        "damper_amplitude_m": [_one_or_list(v) for v in xd],
        "damper_points_amplitude_m": [[list(x.damper_amplitudes_m) for x in sols if x.stable] for sols in sol.solutions],
        **_amplitudes(s, sol, freqs, force_amplitude, labels, idx, dof_amp, xd, xr, (bare, solid, bare_r, solid_r)),
        "jump_frequencies_hz": [], "jumps": [],
        "stability": "the amplitudes' slow flow d(ln X)/dt = -(ln X - ln |x^(X)|) linearised: stable where every "
                     "eigenvalue of its Jacobian has a positive real part (one damper: the slope criterion)",
        "fields_box": [f_.box() for f_ in fl], "fields_source": [str(f_.dataset.attrs.get("source", "")) for f_ in fl],
        "solve_time_per_frequency_s": sol.time_s.tolist(), "solve_time_median_s": float(np.median(sol.time_s)),
    }
    return FieldsResponseResult(case=case, force_amplitude=force_amplitude, frequencies=freqs, solution=sol,
                                bare=bare, solid=solid, bare_response=bare_r, solid_response=solid_r, summary=summary)


def _amplitudes(s, sol, freqs, force_amplitude, labels, idx, dof_amp, xd, xr, curves) -> dict:
    """The summary's amplitudes of a response from the fields, one damper or several: every dof's
    with and without the bed, the branches, the bare and solid-mass curves (``curves``: bare,
    solid, bare at the response point, solid there), the damped peak (the largest of the stable
    damper amplitudes ``xd``) beside the bare resonance, and their ratios."""
    bare, solid, bare_r, solid_r = curves
    flat = [(x, f) for f, xs in zip(freqs, xd) for x in xs]
    x_peak, f_peak = max(flat) if flat else (math.nan, math.nan)
    resonance = bare_resonance(s, force_amplitude, float(f_peak) if math.isfinite(f_peak) else float(freqs[0]))
    return {
        "dofs": list(labels), "response_amplitude_m": dof_amp,
        "response_amplitude_bare_m": np.abs(s.dof_phasors(freqs, force_amplitude)[:, idx]).T.tolist(),
        "response_point_amplitude_m": [_one_or_list(v) for v in xr],
        "branches": [[x.to_dict() for x in sols] for sols in sol.solutions],
        "amplitude_bare_m": bare.tolist(), "amplitude_solid_mass_m": solid.tolist(),
        "response_bare_m": bare_r.tolist(), "response_solid_mass_m": solid_r.tolist(),
        "peak_damped_m": float(x_peak), "peak_damped_frequency_hz": float(f_peak),
        "peak_bare_m": float(np.max(bare)),
        **resonance,
        "peak_reduction": float(x_peak) / resonance["resonance_bare_m"],
        "peak_reduction_on_grid": float(x_peak) / float(np.max(bare)),
        "extrapolated": bool(any(x.extrapolated for sols in sol.solutions for x in sols)),
    }


def _fields_codes(s, sol, freqs, force_amplitude, labels, idx, bed_mass, summary, limits):
    """(codes, [TMD]) of a response from the fields: at each frequency the largest of the stable
    solutions' numbers (:func:`pdamper.analysis.codes.harmonic_numbers` of every dof's phasors), and
    the fields of the peak's solution (its effective mass and equivalent damping) as the damper's fit."""
    from ..analysis.codes import harmonic_numbers

    storeys = s.storeys()
    every = np.arange(len(s.dof_shapes()[0]))
    per: dict = {}
    for f, zs in zip(freqs, _dof_phasors(s, sol, force_amplitude, every)):
        nums = [harmonic_numbers([f], z[None, :], storeys=storeys) for z in zs]
        for key in ("acceleration_peak_m_s2", "acceleration_rms_m_s2", "drift_ratio_peak", "drift_ratio_rms"):
            if storeys is None and key.startswith("drift"):
                continue
            per.setdefault(key, []).append(np.max([np.asarray(n[key])[:, 0] for n in nums], axis=0).tolist()
                                           if nums else None)
    codes = codes_over_frequencies(s, freqs, per, force_amplitude, labels, idx, limits=limits,
                                   method="the fields' stable solutions (the largest at each frequency), harmonic")
    fit = None
    f_peak = summary["peak_damped_frequency_hz"]
    if math.isfinite(f_peak):
        k = int(np.argmin(np.abs(freqs - f_peak)))
        best = max((x for x in sol.solutions[k] if x.stable), key=lambda x: x.damper_amplitude_m, default=None)
        if best is not None:
            fit = {"mass_kg": float(best.effective_mass_kg), "damping_N_s_per_m": float(best.equivalent_damping_N_s_per_m),
                   "offset_N": 0.0, "r2": math.nan, "samples": 0}
    return codes, [response_tmd(s, bed_mass, summary, fit, over="the fields at the damped peak (harmonic balance)")]


def _dof_phasors(s, sol, force_amplitude: float, idx) -> list:
    """Per frequency, per stable solution of the harmonic balance ``sol``, the complex amplitudes
    of the dofs ``idx``: the structure under the force and the bed's force ``-Z x^_d`` at the damper
    (:mod:`pdamper.analysis.harmonic`), ``q_k = (phi_k(f) F0 - phi_k(d) Z x^_d) / (k_k - m_k W^2 + i
    c_k W)``, x = shapes q."""
    mass, k, c, pd, pf, pr = s.modal_arrays()
    _, shapes = s.dof_shapes()
    out = []
    for f, sols in zip(sol.frequencies, sol.solutions):
        w = 2.0 * math.pi * float(f)
        den = k - mass * w * w + 1j * c * w
        per = []
        for x in sols:
            if not x.stable:
                continue
            Z = complex(-w * w * x.effective_mass_kg, w * x.equivalent_damping_N_s_per_m) \
                if math.isfinite(x.effective_mass_kg) else 0j
            per.append(shapes[idx] @ ((pf * force_amplitude - pd * Z * x.damper_phasor) / den))
        out.append(per)
    return out


def fields_decay(case: Case, fields, *, duration: float | None = None, amplitude: float | None = None,
                 extrapolate: bool = False):
    """The free decay's envelope of the case's structure (its first mode at the damper) with the
    damper as its ``fields``, by averaging (:func:`pdamper.analysis.harmonic.decay_envelope`):
    (t [s], A [m], f [Hz]) from ``amplitude`` (default: [structure] displacement) over
    ``duration`` (default: the case's)."""
    from ..analysis.harmonic import decay_envelope

    s = _structure(case)
    a0 = abs(s.displacement) if amplitude is None else float(amplitude)
    if not a0 > 0:
        raise InputError("the decay from the fields needs a start: [structure] displacement > 0, e.g. '20mm'")
    return decay_envelope(fields, mass=s.mass, stiffness=s.stiffness, damping=s.damping, amplitude=a0,
                          duration=case.duration if duration is None else duration, extrapolate=extrapolate)
