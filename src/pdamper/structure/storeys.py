"""The names of a structure's dofs and its storeys: the ``[structure]`` keys ``dof_names``,
``storey_heights`` (or ``storey_height``) and ``storey_dofs``, checked, and the storeys' chain they
give (docs/config.md, docs/structure.md "The numbers codes ask for").

- ``dof_names = ["floor 1", "floor 2", ...]``: one name per dof (FE matrices: per row of M; one
  mode: its one dof; modes given as data: the damper, force and response points), used wherever a
  dof is labelled (tables, JSON ``dofs``, ``--dofs``). A name is not a whole number (that is an
  index) and holds no ``,`` or ``:`` (the ``--dofs`` syntax).
- ``storey_heights = ["3.5m", "3m", "3m"]`` (bottom up) or ``storey_height = "3m"`` (every storey):
  the heights h_j that turn a storey's drift into a drift ratio Delta_j / h_j.
- ``storey_dofs = [0, 1, 2]`` (indices, 0-based, or names): the floors' dofs bottom up, along the
  drive; storey j lies between floor j - 1 and floor j, storey 1 between the ground and the first
  floor. Default: every dof in order (FE matrices of a shear frame: one lateral dof a floor).

The drift of storey j is ``x(floor j) - x(floor j - 1)`` with ``x(ground) = 0``: the displacements
are relative to the ground under a ground acceleration and absolute (the ground at rest) under a
force, so both are storey drifts.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown

__all__ = ["Storeys", "check_dof_names", "storeys_of", "dof_index"]


@dataclass(frozen=True)
class Storeys:
    """The storeys' chain of a structure: storey j between the dofs ``lower[j]`` (-1: the ground)
    and ``upper[j]`` (indices of :meth:`~pdamper.structure.StructureBase.dof_shapes`), its height
    ``heights[j]`` [m]; ``labels[j]`` its name (the upper floor's dof label), ``between[j]`` the labels
    of its floors (``"ground"`` below the first)."""

    labels: tuple
    lower: tuple
    upper: tuple
    heights: tuple
    between: tuple = ()

    def to_dict(self) -> dict:
        return {"storeys": list(self.labels), "storey_dofs": [[lo, up] for lo, up in zip(self.lower, self.upper)],
                "storey_between": [list(b) for b in self.between], "storey_heights_m": list(self.heights)}


def _is_whole(v) -> bool:
    return isinstance(v, (int, np.integer)) and not isinstance(v, bool)


def check_dof_names(names, count: int):
    """``dof_names`` checked against the structure's ``count`` dofs: a tuple of names, or None."""
    if names is None:
        return None
    ex = "e.g. dof_names = ['floor 1', 'floor 2']"
    if isinstance(names, str) or not isinstance(names, (list, tuple)):
        raise InputError(f"structure.dof_names = {shown(names)}; give a list of names, one per dof, {ex}")
    out = []
    for k, n in enumerate(names):
        if not isinstance(n, str) or not n.strip():
            raise InputError(f"structure.dof_names[{k}] = {shown(n)}; give a name (text), {ex}")
        n = n.strip()
        if n.lstrip("-").isdigit() or "," in n or ":" in n:
            raise InputError(f"structure.dof_names[{k}] = {shown(n)}: a name may not be a whole number (that is a dof's "
                             "index) nor hold ',' or ':' (--dofs lists and ranges); e.g. 'floor 1'")
        out.append(n)
    if len(out) != count:
        raise InputError(f"structure.dof_names has {len(out)} name{'s' if len(out) != 1 else ''}; the structure has "
                         f"{count} dof{'s' if count != 1 else ''}: give one name per dof, in order")
    if len(set(out)) != len(out):
        twice = next(n for n in out if out.count(n) > 1)
        raise InputError(f"structure.dof_names: {shown(twice)} is given twice; give each dof its own name")
    return tuple(out)


def dof_index(labels, wanted, *, what: str) -> int:
    """The index of the dof ``wanted`` (a label, or a 0-based index) among ``labels``; ``what``
    names the key or option in the message."""
    if wanted in labels and not (isinstance(wanted, bool)):
        return labels.index(wanted)
    if _is_whole(wanted) and 0 <= int(wanted) < len(labels):
        return int(wanted)
    allowed = (f"0 to {len(labels) - 1}" if all(_is_whole(x) for x in labels)
               else ", ".join(map(str, labels)) + f" (or 0 to {len(labels) - 1})")
    raise InputError(f"{what}: {shown(wanted)} is not a dof of this structure ({allowed})")


def storeys_of(labels, heights, height, dofs):
    """The :class:`Storeys` of a structure with dof ``labels`` from its keys ``storey_heights``
    (``heights``), ``storey_height`` (``height``) and ``storey_dofs`` (``dofs``), checked; None when
    no height is given (then ``storey_dofs`` is refused: it needs a height)."""
    if heights is not None and height is not None:
        raise InputError("structure.storey_heights and structure.storey_height are both given; give the list of "
                         "heights bottom up, or one height for every storey")
    if heights is None and height is None:
        if dofs is not None:
            raise InputError("structure.storey_dofs needs the storeys' heights: give storey_heights = ['3m', ...] "
                             "(bottom up) or storey_height = '3m'")
        return None
    if dofs is None:
        chain = list(range(len(labels)))
    else:
        if isinstance(dofs, (str, bytes)) or not isinstance(dofs, (list, tuple)) or not len(dofs):
            raise InputError(f"structure.storey_dofs = {shown(dofs)}; give the floors' dofs bottom up, e.g. [0, 1, 2] "
                             "(0-based indices or dof names)")
        chain = [dof_index(labels, d if not (isinstance(d, float) and d.is_integer()) else int(d),
                           what=f"structure.storey_dofs[{k}]") for k, d in enumerate(dofs)]
        if len(set(chain)) != len(chain):
            raise InputError(f"structure.storey_dofs = {shown(list(dofs))} names a dof twice; each floor once, bottom up")
    if heights is not None:
        hs = [float(h) for h in heights]
        if len(hs) != len(chain):
            src = "storey_dofs" if dofs is not None else "dofs (storey_dofs: every dof in order)"
            raise InputError(f"structure.storey_heights has {len(hs)} height{'s' if len(hs) != 1 else ''} for "
                             f"{len(chain)} {src}; give one height per storey, bottom up"
                             + ("" if dofs is not None else ", or storey_dofs = [...] for the floors' dofs"))
    else:
        hs = [float(height)] * len(chain)
    for k, h in enumerate(hs):
        if not (h > 0 and math.isfinite(h)):
            key = f"storey_heights[{k}]" if heights is not None else "storey_height"
            raise InputError(f"structure.{key} = {shown(h)} m; must be > 0, e.g. '3m'")
    lower = tuple([-1] + chain[:-1])
    between = tuple(("ground" if lo < 0 else labels[lo], labels[up]) for lo, up in zip(lower, chain))
    return Storeys(labels=tuple(labels[i] for i in chain), lower=lower, upper=tuple(chain), heights=tuple(hs),
                   between=between)
