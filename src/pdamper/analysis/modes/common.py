"""What every motion-mode family shares (:mod:`pdamper.analysis.modes`): the registry of the families,
the one table of thresholds their tables fill, what the case says (its clearance, its floor's
capacity), the measurements on a trajectory more than one family makes (the frames analysed, wall
arrivals, the share of a motion at the drive frequency, flights from the floor) and the base of
every family's features.

A family is a :class:`ModeFamily` registered with :func:`register_family` by its own module
(:mod:`.horizontal`, :mod:`.vertical`, :mod:`.compartments`): its names, which of them are the
efficient collect-and-collide ones, the thresholds its rules bring, whether it applies to a case,
how it measures a trajectory of one and how it says in one line what it measured.
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import asdict, dataclass
from typing import Callable, ClassVar

import numpy as np

__all__ = ["ModeFamily", "FAMILIES", "register_family", "THRESHOLDS", "MODE_FRAMES_PER_CYCLE", "mode_fps",
           "floor_capacity", "case_clearance", "vertical_clearance", "container_track", "majority_mode", "bed_centre",
           "floor_flights", "describe_features", "Features"]

#: The classifiers' thresholds (the module docstrings of the families; measured in docs/motion.md): those
#: of the measurements here, then each family's in the order the families register (one table: a
#: family's thresholds join it when its module registers the family, and none may be given twice).
THRESHOLDS = {
    "touch_gap": 0.1,       # a sphere touches a wall (or a sphere below it) when its gap is below 0.1 r
    "lift_gap": 0.2,        # a sphere is off the floor when its bottom is more than 0.2 r above it
    "lift_time": 0.05,      # ... a flight from the floor lasts at least 0.05 cycle (and 2 frames)
}


@dataclass(frozen=True)
class ModeFamily:
    """One family of motion-mode names: the table its module registers (:func:`register_family`).

    Attributes
    ----------
    name : str
        The family (``features.family``, a run's ``mode_features["family"]``).
    modes : tuple of str
        The names it gives that it introduces, in the order its rules check them (a family may also
        give another's names: a baffled bed's compartment is named as a horizontal bed).
    collide : tuple of str
        Those of ``modes`` that are the efficient collect-and-collide motion (the effective fields'
        "collide" family, :func:`pdamper.analysis.fields.mode_family`).
    thresholds : dict
        The thresholds its rules bring (name -> value), joined to :data:`THRESHOLDS`.
    applies : callable
        ``applies(case, thresholds) -> bool``: whether its names are the case's (asked in the
        order of :data:`pdamper.analysis.modes.CHOICE`).
    measure : callable
        ``measure(trajectory, case, gravity, direction, common) -> features``: its features of a
        recorded trajectory of the case (``gravity``, ``direction``: in the container frame;
        ``common``: the keyword arguments every family's measuring function takes).
    describe : callable
        ``describe(features_dict) -> str``: one line of what a mode was judged on.
    """

    name: str
    modes: tuple
    collide: tuple
    thresholds: dict
    applies: Callable
    measure: Callable
    describe: Callable


#: The registered families by name, in the order they registered.
FAMILIES: dict[str, ModeFamily] = {}


def register_family(family: ModeFamily) -> ModeFamily:
    """Register ``family`` (its module calls this once); its thresholds join :data:`THRESHOLDS`."""
    again = [k for k in family.thresholds if k in THRESHOLDS]
    if again:
        raise ValueError(f"mode family {family.name!r}: thresholds {again} are already given by another family; "
                         "use theirs")
    if not set(family.collide) <= set(family.modes):
        raise ValueError(f"mode family {family.name!r}: collide modes {family.collide} are not among its modes")
    THRESHOLDS.update(family.thresholds)
    FAMILIES[family.name] = family
    return family


#: The classification's coarse trajectory records at least this many frames per drive cycle
#: (:func:`mode_fps`; 50 frames/s up to 2 Hz).
MODE_FRAMES_PER_CYCLE = 25.0


def mode_fps(frequency: float, sample_rate: float, base: float = 50.0) -> float:
    """Frames per second of the trajectory a run records to classify its mode: ``base`` (50, the
    paper's 2 Hz cases), more at higher drive frequencies (:data:`MODE_FRAMES_PER_CYCLE` a cycle,
    e.g. 375 at 15 Hz), at most ``sample_rate``.

    >>> mode_fps(2.0, 1000.0), mode_fps(15.0, 1000.0), mode_fps(60.0, 1000.0)
    (50.0, 375.0, 1000.0)
    """
    return float(min(max(base, MODE_FRAMES_PER_CYCLE * float(frequency or 0.0)), sample_rate))


# --------------------------------------------------------------------------- what the case says

def _largest_radius(case) -> float:
    return float(max(p.radius for p in case.particles))


def floor_capacity(case) -> int:
    """N_p,max of eq. (6) for a case: the cuboid's floor lattice of its largest spheres; for the
    cylinder the floor area over (2r)^2, the paper's 48 for R = 39 mm (as the paper counts)."""
    return int(case.container.geometry.clearance_capacity(_largest_radius(case)))


def case_clearance(case) -> tuple[float, float]:
    """(L, h) [m] of a case's container: the length along the drive and the clearance of eq. (6)
    with N_p,max from :func:`floor_capacity` (NaN when the bed does not fit in one layer, and
    for a drive with a vertical part, to which the horizontal clearance law does not apply)."""
    from ...theory import clearance

    geo = case.container.geometry
    n_max = floor_capacity(case)
    n = case.n_particles
    length = geo.drive_length
    horizontal = case.drive.vertical_share < 1e-6
    h = float(clearance(length, n, n_max)) if n <= n_max and horizontal else float("nan")
    return float(length), h


def vertical_clearance(case) -> tuple[float, float]:
    """(H, h_v) [m]: the container's inner height (floor to lid) and the free height above a bed of
    n_layers = ceil(N / N_p,max) layers, h_v = H - 2 r n_layers (r the largest radius)."""
    lo, hi = case.container.geometry.bounding_box()
    height = float(hi[1] - lo[1])
    layers = math.ceil(case.n_particles / max(floor_capacity(case), 1))
    return height, height - 2 * _largest_radius(case) * layers


def container_track(trajectory: dict, case):
    """The container's track at the trajectory's frames: :func:`pdamper.geometry.track.container_track`
    (imported on use: the geometry package compiles its walls with numba)."""
    from ...geometry.track import container_track as track

    return track(trajectory, case)


def majority_mode(modes) -> tuple[str, bool]:
    """(the mode most of ``modes`` are, whether they disagree) over e.g. the seeds of one stroke;
    empty entries (cases not computed) are left out, ``("", False)`` if nothing is left.

    >>> majority_mode(["scattered", "single-sided", "scattered", ""])
    ('scattered', True)
    """
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


# --------------------------------------------------------------------------- shared measurements

def _prepare(time, position, radius, start_time: float):
    """(t, pos, rad, keep) of the analysed frames (``time >= start_time``; all when fewer than 4)."""
    t = np.asarray(time, dtype=float)
    pos = np.asarray(position, dtype=float)
    if pos.ndim != 3 or pos.shape[2] != 3 or pos.shape[0] != t.shape[0]:
        raise ValueError(f"position must be (frames, N, 3) matching time, got {pos.shape} and {t.shape}")
    rad = np.broadcast_to(np.asarray(radius, dtype=float), pos.shape[1])
    keep = t >= start_time - 1e-12
    if keep.sum() < 4:
        keep = np.ones_like(t, dtype=bool)  # too short a run to drop a transient: use it all
    if keep.sum() < 2:
        raise ValueError(f"a motion mode needs at least 2 trajectory frames, got {int(keep.sum())}; record more "
                         "frames (a higher trajectory_fps or a longer run)")
    return t[keep], pos[keep], rad, keep


def _frame_step(t) -> float:
    return float(np.median(np.diff(t))) if t.size > 1 else 0.0


def _cycles(t, frequency: float) -> float:
    return max((t[-1] - t[0] + _frame_step(t)) * frequency, 1e-12)


def _arrivals(on, cycles: float) -> float:
    """Arrivals per cycle: frames where ``on`` starts after a frame where it was off."""
    return float(np.count_nonzero(on[1:] & ~on[:-1]) / cycles)


def _drive_share(t, centre, frequency: float) -> tuple[float, float]:
    """(share of the variance of ``centre`` at the drive frequency over whole cycles, its phase
    [deg] against sin(Omega t)); (0, NaN) without a whole cycle."""
    dt = _frame_step(t)
    n_whole = int(math.floor(_cycles(t, frequency) + 1e-9))
    if n_whole < 1 or t.size < 4:
        return 0.0, float("nan")
    sel = t <= t[0] - dt / 2 + n_whole / frequency
    c = centre[sel] - centre[sel].mean()
    w = 2 * math.pi * frequency * t[sel]
    a = 2 * np.mean(c * np.sin(w))
    b = 2 * np.mean(c * np.cos(w))
    var = float(np.mean(c * c))
    sync = float(min(1.0, 0.5 * (a * a + b * b) / var)) if var > 0 else 0.0
    return sync, float(math.degrees(math.atan2(b, a)))  # centre ~ A sin(wt + phase)


def _travel(container_position, keep, direction) -> np.ndarray | None:
    """The container's displacement along ``direction`` at the analysed frames (None without it)."""
    if container_position is None:
        return None
    xc = np.asarray(container_position, dtype=float)
    return (xc @ np.asarray(direction, dtype=float) if xc.ndim == 2 else xc)[keep]


def _range(x) -> float:
    return float(np.percentile(x, 95) - np.percentile(x, 5)) if np.size(x) else math.nan


def _shape_or_planar(shape):
    if shape is None:
        from ...geometry.shape import ShapeBase  # (planar end walls; imported here: geometry compiles)

        return ShapeBase()
    return shape


def floor_flights(time, position, radius, *, frequency: float, thresholds: dict | None = None) -> tuple[float, float]:
    """(airborne, raised): the fraction of sphere-frames in **flights from the floor**, and the
    fraction with the sphere's bottom above the floor for any reason.

    A sphere is *on the floor* in a frame when its bottom (y - r) is within ``lift_gap`` x r of it;
    *supported* when it is not, but a sphere below it touches it (centre distance within the two
    radii plus ``touch_gap`` x the smaller radius, the line of centres at least 30 deg above the
    horizontal: riding on the layer, pushed up over a neighbour); *flying* otherwise. A flight
    from the floor is a run of consecutive flying frames right after a frame on the floor that
    lasts at least ``lift_time`` drive cycles and at least 2 frames; its frames count as airborne.
    (The frame before the run is on the floor: a sphere hopping off its neighbours' tops did not
    leave the floor.)
    """
    from scipy.spatial import cKDTree

    th = {**THRESHOLDS, **(thresholds or {})}
    t = np.asarray(time, dtype=float)
    pos = np.asarray(position, dtype=float)
    rad = np.broadcast_to(np.asarray(radius, dtype=float), pos.shape[1])
    if pos.shape[0] == 0 or pos.shape[1] == 0:
        return 0.0, 0.0
    low = (pos[:, :, 1] - rad) <= th["lift_gap"] * rad
    raised = float(np.mean(~low))
    if raised == 0.0 or pos.shape[0] < 2:
        return 0.0, raised
    reach = 2 * float(rad.max()) + th["touch_gap"] * float(rad.min())
    flying = np.zeros_like(low)
    for k in np.flatnonzero(~low.all(axis=1)):
        p = pos[k]
        pairs = cKDTree(p).query_pairs(reach, output_type="ndarray")
        pairs = np.concatenate([pairs, pairs[:, ::-1]])          # (upper, lower) both ways round
        up, below = pairs[:, 0], pairs[:, 1]
        gap = np.linalg.norm(p[up] - p[below], axis=1) - rad[up] - rad[below]
        # below it: touching, the line of centres at least 30 deg above the horizontal (a neighbour
        # beside it pushes it sideways, it does not carry it)
        carries = ((gap <= th["touch_gap"] * np.minimum(rad[up], rad[below]))
                   & (p[up, 1] - p[below, 1] >= 0.5 * (rad[up] + rad[below])))
        carried = np.zeros(p.shape[0], dtype=bool)
        carried[up[carries]] = True
        flying[k] = ~low[k] & ~carried
    step = _frame_step(t)
    shortest = max(2, math.ceil(th["lift_time"] / (frequency * step) - 1e-9)) if frequency * step > 0 else 2
    counted = np.zeros_like(flying)
    for i in np.flatnonzero(flying.any(axis=0)):
        f = np.concatenate([[False], flying[:, i], [False]])
        starts = np.flatnonzero(f[1:] & ~f[:-1])       # first flying frame of each run
        ends = np.flatnonzero(~f[1:] & f[:-1])         # one past its last
        for a, b in zip(starts, ends):
            if a > 0 and low[a - 1, i] and b - a >= shortest:
                counted[a:b, i] = True
    return float(np.mean(counted)), raised

class Features:
    """What every family's features answer: their ``family``, a plain dict and one line."""

    family: ClassVar[str] = ""

    def to_dict(self) -> dict:
        """Plain dict of floats for JSON, with the ``family``."""
        out = {k: float(v) if not isinstance(v, int) else v for k, v in asdict(self).items()}
        return {"family": self.family, **out}

    def describe(self) -> str:
        """One line for ``pdamper run`` (:func:`describe_features`)."""
        return describe_features(self.to_dict())


def describe_features(features: dict) -> str:
    """One line of what a mode was judged on, from a features dict (``to_dict`` of any family, as a
    run's summary stores it); "" for an empty one (a summary without ``family`` is horizontal: older runs)."""
    if not features:
        return ""
    return FAMILIES[features.get("family", "horizontal")].describe(features)
