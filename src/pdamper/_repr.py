"""Short reprs for result objects: names, shapes and the key numbers, never a dump of arrays
(a notebook cell showing a run result prints a line, not 4,000 characters)."""

from __future__ import annotations

import dataclasses

import numpy as np

__all__ = ["short_repr"]

_LIMIT = 400


def _value(v) -> str:
    if isinstance(v, np.ndarray):
        return f"<{v.dtype} array {'x'.join(map(str, v.shape))}>"
    if isinstance(v, (float, np.floating)):
        return f"{float(v):.6g}"
    if isinstance(v, complex):
        return f"{v:.4g}"
    if isinstance(v, dict):
        return f"<dict of {len(v)}>"
    if isinstance(v, (list, tuple)) and len(v) > 4:
        return f"<{type(v).__name__} of {len(v)}>"
    if dataclasses.is_dataclass(v) and not isinstance(v, type):
        return f"<{type(v).__name__}>"
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "..."


def short_repr(obj) -> str:
    """``Name(field=value, ...)`` with arrays as their shape, nested results by their type, cut at
    about 400 characters; a class's ``_repr_first`` names properties shown first (e.g. eta_star)."""
    parts = [f"{name}={_value(getattr(obj, name))}" for name in getattr(type(obj), "_repr_first", ())]
    for f in dataclasses.fields(obj):
        if not f.repr:
            continue
        parts.append(f"{f.name}={_value(getattr(obj, f.name))}")
    text = f"{type(obj).__name__}({', '.join(parts)})"
    return text if len(text) <= _LIMIT else text[:_LIMIT - 4] + " ...)"
