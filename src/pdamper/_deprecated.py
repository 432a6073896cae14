"""Old public names kept for a while (docs/names.md, "Renamed, with the old name kept"): each
warns with a :class:`DeprecationWarning` naming its replacement and gives the same object.

- :class:`renamed` -- an attribute under its old name: ``time_step = renamed("time_step_s")``
  in the class body (a plain descriptor, not a dataclass field).
- :func:`renamed_function` -- a function under its old name (another spelling).
- :func:`renamed_keyword` -- a keyword argument under its old name.
"""

from __future__ import annotations

import functools
import warnings

__all__ = ["renamed", "renamed_function", "renamed_keyword", "warn_renamed"]


def warn_renamed(old: str, new: str, stacklevel: int = 3) -> None:
    """Warn that ``old`` is deprecated in favour of ``new`` (``stacklevel`` 3: the caller of the
    function that calls this)."""
    warnings.warn(f"{old} is deprecated; use {new} (same value; docs/names.md)", DeprecationWarning,
                  stacklevel=stacklevel)


class renamed:
    """Read-only attribute under an old name: warns and returns the attribute ``new``."""

    def __init__(self, new: str):
        self.new = new

    def __set_name__(self, owner, name):
        self.old = name
        self.__doc__ = f"Deprecated: the old name of :attr:`{self.new}`."

    def __get__(self, obj, objtype=None):
        if obj is None:
            return self
        cls = type(obj).__name__
        warn_renamed(f"{cls}.{self.old}", f"{cls}.{self.new}")
        return getattr(obj, self.new)


def renamed_function(func, old: str):
    """``func`` under the old name ``old``: warns on every call, then calls ``func``."""

    @functools.wraps(func)
    def alias(*args, **kwargs):
        warn_renamed(f"{func.__module__}.{old}", f"{func.__module__}.{func.__name__}")
        return func(*args, **kwargs)

    alias.__name__ = alias.__qualname__ = old
    alias.__doc__ = f"Deprecated: the old spelling of :func:`{func.__name__}` (warns)."
    return alias


def renamed_keyword(func: str, old: str, new: str, old_value, new_value):
    """The value of keyword ``new`` of ``func``, or of its deprecated name ``old`` when that was
    given (not None; warns at the caller of ``func``)."""
    if old_value is None:
        return new_value
    warn_renamed(f"{func}({old}=...)", f"{func}({new}=...)", stacklevel=4)
    return old_value
