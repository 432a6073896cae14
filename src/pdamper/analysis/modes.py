"""Motion modes of the particle bed from its trajectory (the paper's Figs. 2, 3, 5 and Sect. 6.2; docs/motion.md).

Pure functions on trajectory arrays in the **container frame** (x along the container's length,
y up from the floor, z across), as :class:`pdamper.simulation.RunResult` records them; they know
nothing of the simulator. :func:`mode_features` measures, over the analysed (steady) part of a
run, what a person watching the bed would judge by; :func:`classify_features` turns them into one
of :data:`MODES` with the thresholds of :data:`THRESHOLDS` (their measurements are in
docs/motion.md).

Measured quantities (``s`` is a sphere centre's coordinate along the drive direction, the two
end walls sit at ``s = -L/2`` and ``+L/2``, h is the clearance of eq. (6)):

- ``spread``: the median over frames of std(s) of the bed, over the std of a compact block that
  fills ``L - h`` (``(L - h)/sqrt(12)``); ~1 for a collected bed, ~L/(L - h) for a bed spread
  over the whole floor.
- ``swing``: the range (5th to 95th percentile) of the bed centre mean(s) over h: ~1 when the
  bed travels from wall to wall, ~0 when it stays put.
- ``touch_lo``, ``touch_hi``: the fraction of frames in which a sphere touches the -L/2 (lo) or
  the +L/2 (hi) end wall (gap below :data:`THRESHOLDS` ``touch_gap`` x r); in a cylinder (L = 2R)
  the curved wall within 60 deg of the drive axis behind or ahead of the centre.
- ``impacts_lo``, ``impacts_hi``: arrivals at that wall per drive cycle (frames where the bed
  starts touching it after not touching it).
- ``sync``: the share of the bed centre's variance at the drive frequency (1: the bed moves as
  one with the drive, 0: no relation); ``phase_deg``: the phase of that component against the
  container position x_c = X sin(Omega t) [deg].
- ``airborne``: the fraction of sphere-frames whose centre is more than ``lift_gap`` x r above
  the floor contact height (y > r (1 + lift_gap)); ``max_height``: the largest (y - r)/r.
- ``relative``: the range (5th to 95th percentile) of the bed centre in the container frame over
  that of the container's own position in the lab (NaN without the container's track): ~0 when
  the bed moves with the container, ~1 and more when the container moves about it.
- ``tilt_pull``: |g_s| / A, the pull of gravity along the drive (from the tilt) over the
  container's measured acceleration amplitude; ``downhill``: +1 if it pulls towards +L/2, -1
  towards -L/2, 0 without a pull.

Modes (:func:`classify_features`, checked in this order):

``lift-off``
    ``airborne`` >= ``lift_fraction``: the bed leaves the floor (container acceleration near or
    above g; fluidised or bouncing).
``rolling-collect-and-collide``
    both end walls hit at least ``impacts_min`` times per cycle, ``swing`` >= ``swing_min``,
    ``sync`` >= ``sync_min``, and the bed centre's phase against the container within
    ``phase_max`` of it (|``phase_deg``| <= 140 deg): the bed crosses the clearance in step with
    the drive, is collected and carried by one wall, released and struck as one block by the
    other, inelastically, once a half cycle (Fig. 3b, Fig. 5).
``swaying``
    the same wall-to-wall motion in step with the drive, but |``phase_deg``| > ``phase_max``:
    the low state near X_opt. The bed stays almost at rest in the lab while the container moves
    about it (in the container frame its centre moves against x_c: phase near -180 deg); the
    walls meet its leading spheres near their turning points, where they barely move, and never
    strike the whole bed. The work the container does on the bed per cycle gives
    eta* = (S/X) |sin(phase)| (S the amplitude of the centre's drive-frequency motion in the
    container frame; within 0.01 of the complex-power eta* in docs/motion.md), so a bed that
    moves as far as the container (S ~ X) but in antiphase dissipates little (eta* 0.1-0.4).
``single-sided``
    one end wall touched in at least ``touch_one`` of the frames and the other in at most
    ``touch_other``, that wall is the low one and the tilt pulls the bed towards it with at least
    ``tilt_pull`` times the container's acceleration amplitude (g_s >= 0.3 A): the tilt keeps the
    bed at (or returning to) the low wall (Sect. 6.2); includes a bed resting on the low wall. An
    untilted bed that merely stays at the wall it started from is ``scattered`` (the paper's
    "almost no particle movement").
``locked``
    ``relative`` <= ``locked_max``: the bed moves with the container, its centre shifting in the
    container by under 5 % of the container's travel; a bed with no room to move (the paper's 48
    spheres filling the floor wall to wall, clearance 0) or held by friction at a small stroke
    (a tilted bed resting on its low wall is ``single-sided``, checked first).
    The container then carries the bed as a rigid mass: the force is the bed mass times the
    container's acceleration, in phase with it, and eta* is near 0 (0.001 measured for 48 spheres
    at X = 13 mm, docs/motion.md).
``scattered``
    anything else with the bed on the floor: the spheres move each their own way, with few wall
    collisions (Fig. 3a), including a bed moving in step in the middle of the container without
    reaching the walls, and one reaching both walls out of step with the drive.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np


__all__ = ["MODES", "THRESHOLDS", "ModeFeatures", "mode_features", "classify_features", "classify_trajectory",
           "case_clearance", "floor_capacity", "bed_centre", "majority_mode", "container_track"]

#: The motion modes, in the order the classifier checks them (plus "unknown" when no trajectory).
MODES = ("lift-off", "rolling-collect-and-collide", "swaying", "single-sided", "locked", "scattered")

#: Thresholds of :func:`classify_features` (see the module docstring; measured in docs/motion.md).
THRESHOLDS = {
    "touch_gap": 0.1,       # a sphere touches an end wall when its gap is below 0.1 r
    "lift_gap": 0.2,        # a sphere is airborne when its centre is more than 0.2 r above y = r
    "lift_fraction": 0.05,  # lift-off: at least 5 % of sphere-frames airborne
    "locked_max": 0.05,     # locked: the bed centre moves in the container by at most 5 % of the container's travel
    "impacts_min": 0.5,     # rolling collect-and-collide: at least 0.5 arrivals per cycle at each end wall
    "swing_min": 0.5,       # ... the bed centre travels at least half the clearance
    "sync_min": 0.7,        # ... at least 70 % of its motion is at the drive frequency
    "phase_max": 140.0,     # ... and it lags the container by at most 140 deg (else: swaying)
    "touch_one": 0.5,       # single-sided: one end wall touched in at least half the frames
    "touch_other": 0.05,    # ... and the other in at most 5 %
    "tilt_pull": 0.3,       # ... the low wall, with the tilt's pull g_s >= 0.3 A (else: scattered)
}


@dataclass(frozen=True)
class ModeFeatures:
    """What :func:`mode_features` measured (see the module docstring for each field)."""

    spread: float
    swing: float
    touch_lo: float
    touch_hi: float
    impacts_lo: float
    impacts_hi: float
    sync: float
    phase_deg: float
    airborne: float
    max_height: float
    tilt_pull: float
    downhill: int
    frames: int
    cycles: float
    relative: float = math.nan

    def to_dict(self) -> dict:
        """Plain dict of floats for JSON."""
        return {k: float(v) if not isinstance(v, int) else v for k, v in asdict(self).items()}


def floor_capacity(case) -> int:
    """N_p,max of eq. (6) for a case: the cuboid's floor lattice of its largest spheres; for the
    cylinder the floor area over (2r)^2, the paper's 48 for R = 39 mm (as the paper counts)."""
    return int(case.container.geometry.clearance_capacity(max(p.radius for p in case.particles)))


def case_clearance(case) -> tuple[float, float]:
    """(L, h) [m] of a case's container: the length along the drive and the clearance of eq. (6)
    with N_p,max from :func:`floor_capacity` (NaN when the bed does not fit in one layer, and
    for a drive with a vertical part, to which the horizontal clearance law does not apply)."""
    from ..theory import clearance

    geo = case.container.geometry
    n_max = floor_capacity(case)
    n = case.n_particles
    length = geo.drive_length
    horizontal = case.drive.vertical_share < 1e-6
    h = float(clearance(length, n, n_max)) if n <= n_max and horizontal else float("nan")
    return float(length), h


def container_track(trajectory: dict, case):
    """The container's track at the trajectory's frames: :func:`pdamper.geometry.track.container_track`
    (imported on use: the geometry package compiles its walls with numba)."""
    from ..geometry.track import container_track as track

    return track(trajectory, case)


def majority_mode(modes) -> tuple[str, bool]:
    """(the mode most of ``modes`` are, whether they disagree) over e.g. the seeds of one stroke;
    empty entries (cases not computed) are left out, ``("", False)`` if nothing is left.

    >>> majority_mode(["scattered", "single-sided", "scattered", ""])
    ('scattered', True)
    """
    from collections import Counter

    counts = Counter(str(m) for m in modes if str(m)).most_common()
    if not counts:
        return "", False
    return counts[0][0], len(counts) > 1


def bed_centre(position, drive_dir=(1.0, 0.0, 0.0)) -> np.ndarray:
    """Bed centre along the drive direction [m] per frame: the mean of the sphere centres' s."""
    d = _unit_horizontal(drive_dir)
    return (np.asarray(position, dtype=float) @ d).mean(axis=1)


def _unit_horizontal(drive_dir) -> np.ndarray:
    d = np.array(drive_dir, dtype=float)
    d[1] = 0.0  # the floor-plane part: the end walls are vertical
    n = np.linalg.norm(d)
    return d / n if n > 0 else np.array([1.0, 0.0, 0.0])


def mode_features(time, position, radius, *, length: float, clearance: float, frequency: float,
                  drive_dir=(1.0, 0.0, 0.0), start_time: float = 0.0, shape=None,
                  gravity_along: float = 0.0, container_position=None,
                  thresholds: dict | None = None) -> ModeFeatures:
    """Measure the bed's motion over the frames at ``time >= start_time``.

    Parameters
    ----------
    time : (F,) frame times [s]; position : (F, N, 3) sphere centres [m], container frame;
    radius : (N,) or scalar [m]; length : L [m], end walls at s = +-L/2 along ``drive_dir``;
    clearance : h [m] (eq. 6); frequency : drive frequency f [Hz];
    drive_dir : drive direction in the container frame (its floor-plane part is used);
    start_time : the transient to leave out [s] (e.g. drop_cycles / f);
    shape : the container shape (:mod:`pdamper.geometry.shape`), which says when a sphere touches
        the wall ahead of (behind) it (a cylinder: the curved wall within 60 deg of the drive
        axis); None: planar end walls across the drive;
    gravity_along : the component of gravity along the drive direction in the container frame
        [m/s^2] (g sin(tilt about z) for the paper's tilt; > 0 pulls towards the +L/2 wall);
    container_position : (F,) or (F, 3) the container's displacement at the frames [m], for its
        acceleration amplitude A = (2 pi f)^2 x half its range (the tilt's pull is |gravity_along| / A).
    """
    th = {**THRESHOLDS, **(thresholds or {})}
    t = np.asarray(time, dtype=float)
    pos = np.asarray(position, dtype=float)
    if pos.ndim != 3 or pos.shape[2] != 3 or pos.shape[0] != t.shape[0]:
        raise ValueError(f"position must be (frames, N, 3) matching time, got {pos.shape} and {t.shape}")
    rad = np.broadcast_to(np.asarray(radius, dtype=float), pos.shape[1])
    keep = t >= start_time - 1e-12
    if keep.sum() < 4:
        keep = np.ones_like(t, dtype=bool)  # too short a run to drop a transient: use it all
    t, pos = t[keep], pos[keep]
    nf = t.shape[0]
    pull, downhill, travel = 0.0, 0, math.nan
    if container_position is not None:
        xc = np.asarray(container_position, dtype=float)
        xc = (xc @ _unit_horizontal(drive_dir) if xc.ndim == 2 else xc)[keep]
        travel = float(np.percentile(xc, 95) - np.percentile(xc, 5)) if xc.size else math.nan
        if gravity_along != 0.0:
            accel = (2 * math.pi * frequency) ** 2 * 0.5 * float(np.ptp(xc)) if xc.size else 0.0
            pull = abs(gravity_along) / accel if accel > 0 else math.inf
            downhill = 1 if gravity_along > 0 else -1
    if nf < 2:
        raise ValueError(f"a motion mode needs at least 2 trajectory frames, got {nf}; record more frames "
                         "(a higher trajectory_fps or a longer run)")
    d = _unit_horizontal(drive_dir)
    s = pos @ d                                   # (F, N) along the drive
    centre = s.mean(axis=1)
    compact = max(length - clearance, 2 * float(rad.max())) / math.sqrt(12.0)
    spread = float(np.median(s.std(axis=1)) / compact)
    h = clearance if clearance > 0 else 2 * float(rad.max())
    centre_range = float(np.percentile(centre, 95) - np.percentile(centre, 5))
    swing = centre_range / h
    relative = centre_range / travel if travel > 0 else math.nan
    gap = th["touch_gap"] * rad
    if shape is None:
        from ..geometry.shape import ShapeBase  # (planar end walls; imported here: geometry compiles)

        shape = ShapeBase()
    on_lo, on_hi = shape.end_contacts(pos, rad, s, length, gap)
    dt = float(np.median(np.diff(t))) if nf > 1 else 0.0
    cycles = max((t[-1] - t[0] + dt) * frequency, 1e-12)

    def arrivals(on):
        return float(np.count_nonzero(on[1:] & ~on[:-1]) / cycles)

    n_whole = int(math.floor(cycles + 1e-9))
    # the drive-frequency share of the centre's variance, over whole cycles
    sync, phase = 0.0, float("nan")
    if n_whole >= 1 and nf >= 4:
        sel = t <= t[0] - dt / 2 + n_whole / frequency
        c = centre[sel] - centre[sel].mean()
        w = 2 * math.pi * frequency * t[sel]
        a = 2 * np.mean(c * np.sin(w))
        b = 2 * np.mean(c * np.cos(w))
        var = float(np.mean(c * c))
        sync = float(min(1.0, 0.5 * (a * a + b * b) / var)) if var > 0 else 0.0
        phase = float(math.degrees(math.atan2(b, a)))  # centre ~ A sin(wt + phase)
    y = pos[:, :, 1]
    height = (y - rad) / rad
    airborne = float(np.mean(height > th["lift_gap"]))
    return ModeFeatures(spread=spread, swing=swing, touch_lo=float(on_lo.mean()), touch_hi=float(on_hi.mean()),
                        impacts_lo=arrivals(on_lo), impacts_hi=arrivals(on_hi), sync=sync, phase_deg=phase,
                        airborne=airborne, max_height=float(height.max()), tilt_pull=float(pull),
                        downhill=int(downhill), frames=int(nf), cycles=float(cycles), relative=float(relative))


def classify_features(f: ModeFeatures, thresholds: dict | None = None) -> str:
    """The motion mode (one of :data:`MODES`) of measured features (see the module docstring)."""
    th = {**THRESHOLDS, **(thresholds or {})}
    if f.airborne >= th["lift_fraction"]:
        return "lift-off"
    if (min(f.impacts_lo, f.impacts_hi) >= th["impacts_min"] and f.swing >= th["swing_min"]
            and f.sync >= th["sync_min"]):
        if abs(f.phase_deg) <= th["phase_max"]:
            return "rolling-collect-and-collide"
        return "swaying"
    hi, lo = max(f.touch_lo, f.touch_hi), min(f.touch_lo, f.touch_hi)
    low_wall = f.touch_hi if f.downhill > 0 else f.touch_lo
    if (hi >= th["touch_one"] and lo <= th["touch_other"] and f.downhill != 0 and low_wall == hi
            and f.tilt_pull >= th["tilt_pull"]):
        return "single-sided"
    if f.relative <= th["locked_max"]:  # False for NaN (no container track)
        return "locked"
    return "scattered"


def classify_trajectory(trajectory: dict, case, *, thresholds: dict | None = None) -> tuple[str, ModeFeatures]:
    """(mode, features) of a recorded trajectory (``time``, ``position``, ``radius``) of ``case``
    (a :class:`pdamper.params.Case`: container, drive and the transient ``drop_cycles`` to skip)."""
    from ..geometry.tilt import container_vectors

    length, h = case_clearance(case)
    drive = case.drive
    freq = float(drive.frequency or 0.0)
    if freq <= 0:
        raise ValueError("motion modes need a periodic drive with a frequency")
    gvec, dvec = container_vectors(case.container.tilt, case.gravity, drive.lab_direction())
    off, _, _ = container_track(trajectory, case)
    feats = mode_features(trajectory["time"], trajectory["position"], trajectory["radius"], length=length,
                          clearance=h, frequency=freq, drive_dir=dvec, start_time=case.drop_cycles / freq,
                          shape=case.container.geometry,
                          gravity_along=float(gvec @ _unit_horizontal(dvec)), container_position=off,
                          thresholds=thresholds)
    return classify_features(feats, thresholds), feats
