"""One case from start to answer: simulation -> recorders -> complex power -> motion mode.

:func:`run_case` is what ``pdamper run``, the sweeps and the studies call. It composes a
:class:`~pdamper.simulation.Simulation` (which only advances and records), the complex-power
analysis of the recorded force and motion (:mod:`pdamper.analysis`, eqs. 3-5) and the motion-mode
classifier (:mod:`pdamper.analysis.modes`), and returns a :class:`RunResult`.
"""

from __future__ import annotations

from ._deprecated import renamed, renamed_function, renamed_keyword
from ._repr import short_repr

import math
from dataclasses import dataclass, field

import numpy as np

from .analysis.steady import MIN_STEADY_CYCLES
from .errors import InputError, shown
from .params import Case
from .simulation import Simulation, default_recorders
from .recorders.trajectory import TrajectoryRecorder

__all__ = ["run_case", "run_cases", "on_gpu", "check_device", "on_device", "RunResult", "analyze_signals", "analyse_signals",
           "SteadyJudge", "MODE_FPS", "MIN_STEADY_CYCLES"]

#: Frames per second of the coarse trajectory recorded (and not returned) to classify the motion
#: mode when no trajectory is asked for (docs/motion.md: 50 frames/s give the same modes as 100);
#: more above 2 Hz, 25 frames a cycle (:func:`pdamper.analysis.modes.mode_fps`).
MODE_FPS = 50.0


@dataclass(frozen=True, kw_only=True)
class RunResult:
    """What one run produced.

    Attributes
    ----------
    case : the Case that was run.
    signals : :class:`pdamper.recorders.signals.Signals` (time, driving force, container motion).
    energy : :class:`pdamper.recorders.energy.EnergyLedger`.
    analysis : complex-power result (``pdamper.analysis.PowerResult``) or None.
    trajectory : dict of arrays (``time`` [s], ``position`` [m], ``velocity`` [m/s], ``spin``
        [rad/s], container frame; ``radius`` [m]; the container's pose ``container_position`` [m]
        and ``container_velocity`` [m/s], (frames, 3): x_c d and v_c d, d the drive direction in
        the container frame) when ``case.recording.trajectory_fps > 0``, else None.
    structure : :class:`pdamper.recorders.structure.StructureRecord` when the container rides on
        a coupled structure, else None.
    recorded : the results of the extra recorders given to :func:`run_case`, by name.
    extras : more summary entries: ``mode`` and ``mode_features`` (the motion mode, classified on
        the trajectory or on a coarse one recorded for it at :data:`MODE_FPS`, 25 frames a cycle
        above 2 Hz), Gear's ``rejected_steps``.
    steps : time steps taken; time_step_s : the step [s] (Verlet) or the mean accepted step (Gear);
    wall_time_s : run time [s]. Numbers on a result carry their unit in the name, as in
    :meth:`summary` (docs/names.md); ``energy_per_cycle`` and ``time_step`` are the old names.
    """

    case: Case
    signals: object
    energy: object
    analysis: object = None
    trajectory: dict | None = None
    steps: int = 0
    time_step_s: float = 0.0
    wall_time_s: float = 0.0
    neighbour_search: str = ""
    extras: dict = field(default_factory=dict)
    structure: object = None
    recorded: dict = field(default_factory=dict)

    @property
    def eta_star(self) -> float:
        """Reduced loss factor eta* [-] (eq. 5)."""
        return float(self.analysis.eta_star) if self.analysis is not None else math.nan

    @property
    def eta_star_error(self) -> float:
        """Standard error of eta* [-] over the analysed cycles (:mod:`pdamper.analysis.steady`: the cycle
        energies' long-run variance); NaN without an analysis or below two analysed cycles."""
        return float(self.analysis.eta_star_error) if self.analysis is not None else math.nan

    @property
    def steady(self) -> bool | None:
        """Whether the run reached steady state: the first and second halves of the analysed cycles
        agree within two standard errors, over at least 4 cycles (:mod:`pdamper.analysis.steady`);
        None without an analysis."""
        return bool(self.analysis.steady) if self.analysis is not None else None

    @property
    def effective_mass_kg(self) -> float:
        """The bed's effective (apparent) mass ``Im(P) / (1/2 Omega |V*|^2)`` [kg], the container's
        own mass ``case.container.mass`` removed (:attr:`pdamper.analysis.PowerResult.effective_mass_kg`)."""
        return float(self.analysis.effective_mass_kg) if self.analysis is not None else math.nan

    @property
    def equivalent_damping_N_s_per_m(self) -> float:
        """The equivalent viscous damping ``c_eq = 2 Re(P) / |V*|^2`` [N s/m]."""
        return float(self.analysis.equivalent_damping_N_s_per_m) if self.analysis is not None else math.nan

    @property
    def mode(self) -> str | None:
        """Motion mode of the bed (:mod:`pdamper.analysis.modes`), None for a drive without a frequency."""
        return self.extras.get("mode")

    @property
    def energy_per_cycle_J(self) -> float:
        """Dissipated energy per cycle [J] (eq. 4)."""
        return float(self.analysis.energy_per_cycle_J) if self.analysis is not None else math.nan

    energy_per_cycle = renamed("energy_per_cycle_J")
    time_step = renamed("time_step_s")

    def to_dataset(self):
        """This run as one ``xarray.Dataset``: signals, energies, structure and trajectory with
        ``time`` as coordinate and units, the case and the summary in the attributes
        (:func:`pdamper.io.datasets.run_dataset`)."""
        from ._version import __version__
        from .config import dumps_case
        from .io.datasets import run_dataset

        return run_dataset(signals=self.signals, energy=self.energy, trajectory=self.trajectory,
                           structure=self.structure, config_text=dumps_case(self.case), summary=self.summary(),
                           description=str(self.case), version=__version__)

    def summary(self) -> dict:
        """Plain dict for JSON output."""
        a = self.analysis
        return {
            "eta_star": self.eta_star,
            "energy_per_cycle_J": self.energy_per_cycle_J,
            "mean_power_check_J": float(a.mean_power_check_J) if a is not None else math.nan,
            "ledger_dissipated_per_cycle_J": self.energy.dissipated_per_cycle(self.case),
            "energy_balance_error": self.energy.balance_error(),
            "stroke_m": self.case.drive.stroke if self.case.drive.stroke is not None else math.nan,
            "frequency_hz": self.case.drive.frequency or (a.frequency_hz if a is not None else math.nan),
            "particles": self.case.n_particles,
            "bed_mass_kg": self.case.bed_mass,
            "effective_mass_kg": self.effective_mass_kg,
            "equivalent_damping_N_s_per_m": self.equivalent_damping_N_s_per_m,
            "container_mass_kg": self.case.container.mass,
            "steps": self.steps,
            "time_step_s": self.time_step_s,
            "wall_time_s": self.wall_time_s,
            "us_per_step": 1e6 * self.wall_time_s / max(self.steps, 1),
            "integrator": self.case.numerics.integrator,
            "neighbour_search": self.neighbour_search,
            **self.extras,
        }


def structure_amplitudes(case: Case, rec, energy=None) -> dict:
    """A coupled structure's amplitudes from its record ``rec``: half the peak-to-peak of the
    damper's stroke (the container) and of the structure's response point over the last period of
    the run's frequency [m], the damper's largest |x| over the run [m], and the error of the coupled
    ledger of structure + bed (``energy``: the bed's :class:`~pdamper.recorders.energy.EnergyLedger`)."""
    n = max(2, int(round(case.recording.sample_rate / case.drive.frequency)))
    last = slice(-min(n, rec.time.size), None)
    resp = rec.response_displacement if rec.response_displacement is not None else rec.displacement
    return {"damper_stroke_m": float(np.ptp(rec.displacement[last]) / 2),
            "structure_amplitude_m": float(np.ptp(resp[last]) / 2),
            "damper_stroke_max_m": float(np.max(np.abs(rec.displacement))),
            "coupled_energy_balance_error": rec.balance_error(energy) if energy is not None else math.nan,
            **case.drive.structure_summary()}


def analyze_signals(case: Case, signals):
    """Complex-power analysis (eqs. 3-5) of a run's recorded ``signals`` for ``case``: the drive
    frequency, the cycles the case drops, its bed mass and its container's mass (removed from the
    bed's effective mass)."""
    from .analysis import complex_power

    return complex_power(signals.time, signals.force, signals.velocity, frequency=case.drive.frequency,
                         drop_cycles=case.drop_cycles, bed_mass=case.bed_mass, container_mass=case.container.mass)


analyse_signals = renamed_function(analyze_signals, "analyse_signals")


def _check_until_steady(case: Case, until_steady, analyze: bool) -> None:
    """Refuse an ``until_steady`` that cannot be judged (one line each)."""
    if until_steady is None:
        return
    if not (until_steady > 0 and math.isfinite(until_steady)):
        raise InputError(f"until_steady = {shown(until_steady)}: give eta*'s standard error to stop at, > 0 (e.g. 0.01)")
    if not (case.drive.periodic and analyze):
        raise InputError("until_steady needs a harmonic drive ([drive] stroke and frequency) and the analysis")


class SteadyJudge:
    """When a run of ``case`` may stop early (``until_steady``): from ``case.drop_cycles +
    MIN_STEADY_CYCLES`` whole cycles on, at the first cycle's end at which the record so far is
    steady and eta*'s standard error is at most ``tolerance``; never before the run's end otherwise.
    One rule for both engines: the CPU engine drives to :meth:`next_samples` and asks, the GPU engine
    asks between its launches with whatever its case has recorded. ``interval``: the sample
    interval [s]; ``n_samples``: the run's driven samples."""

    def __init__(self, case: Case, tolerance: float, interval: float, n_samples: int):
        self.case = case
        self.tolerance = tolerance
        self.interval = interval
        self.n_samples = int(n_samples)
        self.per_cycle = case.recording.sample_rate / case.drive.frequency
        #: the cycles judged next (once the run is stopped: the cycles it keeps)
        self.cycles = case.drop_cycles + MIN_STEADY_CYCLES
        #: the driven samples kept where the run was stopped (None: not stopped)
        self.kept = None

    def next_samples(self) -> int:
        """The driven samples the next judgement needs (the run's whole record: no early stop left)."""
        return min(self.n_samples, int(math.ceil(self.cycles * self.per_cycle - 1e-9)))

    def __call__(self, wall_force: np.ndarray) -> int | None:
        """Judge the record ``wall_force`` (the driven samples recorded so far) at every cycle's end it
        holds that is not judged yet, in order: the samples to keep (the run stops there, its cycles
        :attr:`cycles`, also :attr:`kept`), or None (go on)."""
        from .recorders.signals import Signals

        while True:
            target = self.next_samples()
            if target >= self.n_samples or target > wall_force.shape[0]:
                return None
            sig = Signals.from_run(self.case, self.interval, wall_force[:target])
            st = analyze_signals(self.case, sig).statistics
            if st.steady and st.eta_star_error <= self.tolerance:
                self.kept = target
                return target
            self.cycles += 1


def _run_until_steady(sim: Simulation, case: Case, tolerance: float, progress=None):
    """Drive ``sim`` cycle by cycle as :class:`SteadyJudge` asks and stop where it says; never beyond
    the case's cycles. Returns the cycles driven."""
    sim.settle()
    judge = SteadyJudge(case, tolerance, sim.interval, sim.n_samples)
    while True:
        sim.advance(judge.next_samples() - sim.sample, progress=progress)
        if sim.sample >= sim.n_samples:
            return float(case.cycles)
        if judge(sim.samples.wall_force[:sim.sample]) is not None:
            return float(judge.cycles)


def run_case(case: Case, *, recorders=(), progress=None, analyze: bool = True,
             until_steady: float | None = None, analyse: bool | None = None, checked: bool = False) -> RunResult:
    """Simulate ``case`` and analyze it: energy per cycle and eta* by the complex power method,
    the motion mode from the trajectory.

    ``recorders`` are recorded too (:mod:`pdamper.recorders.base`); their results are in
    ``result.recorded``. ``progress(done_fraction)`` is called as the run goes. With
    ``analyze=False`` only the recording is done (no complex power, no mode); ``analyse`` is its
    deprecated spelling.

    ``until_steady``: stop the run early, after at least ``drop_cycles + MIN_STEADY_CYCLES``
    cycles, at the first whole cycle at which the record is steady and eta*'s standard error
    (:mod:`pdamper.analysis.steady`) is at most this value; never beyond ``case.cycles``. The
    cycles driven are ``result.extras["cycles_run"]``. Harmonic drives only.

    A case with ``numerics.device = "cuda"`` runs on the GPU engine (:func:`run_cases`).

    The case is checked once before anything is simulated (:func:`pdamper.plausible.check_case`,
    by the :class:`~pdamper.simulation.Simulation`); ``checked``: it was checked already (a
    sweep checks its points when it is made) and is not again.
    """
    analyze = renamed_keyword("run_case", "analyse", "analyze", analyse, analyze)
    _check_until_steady(case, until_steady, analyze)
    if on_gpu(case):
        res = run_cases([case], recorders=recorders, analyze=analyze, until_steady=until_steady, checked=checked,
                        progress=None if progress is None else (lambda done, total: progress(done / max(total, 1))))[0]
        if isinstance(res, Exception):
            raise res
        return res
    sim, recorders, classify = _simulation(case, recorders, analyze, checked)
    cycles_run = float(case.cycles)
    if until_steady is not None:
        cycles_run = _run_until_steady(sim, case, until_steady, progress)
    else:
        sim.run(progress=progress)
    return _result(case, sim.finalize(), recorders, analyze, classify, cycles_run)


#: ``numerics.device`` -> whether the case runs on the GPU engine.
_DEVICES = {"cpu": False, "cuda": True}


def on_gpu(case: Case) -> bool:
    """Whether ``case`` runs on the GPU engine (``numerics.device = "cuda"``)."""
    return _DEVICES[case.numerics.device]


def check_device(device: str) -> None:
    """Raise :class:`~pdamper.errors.InputError` (one line) when ``device`` cannot run here: "cuda"
    without numba-cuda or without a GPU (before a long sweep starts, not after)."""
    if _DEVICES[device]:
        from .engine.cuda import require

        require()


def on_device(case: Case, device: str) -> Case:
    """``case`` set to run on ``device`` ("cpu" or "cuda")."""
    from .schema import replace

    return replace(case, {"numerics.device": device})


def run_cases(cases, *, recorders=(), analyze: bool = True, until_steady: float | None = None,
              progress=None, checked: bool = False) -> list:
    """Run ``cases`` and analyze each as :func:`run_case` does; return, per case, its
    :class:`RunResult` or the :class:`~pdamper.errors.SimulationError` of its failed step.

    The cases with ``numerics.device = "cuda"`` run together on one GPU (the GPU engine,
    :mod:`pdamper.engine.cuda`: every case of the batch advanced at once, each with its own
    integrator, Gear's adaptive step or Verlet's); the others one after another on the CPU. ``recorders`` are the extra recorders of every case (a list of them per case: give
    ``[[...], ...]``; kernel-channel recorders only on the GPU). ``progress(done, total)``: the
    GPU's steps done between its launches. A GPU that runs out of memory or faults raises: the
    caller keeps what finished before (the studies run a GPU study in chunks for that).
    ``until_steady`` as :func:`run_case`, on either engine: a GPU case stops at the same cycle as on
    the CPU (:class:`SteadyJudge`, asked between the GPU's launches, so a case runs on until the
    launch in which it became steady ends; its steps count them). ``checked`` as :func:`run_case`.
    """
    from .errors import SimulationError
    from .simulation import run_on_gpu

    cases = list(cases)
    per_case = [list(r) for r in recorders] if recorders and isinstance(recorders[0], (list, tuple)) \
        else [list(recorders)] * len(cases)
    out = [None] * len(cases)
    gpu = [k for k, c in enumerate(cases) if on_gpu(c)]
    if gpu:
        gpu = _beds_the_gpu_takes(cases, gpu)
    for k, c in enumerate(cases):
        if k not in gpu:
            try:
                out[k] = run_case(on_device(c, "cpu") if on_gpu(c) else c, recorders=per_case[k], analyze=analyze,
                                  until_steady=until_steady, checked=checked)
            except SimulationError as exc:
                out[k] = exc
    if not gpu:
        return out
    sims = []
    for k in gpu:
        case = cases[k]
        _check_until_steady(case, until_steady, analyze)
        sim, recs, classify = _simulation(case, per_case[k], analyze, checked)
        sims.append((k, case, sim, recs, classify))
    judges = None if until_steady is None else \
        [SteadyJudge(case, until_steady, sim.interval, sim.n_samples) for _, case, sim, _, _ in sims]
    records = run_on_gpu([s for _, _, s, _, _ in sims], progress=progress, steady=judges)
    for n, ((k, case, sim, recs, classify), rec) in enumerate(zip(sims, records)):
        cycles = float(case.cycles)
        if judges is not None and judges[n].kept is not None:
            cycles = float(judges[n].cycles)
        out[k] = rec if isinstance(rec, Exception) else _result(case, rec, recs, analyze, classify, cycles)
    return out


def _beds_the_gpu_takes(cases, gpu):
    """The indices of ``gpu`` whose beds the GPU engine takes (:func:`pdamper.engine.cuda.takes`);
    the others run on the CPU engine, said in one warning."""
    import warnings

    from .engine.cuda import takes
    from .kernels.gpu.batch import MAX_SPHERES

    big = [k for k in gpu if not takes(cases[k])]
    if big:
        sizes = sorted({cases[k].n_particles for k in big})
        warnings.warn(f"{len(big)} case{'s' if len(big) != 1 else ''} of {', '.join(map(str, sizes))} spheres run on "
                      f"the CPU engine: the GPU engine takes beds of up to {MAX_SPHERES} spheres "
                      "(docs/engine.md, 'The GPU engine')", stacklevel=3)
    return [k for k in gpu if k not in big]


def _simulation(case: Case, recorders, analyze: bool, checked: bool = False):
    """The simulation of ``case`` with its built-in recorders (a coarse trajectory for the motion
    mode when it is classified) and ``recorders``; returns ``(sim, recorders, classify)``. The
    simulation checks the case (with whole cycles for the analysis when it is analysed) unless
    it was ``checked``."""
    recorders = list(recorders)
    builtin = default_recorders(case)
    has_frequency = float(case.drive.frequency or 0.0) > 0
    classify = analyze and has_frequency
    if classify and not case.recording.trajectory_fps:
        from .analysis.modes import mode_fps

        builtin.append(TrajectoryRecorder(mode_fps(case.drive.frequency, case.recording.sample_rate, MODE_FPS)))
    return Simulation(case, builtin + recorders, analyze=analyze, checked=checked), recorders, classify


def _result(case: Case, record, recorders, analyze: bool, classify: bool, cycles_run: float) -> RunResult:
    """The run's :class:`RunResult` from what its simulation recorded: the complex power, the
    motion mode, the coupled structure's amplitudes."""
    out = record.outputs
    has_frequency = float(case.drive.frequency or 0.0) > 0
    analysis = None
    if analyze and case.drive.analysable:
        analysis = analyze_signals(case, record.signals)
    extras = {"rejected_steps": record.rejected_steps} if record.rejected_steps is not None else {}
    if analysis is not None:
        st = analysis.statistics
        extras.update(eta_star_error=st.eta_star_error, steady=st.steady)
    if has_frequency:
        extras["cycles_run"] = cycles_run
    if record.structure is not None:
        extras.update(structure_amplitudes(case, record.structure, record.energy))
    trajectory = record.trajectory
    if classify and trajectory is not None:
        from .analysis.modes import classify_trajectory

        try:
            mode, feats = classify_trajectory(trajectory, case)
            extras.update(mode=mode, mode_features=feats.to_dict())
        except ValueError:  # too short a run for two frames
            extras.update(mode="unknown", mode_features={})
    if not case.recording.trajectory_fps:
        trajectory = None  # recorded only to classify the motion mode
    return RunResult(case=case, signals=record.signals, energy=record.energy, analysis=analysis, trajectory=trajectory,
                     steps=record.steps, time_step_s=record.time_step_s, wall_time_s=record.wall_time_s,
                     neighbour_search=record.neighbour_search, extras=extras, structure=record.structure,
                     recorded={r.name: out[r.name] for r in recorders})


# short reprs: names, shapes and key numbers (a notebook shows a line, not a dump)
RunResult._repr_first = ("eta_star", "eta_star_error", "steady", "mode")
RunResult.__repr__ = short_repr
