"""Quantities as a person types them: ``120mm``, ``2 Hz``, ``3deg``, ``149g`` or plain SI.

pdamper works in SI inside; units are handled only at the edges (CLI options,
config files, CSV headers) with :mod:`pint`. A bare number is taken as SI
(metres, seconds, hertz, kilograms, radians ...), except where a caller says
otherwise.
"""

from __future__ import annotations

import functools
import math
import numbers

from .errors import InputError

__all__ = ["parse_quantity", "unit_factor", "DIMENSIONS"]

#: Dimension names accepted by :func:`parse_quantity`, with their SI unit.
DIMENSIONS = {
    "length": "m",
    "time": "s",
    "frequency": "Hz",
    "mass": "kg",
    "angle": "rad",
    "force": "N",
    "velocity": "m/s",
    "acceleration": "m/s^2",
    "pressure": "Pa",
    "density": "kg/m^3",
    "dimensionless": "",
}


@functools.lru_cache(maxsize=1)
def _registry():
    import pint

    ureg = pint.UnitRegistry(autoconvert_offset_to_baseunit=True)
    return ureg


def _si_unit(ureg, dimension: str):
    try:
        name = DIMENSIONS[dimension]
    except KeyError:  # programming error, not user input
        raise ValueError(f"unknown dimension {dimension!r}; known: {sorted(DIMENSIONS)}") from None
    return ureg.dimensionless if name == "" else ureg(name).units


def parse_quantity(value, dimension: str, *, name: str = "value") -> float:
    """Return ``value`` in SI units of ``dimension`` as a float.

    ``value`` is a number (taken as SI) or a string such as ``"120mm"``,
    ``"2 Hz"``, ``"3deg"``, ``"0.5 m/s^2"``. ``name`` is used in error messages
    (e.g. ``"--length"``).

    >>> parse_quantity("120mm", "length")
    0.12
    >>> round(parse_quantity("3deg", "angle"), 6)
    0.05236
    """
    if isinstance(value, bool):
        raise InputError(f"{name}: expected a {dimension}, got {value!r}")
    if isinstance(value, numbers.Real):
        out = float(value)
    else:
        text = str(value).strip()
        if not text:
            raise InputError(f"{name}: empty value; give a {dimension} such as "
                             f"{_example(dimension)}")
        try:
            out = float(text)
        except ValueError:
            ureg = _registry()
            try:
                q = ureg.Quantity(text.replace("µ", "u").replace("μ", "u"))
            except Exception:
                raise InputError(
                    f"{name}: cannot read {text!r} as a {dimension}; "
                    f"write a number with a unit such as {_example(dimension)}") from None
            target = _si_unit(ureg, dimension)
            if isinstance(q, numbers.Real):
                q = ureg.Quantity(q, "")
            if q.dimensionless and dimension != "dimensionless":
                # A plain number with a dimensionless suffix (e.g. "5 percent"): keep SI meaning.
                if dimension == "angle":
                    out = float(q.to("radian").magnitude)
                else:
                    out = float(q.to("").magnitude)
            else:
                try:
                    out = float(q.to(target).magnitude)
                except Exception:
                    raise InputError(
                        f"{name}: {text!r} is not a {dimension} (its unit is "
                        f"{q.units:~}); use a unit such as {_example(dimension)}") from None
    if not math.isfinite(out):
        raise InputError(f"{name}: {value!r} is not a finite number")
    return out


def unit_factor(unit: str, dimension: str, *, name: str = "unit") -> float:
    """Factor that converts a number in ``unit`` to SI of ``dimension`` (``unit_factor("mm", "length") == 1e-3``)."""
    return parse_quantity(f"1 {unit}", dimension, name=name)


def _example(dimension: str) -> str:
    return {
        "length": "'120mm' or 0.12",
        "time": "'10s' or '5ms'",
        "frequency": "'2Hz' or 2",
        "mass": "'149g' or 0.149",
        "angle": "'3deg' or 0.0524",
        "force": "'2N' or '0.5kN'",
        "velocity": "'0.1m/s'",
        "acceleration": "'9.81m/s^2'",
        "pressure": "'200MPa'",
        "density": "'7900kg/m^3'",
        "dimensionless": "0.9",
    }.get(dimension, "a number")
