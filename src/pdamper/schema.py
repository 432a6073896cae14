"""The one schema of a case: what each parameter field is, kept on the dataclass field itself.

Every parameter dataclass (:mod:`pdamper.params`, :mod:`pdamper.excitation`, the containers of
:mod:`pdamper.geometry`) declares its fields with :func:`param`, which stores a :class:`Spec` in
the field's ``metadata``: the physical dimension (so the config reader knows that ``"12mm"`` is a
length and the writer knows the field is in metres), the allowed values, whether ``"auto"`` stands
for ``None``, the key the field has in a config file, and the paper's value (for messages).

:mod:`pdamper.config` reads and writes every plain field from these specs, so adding a field to a
dataclass with ``param(...)`` makes it a config key, an override (``--set section.key=value``) and
a written key at once, with the same error messages as every other key. Fields whose value is
structured (a material, a restitution law, the container's geometry) say ``kind="custom"`` and
are read by the section's own code in :mod:`pdamper.config`.

The same specs let the Python API take units: :func:`convert_fields`, called first in each
dataclass's ``__post_init__``, turns ``Cuboid(length="120mm")`` or a pint quantity into SI floats
and leaves plain numbers untouched.

This module sits at the bottom of the layers: it imports only :mod:`pdamper.errors` and
:mod:`pdamper.units`.
"""

from __future__ import annotations

import dataclasses
import difflib
from dataclasses import MISSING, dataclass

from .errors import InputError
from .units import _needs_conversion, to_si

__all__ = ["Spec", "param", "spec_of", "plain_fields", "config_keys", "check_choice", "convert_fields"]

#: Kinds of field value: a real number, a whole number, a text, a list of numbers, a list of
#: [x, y, z] rows, a constant type tag (``kind`` / ``shape``, written but not read as a value),
#: or custom (read by the section's own code).
KINDS = ("number", "whole", "text", "list", "rows", "tag", "custom")


@dataclass(frozen=True, kw_only=True)
class Spec:
    """What a parameter field is (stored in ``dataclasses.field(metadata={"pdamper": Spec(...)})``).

    Parameters
    ----------
    kind : one of :data:`KINDS`; by default inferred from the field's default (int: "whole",
        str: "text", otherwise "number").
    dimension : a dimension of :data:`pdamper.units.DIMENSIONS` ("length", "time", ...); the value
        is held in its SI unit and a config may give it with any unit of that dimension. None: a
        plain number.
    unit : the SI unit written in messages when ``dimension`` is None (e.g. "N/m", "s/m").
    choices : the allowed values of a text field.
    auto : None is a value of the field, written ``"auto"`` in a config file.
    key : the field's key in a config file when it differs from the field name.
    paper : the paper's value as a person writes it ("5 mm"), named in messages.
    example : an example value for messages about list rows ("'5mm'").
    """

    kind: str | None = None
    dimension: str | None = None
    unit: str | None = None
    choices: tuple | None = None
    auto: bool = False
    key: str | None = None
    paper: str | None = None
    example: str | None = None

    def __post_init__(self):
        if self.kind is not None and self.kind not in KINDS:
            raise ValueError(f"Spec kind {self.kind!r}; choose one of {KINDS}")


def param(default=MISSING, *, default_factory=MISSING, **spec) -> dataclasses.Field:
    """A dataclass field carrying a :class:`Spec` (keyword arguments) in its metadata."""
    return dataclasses.field(default=default, default_factory=default_factory, metadata={"pdamper": Spec(**spec)})


def spec_of(f: dataclasses.Field) -> Spec:
    """The field's :class:`Spec`, its kind filled in from the default when not given."""
    s = f.metadata.get("pdamper", Spec())
    if s.kind is not None:
        return s
    d = f.default
    kind = ("whole" if isinstance(d, int) and not isinstance(d, bool)
            else "text" if isinstance(d, str) else "number")
    return dataclasses.replace(s, kind=kind)


def plain_fields(cls) -> list[tuple[dataclasses.Field, Spec]]:
    """The fields of ``cls`` that the config reader reads from their spec alone (not custom, not tags)."""
    return [(f, s) for f in dataclasses.fields(cls) for s in (spec_of(f),) if s.kind not in ("custom", "tag")]


def config_keys(cls, *, drop: tuple = ()) -> tuple[str, ...]:
    """The config keys of ``cls``'s fields in field order: plain and custom fields, not type tags
    nor the field names in ``drop``."""
    return tuple(s.key or f.name for f in dataclasses.fields(cls) for s in (spec_of(f),)
                 if s.kind != "tag" and f.name not in drop)


def check_choice(obj, name: str, section: str) -> None:
    """Raise :class:`InputError` when text field ``name`` of ``obj`` is not one of its spec's choices."""
    f = next(f for f in dataclasses.fields(obj) if f.name == name)
    choices = spec_of(f).choices
    v = getattr(obj, name)
    if v in choices:
        return
    near = difflib.get_close_matches(v, choices, n=1, cutoff=0.5) if isinstance(v, str) else []
    hint = f"did you mean {near[0]!r}? " if near else ""
    listed = ", ".join(repr(c) for c in choices[:-1]) + f" or {choices[-1]!r}" if len(choices) > 1 else repr(choices[0])
    raise InputError(f"{section}.{name} = {v!r}; {hint}choose {listed}")


def convert_fields(obj, section: str) -> None:
    """Convert the fields of the (frozen) dataclass ``obj`` given as unit texts or pint quantities to
    SI floats, as their specs say (``"120mm"`` -> 0.12 for a length); called first in
    ``__post_init__``. Numbers, arrays and None are left as they are (the same objects), so a
    case built from SI floats is exactly the case it was before. Fields with a ``dimension``,
    a ``unit`` or a plain number kind are converted; ``section`` names the field in messages
    (``"container.length"``)."""
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if not _needs_conversion(v):
            continue
        s = spec_of(f)
        if s.kind not in ("number", "list", "rows"):
            continue
        name = f"{section}.{s.key or f.name}"
        if s.dimension is None and s.unit is not None:
            new = to_si(v, None, unit=s.unit, name=name)
        else:
            new = to_si(v, s.dimension or "dimensionless", name=name)
        object.__setattr__(obj, f.name, new)
