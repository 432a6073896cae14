"""The vertical family of motion modes: a drive within 45 deg of gravity (``drive.vertical_share``):
``locked``, ``bouncing-collect-and-collide``, ``bouncing-bed``, ``fluidised``. Its table is
:data:`FAMILY`; a new vertical mode is a name there and its rule in :meth:`VerticalFeatures.classify`.
Its rules also read the horizontal family's ``locked_max``, ``impacts_min`` and ``sync_min``.

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
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .common import (THRESHOLDS, Features, ModeFamily, _arrivals, _cycles, _drive_share, _prepare, _range, _travel,
                     register_family, vertical_clearance)

__all__ = ["FAMILY", "VerticalFeatures", "vertical_features"]

@dataclass(frozen=True)
class VerticalFeatures(Features):
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


def _describe(f: dict) -> str:
    g = lambda k: f.get(k, math.nan)  # noqa: E731
    return (f"floor / lid arrivals/cycle {g('floor_impacts'):.2f} / {g('lid_impacts'):.2f}, bed off the floor "
            f"{1 - g('floor_touch'):.2f} of the time, swing {g('swing'):.2f} h_v, sync {g('sync'):.2f}, "
            f"coherence {g('coherence'):.2f}, in-container motion {g('relative'):.2g} of the travel")


def _measure(args, case, gravity, direction, common) -> VerticalFeatures:
    height, h_v = vertical_clearance(case)
    return vertical_features(*args, height=height, clearance=h_v, drive_dir=direction, **common)


#: The vertical family's table (the module docstring; measured in docs/motion.md).
FAMILY = register_family(ModeFamily(
    name="vertical",
    modes=("locked", "bouncing-collect-and-collide", "bouncing-bed", "fluidised"),
    collide=("bouncing-collect-and-collide",),
    thresholds={
        "vertical_share": math.sqrt(0.5),  # the vertical family: the drive within 45 deg of gravity
        "flight_min": 0.25,     # vertical: the bed leaves the floor, none of its spheres on it in >= 25 % of the frames
        "coherence_min": 0.45,  # bouncing bed: ... and moves as one block, var(Y) >= 0.45 x the spheres' mean var(y)
    },
    applies=lambda case, th: case.drive.vertical_share >= th["vertical_share"],
    measure=_measure,
    describe=_describe,
))
