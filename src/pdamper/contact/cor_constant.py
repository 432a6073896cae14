r"""Constant coefficient of restitution: :math:`\varepsilon(v) = \varepsilon_0`.

The usual DEM choice (paper Sect. 3) and pdamper's default (:math:`\varepsilon_0 = 0.9`).
Allowed range (0, 1]; 1 is perfectly elastic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..schema import convert_fields, param, read_quantity
from .restitution import RestitutionLaw, register_restitution

__all__ = ["ConstantRestitution", "read_coefficient"]


def read_coefficient(value, label) -> float:
    """A coefficient of restitution as a config gives it (a number, a percentage), named ``label``."""
    if isinstance(value, bool) or isinstance(value, (dict, list)):
        raise InputError(f"{label} = {shown(value)} must be a number")
    return read_quantity(value, label, "dimensionless")


@register_restitution
@dataclass(frozen=True, kw_only=True)
class ConstantRestitution(RestitutionLaw):
    """Constant coefficient of restitution.

    Parameters
    ----------
    value : float
        epsilon [-], in (0, 1].
    """

    value: float = param(0.9, dimension="dimensionless")
    kind: str = param("constant", kind="tag", key="law")

    def __post_init__(self):
        convert_fields(self, "restitution")
        if not (0.0 < self.value <= 1.0):
            raise InputError(f"restitution = {shown(self.value)}: a coefficient of restitution must be in (0, 1] "
                             "(0.9 is the paper's default; 1 is elastic)")

    def restitution(self, speed, **_):
        """epsilon at impact speed(s) ``speed`` [m/s]."""
        return np.full(np.shape(speed), self.value, dtype=float)[()]

    def config_value(self):
        """A plain number (``restitution = 0.9``)."""
        return float(self.value)

    @classmethod
    def from_config(cls, table: dict, section: str, key: str):
        """``{law = "constant", value = 0.9}``."""
        cls.check_table(table, section, key)
        return cls(value=read_coefficient(table["value"], f"[{section}.{key}] value"))

    def describe(self) -> str:
        return f"constant eps = {self.value:g}"
