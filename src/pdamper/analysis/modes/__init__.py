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

**One module a family**, each with one table of its names and thresholds (a
:class:`~.common.ModeFamily` it registers): :mod:`.horizontal`, :mod:`.vertical`,
:mod:`.compartments`; what they share is :mod:`.common`. The lists here (:data:`MODES`,
:data:`COLLIDE_MODES`, :data:`THRESHOLDS`) are made from those tables. **A new motion mode** is its
name in its family's table and its rule in that family's ``classify``; **a new family** is one
module with its features, its measuring function, its table and one line here (its import, and its
place in :data:`CHOICE`).
"""

from __future__ import annotations

from ..._deprecated import renamed_function
from . import horizontal, vertical, compartments  # noqa: I001  (each registers its family, in this order)
from .common import (FAMILIES, MODE_FRAMES_PER_CYCLE, THRESHOLDS, bed_centre, case_clearance, container_track,
                     describe_features, floor_capacity, floor_flights, majority_mode, mode_fps, vertical_clearance)
from .compartments import CompartmentFeatures, compartment_features
from .horizontal import ModeFeatures, mode_features
from .vertical import VerticalFeatures, vertical_features

__all__ = ["MODES", "HORIZONTAL_MODES", "VERTICAL_MODES", "COMPARTMENT_MODES", "COLLIDE_MODES", "THRESHOLDS",
           "MODE_FRAMES_PER_CYCLE", "FAMILIES", "CHOICE", "ModeFeatures", "VerticalFeatures", "CompartmentFeatures",
           "mode_features", "vertical_features", "compartment_features", "floor_flights", "classify_features",
           "classify_trajectory", "family_of", "mode_fps", "describe_features", "case_clearance", "vertical_clearance",
           "floor_capacity", "bed_centre", "majority_mode", "container_track"]

#: The names of a bed moved along the floor, in the order the classifier checks them.
HORIZONTAL_MODES = horizontal.FAMILY.modes
#: The names of a bed shaken along gravity (``locked`` as in the horizontal family).
VERTICAL_MODES = vertical.FAMILY.modes
#: The name of a baffled bed whose compartments collect and collide (the others: horizontal names).
COMPARTMENT_MODES = compartments.FAMILY.modes
#: Every motion mode, each once, family by family (plus "unknown" when no trajectory).
MODES = tuple(dict.fromkeys(m for f in FAMILIES.values() for m in f.modes))
#: The efficient modes: the bed (or each compartment's bed) collected at one wall and striking the
#: other as a group in step with the drive (the effective fields' "collide" family).
COLLIDE_MODES = tuple(m for f in FAMILIES.values() for m in f.collide)
#: The families in the order a case is asked which applies (the first that does): the vertical
#: names for a drive along gravity, the compartments' for a baffled floor, else the horizontal.
CHOICE = (vertical.FAMILY, compartments.FAMILY, horizontal.FAMILY)


def _family(case, thresholds: dict | None = None):
    th = {**THRESHOLDS, **(thresholds or {})}
    return next(f for f in CHOICE if f.applies(case, th))


def family_of(case, thresholds: dict | None = None) -> str:
    """Which family of names applies to ``case``: ``"vertical"`` when its drive is within 45 deg of
    gravity (``drive.vertical_share`` >= cos 45 deg), ``"compartments"`` when baffles split the
    floor into sections along x (``container.compartments``) and the drive moves the bed across
    them (within 45 deg of x), ``"horizontal"`` otherwise (:data:`CHOICE`)."""
    return _family(case, thresholds).name


#: The old name of :func:`family_of` (warns; docs/names.md): :func:`pdamper.analysis.fields.mode_family`
#: is the family of a mode ("collide", "other"), a different thing.
mode_family = renamed_function(family_of, "mode_family")


def classify_features(f, thresholds: dict | None = None) -> str:
    """The motion mode (one of :data:`MODES`) of measured features (any family's)."""
    return f.classify(thresholds)


def classify_trajectory(trajectory: dict, case, *, thresholds: dict | None = None):
    """(mode, features) of a recorded trajectory (``time``, ``position``, ``radius``) of ``case``
    (a :class:`pdamper.params.Case`: container, drive and the transient ``drop_cycles`` to skip),
    in the family :func:`family_of` picks."""
    from ...geometry.tilt import container_vectors

    drive = case.drive
    freq = float(drive.frequency or 0.0)
    if freq <= 0:
        raise ValueError("motion modes need a drive with a frequency")
    gvec, dvec = container_vectors(case.container.tilt, case.gravity, drive.lab_direction())
    off, _, _ = container_track(trajectory, case)
    args = (trajectory["time"], trajectory["position"], trajectory["radius"])
    common = dict(frequency=freq, start_time=case.drop_cycles / freq, container_position=off, thresholds=thresholds)
    feats = _family(case, thresholds).measure(args, case, gvec, dvec, common)
    return feats.classify(thresholds), feats
