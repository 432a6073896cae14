"""What a tangential (friction) law is to pdamper: a name, a kernel marker, and whether it keeps a
state per contact.

A law lives in its own file of :mod:`pdamper.contact` (the formula, its reference, its compiled
scalar functions) and is registered by name in :data:`pdamper.contact.TANGENTIAL_LAWS`
(``ContactModel.tangential``). The kernels receive the law's ``marker`` (an empty ``NamedTuple``)
in their contact table (``ContactTable.tangential``); its *type* selects, when numba compiles,
which friction code the one contact function (:func:`pdamper.kernels.contact.contact`) runs and
whether the force loops, the neighbour lists and Gear carry the law's per-contact history, so a
run compiles the law it uses and no other, and no run pays for a branch on the law.

Adding a law: write ``contact/<model>.py`` with a marker class and its scalar functions, list its
:class:`TangentialLaw` in ``contact/__init__.py`` and give :mod:`pdamper.kernels.contact` the
function that applies it to one contact.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = ["TangentialLaw"]


@dataclass(frozen=True)
class TangentialLaw:
    """A tangential contact law.

    Attributes
    ----------
    name : str
        The value of ``contact.tangential`` that chooses it.
    marker : type
        An empty ``typing.NamedTuple`` class; an instance travels in the kernels' contact table
        and its numba type selects the law's code at compile time.
    history : bool
        The law keeps a state per contact between steps (a spring's stored force): the kernels
        then carry it over neighbour-list rebuilds, drop it when the contact opens, and Gear
        saves and restores it with a rejected step. A law without history compiles none of that.
    summary : str
        One line for help texts and docs.
    """

    name: str
    marker: type
    history: bool
    summary: str
