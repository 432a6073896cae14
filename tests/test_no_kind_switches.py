"""Nobody switches on a drive's, a container shape's or a restitution law's kind outside the kind's own
module: callers ask the drive, the shape or the law what it can do (docs/engine.md, 3a and 3b;
:mod:`pdamper.contact.restitution`).

The scan reads every module of ``src/pdamper`` with :mod:`ast` (not its text) and reports, outside
the owners (``geometry/``: the shapes; ``excitation.py`` and ``structure/``: the drives;
``kernels/drive.py``: the kernels' side of the drive protocol; ``contact/cor_*.py`` and
``contact/restitution.py``: the restitution laws):

- a comparison (``==``, ``!=``, ``in``, ``not in``, ``is``, ``is not``) of a kind tag or a drive
  section (``"harmonic"``, ``"structure"``, ``"cuboid"``, ...) with an expression about a kind
  (one that names ``kind``, ``shape``, ``drive``, ``geo``, ``section``), or of anything with the
  kernels' drive numbers (``DRIVE_STRUCTURE``; not the table of them, ``DRIVE_KINDS``);
- a list, tuple or set of two or more kind tags (a ``click.Choice`` of two shapes, ``SHAPES =
  ("cuboid", "cylinder")``);
- a subscript by a kind tag of a table about kinds (``_DRIVE_OWN["samples"]``);
- ``isinstance(x, C)`` / ``type(x) is C`` with C a registered drive, shape or restitution-law class;
- ``hasattr(x, ...)`` on a drive, structure, shape or geometry, or with an attribute only some
  kinds have; ``getattr(x, name, default)`` with such an attribute (a switch in disguise).

``design/`` has no exemption. The same scan fails on pdamper 8500ec3 (the issue 30 review).
"""

from __future__ import annotations

import ast
import dataclasses
import os
from pathlib import Path

import pytest

SRC = Path(os.environ.get("PDAMPER_SRC", Path(__file__).resolve().parents[1] / "src" / "pdamper"))
#: the modules that own the kinds
OWNERS = ("geometry/", "excitation.py", "structure/", "kernels/drive.py", "contact/cor_", "contact/restitution.py")
#: words of an expression about a kind
KIND_WORDS = ("kind", "shape", "drive", "geo", "section")
#: objects whose attributes a hasattr may not ask about
KIND_OBJECTS = ("drive", "structure", "shape", "geo", "geometry")


def _registry():
    """(tags, class names, attributes only some kinds have), from the registries as they are now."""
    import pdamper.config  # noqa: F401  (registers the structures)
    from pdamper.contact import RESTITUTION_LAWS
    from pdamper.excitation import DRIVES
    from pdamper.geometry import SHAPES

    tags = set(DRIVES) | set(SHAPES) | set(RESTITUTION_LAWS) | {cls.config_section for cls in DRIVES.values()}
    names = {cls.__name__ for cls in (*DRIVES.values(), *SHAPES.values(), *RESTITUTION_LAWS.values())}
    partial = set()
    for family in (DRIVES.values(), SHAPES.values(), RESTITUTION_LAWS.values()):
        attrs = [set(dir(cls)) | {f.name for f in dataclasses.fields(cls)} for cls in family]
        partial |= set.union(*attrs) - set.intersection(*attrs)
    return tags, names, {a for a in partial if not a.startswith("__")}


def _text(node) -> str:
    return ast.unparse(node)


def _about_kind(node) -> bool:
    text = _text(node).lower()
    return any(w in text for w in KIND_WORDS)


def _strings(node) -> list:
    """The string constants of ``node``: itself, or the items of a tuple/list/set display."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [e.value for e in node.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)]
    return []


def switches(tree, tags, names, partial) -> list:
    """(line, what) of every switch on a kind in the module ``tree``."""
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(isinstance(s, ast.Name) and s.id.startswith("DRIVE_") and s.id != "DRIVE_KINDS"
                   for side in sides for s in ast.walk(side)):
                found.append((node.lineno, _text(node)))
                continue
            for i, side in enumerate(sides):
                hit = [v for v in _strings(side) if v in tags]
                others = sides[:i] + sides[i + 1:]
                if hit and any(_about_kind(o) for o in others):
                    found.append((node.lineno, _text(node)))
                    break
            if isinstance(node.ops[0], (ast.Is, ast.IsNot)) and any(
                    isinstance(s, ast.Name) and s.id in names for s in sides):
                found.append((node.lineno, _text(node)))
        elif isinstance(node, (ast.Tuple, ast.List, ast.Set)):
            if len([v for v in _strings(node) if v in tags]) >= 2:
                found.append((node.lineno, _text(node)))
        elif isinstance(node, ast.Subscript):
            key = node.slice
            if isinstance(key, ast.Constant) and key.value in tags and _about_kind(node.value):
                found.append((node.lineno, _text(node)))
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            fn, args = node.func.id, node.args
            if fn == "isinstance" and len(args) == 2:
                classes = [n.id if isinstance(n, ast.Name) else n.attr if isinstance(n, ast.Attribute) else None
                           for n in ([args[1]] + (args[1].elts if isinstance(args[1], ast.Tuple) else []))]
                if any(c in names for c in classes):
                    found.append((node.lineno, _text(node)))
            elif fn == "hasattr" and len(args) == 2:
                attr = args[1].value if isinstance(args[1], ast.Constant) else None
                if attr in partial or any(w in _text(args[0]).lower() for w in KIND_OBJECTS):
                    found.append((node.lineno, _text(node)))
            elif fn == "getattr" and len(args) == 3:
                attr = args[1].value if isinstance(args[1], ast.Constant) else None
                if attr in partial:
                    found.append((node.lineno, _text(node)))
    return sorted(set(found))


def scan(src: Path = SRC) -> list:
    tags, names, partial = _registry()
    out = []
    for f in sorted(src.rglob("*.py")):
        rel = f.relative_to(src).as_posix()
        if rel.startswith(OWNERS):
            continue
        for line, what in switches(ast.parse(f.read_text(), filename=str(f)), tags, names, partial):
            out.append(f"{rel}:{line}: {what}")
    return out


def test_no_drive_shape_or_law_switch_outside_their_modules():
    found = scan()
    assert not found, "switches on a drive, shape or restitution-law kind outside its module:\n" + "\n".join(found)


@pytest.mark.parametrize("code", [
    'if case.drive.kind != "harmonic": pass',
    'ok = drive.kind in ("harmonic", "samples")',
    'periodic = hasattr(case.drive, "stroke")',
    'if isinstance(geo, Cuboid): pass',
    'if type(s) is CoupledStructure: pass',
    'choices = click.Choice(["cuboid", "cylinder"])',
    'if shape == "cylinder": pass',
    'coupled = int(kind) in (DRIVE_STRUCTURE, DRIVE_MODAL)',
    'fs = getattr(s, "mode_frequencies", [s.natural_frequency])',
    'w = getattr(geo, "width", L)',
    'own = _DRIVE_OWN["samples"]',
    'if drive_key == "structure": pass',
    'if isinstance(cor, ThorntonRestitution): pass',
    'if law.kind == "thornton": pass',
    'p_y = getattr(cor, "yield_pressure", 0.0)',
])
def test_the_scan_sees_each_form_of_a_switch(code):
    tags, names, partial = _registry()
    assert switches(ast.parse(code), tags, names, partial), code


@pytest.mark.parametrize("code", [
    'if case.drive.periodic: pass',
    'if "structure" in data.channels: pass',
    'if s.kind == "text": pass',
    '"""A docstring naming the cuboid and the cylinder: ("cuboid", "cylinder")."""',
    'geo = SHAPES[shape](**keys)',
])
def test_the_scan_leaves_capabilities_and_other_kinds_alone(code):
    tags, names, partial = _registry()
    assert not switches(ast.parse(code), tags, names, partial), code
