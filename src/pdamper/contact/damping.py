"""What a normal damping law is to pdamper: a name, how its per-material-pair coefficient follows
from the coefficient of restitution, and two compiled functions the contact kernel calls.

A law lives in its own file of :mod:`pdamper.contact` (the formula, its reference, the
functions) and is registered by name in :data:`pdamper.contact.DAMPING_LAWS`; nothing in the
kernels names a law. The kernels receive the law's ``marker`` (an empty ``NamedTuple``) in their
contact table; its *type* selects, when numba compiles, which ``touch``/``force`` the one contact
function (:func:`pdamper.kernels.contact.contact`) calls, so every law gets its own compiled,
disk-cached kernels and no run pays for a branch on the law.

Adding a law: write ``contact/<model>.py`` with a marker class, ``touch``, ``force`` and a
``coefficient`` function, and list its :class:`DampingLaw` in ``contact/__init__.py``
(``tests/contact/test_damping_laws.py`` then checks its restitution like the others').
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

__all__ = ["DampingLaw"]


@dataclass(frozen=True)
class DampingLaw:
    """A normal contact law: Hertz elasticity with a damping term.

    The elastic part is the same for every law, :mod:`pdamper.contact.hertz`: the kernels take each
    contact's stiffness ``k`` (:func:`~pdamper.contact.hertz.hertz_stiffness`) and the energy in its
    spring (:func:`~pdamper.contact.hertz.hertz_energy`) from there, and ``force`` adds the damping.

    Attributes
    ----------
    name : str
        The value of ``contact.damping`` that chooses it.
    marker : type
        An empty ``typing.NamedTuple`` class; an instance travels in the kernels' contact table
        and its numba type selects ``touch`` and ``force`` at compile time.
    coefficient : callable
        ``coefficient(eps) -> array``: the law's dimensionless damping coefficient for
        coefficients of restitution ``eps`` (array in (0, 1]); tabulated over impact speed per
        material pair (velocity-dependent COR laws give a table that varies).
    touch : numba function
        ``touch(coefficient, v_in, k, m_star) -> d``: the contact's damping parameter, fixed when it
        starts (or is struck harder than before) at approach speed ``v_in`` [m/s] (floored),
        Hertz stiffness ``k`` [N/m^1.5] and effective mass ``m_star`` [kg].
    force : numba function
        ``force(k, delta, delta_dot, d) -> (F_N, F_damp)``: the normal force [N] at overlap
        ``delta`` [m] and approach rate ``delta_dot`` [m/s] (> 0 approaching), and the damping
        part of it actually applied (its power ``F_damp delta_dot`` goes to the energy ledger).
    summary : str
        One line for help texts and docs.
    """

    name: str
    marker: type
    coefficient: Callable
    touch: Callable
    force: Callable
    summary: str
