r"""Coefficient of restitution tabulated against impact speed (user table).

The paper used a velocity-dependent COR from finite-element simulations and experiments
([23, 24] of the paper). A user gives pairs (impact speed [m/s], epsilon); between points
epsilon is interpolated linearly in ``log(speed)``, outside the table it is held at the end
values.

This module also holds :func:`tabulate_law`, the one representation the kernels use for
*every* COR law: epsilon sampled on :data:`SPEED_GRID` (257 log-spaced speeds from 1e-5 to
100 m/s; the interpolation error of a smooth law such as Thornton's is below 1e-4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError
from ..schema import convert_fields, param

__all__ = ["TabulatedRestitution", "SPEED_GRID", "tabulate_law"]

#: Impact speeds [m/s] at which every COR law is sampled for the kernels.
SPEED_GRID = np.geomspace(1e-5, 100.0, 257)


@dataclass(frozen=True, kw_only=True)
class TabulatedRestitution:
    """epsilon(v) from a table.

    Parameters
    ----------
    speeds : tuple of float
        Impact speeds [m/s], strictly increasing, > 0.
    values : tuple of float
        epsilon at those speeds, each in (0, 1].
    """

    speeds: tuple = param((), kind="list", dimension="velocity")
    values: tuple = param((), kind="list", dimension="dimensionless")
    kind: str = "table"

    def __post_init__(self):
        convert_fields(self, "restitution")
        s = np.asarray(self.speeds, dtype=float)
        e = np.asarray(self.values, dtype=float)
        if s.ndim != 1 or s.size < 1 or s.shape != e.shape:
            raise InputError("restitution table: give 'speeds' and 'values' as two lists of equal length (>= 1), "
                             f"got {s.size} speeds and {e.size} values")
        if np.any(~np.isfinite(s)) or np.any(s <= 0) or np.any(np.diff(s) <= 0):
            raise InputError(f"restitution table: speeds {s.tolist()} must be positive and strictly increasing [m/s]")
        if np.any(~(e > 0)) or np.any(e > 1):
            raise InputError(f"restitution table: values {e.tolist()} must each be in (0, 1]")
        object.__setattr__(self, "speeds", tuple(s.tolist()))
        object.__setattr__(self, "values", tuple(e.tolist()))

    def restitution(self, speed, **_):
        """epsilon at impact speed(s) ``speed`` [m/s] (log-linear interpolation, held at the ends)."""
        v = np.maximum(np.asarray(speed, dtype=float), 1e-300)
        return np.interp(np.log(v), np.log(self.speeds), self.values)[()]


def tabulate_law(law, **context) -> np.ndarray:
    """epsilon of ``law`` on :data:`SPEED_GRID`; ``context`` (E*, R*, m*) is passed to laws that need it."""
    eps = np.asarray(law.restitution(SPEED_GRID, **context), dtype=float)
    return np.clip(np.broadcast_to(eps, SPEED_GRID.shape).copy(), 1e-6, 1.0)
