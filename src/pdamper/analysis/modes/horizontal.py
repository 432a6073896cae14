"""The horizontal family of motion modes: a drive within 45 deg of the floor plane moving one bed
along the floor (the paper's Figs. 2, 3, 5 and Sect. 6.2): ``lift-off``,
``rolling-collect-and-collide``, ``swaying``, ``single-sided``, ``locked``, ``scattered``. Its table
is :data:`FAMILY` (the names in the order :meth:`ModeFeatures.classify` checks them, the thresholds
they bring); a new horizontal mode is a name there and its rule in :meth:`ModeFeatures.floor_mode`.

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
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .common import (THRESHOLDS, Features, ModeFamily, _arrivals, _cycles, _drive_share, _prepare, _range, _travel,
                     _shape_or_planar, _unit_horizontal, case_clearance, floor_flights, register_family)

__all__ = ["FAMILY", "ModeFeatures", "mode_features"]

@dataclass(frozen=True)
class ModeFeatures(Features):
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


def _describe(f: dict) -> str:
    g = lambda k: f.get(k, math.nan)  # noqa: E731
    return (f"sync {g('sync'):.2f}, swing {g('swing'):.2f} h, phase {g('phase_deg'):.0f} deg, wall arrivals/cycle "
            f"-x {g('impacts_lo'):.2f} +x {g('impacts_hi'):.2f}, in-container motion {g('relative'):.2g} of the "
            f"travel, in flight from the floor {g('airborne'):.2g} of the sphere-frames")


def _measure(args, case, gravity, direction, common) -> ModeFeatures:
    length, h = case_clearance(case)
    return mode_features(*args, length=length, clearance=h, drive_dir=direction, shape=case.container.geometry,
                         gravity_along=float(gravity @ _unit_horizontal(direction)), **common)


#: The horizontal family's table: its names in the order the classifier checks them, the efficient one,
#: and the thresholds its rules bring (the module docstring; measured in docs/motion.md).
FAMILY = register_family(ModeFamily(
    name="horizontal",
    modes=("lift-off", "rolling-collect-and-collide", "swaying", "single-sided", "locked", "scattered"),
    collide=("rolling-collect-and-collide",),
    thresholds={
        "lift_fraction": 0.05,  # lift-off: at least 5 % of sphere-frames in flights from the floor
        "locked_max": 0.05,     # locked: the bed centre moves in the container by at most 5 % of the container's travel
        "impacts_min": 0.5,     # collect-and-collide: at least 0.5 arrivals per cycle at each of the two walls
        "swing_min": 0.5,       # ... the bed centre travels at least half the clearance
        "sync_min": 0.7,        # ... at least 70 % of its motion is at the drive frequency
        "phase_max": 140.0,     # ... and (horizontal) it lags the container by at most 140 deg (else: swaying)
        "touch_one": 0.5,       # single-sided: one end wall touched in at least half the frames
        "touch_other": 0.05,    # ... and the other in at most 5 %
        "tilt_pull": 0.3,       # ... the low wall, with the tilt's pull g_s >= 0.3 A (else: scattered)
    },
    applies=lambda case, th: True,   # the family of every case no other family claims
    measure=_measure,
    describe=_describe,
))
