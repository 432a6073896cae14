"""The integrators as seen from Python: each drives its compiled kernel over a span of time.

A stepper owns its integrator's state bundle, calls the kernel until the span is done, grows the
neighbour lists when they overflow (the kernels stop before anything moves, so the call is
simply repeated) and turns a failed step into a :class:`~pdamper.errors.SimulationError` that
says what happened, when, to which sphere, and what to change.
"""

from __future__ import annotations

import dataclasses

import numpy as np
from numba import types

from ..errors import SimulationError
from ..kernels import forces as kf
from ..kernels.bundles import SAVED_HISTORY_ROWS, FrictionRecord, GearSpan, GearState, VerletSpan, VerletState
from .build import Engine, auto_time_step, grow_pairs, grow_walls

__all__ = ["VerletStepper", "GearStepper", "stepper_for", "failure_message", "GEAR_MIN_STEP"]

#: Gear's shortest step [s]: far below any Hertz contact time of the paper's materials.
GEAR_MIN_STEP = 1e-9


def failure_message(case, status, culprit, t_fail, step) -> str:
    """What a failed step (``status``: an overlap or a non-finite velocity) says: when, which
    sphere, what happened, what to change (the CPU steppers and the GPU engine alike)."""
    what = "an overlap beyond " + f"{100 * case.numerics.overlap_limit:g} % of the radius" \
        if status == kf.STATUS_OVERLAP else "a non-finite velocity (NaN/inf)"
    when = f"t = {t_fail:.6f} s" if t_fail >= 0 else f"t = {t_fail:.6f} s (during settling, before the drive)"
    if case.numerics.integrator == "gear":
        fix = "a smaller numerics.gear_tolerance or numerics.gear_max_step"
    else:
        suggest = min(step, auto_time_step(dataclasses.replace(
            case, numerics=dataclasses.replace(case.numerics, time_step=None)))) / 2
        fix = (f"a smaller numerics.time_step (e.g. {suggest * 1e6:.3g} us), more numerics.steps_per_contact, "
               "a larger numerics.max_impact_speed, or integrator = 'gear'")
    return (f"the run became unstable at {when}: particle {culprit} reached {what} with time step "
            f"{step * 1e6:.3g} us; use {fix}")


class _Stepper:
    """What both steppers share: priming, list growth and failure messages."""

    #: Gear's rejected steps (None for a fixed-step integrator)
    rejected = None

    def __init__(self, engine: Engine, interval: float, settle_samples: int = 0):
        self.engine = engine
        self.interval = interval
        self.settle_samples = settle_samples
        self.primed = False  # initial accelerations not computed yet
        self.steps = 0

    def mean_step(self, span: float) -> float:
        """The mean step [s] over ``span`` [s] of simulated time."""
        return span / max(self.steps, 1)

    def _grow(self, status) -> None:
        e = self.engine
        if status == kf.STATUS_LIST_OVERFLOW:
            e.pairs = grow_pairs(e.pairs, 2 * e.pairs.second.shape[0])
        else:
            e.walls = grow_walls(e.walls, 2 * e.walls.candidate_body.shape[0])

    def _check(self, status, steps, culprit, t_fail, step) -> None:
        """After a kernel call: mark primed, grow the lists or raise on a failed step."""
        if status == kf.STATUS_OK or steps > 0:
            self.primed = True
        if status == kf.STATUS_OK:
            return
        if status in (kf.STATUS_LIST_OVERFLOW, kf.STATUS_WALL_OVERFLOW):
            self._grow(status)
            return
        raise SimulationError(failure_message(self.engine.case, status, culprit, t_fail, step))


class VerletStepper(_Stepper):
    """Fixed-step velocity Verlet (:func:`pdamper.kernels.verlet.run_verlet`)."""

    name = "verlet"

    def __init__(self, engine: Engine, interval: float, settle_samples: int = 0):
        super().__init__(engine, interval, settle_samples)
        n = engine.n
        #: steps per sample interval, and the step [s] that divides the interval exactly
        self.sub = max(1, int(np.ceil(interval / engine.dt - 1e-9)))
        self.dt = interval / self.sub
        self.state = VerletState(np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3)),
                                 np.zeros((n, 6)))

    @property
    def sample_interval(self) -> float:
        """The interval the kernel's sample means divide by (``sub`` steps)."""
        return self.sub * self.dt

    def mean_step(self, span: float) -> float:
        """The fixed step [s]."""
        return self.dt

    def advance(self, samples, t0, t_end, record) -> int:
        """Steps from ``t0`` to ``t_end`` [s], both on sample boundaries (negative times: the
        settling, before the drive starts); returns the steps taken."""
        k0 = int(round(t0 / self.interval))
        k1 = int(round(t_end / self.interval))
        if k0 < 0:
            t0 = k0 * self.sub * self.dt  # the settling's clock, counted in steps from its start
        return self._steps(samples, (k1 - k0) * self.sub, t0, (self.settle_samples + k0) * self.sub, record,
                           self.settle_samples if record else 0)

    def _steps(self, samples, n_steps, t0, step0, record, skip_samples) -> int:
        """``n_steps`` steps from ``t0`` [s]; ``step0`` the global step count at ``t0`` (samples end
        every ``sub`` steps; the first ``skip_samples`` samples are the settling's)."""
        from ..kernels.verlet import run_verlet

        e = self.engine
        done = 0
        while done < n_steps:
            span = VerletSpan(steps=int(n_steps - done), dt=float(self.dt), t0=float(t0 + done * self.dt),
                              step0=int(step0 + done), sub=int(self.sub), record=bool(record),
                              skip_samples=int(skip_samples), prime=not self.primed)
            status, steps, culprit = run_verlet(span, e.bodies, self.state, e.pairs, e.walls, e.search, e.table,
                                                e.drive, samples)
            done += steps
            self._check(status, steps, culprit, t0 + done * self.dt, self.dt)
        self.steps += done
        return done

    def warm_jobs(self, samples):
        """``[(kernel, arguments), (callee, arguments), ...]``: the kernel, then its larger callees
        in the order opposite to the one it meets them in (:mod:`pdamper.engine.warmup`)."""
        from ..kernels.forces import compute_forces, no_friction_record
        from ..kernels.neighbours import rebuild_lists
        from ..kernels.record import record_sample
        from ..kernels.verlet import run_verlet

        e = self.engine
        b = e.bodies
        span = VerletSpan(steps=0, dt=1.0, t0=0.0, step0=0, sub=1, record=False, skip_samples=0, prime=False)
        return [(run_verlet, (span, b, self.state, e.pairs, e.walls, e.search, e.table, e.drive, samples)),
                (record_sample, (0, samples, b, e.pairs, e.walls, e.drive, 0.0, 0.0)),
                (compute_forces, (b, e.pairs, e.walls, e.table, 1.0, 1.0, self.state.moved, no_friction_record(),
                                  samples.split)),
                (rebuild_lists, (b, e.pairs, e.walls, e.search, e.table))]

    def start_drive(self, jump, a0) -> None:
        """The drive starts: the spheres' velocities relative to the container jumped by
        ``-jump`` (done by the caller); a coupled structure starts with acceleration ``a0``
        (None: no structure)."""
        if a0 is not None:
            d = self.engine.drive.direction
            self.state.acceleration[:] -= a0 * d
            self.state.previous_acceleration[:] -= a0 * d


class GearStepper(_Stepper):
    """Variable-step fifth-order Gear (:func:`pdamper.kernels.gear.run_gear`)."""

    name = "gear"

    def __init__(self, engine: Engine, interval: float, settle_samples: int = 0):
        super().__init__(engine, interval, settle_samples)
        n = engine.n
        sub = max(1, int(np.ceil(interval / engine.dt - 1e-9)))
        h0 = interval / sub
        self.h_next = h0
        self.rejected = 0
        self.state = GearState(nordsieck=np.zeros((6, n, 6)), predicted=np.zeros((6, n, 6)),
                               increments=np.zeros((n, 6)), step=np.array([h0]),
                               integrands=np.zeros(4),
                               saved_pair_history=np.zeros((SAVED_HISTORY_ROWS, engine.pairs.second.shape[0])),
                               saved_wall_history=np.zeros((SAVED_HISTORY_ROWS,) + engine.walls.approach_speed.shape),
                               saved_structure=np.zeros_like(engine.drive.state), friction=self._record(None),
                               anchor=np.zeros((n, 6)), moved=np.zeros((n, 6)))

    def _record(self, old):
        """The friction record, sized for every listed pair, every sphere on the floor and every
        wall candidate (grown with the lists)."""
        e = self.engine
        cap = e.pairs.second.shape[0] + e.n + e.walls.candidate_body.shape[0]
        if old is not None and old.rows.shape[0] >= cap:
            return old
        return FrictionRecord(np.zeros((cap, 2), dtype=np.int64), np.zeros((cap, 8)), np.zeros(3, dtype=np.int64))

    def _grow(self, status) -> None:
        super()._grow(status)
        s = self.state
        cap = self.engine.pairs.second.shape[0]
        if s.saved_pair_history.shape[1] < cap:
            s = s._replace(saved_pair_history=np.zeros((SAVED_HISTORY_ROWS, cap)))
        self.state = s._replace(friction=self._record(s.friction))

    @property
    def sample_interval(self) -> float:
        """The interval the kernel's sample means divide by."""
        return self.interval

    def advance(self, samples, t0, t_end, record) -> int:
        """Accepted steps from ``t0`` to ``t_end`` [s] (both on sample boundaries; negative times:
        the settling, before the drive starts); returns the steps taken."""
        from ..kernels.gear import run_gear

        e = self.engine
        num = e.case.numerics
        t = t0
        steps = 0
        while t < t_end - 1e-12 * self.interval:
            span = GearSpan(t0=float(t), t_end=float(t_end), h_try=float(self.h_next), interval=float(self.interval),
                            record=bool(record), prime=not self.primed, tolerance=float(num.gear_tolerance),
                            h_min=GEAR_MIN_STEP, h_max=float(num.gear_max_step), max_steps=10**9)
            status, k, culprit, t, self.h_next, rej = run_gear(span, e.bodies, self.state, e.pairs, e.walls, e.search,
                                                              e.table, e.drive, samples)
            steps += k
            self.rejected += rej
            self._check(status, k, culprit, t, self.h_next)
        self.steps += steps
        return steps

    def warm_jobs(self, samples):
        """``[(kernel, arguments), (callee, arguments), ...]``: the kernel, then its larger callees
        in the order opposite to the one it meets them in (:mod:`pdamper.engine.warmup`)."""
        from ..kernels.forces import compute_forces
        from ..kernels.gear import _implicit_friction, _predict, run_gear
        from ..kernels.neighbours import rebuild_lists
        from ..kernels.record import record_sample

        e = self.engine
        b = e.bodies
        s = self.state
        span = GearSpan(t0=0.0, t_end=0.0, h_try=1.0, interval=1.0, record=False, prime=False, tolerance=1.0,
                        h_min=1.0, h_max=1.0, max_steps=0)
        view = types.Array(types.float64, 2, "A")
        return [(run_gear, (span, b, s, e.pairs, e.walls, e.search, e.table, e.drive, samples)),
                (record_sample, (0, samples, b, e.pairs, e.walls, e.drive, 0.0, 0.0)),
                # the kernel passes column views, which numba types as layout 'A' (from Python a
                # one-sphere view would be typed 'C')
                (_implicit_friction, (b, view, view, 1.0, s.friction, samples.split)),
                (_predict, (s.nordsieck, s.predicted, 1.0, 1.0, b)),
                (compute_forces, (b, e.pairs, e.walls, e.table, 1.0, 1.0, s.moved, s.friction, samples.split)),
                (rebuild_lists, (b, e.pairs, e.walls, e.search, e.table))]

    def start_drive(self, jump, a0) -> None:
        """The drive starts: the spheres' velocities relative to the container jumped by
        ``-jump`` (done by the caller on the bodies; here in the Nordsieck vector); a coupled
        structure starts with acceleration ``a0`` (the spheres' r_2 follow)."""
        if not self.primed:
            return
        h = self.state.step[0]
        nord = self.state.nordsieck
        nord[1, :, 0:3] -= h * jump
        if a0 is not None:
            nord[2, :, 0:3] -= 0.5 * h * h * a0 * self.engine.drive.direction


#: The steppers by ``numerics.integrator``.
STEPPERS = {"verlet": VerletStepper, "gear": GearStepper}


def stepper_for(engine: Engine, interval: float, settle_samples: int = 0):
    """The stepper of the case's ``numerics.integrator``, for samples of ``interval`` [s] after
    ``settle_samples`` samples of settling."""
    return STEPPERS[engine.case.numerics.integrator](engine, interval, settle_samples)
