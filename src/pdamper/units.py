"""Quantities as a person types them: ``120mm``, ``2 Hz``, ``3deg``, ``149g`` or plain SI.

pdamper works in SI inside; units are handled only at the edges (CLI options,
config files, CSV headers). A bare number (``0.12``, ``"0.12"``) is taken as SI
(metres, seconds, hertz, kilograms, radians ...) and returned unchanged.

Rules
-----
- A number with a unit is converted to SI and rounded to 15 significant digits,
  so ``"13mm"`` is exactly ``0.013`` (not ``0.013000000000000001``).
- The unit must have the dimension asked for: ``"12kg"`` is not a length, and a
  unit without physical dimension (``"5 percent"``, ``"5 deg"``) is not a length
  either. An angle takes angle units only (``deg``, ``rad``, ``arcmin``, ``turn``).
- ``"frequency"`` is any rate in 1/s: ``"2Hz"``, ``"120/min"``, and also an angular
  velocity with the radian taken as 1 (``"10rad/s"`` is 10 1/s, as for spins).
- ``µ``, ``μ`` and ``u`` are all "micro": ``"20µm"``, ``"20um"``.

Common units (``mm``, ``Hz``, ``deg``, ``g``, ``GPa``, ``kg/m^3``, ``mm/s`` ...) are read
from a small table; anything else (``"120/min"``, ``"2 inch"``, ``"0.5 g_0"``) goes to
:mod:`pint`, which is imported only then (it takes about half a second). The table agrees
with pint (tested).

The Python API takes the same inputs: every parameter object converts its fields in
``__post_init__`` (:func:`pdamper.schema.convert_fields`) and every public function declares
the dimension of its arguments with :func:`quantities`; both go through :func:`to_si`, which
also takes pint quantities (of any unit registry) and leaves plain numbers untouched.
"""

from __future__ import annotations

import functools
import math
import numbers
import re

from .errors import InputError, shown

__all__ = ["parse_quantity", "to_si", "quantities", "is_quantity", "unit_factor", "DIMENSIONS", "thousandth_hint"]

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

#: Significant digits kept after a unit conversion.
SIGNIFICANT_DIGITS = 15

_MICRO = ("µ", "μ")  # micro sign U+00B5 and Greek mu U+03BC; both mean "u"
#: Longest text read as a number with a unit (``"1.2345678901234567e-300 kg/m^3"`` is 31).
_LONGEST = 100


def _table() -> dict[str, tuple[str, float]]:
    """Unit text -> (dimension, factor to SI) for the units people type most."""
    prefixes = {"G": 1e9, "M": 1e6, "k": 1e3, "": 1.0, "c": 1e-2, "m": 1e-3, "u": 1e-6, "n": 1e-9}
    out: dict[str, tuple[str, float]] = {}

    def add(dimension, names, factors):
        for name in names:
            for p, f in factors.items():
                out[name.format(p=p)] = (dimension, f)

    add("length", ["{p}m"], {k: prefixes[k] for k in ("k", "", "c", "m", "u", "n")})
    add("time", ["{p}s"], {k: prefixes[k] for k in ("", "m", "u", "n")})
    add("time", ["min"], {"": 60.0})
    add("frequency", ["{p}Hz"], {k: prefixes[k] for k in ("M", "k", "", "m")})
    add("mass", ["{p}g"], {"k": 1.0, "": 1e-3, "m": 1e-6})
    add("angle", ["rad"], {"": 1.0})
    add("angle", ["{p}rad"], {"m": 1e-3, "u": 1e-6})
    add("angle", ["deg"], {"": math.pi / 180.0})
    add("force", ["{p}N"], {k: prefixes[k] for k in ("M", "k", "", "m")})
    for unit in ("{p}m/s",):
        add("velocity", [unit], {k: prefixes[k] for k in ("k", "", "c", "m", "u")})
    for unit in ("{p}m/s^2", "{p}m/s**2", "{p}m/s²"):
        add("acceleration", [unit], {k: prefixes[k] for k in ("", "c", "m")})
    add("pressure", ["{p}Pa"], {k: prefixes[k] for k in ("G", "M", "k", "")})
    for unit in ("kg/m^3", "kg/m**3", "kg/m³"):
        add("density", [unit], {"": 1.0})
    for unit in ("g/cm^3", "g/cm**3", "g/cm³"):
        add("density", [unit], {"": 1e3})
    return out


#: The fast path of :func:`parse_quantity` (see :func:`_table`).
COMMON_UNITS = _table()

_NUMBER_UNIT = re.compile(
    r"^\s*([+-]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][+-]?\d+)?)\s*([A-Za-z][A-Za-z/^*²³0-9]*)\s*$")


@functools.lru_cache(maxsize=1)
def _registry():
    import pint

    return pint.UnitRegistry(autoconvert_offset_to_baseunit=True)


def _a(dimension: str) -> str:
    """``"a length"``, ``"an angle"``, ``"a pure number"``."""
    noun = "pure number" if dimension == "dimensionless" else dimension
    return ("an " if noun[0] in "aeiou" else "a ") + noun


def _si(dimension: str) -> str:
    return DIMENSIONS[dimension] or "a pure number"


def _round(x: float) -> float:
    """``x`` rounded to :data:`SIGNIFICANT_DIGITS` significant digits (removes conversion noise)."""
    if x == 0.0 or not math.isfinite(x):
        return x
    return float(f"{x:.{SIGNIFICANT_DIGITS - 1}e}")


def parse_quantity(value, dimension: str, *, name: str = "value") -> float:
    """Return ``value`` in SI units of ``dimension`` as a float.

    ``value`` is a number (taken as SI, returned unchanged), a string such as
    ``"120mm"``, ``"2 Hz"``, ``"3deg"``, ``"0.5 m/s^2"`` or a pint quantity; converted values are rounded
    to 15 significant digits. ``dimension`` is a key of :data:`DIMENSIONS`. ``name``
    is used in error messages (e.g. ``"--length"``). Raises
    :class:`~pdamper.errors.InputError` with a one-line message for anything else.

    >>> parse_quantity("120mm", "length")
    0.12
    >>> parse_quantity("13mm", "length")
    0.013
    >>> round(parse_quantity("3deg", "angle"), 6)
    0.05236
    >>> parse_quantity("0.12", "length")
    0.12
    """
    if dimension not in DIMENSIONS:  # programming error, not user input
        raise ValueError(f"unknown dimension {dimension!r}; known: {sorted(DIMENSIONS)}")
    if isinstance(value, bool):
        raise InputError(f"{name}: expected {_a(dimension)} such as {_example(dimension)}, "
                         f"got {shown(value)}")
    if isinstance(value, numbers.Real):
        try:
            out = float(value)
        except OverflowError:  # a whole number beyond the largest float (10**309 and more)
            raise InputError(f"{name}: {shown(value)} is too large a number; give {_a(dimension)} such as "
                             f"{_example(dimension)}") from None
    elif is_quantity(value):
        out = _quantity_to_si(value, dimension, None, name)
        if not isinstance(out, float):
            raise InputError(f"{name}: expected one value, got an array {shown(_shown(value))}")
    else:
        text = str(value).strip()
        if not text:
            raise InputError(f"{name}: empty value; give {_a(dimension)} such as "
                             f"{_example(dimension)}")
        try:
            out = float(text)
        except ValueError:
            out = _convert(text, dimension, name)
    if not math.isfinite(out):
        raise InputError(f"{name}: {shown(value)} is not a finite number; give {_a(dimension)} "
                         f"such as {_example(dimension)}")
    return out


def _convert(text: str, dimension: str, name: str) -> float:
    """A number with a unit -> SI float of ``dimension`` (rounded), or InputError."""
    written = text
    if len(text) > _LONGEST:  # no quantity is written so long (and pint's parser takes a tenth of a second on it)
        raise InputError(f"{name}: cannot read {shown(written)} as {_a(dimension)}; write a number with a unit "
                         f"such as {_example(dimension)}")
    for mu in _MICRO:
        text = text.replace(mu, "u")
    m = _NUMBER_UNIT.match(text)
    if m is not None:
        known = COMMON_UNITS.get(m.group(2))
        if known is not None and known[0] == dimension:
            return _round(float(m.group(1)) * known[1])
    return _round(_convert_pint(text, written, dimension, name))


def _convert_pint(text: str, written: str, dimension: str, name: str) -> float:
    ureg = _registry()
    try:
        q = ureg.Quantity(text)
    except Exception:
        raise InputError(
            f"{name}: cannot read {shown(written)} as {_a(dimension)}; "
            f"write a number with a unit such as {_example(dimension)}") from None
    try:
        if isinstance(q, numbers.Real) or not list(q.unit_items()):
            # No unit at all ("1/2", "2*3"): a plain number, SI.
            magnitude = q if isinstance(q, numbers.Real) else q.magnitude
            return float(magnitude)
        return float(_from_quantity(q, written, dimension, name))
    except OverflowError:  # pint read a whole number beyond the largest float ("1111...1 mm", 400 digits)
        raise InputError(f"{name}: {shown(written)} is too large a number; give {_a(dimension)} such as "
                         f"{_example(dimension)}") from None


def _from_quantity(q, written: str, dimension: str, name: str):
    """A pint quantity (of any registry; scalar or array) -> its SI magnitude in ``dimension``."""
    unit = f"{q.units:~}" or str(q.units)
    root = str(q.to_root_units().units)
    is_angle = root == "radian"
    has_angle = "radian" in root
    if dimension == "angle":
        if is_angle or not list(q.unit_items()):
            return q.to("radian").magnitude
        raise InputError(f"{name}: {shown(written)} is not an angle (its unit is {unit}); use an angle "
                         f"unit such as {_example(dimension)} (a bare number is radians)")
    if dimension == "dimensionless":
        if q.dimensionless and not has_angle:
            return q.to("").magnitude
        raise InputError(f"{name}: {shown(written)} is not a pure number (its unit is {unit}); "
                         f"give a number such as {_example(dimension)}")
    if q.dimensionless:
        raise InputError(
            f"{name}: {shown(written)} is not {_a(dimension)}: {unit or 'a bare quantity'} has no physical "
            f"dimension; use a unit such as {_example(dimension)} (a bare number is taken in "
            f"{_si(dimension)})")
    if has_angle and dimension != "frequency":
        # "frequency" [1/s] also reads angular velocities (spins in rad/s, radian taken as 1).
        raise InputError(f"{name}: {shown(written)} is not {_a(dimension)} (its unit {unit} contains "
                         f"an angle); use a unit such as {_example(dimension)}")
    try:
        return q.to(DIMENSIONS[dimension]).magnitude
    except Exception:
        raise InputError(
            f"{name}: {shown(written)} is not {_a(dimension)} (its unit is {unit}); "
            f"use a unit such as {_example(dimension)}") from None


def is_quantity(value) -> bool:
    """True for a pint quantity (of any unit registry); pint itself is not imported."""
    return hasattr(value, "dimensionality") and hasattr(value, "magnitude") and hasattr(value, "to")


def _needs_conversion(value) -> bool:
    """True for what :func:`to_si` converts: a text, a pint quantity, or a list/tuple holding one."""
    if isinstance(value, str) or is_quantity(value):
        return True
    if isinstance(value, (list, tuple)):
        return any(_needs_conversion(v) for v in value)
    return False


def _shown(q) -> str:
    try:
        return f"{q:~}"
    except Exception:  # pragma: no cover - a quantity that cannot format itself
        return str(q)


def _quantity_to_si(q, dimension: str | None, unit: str | None, name: str):
    """A pint quantity -> SI float (rounded like a unit text) or float array (not rounded)."""
    if unit is not None:
        try:
            out = q.to(unit).magnitude
        except Exception:
            raise InputError(f"{name}: {shown(_shown(q))} is not in {unit} or a unit convertible to it; "
                             f"give e.g. '1 {unit}' or a bare number in {unit}") from None
    else:
        out = _from_quantity(q, _shown(q), dimension, name)
    if isinstance(out, numbers.Real):
        out = _round(float(out))
        if not math.isfinite(out):
            raise InputError(f"{name}: {shown(_shown(q))} is not a finite number")
        return out
    import numpy as np

    return np.asarray(out, dtype=float)  # arrays (records) are not rounded: a quantity in SI stays bit for bit


def _text_to_unit(text: str, unit: str, name: str) -> float:
    """A text in a unit that is not one of :data:`DIMENSIONS` (``"1.1 kN/m"`` for N/m)."""
    try:
        return float(text)
    except ValueError:
        pass
    try:
        if len(text) > _LONGEST:
            raise ValueError(text)
        q = _registry().Quantity(text.replace("µ", "u").replace("μ", "u"))
    except Exception:
        raise InputError(f"{name}: cannot read {shown(text)}; give a number in {unit} or a number with a unit "
                         f"such as '1 {unit}'") from None
    if isinstance(q, numbers.Real):
        return float(q)
    return _quantity_to_si(q, None, unit, name)


def to_si(value, dimension: str | None = "dimensionless", *, unit: str | None = None, name: str = "value"):
    """``value`` in SI: what every public function and parameter object does with its inputs.

    - a number, a numpy array, None or anything else that is not a text nor a pint quantity is
      returned *unchanged* (the same object: plain SI floats are never touched);
    - a text (``"120mm"``, ``"2 Hz"``) goes through :func:`parse_quantity`;
    - a pint quantity (scalar or array, any unit registry) is converted to the SI unit of
      ``dimension`` (a float, or a float array), checked like a text;
    - a list or tuple holding texts or quantities is converted entry by entry (same type back).

    ``unit`` instead of ``dimension`` names the SI unit of a quantity without a dimension name
    (``"N/m"``, ``"s/m"``). Raises :class:`~pdamper.errors.InputError` naming ``name``, what was
    expected and an example.

    >>> to_si("120mm", "length", name="length")
    0.12
    >>> to_si(0.12, "length") is not None
    True
    >>> to_si(["5mm", 0.01], "length")
    [0.005, 0.01]
    """
    if isinstance(value, str):
        if unit is not None:
            return _text_to_unit(value.strip(), unit, name)
        return parse_quantity(value, dimension, name=name)
    if is_quantity(value):
        return _quantity_to_si(value, dimension, unit, name)
    if isinstance(value, (list, tuple)) and _needs_conversion(value):
        return type(value)(to_si(v, dimension, unit=unit, name=f"{name}[{i}]") for i, v in enumerate(value))
    return value


def quantities(**dimensions):
    """Decorator: the named arguments of a function accept unit texts and pint quantities.

    ``dimensions`` maps an argument's name to a key of :data:`DIMENSIONS` (``stroke="length"``)
    or to an SI unit (``stiffness="N/m"``). Each such argument goes through :func:`to_si`
    before the function sees it; numbers and arrays are passed on as they are (a call with SI
    floats only costs one quick look at its arguments). The mapping is kept on the wrapper as
    ``__quantities__``.

    >>> @quantities(stroke="length")
    ... def twice(stroke):
    ...     return 2 * stroke
    >>> twice("6mm")
    0.012
    """
    def decorate(func):
        import inspect

        sig = inspect.signature(func)
        unknown = set(dimensions) - set(sig.parameters)
        if unknown:  # a programming error, caught when the module is imported
            raise TypeError(f"{func.__qualname__} has no argument(s) {sorted(unknown)}")

        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            if not any(map(_needs_conversion, args)) and not any(map(_needs_conversion, kwargs.values())):
                return func(*args, **kwargs)
            bound = sig.bind(*args, **kwargs)
            for key, dim in dimensions.items():
                if key in bound.arguments:
                    v = bound.arguments[key]
                    if dim in DIMENSIONS:
                        bound.arguments[key] = to_si(v, dim, name=key)
                    else:
                        bound.arguments[key] = to_si(v, None, unit=dim, name=key)
            return func(*bound.args, **bound.kwargs)

        wrapper.__quantities__ = dict(dimensions)
        return wrapper

    return decorate


def unit_factor(unit: str, dimension: str, *, name: str = "unit") -> float:
    """Factor that converts a number in ``unit`` to SI of ``dimension``.

    >>> unit_factor("mm", "length")
    0.001
    """
    return parse_quantity(f"1 {unit}", dimension, name=name)


def _example(dimension: str) -> str:
    return {
        "length": "'120mm' or 0.12",
        "time": "'10s' or '5ms'",
        "frequency": "'2Hz' or 2",
        "mass": "'149g' or 0.149",
        "angle": "'3deg' or 0.0524",
        "force": "'2N' or '0.5kN'",
        "velocity": "'0.1m/s' or '5mm/s'",
        "acceleration": "'9.81m/s^2'",
        "pressure": "'200MPa'",
        "density": "'7900kg/m^3'",
        "dimensionless": "0.9",
    }.get(dimension, "a number")


def thousandth_hint(value: float, upper: float, unit: str = "mm") -> str:
    """``"; did you mean '13mm'?"`` when a bare number (SI) read in ``unit``, a thousandth of the SI
    unit ("mm", "ms", "mm/s"), would be at most ``upper``; else ``""``."""
    return f"; did you mean '{value:g}{unit}'?" if 1e-3 * value <= upper else ""
