"""Motion modes of the particle bed from its trajectory (the paper's Figs. 2, 3, 5 and Sect. 6.2; docs/motion.md).

Pure functions on trajectory arrays in the **container frame** (x along the container's length,
y up from the floor, z across), as :class:`pdamper.simulation.RunResult` records them; they know
nothing of the simulator. Three families of names, one per kind of bed motion; which one applies
is asked of the case (:func:`family_of`): the drive's direction against gravity
(``drive.vertical_share``) and the container's floor sections (``container.compartments``).

- **horizontal** (:func:`mode_features`, :class:`ModeFeatures`): a drive within 45 deg of the
  floor plane moving one bed along the floor: ``lift-off``, ``rolling-collect-and-collide``,
  ``swaying``, ``single-sided``, ``locked``, ``scattered``.
- **compartments** (:func:`compartment_features`, :class:`CompartmentFeatures`): the same drive
  with baffles that split the floor into sections along x; each section's bed gets a horizontal
  name, the container ``compartment-collect-and-collide`` when most spheres are in sections that
  collect and collide (Meyer & Seifried, Granular Matter 25 (2023) 20: each compartment's bed
  collects and collides on its own).
- **vertical** (:func:`vertical_features`, :class:`VerticalFeatures`): a drive within 45 deg of
  gravity: ``locked``, ``bouncing-collect-and-collide``, ``bouncing-bed``, ``fluidised``.

Each features object classifies itself (``f.classify(thresholds)``; :func:`classify_features`)
with the thresholds of :data:`THRESHOLDS` (their measurements are in docs/motion.md).

Horizontal features (``s`` is a sphere centre's coordinate along the drive direction, the two
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
- ``airborne``: the fraction of sphere-frames in **flights from the floor** (:func:`floor_flights`):
  a sphere that was on the floor (its bottom within ``lift_gap`` x r of it) leaves it, its bottom
  more than ``lift_gap`` x r above the floor with nothing under it (no sphere below it within
  ``touch_gap`` x r, the line of centres at least 30 deg above the horizontal), for at least
  ``lift_time`` cycles and 2 frames. A sphere squeezed up onto its neighbours
  in a collision, riding on the layer or hopping on top of it, has not left the floor.
- ``raised``: the fraction of sphere-frames with the bottom more than ``lift_gap`` x r above the
  floor for any reason (riding on neighbours included; the measure the ``lift-off`` rule used
  before, reported, not used); ``max_height``: the largest (y - r)/r.
- ``relative``: the range (5th to 95th percentile) of the bed centre in the container frame over
  that of the container's own position in the lab (NaN without the container's track): ~0 when
  the bed moves with the container, ~1 and more when the container moves about it.
- ``tilt_pull``: |g_s| / A, the pull of gravity along the drive (from the tilt) over the
  container's measured acceleration amplitude; ``downhill``: +1 if it pulls towards +L/2, -1
  towards -L/2, 0 without a pull.

Horizontal modes (:meth:`ModeFeatures.classify`, checked in this order):

``lift-off``
    ``airborne`` >= ``lift_fraction``: spheres leave the floor (container acceleration near or
    above g, impacts throwing spheres up; fluidised or bouncing). Not given for spheres that
    only ride on their neighbours (36 spheres at 24 mm, 2.4 Hz, A = 0.56 g: docs/motion.md).
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

Vertical features and modes (:meth:`VerticalFeatures.classify`): the floor at y = 0, the lid at
y = H, the bed centre Y = mean(y), the free height h_v = H - 2 r n_layers (n_layers = N over the
floor's one-layer capacity, rounded up). The regimes are those of vertically shaken beds in
particle dampers: the **bouncing bed** that leaves the floor as one block and lands (Sanchez,
Rosenthal & Pugnaloni, J. Sound Vib. 331 (2012) 4389; Ansari & Alam, Phys. Rev. E 93 (2016)
052901: solid bed, bouncing bed, Leidenfrost state, convection, gas), the **collect-and-collide**
motion in which the bed is gathered at one wall and strikes the opposite one as a group once a
cycle, the regime of the optimal damper (Bannerman et al., Phys. Rev. E 84 (2011) 011301; Sack et
al., Granular Matter 22 (2020) 12), and the **gas-like**, fluidised bed whose spheres move each on
its own, nearly independent of the drive phase (Sack et al. 2020).

- ``floor_touch``, ``lid_touch``: fraction of frames a sphere is within ``touch_gap`` x r of the
  floor / the lid; ``floor_impacts``, ``lid_impacts``: arrivals per cycle.
- ``swing``: range (5th to 95th percentile) of Y over h_v (reported, not used: a flying bed is
  dilated, its centre travels less than h_v); ``sync``, ``phase_deg``: as above, of Y.
- ``coherence``: var(Y) over the mean of the spheres' var(y): 1 for a rigid block, ~1/N for
  spheres moving independently.
- ``relative``: range of Y over the container's travel along the drive (0: moves with it).

``locked`` (``relative`` <= ``locked_max``: the bed rests on the floor and moves with the
container, the solid bed below 1 g); ``fluidised`` when the bed as a whole does not leave the
floor (a sphere on it in more than 1 - ``flight_min`` of the frames) while it moves about the
container: its spheres fly each on its own from a bed that stays on the floor (the gas-like state;
the Leidenfrost and convective states are not told apart here); ``bouncing-collect-and-collide``
when the bed leaves the floor (no sphere on it in at least ``flight_min`` of the frames), floor and
lid are each reached ``impacts_min`` times a cycle and the bed centre moves in step with the drive
(``sync`` >= ``sync_min``): it is thrown from the floor to the lid and back once a cycle;
``bouncing-bed`` when it leaves the floor as one block (``coherence`` >= ``coherence_min``) but
does not strike the lid each cycle in step (it lands once a cycle or every few cycles);
``fluidised`` otherwise (a bed off the floor that is no block and not in step).
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import asdict, dataclass
from typing import ClassVar

import numpy as np

from .._deprecated import renamed_function

__all__ = ["MODES", "HORIZONTAL_MODES", "VERTICAL_MODES", "COMPARTMENT_MODES", "COLLIDE_MODES", "THRESHOLDS",
           "MODE_FRAMES_PER_CYCLE", "ModeFeatures", "VerticalFeatures", "CompartmentFeatures", "mode_features",
           "vertical_features", "compartment_features", "floor_flights", "classify_features", "classify_trajectory",
           "family_of", "mode_fps", "describe_features", "case_clearance", "vertical_clearance", "floor_capacity",
           "bed_centre", "majority_mode", "container_track"]

#: The names of a bed moved along the floor, in the order the classifier checks them.
HORIZONTAL_MODES = ("lift-off", "rolling-collect-and-collide", "swaying", "single-sided", "locked", "scattered")
#: The names of a bed shaken along gravity (``locked`` as in the horizontal family).
VERTICAL_MODES = ("locked", "bouncing-collect-and-collide", "bouncing-bed", "fluidised")
#: The name of a baffled bed whose compartments collect and collide (the others: horizontal names).
COMPARTMENT_MODES = ("compartment-collect-and-collide",)
#: Every motion mode (plus "unknown" when no trajectory).
MODES = HORIZONTAL_MODES + tuple(m for m in VERTICAL_MODES + COMPARTMENT_MODES if m not in HORIZONTAL_MODES)
#: The efficient modes: the bed (or each compartment's bed) collected at one wall and striking the
#: other as a group in step with the drive (the effective fields' "collide" family).
COLLIDE_MODES = ("rolling-collect-and-collide", "bouncing-collect-and-collide", "compartment-collect-and-collide")

#: Thresholds of the classifiers (see the module docstring; measured in docs/motion.md).
THRESHOLDS = {
    "touch_gap": 0.1,       # a sphere touches a wall (or a sphere below it) when its gap is below 0.1 r
    "lift_gap": 0.2,        # a sphere is off the floor when its bottom is more than 0.2 r above it
    "lift_time": 0.05,      # ... a flight from the floor lasts at least 0.05 cycle (and 2 frames)
    "lift_fraction": 0.05,  # lift-off: at least 5 % of sphere-frames in flights from the floor
    "locked_max": 0.05,     # locked: the bed centre moves in the container by at most 5 % of the container's travel
    "impacts_min": 0.5,     # collect-and-collide: at least 0.5 arrivals per cycle at each of the two walls
    "swing_min": 0.5,       # ... the bed centre travels at least half the clearance
    "sync_min": 0.7,        # ... at least 70 % of its motion is at the drive frequency
    "phase_max": 140.0,     # ... and (horizontal) it lags the container by at most 140 deg (else: swaying)
    "touch_one": 0.5,       # single-sided: one end wall touched in at least half the frames
    "touch_other": 0.05,    # ... and the other in at most 5 %
    "tilt_pull": 0.3,       # ... the low wall, with the tilt's pull g_s >= 0.3 A (else: scattered)
    "vertical_share": math.sqrt(0.5),  # the vertical family: the drive within 45 deg of gravity
    "flight_min": 0.25,     # vertical: the bed leaves the floor, none of its spheres on it in >= 25 % of the frames
    "coherence_min": 0.45,  # bouncing bed: ... and moves as one block, var(Y) >= 0.45 x the spheres' mean var(y)
}

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

def family_of(case, thresholds: dict | None = None) -> str:
    """Which family of names applies to ``case``: ``"vertical"`` when its drive is within 45 deg of
    gravity (``drive.vertical_share`` >= cos 45 deg), ``"compartments"`` when baffles split the
    floor into sections along x (``container.compartments``) and the drive moves the bed across
    them (within 45 deg of x), ``"horizontal"`` otherwise."""
    th = {**THRESHOLDS, **(thresholds or {})}
    if case.drive.vertical_share >= th["vertical_share"]:
        return "vertical"
    d = np.asarray(case.drive.lab_direction(), dtype=float)
    across = abs(float(d[0])) >= th["vertical_share"] * math.hypot(float(d[0]), float(d[2]))
    if across and len(case.container.compartments(_largest_radius(case))) > 1:
        return "compartments"
    return "horizontal"


#: The old name of :func:`family_of` (warns; docs/names.md): :func:`pdamper.analysis.fields.mode_family`
#: is the family of a mode ("collide", "other"), a different thing.
mode_family = renamed_function(family_of, "mode_family")


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
    from ..theory import clearance

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
    from ..geometry.track import container_track as track

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


class _Features:
    """What every family's features answer: their ``family``, a plain dict and one line."""

    family: ClassVar[str] = ""

    def to_dict(self) -> dict:
        """Plain dict of floats for JSON, with the ``family``."""
        out = {k: float(v) if not isinstance(v, int) else v for k, v in asdict(self).items()}
        return {"family": self.family, **out}

    def describe(self) -> str:
        """One line for ``pdamper run`` (:func:`describe_features`)."""
        return describe_features(self.to_dict())


# --------------------------------------------------------------------------- horizontal family

@dataclass(frozen=True)
class ModeFeatures(_Features):
    """What :func:`mode_features` measured (see the module docstring for each field)."""

    family: ClassVar[str] = "horizontal"

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
    raised: float = math.nan

    def classify(self, thresholds: dict | None = None) -> str:
        """The horizontal mode (the module docstring's rules, in order)."""
        th = {**THRESHOLDS, **(thresholds or {})}
        if self.airborne >= th["lift_fraction"]:
            return "lift-off"
        return self.floor_mode(th)

    def floor_mode(self, thresholds: dict | None = None) -> str:
        """The mode of a bed on the floor: every horizontal rule but ``lift-off``."""
        th = {**THRESHOLDS, **(thresholds or {})}
        if (min(self.impacts_lo, self.impacts_hi) >= th["impacts_min"] and self.swing >= th["swing_min"]
                and self.sync >= th["sync_min"]):
            if abs(self.phase_deg) <= th["phase_max"]:
                return "rolling-collect-and-collide"
            return "swaying"
        hi, lo = max(self.touch_lo, self.touch_hi), min(self.touch_lo, self.touch_hi)
        low_wall = self.touch_hi if self.downhill > 0 else self.touch_lo
        if (hi >= th["touch_one"] and lo <= th["touch_other"] and self.downhill != 0 and low_wall == hi
                and self.tilt_pull >= th["tilt_pull"]):
            return "single-sided"
        if self.relative <= th["locked_max"]:  # False for NaN (no container track)
            return "locked"
        return "scattered"


def _line_features(t, centre, spread, rad, on_lo, on_hi, *, length: float, clearance: float, frequency: float,
                   travel, gravity_along: float) -> dict:
    """The horizontal features of one bed along one line: ``centre`` and ``spread`` (F,) the mean
    and std of its spheres' coordinates along the line, from the middle of the section ``length``
    long; ``on_lo``/``on_hi`` (F,) its end-wall contacts; ``travel`` (F,) the container's
    displacement along the line (or None)."""
    compact = max(length - clearance, 2 * float(rad.max())) / math.sqrt(12.0)
    h = clearance if clearance > 0 else 2 * float(rad.max())
    centre_range = _range(centre)
    pull, downhill, moved = 0.0, 0, math.nan
    if travel is not None:
        moved = _range(travel)
        if gravity_along != 0.0:
            accel = (2 * math.pi * frequency) ** 2 * 0.5 * float(np.ptp(travel)) if travel.size else 0.0
            pull = abs(gravity_along) / accel if accel > 0 else math.inf
            downhill = 1 if gravity_along > 0 else -1
    cycles = _cycles(t, frequency)
    sync, phase = _drive_share(t, centre, frequency)
    return dict(spread=float(np.median(spread)) / compact, swing=centre_range / h,
                touch_lo=float(on_lo.mean()), touch_hi=float(on_hi.mean()), impacts_lo=_arrivals(on_lo, cycles),
                impacts_hi=_arrivals(on_hi, cycles), sync=sync, phase_deg=phase, tilt_pull=float(pull),
                downhill=int(downhill), frames=int(t.size), cycles=float(cycles),
                relative=float(centre_range / moved) if moved > 0 else math.nan)


def _shape_or_planar(shape):
    if shape is None:
        from ..geometry.shape import ShapeBase  # (planar end walls; imported here: geometry compiles)

        return ShapeBase()
    return shape


def mode_features(time, position, radius, *, length: float, clearance: float, frequency: float,
                  drive_dir=(1.0, 0.0, 0.0), start_time: float = 0.0, shape=None,
                  gravity_along: float = 0.0, container_position=None,
                  thresholds: dict | None = None) -> ModeFeatures:
    """Measure the bed's motion along the floor over the frames at ``time >= start_time``.

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
    t, pos, rad, keep = _prepare(time, position, radius, start_time)
    d = _unit_horizontal(drive_dir)
    s = pos @ d                                   # (F, N) along the drive
    on_lo, on_hi = _shape_or_planar(shape).end_contacts(pos, rad, s, length, th["touch_gap"] * rad)
    line = _line_features(t, s.mean(axis=1), s.std(axis=1), rad, on_lo, on_hi, length=length, clearance=clearance, frequency=frequency,
                          travel=_travel(container_position, keep, d), gravity_along=gravity_along)
    airborne, raised = floor_flights(t, pos, rad, frequency=frequency, thresholds=th)
    height = (pos[:, :, 1] - rad) / rad
    return ModeFeatures(**line, airborne=airborne, raised=raised, max_height=float(height.max()))


# --------------------------------------------------------------------------- compartments

@dataclass(frozen=True)
class CompartmentFeatures(_Features):
    """What :func:`compartment_features` measured: the whole bed's flights from the floor and, per
    section of the floor (``sections`` [(a, b)] [m] along x), the spheres in it (median over
    frames) and its bed's horizontal features."""

    family: ClassVar[str] = "compartments"

    sections: tuple
    spheres: tuple
    compartments: tuple
    airborne: float
    raised: float
    max_height: float
    frames: int
    cycles: float

    def modes(self, thresholds: dict | None = None) -> list[str]:
        """The mode of each section's bed on the floor (:meth:`ModeFeatures.floor_mode`; "" when empty)."""
        return [f.floor_mode(thresholds) if f is not None else "" for f in self.compartments]

    def classify(self, thresholds: dict | None = None) -> str:
        """``lift-off`` as for one bed; else the mode of most spheres' sections,
        ``compartment-collect-and-collide`` where that is rolling collect-and-collide."""
        th = {**THRESHOLDS, **(thresholds or {})}
        if self.airborne >= th["lift_fraction"]:
            return "lift-off"
        weight = Counter()
        for m, n in zip(self.modes(th), self.spheres):
            if m:
                weight[m] += n
        if not weight:
            return "scattered"
        order = {m: k for k, m in enumerate(HORIZONTAL_MODES)}
        top = max(weight.values())
        mode = min((m for m, n in weight.items() if n == top), key=lambda m: order.get(m, len(order)))
        return "compartment-collect-and-collide" if mode == "rolling-collect-and-collide" else mode

    def to_dict(self) -> dict:
        """Plain dict for JSON: the ``family``, each section's mode, spheres and features."""
        return {"family": self.family, "sections_m": [list(map(float, s)) for s in self.sections],
                "spheres": [int(n) for n in self.spheres], "compartment_modes": self.modes(),
                "compartments": [f.to_dict() if f is not None else {} for f in self.compartments],
                "airborne": float(self.airborne), "raised": float(self.raised), "max_height": float(self.max_height),
                "frames": int(self.frames), "cycles": float(self.cycles)}


def compartment_features(time, position, radius, *, sections, spheres_per_length: float, frequency: float,
                         start_time: float = 0.0, shape=None, length: float | None = None,
                         gravity_along: float = 0.0, container_position=None,
                         thresholds: dict | None = None) -> CompartmentFeatures:
    """Measure a baffled bed section by section: the spheres whose centres lie in a section
    ``(a, b)`` [m] along x form its bed (per frame); each is measured as a bed along x between the
    section's ends (:func:`mode_features`' quantities) with the clearance of eq. (6) taken per
    section, h = (b - a) - n / ``spheres_per_length`` (n its spheres, median over frames;
    ``spheres_per_length`` = N_p,max / L of the container). A section's end that is the
    container's end wall is asked of ``shape`` (``length``: the container's length along x); a
    baffle's face is a plane across x."""
    th = {**THRESHOLDS, **(thresholds or {})}
    t, pos, rad, keep = _prepare(time, position, radius, start_time)
    x = pos[:, :, 0]
    gap = th["touch_gap"] * rad
    travel = _travel(container_position, keep, (1.0, 0.0, 0.0))
    sections = [tuple(map(float, s)) for s in sections]
    x_lo, x_hi = sections[0][0], sections[-1][1]
    length = float(length if length is not None else x_hi - x_lo)
    shape = _shape_or_planar(shape)
    feats, counts = [], []
    for a, b in sections:
        member = (x >= a) & (x <= b)
        n = int(round(float(np.median(member.sum(axis=1)))))
        counts.append(n)
        if n == 0:
            feats.append(None)
            continue
        # the section's spheres at their places, the others out of the way (the floor's middle)
        away = np.where(member[:, :, None], pos, np.array([0.0, float(rad.max()), 0.0]))
        wall_lo, wall_hi = shape.end_contacts(away, rad, np.where(member, x, 0.0), length, gap)
        on_lo = wall_lo if a <= x_lo else np.any(member & (x - rad <= a + gap), axis=1)
        on_hi = wall_hi if b >= x_hi else np.any(member & (x + rad >= b - gap), axis=1)
        count = np.maximum(member.sum(axis=1), 1)
        centre = np.where(member, x, 0.0).sum(axis=1) / count          # the section's bed, frame by frame
        spread = np.sqrt(np.where(member, (x - centre[:, None]) ** 2, 0.0).sum(axis=1) / count)
        line = _line_features(t, centre - 0.5 * (a + b), spread, rad, on_lo, on_hi, length=b - a,
                              clearance=(b - a) - n / spheres_per_length, frequency=frequency, travel=travel,
                              gravity_along=gravity_along)
        feats.append(ModeFeatures(**line, airborne=math.nan, raised=math.nan, max_height=math.nan))
    airborne, raised = floor_flights(t, pos, rad, frequency=frequency, thresholds=th)
    return CompartmentFeatures(sections=tuple(sections), spheres=tuple(counts), compartments=tuple(feats),
                               airborne=airborne, raised=raised, max_height=float(((pos[:, :, 1] - rad) / rad).max()),
                               frames=int(t.size), cycles=_cycles(t, frequency))


# --------------------------------------------------------------------------- vertical family

@dataclass(frozen=True)
class VerticalFeatures(_Features):
    """What :func:`vertical_features` measured (see the module docstring)."""

    family: ClassVar[str] = "vertical"

    floor_touch: float
    lid_touch: float
    floor_impacts: float
    lid_impacts: float
    swing: float
    sync: float
    phase_deg: float
    coherence: float
    relative: float
    frames: int
    cycles: float

    def classify(self, thresholds: dict | None = None) -> str:
        """The vertical mode (the module docstring's rules, in order)."""
        th = {**THRESHOLDS, **(thresholds or {})}
        if self.relative <= th["locked_max"]:  # False for NaN (no container track)
            return "locked"
        if 1.0 - self.floor_touch < th["flight_min"]:
            return "fluidised"   # the bed as a whole stays on the floor: its spheres fly each on its own
        if min(self.floor_impacts, self.lid_impacts) >= th["impacts_min"] and self.sync >= th["sync_min"]:
            return "bouncing-collect-and-collide"
        if self.coherence >= th["coherence_min"]:
            return "bouncing-bed"
        return "fluidised"


def vertical_features(time, position, radius, *, height: float, clearance: float, frequency: float,
                      start_time: float = 0.0, container_position=None, drive_dir=(0.0, 1.0, 0.0),
                      thresholds: dict | None = None) -> VerticalFeatures:
    """Measure a vertically shaken bed over the frames at ``time >= start_time``: ``height`` H [m]
    floor (y = 0) to lid, ``clearance`` the free height h_v [m] above the bed at rest
    (:func:`vertical_clearance`), ``container_position`` (F,) or (F, 3) the container's displacement
    (its travel along ``drive_dir``, the drive direction in the container frame)."""
    th = {**THRESHOLDS, **(thresholds or {})}
    t, pos, rad, keep = _prepare(time, position, radius, start_time)
    y = pos[:, :, 1]
    gap = th["touch_gap"] * rad
    on_floor = np.any(y - rad <= gap, axis=1)
    on_lid = np.any(y + rad >= height - gap, axis=1)
    centre = y.mean(axis=1)
    cycles = _cycles(t, frequency)
    sync, phase = _drive_share(t, centre, frequency)
    spread = float(np.mean(np.var(y, axis=0)))
    coherence = float(np.var(centre) / spread) if spread > 0 else math.nan
    travel = _travel(container_position, keep, np.asarray(drive_dir, dtype=float) / np.linalg.norm(drive_dir))
    moved = _range(travel) if travel is not None else math.nan
    centre_range = _range(centre)
    return VerticalFeatures(floor_touch=float(on_floor.mean()), lid_touch=float(on_lid.mean()),
                            floor_impacts=_arrivals(on_floor, cycles), lid_impacts=_arrivals(on_lid, cycles),
                            swing=centre_range / clearance if clearance > 0 else math.nan, sync=sync, phase_deg=phase,
                            coherence=coherence, relative=centre_range / moved if moved > 0 else math.nan,
                            frames=int(t.size), cycles=float(cycles))


# --------------------------------------------------------------------------- one call per trajectory

def classify_features(f, thresholds: dict | None = None) -> str:
    """The motion mode (one of :data:`MODES`) of measured features (any family's)."""
    return f.classify(thresholds)


def _describe_horizontal(f: dict) -> str:
    g = lambda k: f.get(k, math.nan)  # noqa: E731
    return (f"sync {g('sync'):.2f}, swing {g('swing'):.2f} h, phase {g('phase_deg'):.0f} deg, wall arrivals/cycle "
            f"-x {g('impacts_lo'):.2f} +x {g('impacts_hi'):.2f}, in-container motion {g('relative'):.2g} of the "
            f"travel, in flight from the floor {g('airborne'):.2g} of the sphere-frames")


def _describe_vertical(f: dict) -> str:
    g = lambda k: f.get(k, math.nan)  # noqa: E731
    return (f"floor / lid arrivals/cycle {g('floor_impacts'):.2f} / {g('lid_impacts'):.2f}, bed off the floor "
            f"{1 - g('floor_touch'):.2f} of the time, swing {g('swing'):.2f} h_v, sync {g('sync'):.2f}, "
            f"coherence {g('coherence'):.2f}, in-container motion {g('relative'):.2g} of the travel")


def _describe_compartments(f: dict) -> str:
    parts = [f"{n} spheres {m or 'empty'}" + (f" (sync {c['sync']:.2f}, arrivals {c['impacts_lo']:.2f} / "
                                               f"{c['impacts_hi']:.2f})" if c else "")
             for m, n, c in zip(f.get("compartment_modes", []), f.get("spheres", []), f.get("compartments", []))]
    return "compartments along x: " + "; ".join(parts)


#: One line of each family's features (a summary without ``family`` is horizontal: older runs).
_DESCRIBE = {"horizontal": _describe_horizontal, "vertical": _describe_vertical,
             "compartments": _describe_compartments}


def describe_features(features: dict) -> str:
    """One line of what a mode was judged on, from a features dict (``to_dict`` of any family, as a
    run's summary stores it); "" for an empty one."""
    if not features:
        return ""
    return _DESCRIBE[features.get("family", "horizontal")](features)


def classify_trajectory(trajectory: dict, case, *, thresholds: dict | None = None):
    """(mode, features) of a recorded trajectory (``time``, ``position``, ``radius``) of ``case``
    (a :class:`pdamper.params.Case`: container, drive and the transient ``drop_cycles`` to skip),
    in the family :func:`family_of` picks."""
    from ..geometry.tilt import container_vectors

    drive = case.drive
    freq = float(drive.frequency or 0.0)
    if freq <= 0:
        raise ValueError("motion modes need a drive with a frequency")
    gvec, dvec = container_vectors(case.container.tilt, case.gravity, drive.lab_direction())
    off, _, _ = container_track(trajectory, case)
    args = (trajectory["time"], trajectory["position"], trajectory["radius"])
    common = dict(frequency=freq, start_time=case.drop_cycles / freq, container_position=off, thresholds=thresholds)
    family = family_of(case, thresholds)
    if family == "vertical":
        height, h_v = vertical_clearance(case)
        feats = vertical_features(*args, height=height, clearance=h_v, drive_dir=dvec, **common)
    elif family == "compartments":
        length = case.container.geometry.drive_length
        feats = compartment_features(*args, sections=case.container.compartments(_largest_radius(case)),
                                     spheres_per_length=floor_capacity(case) / length, shape=case.container.geometry,
                                     length=length, gravity_along=float(gvec[0]), **common)
    else:
        length, h = case_clearance(case)
        feats = mode_features(*args, length=length, clearance=h, drive_dir=dvec, shape=case.container.geometry,
                              gravity_along=float(gvec @ _unit_horizontal(dvec)), **common)
    return feats.classify(thresholds), feats
