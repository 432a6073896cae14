"""The compartments family of motion modes: a drive within 45 deg of x with baffles that split the
floor into sections along x (``container.compartments``). Each section's bed gets a horizontal name
(:meth:`pdamper.analysis.modes.horizontal.ModeFeatures.floor_mode`), the container the mode of most
spheres' sections, ``compartment-collect-and-collide`` where that is rolling collect-and-collide
(Meyer & Seifried, Granular Matter 25 (2023) 20: each compartment's bed collects and collides on its
own); ``lift-off`` as for one bed. Its table is :data:`FAMILY`; its rules read the horizontal
family's thresholds and the vertical family's ``vertical_share`` (the drive across the plates).
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .common import (THRESHOLDS, Features, ModeFamily, _cycles, _largest_radius, _prepare, _shape_or_planar, _travel,
                     floor_capacity, floor_flights, register_family)
from .horizontal import FAMILY as HORIZONTAL
from .horizontal import ModeFeatures, _line_features

__all__ = ["FAMILY", "CompartmentFeatures", "compartment_features"]

@dataclass(frozen=True)
class CompartmentFeatures(Features):
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
        order = {m: k for k, m in enumerate(HORIZONTAL.modes)}
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


def _describe(f: dict) -> str:
    parts = [f"{n} spheres {m or 'empty'}" + (f" (sync {c['sync']:.2f}, arrivals {c['impacts_lo']:.2f} / "
                                               f"{c['impacts_hi']:.2f})" if c else "")
             for m, n, c in zip(f.get("compartment_modes", []), f.get("spheres", []), f.get("compartments", []))]
    return "compartments along x: " + "; ".join(parts)


def _applies(case, th) -> bool:
    """The drive within 45 deg of x (across the plates) and two or more floor sections."""
    d = np.asarray(case.drive.lab_direction(), dtype=float)
    across = abs(float(d[0])) >= th["vertical_share"] * math.hypot(float(d[0]), float(d[2]))
    return across and len(case.container.compartments(_largest_radius(case))) > 1


def _measure(args, case, gravity, direction, common) -> CompartmentFeatures:
    length = case.container.geometry.drive_length
    return compartment_features(*args, sections=case.container.compartments(_largest_radius(case)),
                                spheres_per_length=floor_capacity(case) / length, shape=case.container.geometry,
                                length=length, gravity_along=float(gravity[0]), **common)


#: The compartments family's table: the one name it brings (the others are the horizontal family's).
FAMILY = register_family(ModeFamily(
    name="compartments",
    modes=("compartment-collect-and-collide",),
    collide=("compartment-collect-and-collide",),
    thresholds={},
    applies=_applies,
    measure=_measure,
    describe=_describe,
))
