"""What a coefficient-of-restitution (COR) law is to pdamper: one module a law behind one protocol.

A law is a frozen, keyword-only dataclass subclassing :class:`RestitutionLaw`, registered with
:func:`register_restitution` under its ``kind`` tag (the ``law`` key of its config table). Nobody
outside the law's module asks which law it is; callers ask what it does:

=========================  ====================================================================
``restitution(speed, **)``  epsilon at impact speed(s) [m/s]; ``e_star``, ``r_star``, ``m_star``
                            of the contact are passed to a law that needs them
``kernel_table()``          ``(eps, p_y)``: what the kernels hold for it -- epsilon on
                            :data:`SPEED_GRID` (over impact speed, ``p_y = 0``) or over
                            ``v / v_y`` with the contact's yield speed from the pressure
                            ``p_y > 0`` [Pa] (Thornton's: the kernel computes ``v_y`` per contact,
                            :func:`pdamper.kernels.contact.tabulated`)
``config_value()``          what a config file holds for it: a number (a constant) or its table
                            ``{law = ..., ...}``
``from_config(table, at)``  (class) the law of a config table (``at``: ``[contact] restitution``
                            for messages); the keys it may hold are its fields' (``table_keys()``)
``describe()``              one line for people
=========================  ====================================================================

**A new law** is one module ``contact/cor_<model>.py`` (the formula, its reference, the class)
and one registration line, the import in ``contact/__init__.py`` that runs its
``@register_restitution``; config files then read ``{law = "<kind>", ...}`` with its fields as
keys, cases write it back, the kernels take its :meth:`~RestitutionLaw.kernel_table`.

**A law of your own** need not be registered: any object with ``restitution(speed)`` runs
(:func:`pdamper.contact.kernel_law` tabulates it on :data:`SPEED_GRID`, as the kernels see every law), and a case
holding one is written to a config file (a sweep's result store, a run directory) as the table law
of those values (:meth:`~pdamper.contact.cor_table.TabulatedRestitution.from_law`), which the kernels
take to the same bits. A law whose ``restitution`` needs the contact (``e_star``, ...) cannot be
tabulated once for every contact: register it, or tabulate it for your contact yourself.
"""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ..schema import OwnTable, check_keys, read_fields, register_tagged, write_fields

__all__ = ["RestitutionLaw", "RESTITUTION_LAWS", "register_restitution", "SPEED_GRID", "tabulate_law"]

#: Registered COR laws by tag (``restitution = {law = "<tag>", ...}``).
RESTITUTION_LAWS: dict[str, type] = {}

#: Impact speeds [m/s] at which every COR law is sampled for the kernels: 257 log-spaced speeds from
#: 1e-5 to 100 m/s (the interpolation error of a smooth law such as Thornton's is below 1e-4).
SPEED_GRID = np.geomspace(1e-5, 100.0, 257)


def register_restitution(cls):
    """Class decorator: register a COR law class under its ``kind`` tag (read from config files from
    then on)."""
    return register_tagged(RESTITUTION_LAWS, cls, "kind", "restitution law",
                           needs=("restitution", "kernel_table", "config_value", "from_config"))


def tabulate_law(law, **context) -> np.ndarray:
    """epsilon of ``law`` on :data:`SPEED_GRID`, clipped to [1e-6, 1]; ``context`` (``e_star``,
    ``r_star``, ``m_star``) is passed to laws that need it."""
    eps = np.asarray(law.restitution(SPEED_GRID, **context), dtype=float)
    return np.clip(np.broadcast_to(eps, SPEED_GRID.shape).copy(), 1e-6, 1.0)


class RestitutionLaw(OwnTable):
    """The answers of the COR-law protocol that most laws share (module docstring): a law tabulated
    over impact speed, written as its fields under ``law = <kind>``."""

    config_section = "restitution"

    def restitution(self, speed, **context):  # pragma: no cover - every law defines it
        raise NotImplementedError

    def kernel_table(self):
        """``(eps, 0.0)``: epsilon on :data:`SPEED_GRID` (over impact speed)."""
        return tabulate_law(self), 0.0

    def config_value(self):
        """Its config table: ``{law = <kind>, <field> = ...}`` in plain SI."""
        return write_fields(self)

    @classmethod
    def from_config(cls, table: dict, section: str, key: str):
        """The law of the config ``table`` given as ``[section] key`` (its keys: ``law`` and
        :meth:`table_keys`, each required; read by their fields' specs)."""
        cls.check_table(table, section, key)
        return cls(**read_fields(table, f"{section}.{key}", cls))

    @classmethod
    def check_table(cls, table: dict, section: str, key: str) -> None:
        """Refuse a key of no field, and a table that leaves a field out."""
        check_keys(table, f"{section}.{key}", ("law", *cls.table_keys()))
        for req in cls.table_keys():
            if req not in table:
                raise InputError(f"[{section}] {key}: law = {cls.tag()!r} needs {req!r}")

    @classmethod
    def tag(cls) -> str:
        """Its ``law`` tag."""
        return cls.__dataclass_fields__["kind"].default

    def describe(self) -> str:
        return self.label()

