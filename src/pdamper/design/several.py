"""One damper per mode: the design for several modes of a structure together.

The structure has a damper point per mode (``damper_dof = [..]``, ``damper_nodes = [..]``); the
damper for mode ``modes[k]`` sits at point k and is designed as the search designs one damper
(:func:`~pdamper.design.case.design_for_case`): for that mode under ``force`` at its resonance,
seen at that point. The designs are made one mode at a time: each damper's effect on the other
modes is left out of the others' designs (small where a mode's shape at the other damper is small;
the DEM run of the written case, several dampers in the coupling loop, is the check).
:func:`design_case_several` writes them as one case with a ``[[damper]]`` table each.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

from ..errors import InputError
from .case import _bed, design_for_case
from .search import StructureDesign

__all__ = ["SeveralDesign", "design_for_modes", "design_case_several"]


@dataclass(frozen=True)
class SeveralDesign:
    """The dampers for ``modes`` (1-based), ``designs[k]`` the :class:`StructureDesign` of the damper
    at the structure's damper point k for mode ``modes[k]``."""

    modes: tuple
    designs: tuple

    def to_dict(self) -> dict:
        return {"modes": list(self.modes), "designs": [d.to_dict() for d in self.designs],
                "note": "one damper per mode, each designed for its mode alone at its damper point"}


def design_for_modes(case, *, force: float, modes, **search) -> SeveralDesign:
    """A damper for each of ``modes`` (1-based mode numbers) of the structure of ``case`` (a
    structure file, :func:`~pdamper.design.case.load_structure`), the one for ``modes[k]`` at the
    structure's damper point k, each under ``force`` [N] at its mode's resonance; ``search``: the
    other parameters of :func:`~pdamper.design.case.design_for_case` (one container shape and
    bounds for all)."""
    modes = tuple(modes)
    if len(modes) < 2 or len(set(modes)) != len(modes):
        raise InputError(f"--mode {', '.join(map(str, modes))}: give two or more different modes for a damper each")
    s = case.drive
    if s.damper_count != len(modes):
        raise InputError(f"{len(modes)} modes need a damper point each: the structure has {s.damper_count}; give "
                         f"[structure] damper_dof = [..] (FE matrices) or damper_nodes = [..] (an OpenSees model) with "
                         f"{len(modes)} points, the damper for mode {modes[0]} at the first")
    designs = []
    for k, mode in enumerate(modes):
        one = dataclasses.replace(case, drive=s.at_damper(k), dampers=())
        designs.append(design_for_case(one, force=force, mode=mode, **search))
    return SeveralDesign(modes=modes, designs=tuple(designs))


def design_case_several(sd: SeveralDesign, case, *, cycles: float | None = None):
    """The dampers of ``sd`` on the structure of ``case`` as one runnable
    :class:`~pdamper.params.Case`: a ``[[damper]]`` each (its container and filling, at its point),
    the structure forced by the designs' force at the first mode's design resonance, from rest
    (``pdamper response`` and ``transient`` run it, several dampers in the coupling loop); no rig drive
    (each damper's own sweep is its single-mode design's, ``pdamper design --mode K --write-case``).
    ``cycles``: forcing periods, default five decay times of the least damped designed mode."""
    from ..params import Damper

    first: StructureDesign = sd.designs[0]
    f = round(first.frequency_hz, 4)
    structure = dataclasses.replace(case.drive, force_amplitude=first.force_N, force_frequency=f, displacement=0.0,
                                    velocity=0.0, load=None)
    dampers = tuple(Damper(**_bed(case, d.filling)) for d in sd.designs)
    if cycles is None:
        zeta = min(d.zeta_total for d in sd.designs)
        cycles = 10 * math.ceil(5.0 / (2 * math.pi * zeta) / 10)
    return dataclasses.replace(case, drive=structure, rig=None, dampers=dampers, particles=dampers[0].particles,
                               container=dampers[0].container, cycles=cycles, drop_cycles=2)
