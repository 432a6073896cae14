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

:func:`read_value` reads one value as its spec says, with the config reader's messages (the
reader and :func:`replace` both use it), and :func:`replace` changes a case by config keys:
``replace(case, {"drive.stroke": "13mm", "contact.friction": 0.2})`` walks the parameter
objects by their specs (``section=`` on the fields of the root object says which config section
each holds, ``inline=True`` merges a nested object's keys into its section, ``read=`` converts a
custom field's value) and rebuilds them with :func:`dataclasses.replace`, so every
``__post_init__`` checks the new values.

This module sits at the bottom of the layers: it imports only :mod:`pdamper.errors` and
:mod:`pdamper.units`.
"""

from __future__ import annotations

import dataclasses
import difflib
from collections.abc import Callable
from dataclasses import MISSING, dataclass

from .errors import InputError, shown
from .units import _example, _needs_conversion, is_quantity, parse_quantity, to_si

__all__ = ["Spec", "param", "spec_of", "plain_fields", "config_keys", "check_choice", "convert_fields",
           "read_value", "read_fields", "write_fields", "read_quantity", "read_number", "check_keys", "suggest",
           "replace", "OwnTable"]

#: Kinds of field value: a real number, a whole number, a text, a list of numbers, a list of
#: [x, y, z] rows, a switch (true or false), a constant type tag (``kind`` / ``shape``, written
#: but not read as a value), or custom (read by the section's own code).
KINDS = ("number", "whole", "text", "list", "rows", "flag", "tag", "custom")


@dataclass(frozen=True, kw_only=True)
class Spec:
    """What a parameter field is (stored in ``dataclasses.field(metadata={"pdamper": Spec(...)})``).

    Parameters
    ----------
    kind : one of :data:`KINDS`; by default inferred from the field's default (bool: "flag",
        int: "whole", str: "text", otherwise "number").
    dimension : a dimension of :data:`pdamper.units.DIMENSIONS` ("length", "time", ...); the value
        is held in its SI unit and a config may give it with any unit of that dimension. None: a
        plain number.
    unit : the SI unit written in messages when ``dimension`` is None (e.g. "N/m", "s/m").
    choices : the allowed values of a text field.
    auto : None is a value of the field, written ``"auto"`` in a config file.
    key : the field's key in a config file when it differs from the field name.
    paper : the paper's value as a person writes it ("5 mm"), named in messages.
    example : an example value for messages about list rows ("'5mm'").
    section : on a field of the root object (a case): the config section the field is in. A field
        holding a parameter object (or a tuple of them) makes that object's fields the section's
        keys; a plain field is a key of the section itself. The object's class may name another
        section with a class attribute ``config_section`` (a coupled structure is ``[structure]``,
        not ``[drive]``).
    inline : the field holds a parameter object whose keys are keys of the enclosing section
        (the container's geometry: ``container.length``).
    read : for a custom field, ``read(value, section)`` turns a config value (a material name, a
        restitution number, ...) into the field's value; objects already built pass through.
    write_default : False: the key is written to a config file only when its value differs from
        the field's default, so that the configs of cases that leave it alone -- and the
        fingerprints of the result stores made of them -- stay what they were before the key
        existed (a key added to an established section).
    many : a whole number or a list of them (``damper_dof = 2`` or ``[2, 1]``: a damper at each);
        the value is then an int or a tuple of ints, written as it is.
    """

    kind: str | None = None
    dimension: str | None = None
    unit: str | None = None
    choices: tuple | None = None
    auto: bool = False
    key: str | None = None
    paper: str | None = None
    example: str | None = None
    section: str | None = None
    inline: bool = False
    read: Callable | None = None
    write_default: bool = True
    many: bool = False

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
    kind = ("flag" if isinstance(d, bool) else "whole" if isinstance(d, int)
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
    raise InputError(f"{section}.{name} = {shown(v)}; {hint}choose {listed}")


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


# --------------------------------------------------------------------------- reading one value

def suggest(word: str, allowed, what: str = "{!r}") -> str:
    """``"did you mean ...?"`` for the nearest of ``allowed``, else ``"allowed: ..."``; ``what``
    formats each name (``"[{}]"`` for a section)."""
    near = difflib.get_close_matches(str(word), list(allowed), n=1, cutoff=0.6)
    if near:
        return f"did you mean {what.format(near[0])}?"
    return "allowed: " + ", ".join(what.format(a) for a in allowed)


def _quoted(key, allowed) -> str:
    near = difflib.get_close_matches(str(key), list(allowed), n=1, cutoff=0.6)
    if near:
        return f"did you mean {near[0]!r}?"
    return "allowed keys: " + ", ".join(allowed)


def check_keys(table, section: str, allowed) -> None:
    """Raise :class:`InputError` for the first key of ``table`` not in ``allowed``, suggesting the nearest."""
    for key in table:
        if key not in allowed:
            raise InputError(f"unknown key {shown(key)} in [{section}]; {_quoted(key, allowed)}")


def _a(word: str) -> str:
    return ("an " if word[:1] in "aeiou" else "a ") + word


def _grammar(msg: str) -> str:
    for word in ("angle", "acceleration"):
        msg = msg.replace(f" a {word}", f" an {word}")
    return msg


def read_quantity(value, label: str, dimension: str) -> float:
    """``value`` (a number in SI, a text with a unit, a pint quantity) in SI units of ``dimension``;
    ``label`` (``"[drive] stroke"``) names it in messages."""
    if isinstance(value, (dict, list)):
        kind = "table" if isinstance(value, dict) else "list"
        raise InputError(f"{label} = {shown(value)}: expected {_a(dimension)} such as {_example(dimension)}, not a {kind}")
    try:
        return parse_quantity(value, dimension, name=label)
    except InputError as exc:
        msg = _grammar(str(exc))
        rest = msg[len(label) + 2:] if msg.startswith(label + ": ") else msg
        raise InputError(f"{label} = {rest}" if rest.startswith(("'", '"')) else f"{label}: {rest}") from None


def _finite_size(value: int, label: str) -> int:
    """A whole number a float can hold (TOML's integers have no bound: ``10**400`` is one)."""
    try:
        float(value)
    except OverflowError:
        raise InputError(f"{label} = {shown(value)} is too large a number") from None
    return value


def read_number(value, label: str) -> float:
    """A pure number: a number as it is, or a text such as ``"0.5"``."""
    if isinstance(value, int) and not isinstance(value, bool):
        return _finite_size(value, label)
    if isinstance(value, float):
        return value
    if isinstance(value, bool) or isinstance(value, (dict, list)):
        raise InputError(f"{label} = {shown(value)} must be a number")
    return read_quantity(value, label, "dimensionless")


def _entry(value, name, index, dimension) -> float:
    label = f"{name}[{index}]"
    if isinstance(value, (dict, list)):
        raise InputError(f"{label} = {shown(value)}: expected a {dimension} such as {_example(dimension)}")
    return read_quantity(value, label, dimension)


def read_list(value, label: str, dimension: str) -> tuple:
    """A list of quantities of ``dimension`` as a tuple of SI floats."""
    if not isinstance(value, list):
        raise InputError(f"{label} = {shown(value)} must be a list of {dimension}s, e.g. [1, 2, 3]")
    return tuple(_entry(v, label, k, dimension) for k, v in enumerate(value))


def _rows(rows, label, dimension, example) -> tuple:
    if not isinstance(rows, list) or not all(isinstance(r, list) and len(r) == 3 for r in rows):
        raise InputError(f"{label} must be a list of [x, y, z] rows (one per sphere, container frame), "
                         f"e.g. [[0, {example}, 0], [{example}, 0, 0]]")
    return tuple(tuple(_entry(v, f"{label}[{i}]", k, dimension) for k, v in enumerate(r)) for i, r in enumerate(rows))


def _choice(v, label, choices):
    if not isinstance(v, str):
        raise InputError(f"{label} = {shown(v)} must be a string: one of " + ", ".join(repr(c) for c in choices))
    if v not in choices:
        near = difflib.get_close_matches(v, choices, n=1, cutoff=0.5)
        hint = f"did you mean {near[0]!r}? " if near else ""
        raise InputError(f"{label} = {shown(v)} is not allowed; {hint}choose one of " + ", ".join(repr(c) for c in choices))
    return v


def read_value(v, s: Spec, section: str, key: str):
    """The config value ``v`` of key ``key`` in ``[section]`` read as the spec ``s`` says: a
    quantity with or without a unit, a whole number, a choice, ``"auto"`` (None), a list or rows
    of quantities; a custom field through its ``read`` (or as it is). Messages name
    ``[section] key`` and the paper's value."""
    label = f"[{section}] {key}"
    if s.kind == "custom":
        return s.read(v, section) if s.read is not None else v
    try:
        if s.choices is not None:
            return _choice(v, label, s.choices)
        if s.kind == "text":
            if not isinstance(v, str):
                raise InputError(f"{label} = {shown(v)} must be a string")
            return v
        if s.kind == "flag":
            if not isinstance(v, bool):
                raise InputError(f"{label} = {shown(v)} must be true or false")
            return v
        if s.kind == "whole":
            if s.many and isinstance(v, (list, tuple)):
                if not v:
                    raise InputError(f"{label} = []: give a whole number or a list of them, e.g. [2, 1]")
                return tuple(_whole(x, f"{label}[{k}]") for k, x in enumerate(v))
            if s.many and (isinstance(v, bool) or not isinstance(v, (int, float)) or not _integral(v)):
                raise InputError(f"{label} = {shown(v)} must be a whole number or a list of them, e.g. [2, 1]")
            return _whole(v, label)
        if s.kind == "list":
            return read_list(v, label, s.dimension or "dimensionless")
        if s.kind == "rows":
            return _rows(v, label, s.dimension, s.example)
        if s.auto and isinstance(v, str) and v.strip().lower() == "auto":
            return None
        if s.dimension is not None:
            return read_quantity(v, label, s.dimension)
        if s.unit is not None and (isinstance(v, str) or is_quantity(v)):
            return to_si(v, None, unit=s.unit, name=label)
        return read_number(v, label)
    except InputError as exc:
        if s.paper is None or "paper" in str(exc):
            raise
        raise InputError(f"{exc} (paper: {s.paper})") from None


def _whole(v, label: str) -> int:
    if isinstance(v, float) and v.is_integer():
        return int(v)
    if isinstance(v, bool) or not isinstance(v, int):
        raise InputError(f"{label} = {shown(v)} must be a whole number")
    return _finite_size(v, label)


def _integral(v) -> bool:
    """A number with no fraction (an int of any size, a float like 3.0)."""
    return isinstance(v, int) or (isinstance(v, float) and v.is_integer())


def read_fields(t: dict, section: str, cls) -> dict:
    """Keyword arguments for ``cls`` from the config table ``t``: each plain field present, read by its spec."""
    return {f.name: read_value(t[s.key or f.name], s, section, s.key or f.name)
            for f, s in plain_fields(cls) if (s.key or f.name) in t}


def _num(v):
    """Keep ints as ints (TOML integer), everything else a float."""
    if isinstance(v, bool):
        return v
    if isinstance(v, int):
        return v
    return float(v)


def write_fields(obj) -> dict:
    """The plain fields of ``obj`` as config keys in plain SI numbers, type tags first (the inverse
    of :func:`read_fields`); None is left out, or written ``"auto"`` where the spec says so."""
    out = {}
    for f in dataclasses.fields(obj):
        s = spec_of(f)
        if s.kind == "tag":
            out[s.key or f.name] = getattr(obj, f.name)
    for f, s in plain_fields(type(obj)):
        v = getattr(obj, f.name)
        key = s.key or f.name
        if not s.write_default and v == f.default:
            continue
        if v is None:
            if s.auto:
                out[key] = "auto"
        elif s.kind == "flag":
            out[key] = bool(v)
        elif s.kind == "text":
            out[key] = v
        elif s.kind == "whole":
            out[key] = [int(x) for x in v] if isinstance(v, (list, tuple)) else int(v)
        elif s.kind == "list":
            out[key] = [float(x) for x in v]
        elif s.kind == "rows":
            out[key] = [[float(x) for x in row] for row in v]
        else:
            out[key] = float(v) if s.dimension is not None else _num(v)
    return out


# --------------------------------------------------------------------------- changing a case

def _plain(value, s: Spec):
    """A value given in Python as the config reader takes it: tuples as lists, numpy scalars as
    numbers, None of an optional field as ``"auto"``."""
    if value is None and s.auto:
        return "auto"
    if isinstance(value, tuple) and s.kind in ("list", "rows"):
        return [list(r) if isinstance(r, tuple) else r for r in value] if s.kind == "rows" else list(value)
    if s.kind in ("list", "rows") and hasattr(value, "tolist") and not is_quantity(value):
        return value.tolist()
    if hasattr(value, "item") and not isinstance(value, (str, bytes)) and not is_quantity(value) \
            and getattr(value, "ndim", None) == 0:
        return value.item()
    return value


def _is_param(obj) -> bool:
    return dataclasses.is_dataclass(obj) and not isinstance(obj, type)


def _section_of(f: dataclasses.Field, value) -> str | None:
    """The config section field ``f`` of the root holds (its value's own ``config_section`` first; an
    optional object that is None, such as a case's ``rig``, holds none)."""
    s = spec_of(f).section
    if s is None or value is None:
        return None
    items = value if isinstance(value, tuple) and value and all(_is_param(v) for v in value) else (value,)
    if _is_param(items[0]):
        return getattr(type(items[0]), "config_section", s)
    return s


def _keys(obj) -> dict:
    """The config keys of the parameter object ``obj``: ``key -> (inline field or None, field, spec)``."""
    out = {}
    for f in dataclasses.fields(obj):
        s = spec_of(f)
        if s.inline:
            for g in dataclasses.fields(getattr(obj, f.name)):
                out.setdefault(spec_of(g).key or g.name, (f.name, g, spec_of(g)))
        else:
            out.setdefault(s.key or f.name, (None, f, s))
    return out


def _what(obj, section) -> str:
    """``" (this [drive] has kind = 'samples')"``: the type tags of ``obj`` and its inline objects,
    for messages."""
    tags = [f"{k} = {getattr(obj if i is None else getattr(obj, i), f.name)!r}"
            for k, (i, f, s) in _keys(obj).items() if s.kind == "tag"]
    return f" (this [{section}] has {', '.join(tags)})" if tags else ""


def _change(obj, items: dict, section: str):
    """``obj`` with the config keys of ``items`` (``key -> (dotted, value)``) changed."""
    keys = _keys(obj)
    own, inner = {}, {}
    for key, (dotted, value) in items.items():
        if key not in keys:
            raise InputError(f"{shown(dotted)}: unknown key {shown(key)} in [{section}]; "
                             + _quoted(key, list(keys)) + _what(obj, section))
        where, f, s = keys[key]
        holder = obj if where is None else getattr(obj, where)
        if s.kind == "tag":
            if value == getattr(holder, f.name):
                continue
            raise InputError(f"{shown(dotted)}: {key} = {shown(getattr(holder, f.name))} cannot be changed key by key; "
                             f"give the whole new object as {shown(section)}")
        new = read_value(_plain(value, s), s, section, key)
        (own if where is None else inner.setdefault(where, {}))[f.name] = new
    for where, kw in inner.items():
        own[where] = dataclasses.replace(getattr(obj, where), **kw)
    return dataclasses.replace(obj, **own) if own else obj


def replace(obj, changes: dict):
    """``obj`` (a case) with the config keys of ``changes`` set: ``{"drive.stroke": "13mm",
    "contact.friction": 0.2, "run.cycles": 30}``.

    Each value is read as the key's spec says, exactly as in a config file (a unit text, a pint
    quantity or an SI number; ``"auto"`` or None for an optional value; a material name or a
    restitution number where the field's spec has a ``read``; a parameter object already built
    as it is), and the objects are rebuilt with :func:`dataclasses.replace` from the bottom up,
    so each ``__post_init__`` checks its new values. A key given as a section alone
    (``{"drive": Still(duration_s=1.0)}``) replaces that whole object. A section holding several
    objects (a bed of several particle sets) is refused: replace the tuple itself. Keys not given
    keep their values, the same objects. Unknown sections and keys raise :class:`InputError`
    naming the key and the nearest allowed one.
    """
    if not changes:
        return obj
    sections: dict[str, list] = {}  # section -> the root's fields in it
    declared = {}  # section named by a field's spec -> the field
    for f in dataclasses.fields(obj):
        name = _section_of(f, getattr(obj, f.name))
        if name is not None:
            sections.setdefault(name, []).append(f)
            declared.setdefault(spec_of(f).section, f)
    groups: dict[str, dict] = {}
    for dotted, value in changes.items():
        section, sep, key = str(dotted).partition(".")
        if not section or (sep and (not key or "." in key)):
            raise InputError(f"{shown(dotted)}: write a key as 'section.key', e.g. 'drive.stroke'")
        if section not in sections:
            if section in declared:
                f = declared[section]
                other = _section_of(f, getattr(obj, f.name))
                raise InputError(f"{shown(dotted)}: this case's {f.name} is a [{other}], not a [{section}]; "
                                 f"give [{other}] keys")
            raise InputError(f"{shown(dotted)}: unknown section [{section}]; " + suggest(section, sections, "[{}]"))
        groups.setdefault(section, {})[key] = (dotted, value)
    kw = {}
    for section, items in groups.items():
        kw.update(_change_section(obj, sections[section], items, section))
    return dataclasses.replace(obj, **kw)


def _change_section(obj, fields: list, items: dict, section: str) -> dict:
    """The new values of the root's ``fields`` that make up ``section``: its plain keys read by
    their specs, the rest changed in the section's parameter object (or the one object of a tuple)."""
    def holds(f):
        v = getattr(obj, f.name)
        return _is_param(v) or isinstance(v, tuple) and spec_of(f).kind == "custom"

    holder = next((f for f in fields if holds(f)), None)
    own = {spec_of(f).key or f.name: f for f in fields if not holds(f)}
    if "" in items:  # the whole object of the section
        if len(items) > 1 or holder is None:
            raise InputError(f"{shown(section)}: give the whole [{section}] object alone, or its keys")
        return {holder.name: items[""][1]}
    kw = {own[k].name: read_value(_plain(v, spec_of(own[k])), spec_of(own[k]), section, k)
          for k, (_, v) in items.items() if k in own}
    rest = {k: v for k, v in items.items() if k not in own}
    if not rest:
        return kw
    if holder is None:
        k, (dotted, _) = next(iter(rest.items()))
        raise InputError(f"{shown(dotted)}: unknown key {shown(k)} in [{section}]; " + _quoted(k, list(own)))
    value = getattr(obj, holder.name)
    if isinstance(value, tuple):
        if len(value) != 1:
            dotted = next(iter(rest.values()))[0]
            raise InputError(f"{shown(dotted)}: the case has {len(value)} [[{section}]] sets; replace "
                             f"the {holder.name} tuple itself (e.g. with dataclasses.replace on the one set)")
        kw[holder.name] = (_change(value[0], rest, section),)
    else:
        kw[holder.name] = _change(value, rest, section)
    return kw


class OwnTable:
    """What a kind that reads its own config table answers about it (a drive of
    :mod:`pdamper.excitation`, a load of :mod:`pdamper.structure.loads`): its words for messages and
    the keys its table may hold (its fields' and ``config_extra_keys``)."""

    #: the config section the kind is read from; the kind in words; keys beyond the fields
    config_section = ""
    config_label = ""
    config_extra_keys: tuple = ()

    @classmethod
    def label(cls) -> str:
        """The kind in words, for messages (``"a 'samples' drive"``)."""
        return cls.config_label or f"a {cls.__dataclass_fields__['kind'].default!r} {cls.config_section}"

    @classmethod
    def table_keys(cls) -> tuple:
        """Every key a config table of this kind may hold (``kind`` aside)."""
        return config_keys(cls) + tuple(cls.config_extra_keys)


def register_tagged(registry: dict, cls, tag_field: str, what: str, needs: tuple = (), has: tuple = ()):
    """Put the dataclass ``cls`` into ``registry`` under the default of its field ``tag_field``
    (a shape's ``shape``, a drive's ``kind``), once it has the methods ``needs`` and the
    attributes (or properties) ``has``; returns ``cls`` (so it serves as a class decorator)."""
    tag = next((f.default for f in dataclasses.fields(cls) if f.name == tag_field), None)
    if not isinstance(tag, str) or not tag:
        raise TypeError(f"{cls.__name__}: a {what} needs a field {tag_field!r} with its tag as default")
    missing = [m for m in needs if not callable(getattr(cls, m, None))]
    missing += [a for a in has if not hasattr(cls, a)]
    if missing:
        raise TypeError(f"{cls.__name__} does not answer the {what} protocol: missing {', '.join(missing)}")
    registry[tag] = cls
    return cls

