"""Griffe extension for the docs site: Sphinx roles in docstrings become inline code.

The docstrings use Sphinx-style roles (``:class:`Case```, ``:func:`~pdamper.run.run_case```);
Markdown would show them as ``:class:Case``. This turns each into inline code of its target
(``~`` keeps only the last name, as Sphinx does). Loaded by mkdocs.yml.
"""

from __future__ import annotations

import re

import griffe

_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|exc|obj|const|math):`(~?)([^`]+)`")


def _code(match: re.Match) -> str:
    tilde, target = match.groups()
    return f"`{target.rsplit('.', 1)[-1] if tilde else target}`"


def plain_roles(text: str) -> str:
    """``text`` with every Sphinx role replaced by inline code."""
    return _ROLE.sub(_code, text)


class RstRoles(griffe.Extension):
    def on_instance(self, *, obj, **kwargs) -> None:  # noqa: D102 - griffe hook
        if obj.docstring is not None:
            obj.docstring.value = plain_roles(obj.docstring.value)
