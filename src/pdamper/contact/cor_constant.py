r"""Constant coefficient of restitution: :math:`\varepsilon(v) = \varepsilon_0`.

The usual DEM choice (paper Sect. 3) and pdamper's default (:math:`\varepsilon_0 = 0.9`).
Allowed range (0, 1]; 1 is perfectly elastic.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..schema import convert_fields, param

__all__ = ["ConstantRestitution"]


@dataclass(frozen=True, kw_only=True)
class ConstantRestitution:
    """Constant coefficient of restitution.

    Parameters
    ----------
    value : float
        epsilon [-], in (0, 1].
    """

    value: float = param(0.9, dimension="dimensionless")
    kind: str = "constant"

    def __post_init__(self):
        convert_fields(self, "restitution")
        if not (0.0 < self.value <= 1.0):
            raise InputError(f"restitution = {self.value!r}: a coefficient of restitution must be in (0, 1] "
                             "(0.9 is the paper's default; 1 is elastic)")

    def restitution(self, speed, **_):
        """epsilon at impact speed(s) ``speed`` [m/s]."""
        return np.full(np.shape(speed), self.value, dtype=float)[()]
