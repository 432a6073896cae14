"""Build a case from its parameters, run it, and feed the recorders.

:class:`Simulation` turns a :class:`pdamper.params.Case` into the plain arrays the kernels
take, settles the particles, runs the drive in segments (for progress and clean interrupts)
and returns a :class:`RunResult` with the recorded signals, the energy ledger and the
complex-power analysis.
"""

from __future__ import annotations

import dataclasses
import math
import time as _time
from dataclasses import dataclass, field

import numpy as np

from .contact.cor_table import SPEED_GRID, tabulate_law
from .contact.cor_thornton import ThorntonRestitution
from .contact.hertz_gonthier import chi_for_restitution, contact_time, effective_radius
from .errors import InputError, SimulationError
from .excitation import CoupledStructure, HarmonicDrive
from .geometry.tilt import container_vectors
from .geometry.walls import CYLINDER_INSIDE
from .initial import initial_positions
from .kernels import forces as kf
from .materials import effective_modulus
from .params import Case
from .recorders.signals import Signals
from .recorders.energy import EnergyLedger
from .recorders.structure import StructureRecord

__all__ = ["Simulation", "RunResult", "run_case", "auto_time_step", "run_bare_structure"]

#: Gear's shortest step [s]: far below any Hertz contact time of the paper's materials.
GEAR_MIN_STEP = 1e-9

#: Frames per second of the coarse trajectory recorded (and not returned) to classify the motion
#: mode when no trajectory is asked for (docs/motion.md: 50 frames/s give the same modes as 100).
MODE_FPS = 50.0

#: Above this many spheres the Verlet list is built with link cells ("auto" search).
CELLS_THRESHOLD = 200


def _radii_masses(case):
    rad = np.concatenate([np.full(p.count, p.radius) for p in case.particles])
    mass = np.concatenate([np.full(p.count, p.mass) for p in case.particles])
    return rad, mass


def auto_time_step(case: Case) -> float:
    """Time step [s] for the fixed-step integrator: the shortest Hertz contact time among the
    case's contact types at the expected largest impact speed, over ``steps_per_contact``,
    capped by ``max_time_step``. The expected impact speed is ``numerics.max_impact_speed`` or
    2.5 x the drive's largest velocity (2.5 x the largest initial velocity in a still
    container) plus 0.1 m/s."""
    num = case.numerics
    if num.time_step is not None:
        return num.time_step
    if num.max_impact_speed is not None:
        v = num.max_impact_speed
    elif isinstance(case.drive, HarmonicDrive):
        v = 2.5 * case.drive.velocity_amplitude + 0.1
    elif isinstance(case.drive, CoupledStructure):
        v = 2.5 * case.drive.velocity_bound + 0.1
    elif case.drive.kind == "still":
        v0 = np.asarray(case.initial.velocities if case.initial.velocities is not None else [[0.0, 0.0, 0.0]])
        v = 2.5 * float(np.max(np.linalg.norm(v0, axis=-1))) + 0.1
    else:
        _, vc, _ = case.drive.motion(np.asarray(case.drive.time))
        v = 2.5 * float(np.max(np.abs(vc))) + 0.1
    wall = case.container.material
    best = math.inf
    for a in case.particles:
        for b in case.particles:
            es = effective_modulus(a.material, b.material)
            rs = effective_radius(a.radius, b.radius)
            ms = a.mass * b.mass / (a.mass + b.mass)
            best = min(best, contact_time(ms, rs, es, v))
        best = min(best, contact_time(a.mass, a.radius, effective_modulus(a.material, wall), v))
    return min(best / num.steps_per_contact, num.max_time_step)


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
    extras : more summary entries: ``mode`` and ``mode_features`` (the motion mode, classified on
        the trajectory or on a coarse one recorded for it at :data:`MODE_FPS`), Gear's
        ``rejected_steps``.
    steps : time steps taken; time_step : the step [s] (Verlet) or the mean accepted step (Gear);
    wall_time_s : run time [s].
    """

    case: Case
    signals: Signals
    energy: EnergyLedger
    analysis: object = None
    trajectory: dict | None = None
    steps: int = 0
    time_step: float = 0.0
    wall_time_s: float = 0.0
    neighbour_search: str = ""
    extras: dict = field(default_factory=dict)
    structure: object = None

    @property
    def eta_star(self) -> float:
        """Reduced loss factor eta* [-] (eq. 5)."""
        return float(self.analysis.eta_star) if self.analysis is not None else math.nan

    @property
    def mode(self) -> str | None:
        """Motion mode of the bed (:mod:`pdamper.analysis.modes`), None without a periodic drive."""
        return self.extras.get("mode")

    @property
    def energy_per_cycle(self) -> float:
        """Dissipated energy per cycle [J] (eq. 4)."""
        return float(self.analysis.energy_per_cycle_J) if self.analysis is not None else math.nan

    def summary(self) -> dict:
        """Plain dict for JSON output."""
        a = self.analysis
        return {
            "eta_star": self.eta_star,
            "energy_per_cycle_J": self.energy_per_cycle,
            "mean_power_check_J": float(a.mean_power_check_J) if a is not None else math.nan,
            "ledger_dissipated_per_cycle_J": self.energy.dissipated_per_cycle(self.case),
            "energy_balance_error": self.energy.balance_error(),
            "stroke_m": getattr(self.case.drive, "stroke", math.nan),
            "frequency_hz": getattr(self.case.drive, "frequency", None) or (a.frequency_hz if a is not None else math.nan),
            "particles": self.case.n_particles,
            "bed_mass_kg": self.case.bed_mass,
            "steps": self.steps,
            "time_step_s": self.time_step,
            "wall_time_s": self.wall_time_s,
            "us_per_step": 1e6 * self.wall_time_s / max(self.steps, 1),
            "integrator": self.case.numerics.integrator,
            "neighbour_search": self.neighbour_search,
            **self.extras,
        }


class Simulation:
    """A case turned into kernel arrays, ready to run.

    >>> from pdamper.params import Case, ParticleSet
    >>> sim = Simulation(Case(particles=(ParticleSet(count=4),), cycles=1, drop_cycles=0))
    >>> sim.n
    4
    """

    def __init__(self, case: Case):
        self.case = case
        self._build()

    # ------------------------------------------------------------------ building
    def _build(self):
        case = self.case
        rng = np.random.default_rng(case.initial.seed)
        rad, mass = _radii_masses(case)
        self.n = n = rad.size
        self.rad, self.mass = rad, mass
        self.inv_m = 1.0 / mass
        self.inv_i = 1.0 / (0.4 * mass * rad * rad)
        # materials: particle materials first, the wall material last
        mats = []
        for p in case.particles:
            if p.material.name not in [m.name for m in mats]:
                mats.append(p.material)
        wall_mat = case.container.material
        allm = mats + [wall_mat]
        nmat = len(allm)
        self.nmat = nmat
        self.mat = np.concatenate([np.full(p.count, [m.name for m in mats].index(p.material.name))
                                   for p in case.particles]).astype(np.int64)
        npair = nmat * nmat
        self.estar = np.empty(npair)
        self.mu = np.empty(npair)
        self.cor_tab = np.empty((npair, SPEED_GRID.size))
        self.cor_py = np.zeros(npair)
        for a in range(nmat):
            for b in range(nmat):
                mp = a * nmat + b
                self.estar[mp] = effective_modulus(allm[a], allm[b])
                self.mu[mp] = case.contact.friction_for(allm[a].name, allm[b].name)
                law = case.contact.restitution_for(allm[a].name, allm[b].name)
                if isinstance(law, ThorntonRestitution):
                    # the table is epsilon over v / v_y; the kernel computes v_y per contact
                    self.cor_py[mp] = law.yield_pressure
                    from .contact.cor_thornton import thornton_restitution

                    eps = np.clip(thornton_restitution(SPEED_GRID, 1.0), 1e-6, 1.0)
                else:
                    eps = tabulate_law(law)
                self.cor_tab[mp] = chi_for_restitution(eps, case.contact.damping)
        self.logv0 = math.log(SPEED_GRID[0])
        self.dlogv = math.log(SPEED_GRID[1]) - math.log(SPEED_GRID[0])
        # walls
        geo = case.container.geometry
        kinds, data, names = geo.walls()
        self.wall_kind, self.wall_data, self.wall_names = kinds, np.ascontiguousarray(data), names
        nw = len(kinds)
        # the floor (plane y = 0, normal +y) gets the force loop's direct path
        self.floor = -1
        for w in range(nw):
            if kinds[w] == 0 and np.allclose(data[w, :4], [0.0, 1.0, 0.0, 0.0]):
                self.floor = w
        self.wk = np.empty((n, nw))
        self.wrs = np.empty((n, nw))
        self.wmp = np.empty((n, nw), dtype=np.int64)
        for w in range(nw):
            for i in range(n):
                if kinds[w] == CYLINDER_INSIDE:
                    rs = effective_radius(rad[i], concave_radius=data[w, 6])
                else:
                    rs = rad[i]
                mp = self.mat[i] * nmat + (nmat - 1)
                self.wrs[i, w] = rs
                self.wmp[i, w] = mp
                self.wk[i, w] = 4.0 / 3.0 * self.estar[mp] * math.sqrt(rs)
        # vectors in the container frame
        self.gvec, self.dvec = container_vectors(case.container.tilt, case.gravity,
                                                 getattr(case.drive, "angle", 0.0))
        # state
        self.pos = initial_positions(case, rng)
        self.vel = self._initial_vectors(case.initial.velocities, "velocities")
        self.omg = self._initial_vectors(case.initial.spins, "spins")
        self.acc = np.zeros((n, 3))
        self.alp = np.zeros((n, 3))
        self.acc_prev = np.zeros((n, 3))
        self.alp_prev = np.zeros((n, 3))
        self.force = np.zeros((n, 3))
        self.torque = np.zeros((n, 3))
        # neighbour lists
        num = case.numerics
        self.skin = num.skin if num.skin is not None else 0.2 * float(rad.max())
        search = num.neighbour_search
        if search == "auto":
            search = "cells" if n > CELLS_THRESHOLD else "direct"
        self.search = search
        cut = 2 * float(rad.max()) + self.skin
        vmin, vmax = self._bounding_box()
        self.lo = vmin - cut
        span = vmax - vmin + 2 * cut
        self.ncell = np.maximum(1, np.floor(span / cut)).astype(np.int64)
        self.cell = float(np.max(span / self.ncell))
        # keep cells at least `cut` wide in every direction
        self.cell = max(self.cell, cut)
        self.head = np.empty(int(np.prod(self.ncell)), dtype=np.int64)
        self.nxt = np.empty(n, dtype=np.int64)
        self.counts = np.zeros(n, dtype=np.int64)
        self.ref = np.full((n, 3), np.inf)
        cap = max(16, n * 8)
        self._alloc_pairs(cap)
        self.wl_i = np.empty(max(8, n * nw), dtype=np.int64)
        self.wl_w = np.empty(max(8, n * nw), dtype=np.int64)
        self.nwl = np.zeros(1, dtype=np.int64)
        self.wvin = np.zeros((n, nw))
        self.wd = np.zeros((n, nw))
        # running sums: work, damping, friction, impulse; [4:8] Gear's integrands at the last step
        self.ledger = np.zeros(8)
        self.dt = auto_time_step(case)
        self._primed = False  # initial accelerations not computed yet

    def _initial_vectors(self, given, name):
        if given is None:
            return np.zeros((self.n, 3))
        arr = np.array(given, dtype=float)
        if arr.shape != (self.n, 3) or not np.all(np.isfinite(arr)):
            raise InputError(f"initial.{name}: expected {self.n} finite rows of (x, y, z), got shape {arr.shape}")
        return arr

    def _bounding_box(self):
        g = self.case.container.geometry
        if g.shape == "cuboid":
            return (np.array([-g.length / 2, 0.0, -g.width / 2]), np.array([g.length / 2, g.height, g.width / 2]))
        return (np.array([-g.radius, 0.0, -g.radius]), np.array([g.radius, g.height, g.radius]))

    def _alloc_pairs(self, cap, keep=None):
        n = self.n
        new = dict(row=np.zeros(n + 1, dtype=np.int64), pi=np.zeros(cap, dtype=np.int64), pj=np.zeros(cap, dtype=np.int64),
                   pvin=np.zeros(cap), pd=np.zeros(cap), pk=np.zeros(cap), pmp=np.zeros(cap, dtype=np.int64),
                   pms=np.zeros(cap),
                   row2=np.zeros(n + 1, dtype=np.int64), pj2=np.zeros(cap, dtype=np.int64),
                   pvin2=np.zeros(cap), pd2=np.zeros(cap))
        if keep is not None:
            for k, arr in new.items():
                old = getattr(self, k)
                arr[: old.shape[0]] = old
        for k, arr in new.items():
            setattr(self, k, arr)
        self.hist_p = np.zeros((2, cap))  # Gear: pair history saved before each step

    # ------------------------------------------------------------------ running
    def _advance(self, n_steps, t0, step0, sub, record, rec_offset, sig, eng, traj_every, traj):
        """Run ``n_steps`` steps, growing the neighbour arrays when they overflow."""
        from .kernels.verlet import run_verlet

        done = 0
        while done < n_steps:
            status, steps, culprit = run_verlet(
                n_steps - done, self.dt, t0 + done * self.dt, step0 + done, sub, record, rec_offset,
                not self._primed,
                self.pos, self.vel, self.omg, self.acc, self.alp, self.acc_prev, self.alp_prev, self.rad, self.mass, self.inv_m, self.inv_i,
                self.mat, self.force, self.torque, self.gvec, self.dvec, *self._drive,
                self.nmat, self.estar, self.mu, self.cor_tab, self.cor_py, self.logv0, self.dlogv,
                self.case.contact.tau, self.case.contact.v_in_floor, self.case.numerics.overlap_limit,
                self.skin, self.search == "cells", self.lo, self.cell, self.ncell, self.head, self.nxt, self.counts,
                self.ref, self.row, self.pi, self.pj, self.pvin, self.pd, self.pk, self.pmp, self.pms,
                self.row2, self.pj2, self.pvin2, self.pd2,
                self.wall_kind, self.wall_data, self.floor, self.wl_i, self.wl_w, self.nwl, self.wk, self.wmp, self.wvin,
                self.wd, self.wrs, self.ledger, sig, eng, traj_every, traj)
            done += steps
            if status == kf.STATUS_OK or steps > 0:
                self._primed = True
            if status == kf.STATUS_OK:
                continue
            self._handle_status(status, culprit, t0 + done * self.dt, self.dt)
        return done

    def _advance_gear(self, t0, t_end, record, sig, eng, traj_every, traj):
        """Gear steps from ``t0`` to ``t_end`` [s]; returns accepted steps."""
        from .kernels.gear import run_gear

        num = self.case.numerics
        ts = 1.0 / self.case.recording.sample_rate
        t = t0
        steps = 0
        while t < t_end - 1e-12 * ts:
            status, k, culprit, t, self._h_next, rej = run_gear(
                t_end, self._h_next, t, ts, record, not self._primed, num.gear_tolerance, self._dt_min,
                self._dt_max, self.nord, self.pred, self.hist_p, self.hist_w, self.h_state,
                *self._friction_record(),
                self.pos, self.vel, self.omg, self.rad, self.mass, self.inv_m, self.inv_i, self.mat,
                self.force, self.torque, self.gvec, self.dvec, *self._drive,
                self.nmat, self.estar, self.mu, self.cor_tab, self.cor_py, self.logv0, self.dlogv,
                self.case.contact.tau, self.case.contact.v_in_floor, num.overlap_limit,
                self.skin, self.search == "cells", self.lo, self.cell, self.ncell, self.head, self.nxt, self.counts,
                self.ref, self.row, self.pi, self.pj, self.pvin, self.pd, self.pk, self.pmp, self.pms,
                self.row2, self.pj2, self.pvin2, self.pd2,
                self.wall_kind, self.wall_data, self.floor, self.wl_i, self.wl_w, self.nwl, self.wk, self.wmp, self.wvin,
                self.wd, self.wrs, self.ledger, sig, eng, traj_every, traj, 10**9)
            steps += k
            self.rejected_steps += rej
            if status == kf.STATUS_OK or k > 0:
                self._primed = True
            if status == kf.STATUS_OK:
                continue
            self._handle_status(status, culprit, t, self._h_next)
        return steps

    def _friction_record(self):
        """Gear's record of the touching friction contacts (``compute_forces``), sized for every
        listed pair, every sphere on the floor and every wall candidate (grown with the lists)."""
        cap = self.pj.shape[0] + self.n + self.wl_i.shape[0]
        if self.fr is None or self.fr.shape[0] < cap:
            self.fr_i = np.zeros((cap, 2), dtype=np.int64)
            self.fr = np.zeros((cap, 8))
            self.fr_n = np.zeros(3, dtype=np.int64)
        return self.fr_i, self.fr, self.fr_n

    def _handle_status(self, status, culprit, t_fail, dt):
        if status == kf.STATUS_LIST_OVERFLOW:
            self._alloc_pairs(2 * self.pj.shape[0], keep=True)
            return
        if status == kf.STATUS_WALL_OVERFLOW:
            self.wl_i = np.empty(2 * self.wl_i.shape[0], dtype=np.int64)
            self.wl_w = np.empty(2 * self.wl_w.shape[0], dtype=np.int64)
            return
        what = "an overlap beyond " + f"{100 * self.case.numerics.overlap_limit:g} % of the radius" \
            if status == kf.STATUS_OVERLAP else "a non-finite velocity (NaN/inf)"
        when = f"t = {t_fail:.6f} s" if t_fail >= 0 else f"t = {t_fail:.6f} s (during settling, before the drive)"
        if self.case.numerics.integrator == "gear":
            fix = "a smaller numerics.gear_tolerance or numerics.gear_max_step"
        else:
            suggest = min(dt, auto_time_step(dataclasses.replace(
                self.case, numerics=dataclasses.replace(self.case.numerics, time_step=None)))) / 2
            fix = (f"a smaller numerics.time_step (e.g. {suggest * 1e6:.3g} us), more numerics.steps_per_contact, "
                   "a larger numerics.max_impact_speed, or integrator = 'gear'")
        raise SimulationError(
            f"the run became unstable at {when}: particle {culprit} reached {what} with time step "
            f"{dt * 1e6:.3g} us; use {fix}")

    def run(self, *, progress=None, analyse: bool = True) -> RunResult:
        """Settle, drive for ``case.cycles`` cycles, record, analyse.

        ``progress(done_fraction)`` is called after every segment if given.
        """
        case = self.case
        gear = case.numerics.integrator == "gear"
        wall0 = _time.perf_counter()
        fs = case.recording.sample_rate
        ts = 1.0 / fs
        sub = max(1, int(math.ceil(ts / self.dt - 1e-9)))
        self.dt = ts / sub
        self._drive = case.drive.kernel_args()
        n_samples = int(math.floor(case.duration * fs + 1e-9))
        if n_samples < 2:
            raise InputError(f"run: {case.duration:g} s at {fs:g} Hz gives fewer than 2 samples; run longer")
        coupled = isinstance(case.drive, CoupledStructure)
        sig = np.zeros((n_samples, 5 if coupled else 1))
        eng = np.zeros((n_samples, 7))
        traj_every = 0
        traj = np.zeros((1, 1, 9))
        periodic = float(getattr(case.drive, "frequency", 0.0) or 0.0) > 0
        fps = case.recording.trajectory_fps or (min(MODE_FPS, fs) if periodic and analyse else 0.0)
        if fps > 0:
            traj_every = max(1, int(round(fs / fps)))
            traj = np.zeros((n_samples // traj_every, self.n, 9))
        if gear:
            self.nord = np.zeros((6, self.n, 6))
            self.pred = np.zeros((6, self.n, 6))
            self.fr = None  # the friction-contact record, sized at each call (_friction_record)
            self.hist_w = np.zeros((2,) + self.wvin.shape)
            self.h_state = np.array([self.dt])
            self._h_next = self.dt
            self._dt_min = GEAR_MIN_STEP
            self._dt_max = case.numerics.gear_max_step
            self.rejected_steps = 0
        steps = 0
        # settling: the container rests; whole samples so the drive starts on a sample boundary
        settle_samples = int(math.ceil(case.initial.settle_time / ts))
        settle_steps = settle_samples * sub
        empty_sig = np.zeros((0, 1))
        empty_eng = np.zeros((0, 7))
        if settle_samples:
            if gear:
                steps += self._advance_gear(-settle_samples * ts, 0.0, False, empty_sig, empty_eng, 0, traj)
            else:
                steps += self._advance(settle_steps, -settle_steps * self.dt, 0, sub, False, 0, empty_sig,
                                       empty_eng, 0, traj)
        # the drive starts: particles keep their lab velocity, so their velocity relative to
        # the container jumps by -v_c(0+)
        _, v0, _ = case.drive.motion(np.array([0.0]))
        jump = float(v0[0]) * self.dvec
        self.vel -= jump
        if coupled:
            # release the structure; the particles' accelerations get its a(0)
            a0 = case.drive.start_state(self._drive[2])
            self.acc -= a0 * self.dvec
            self.acc_prev -= a0 * self.dvec
        if gear and self._primed:
            self.nord[1, :, 0:3] -= self.h_state[0] * jump
        self.ledger[:4] = 0.0
        seg_samples = max(1, int(0.25 * fs))  # ~0.25 s of simulated time per call
        done = 0
        while done < n_samples:
            k = min(seg_samples, n_samples - done)
            if gear:
                steps += self._advance_gear(done * ts, (done + k) * ts, True, sig, eng, traj_every, traj)
            else:
                steps += self._advance(k * sub, done * ts, settle_steps + done * sub, sub, True, settle_samples,
                                       sig, eng, traj_every, traj)
            done += k
            if progress is not None:
                progress(done / n_samples)
        wall = _time.perf_counter() - wall0
        structure = None
        if coupled:
            structure = StructureRecord.from_run(case, ts, sig)
            signals = Signals.from_run(case, ts, sig[:, 0], motion=structure.edges())
        else:
            signals = Signals.from_run(case, ts, sig[:, 0])
        energy = EnergyLedger.from_array(signals.time_end, eng)
        trajectory = None
        if traj_every:
            t_frames = (np.arange(traj.shape[0]) + 1) * traj_every * ts
            if structure is not None:  # the container rides on the structure: its recorded motion
                at = (np.arange(traj.shape[0]) + 1) * traj_every - 1
                xc, vc = structure.displacement[at], structure.velocity[at]
            else:
                xc, vc, _ = case.drive.motion(t_frames)
            trajectory = {"time": t_frames, "position": traj[:, :, 0:3],
                          "velocity": traj[:, :, 3:6], "spin": traj[:, :, 6:9], "radius": self.rad.copy(),
                          # the container's pose: its displacement x_c d (container-frame axes; the
                          # tilt is constant) and velocity at each frame
                          "container_position": np.outer(xc, self.dvec), "container_velocity": np.outer(vc, self.dvec)}
        analysis = None
        if analyse and case.drive.kind not in ("still", "structure"):
            analysis = signals.analyse(case)
        extras = {"rejected_steps": self.rejected_steps} if gear else {}
        if periodic and analyse and trajectory is not None:
            from .analysis.modes import classify_trajectory

            try:
                mode, feats = classify_trajectory(trajectory, case)
                extras.update(mode=mode, mode_features=feats.to_dict())
            except ValueError:  # too short a run for two frames
                extras.update(mode="unknown", mode_features={})
        if not case.recording.trajectory_fps:
            trajectory = None  # recorded only to classify the motion mode
        # Gear: report the mean accepted step over the whole run (settling included)
        step = (settle_samples + n_samples) * ts / max(steps, 1) if gear else self.dt
        return RunResult(case=case, signals=signals, energy=energy, analysis=analysis, trajectory=trajectory,
                         steps=steps, time_step=step, wall_time_s=wall, neighbour_search=self.search,
                         extras=extras, structure=structure)


def run_case(case: Case, **kwargs) -> RunResult:
    """Build and run ``case`` (see :meth:`Simulation.run`)."""
    return Simulation(case).run(**kwargs)


def run_bare_structure(structure: CoupledStructure, duration: float, *, sample_rate: float = 1000.0,
                       time_step: float | None = None) -> StructureRecord:
    """The structure of ``structure`` without a bed, for ``duration`` [s]: the same compiled step
    as the coupled run (:func:`pdamper.kernels.structure.structure_step`) with no wall force.

    ``time_step`` [s] defaults to a tenth of the sample interval (and at most 1/2000 of the
    shortest period). Returns a :class:`~pdamper.recorders.structure.StructureRecord`.
    """
    from .kernels.structure import run_structure_alone

    if not (duration > 0 and math.isfinite(duration)):
        raise InputError(f"duration = {duration!r} s; must be > 0")
    ts = 1.0 / sample_rate
    fmax = max(structure.natural_frequency, structure.force_frequency or 0.0)
    dt = time_step if time_step is not None else min(ts / 10, 1.0 / (2000.0 * fmax))
    sub = max(1, int(math.ceil(ts / dt - 1e-9)))
    dt = ts / sub
    n = int(math.floor(duration * sample_rate + 1e-9))
    _, par, st = structure.kernel_args()
    structure.start_state(st)
    sig = np.zeros((n, 5))
    run_structure_alone(n * sub, dt, 0.0, sub, par, st, sig)
    return StructureRecord(time=(np.arange(n) + 1) * ts, displacement=sig[:, 1].copy(), velocity=sig[:, 2].copy(),
                           external_work=sig[:, 3].copy(), damping_loss=sig[:, 4].copy(), mass=structure.mass,
                           stiffness=structure.stiffness, x0=structure.displacement, v0=structure.velocity)
