r"""Coefficient of restitution tabulated against impact speed (user table).

The paper used a velocity-dependent COR from finite-element simulations and experiments
([23, 24] of the paper). A user gives pairs (impact speed [m/s], epsilon); between points
epsilon is interpolated linearly in ``log(speed)``, outside the table it is held at the end
values.

It is also the law a config file holds for a COR law of a user's own (any object with
``restitution(speed)``, :meth:`TabulatedRestitution.from_law`): its values at the kernels' speeds
(:data:`~pdamper.contact.restitution.SPEED_GRID`), which the kernels take to the same bits.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..schema import convert_fields, param, read_list
from .cor_constant import read_coefficient
from .restitution import SPEED_GRID, RestitutionLaw, register_restitution, tabulate_law

__all__ = ["TabulatedRestitution", "SPEED_GRID", "tabulate_law"]


@register_restitution
@dataclass(frozen=True, kw_only=True)
class TabulatedRestitution(RestitutionLaw):
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
    kind: str = param("table", kind="tag", key="law")

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

    @classmethod
    def from_config(cls, table: dict, section: str, key: str):
        """``{law = "table", speeds = ["10mm/s", "1m/s"], values = [0.95, 0.85]}``."""
        cls.check_table(table, section, key)
        sub = f"{section}.{key}"
        speeds = read_list(table["speeds"], f"[{sub}] speeds", "velocity")
        vals = table["values"]
        if not isinstance(vals, list):
            raise InputError(f"[{sub}] values = {shown(vals)} must be a list of numbers in (0, 1]")
        return cls(speeds=speeds, values=tuple(read_coefficient(v, f"[{sub}] values[{k}]") for k, v in enumerate(vals)))

    @classmethod
    def from_law(cls, law) -> "TabulatedRestitution":
        """The table of a COR law of your own, ``law`` (any object with ``restitution(speed)``, epsilon
        at impact speeds [m/s]), at the kernels' speeds :data:`~pdamper.contact.restitution.SPEED_GRID`
        (clipped to [1e-6, 1], as the kernels clip every law): the law the kernels run for ``law``,
        bit for bit, and what a config file holds for it. A law whose ``restitution`` needs the
        contact (``e_star``, ``r_star``, ``m_star``) cannot be tabulated once for every contact and is
        refused in one line saying how to tabulate it for yours."""
        name = type(law).__name__
        how = ("tabulate it for your contact: pdamper.TabulatedRestitution(speeds=pdamper.contact.SPEED_GRID, "
               "values=law.restitution(pdamper.contact.SPEED_GRID, e_star=..., r_star=..., m_star=...)), or make it "
               "a registered law (pdamper.contact.register_restitution)")
        if not callable(getattr(law, "restitution", None)):
            raise InputError(f"restitution law {name}: has no restitution(speed) method; give a number in (0, 1], "
                             "a pdamper restitution law, or an object with restitution(speed)")
        try:
            eps = tabulate_law(law)
        except TypeError as exc:
            raise InputError(f"restitution law {name}: its restitution(speed) needs more than the impact speed "
                             f"({' '.join(str(exc).split())}), so one table cannot stand for it at every contact; "
                             f"{how}") from None
        except Exception as exc:  # noqa: BLE001  (a user's code: any failure, said in one line)
            raise InputError(f"restitution law {name}: restitution(speed) failed at the kernels' speeds "
                             f"({type(exc).__name__}: {' '.join(str(exc).split())}); {how}") from None
        if not np.all(np.isfinite(eps)):
            raise InputError(f"restitution law {name}: restitution(speed) is not a finite number at every impact "
                             f"speed from {SPEED_GRID[0]:g} to {SPEED_GRID[-1]:g} m/s")
        return cls(speeds=tuple(SPEED_GRID.tolist()), values=tuple(eps.tolist()))
