"""How the design's messages name its parameters.

The design speaks of its own parameters (``force``, ``target_ratio``, ``length_range``,
``sizes['height']``); a front end that takes them under other names -- the CLI's options
(``--force``, ``--target-ratio``, ``--length LOW:HIGH``, ``--size height=VALUE``) -- says so with
:func:`naming`, and the design's errors, warnings and verdicts use its words (:func:`name`).

>>> name("target_ratio"), name("sizes.height")
('target_ratio', "sizes['height']")
>>> with naming({"target_ratio": "--target-ratio"}.get):
...     name("target_ratio")
'--target-ratio'
"""

from __future__ import annotations

import contextlib
import contextvars

__all__ = ["name", "naming"]

#: A Python caller's words for what is not one parameter: the DEM check is a function of its own.
_PYTHON = {"verify": "verify_design"}

_WORDS: contextvars.ContextVar = contextvars.ContextVar("pdamper_design_words", default=None)


def name(key: str) -> str:
    """The words for the design's parameter ``key``: the front end's (:func:`naming`; a key it does
    not name keeps the design's own words), else the parameter itself (``sizes.KEY``, another
    [container] key of the shape: ``sizes['KEY']``)."""
    words = _WORDS.get()
    said = words(key) if words is not None else None
    if said is not None:
        return said
    if key.startswith("sizes."):
        return f"sizes[{key[len('sizes.'):]!r}]"
    return _PYTHON.get(key, key)


@contextlib.contextmanager
def naming(words):
    """Within the block, the design names its parameter ``key`` as ``words(key)`` (None: its own words)."""
    token = _WORDS.set(words)
    try:
        yield
    finally:
        _WORDS.reset(token)
