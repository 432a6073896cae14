"""No compiled function takes more than 12 arguments (issue 41): a kernel's many values travel in the
typed bundles of :mod:`pdamper.kernels.bundles` (a contact's constants and geometry, the state) or
as ``(x, y, z)`` tuples, not as a long list of floats whose order every caller must get right.

The scan reads the Python source of every module of ``contact/``, ``kernels/`` (with ``kernels/gpu/``)
and ``geometry/`` with :mod:`ast` -- the functions as they are before numba compiles them -- and
counts the parameters of each function that is compiled: decorated with ``njit``, ``numba.njit``,
``cuda.jit``, ``overload`` (with the ``impl`` it returns, and the stub it overloads), or handed to
such a call (``cuda.jit(cache=True)(batch_verlet)``).
"""

from __future__ import annotations

import ast
from pathlib import Path

SRC = Path(__file__).resolve().parents[2] / "src" / "pdamper"
FOLDERS = ("contact", "kernels", "kernels/gpu", "geometry")
LIMIT = 12
#: The GPU engine's launch kernels and its sample writer, which the warp-per-case rewrite of
#: ``kernels/gpu/`` (issue 38) replaces; the rewrite takes them off this list (the test below fails
#: once one of them is gone or within the limit, so the list cannot outlive them).
PENDING = {}

_JIT_WORDS = ("njit", "jit", "overload", "register_jitable")


def _is_jit(node) -> bool:
    """Whether a decorator (or the function of a call) is one of numba's compilers."""
    target = node.func if isinstance(node, ast.Call) else node
    name = target.attr if isinstance(target, ast.Attribute) else getattr(target, "id", "")
    return name in _JIT_WORDS


def _arity(fn) -> int:
    a = fn.args
    return len(a.posonlyargs) + len(a.args) + len(a.kwonlyargs) + (a.vararg is not None) + (a.kwarg is not None)


def compiled_functions(tree) -> dict:
    """name -> parameter count of every compiled function of a module's tree."""
    defs = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef):
            defs.setdefault(node.name, node)
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.FunctionDef) and any(_is_jit(d) for d in node.decorator_list):
            names.add(node.name)
            for d in node.decorator_list:
                # overload(stub, ...): the stub's signature is the compiled one's
                if isinstance(d, ast.Call) and _is_jit(d) and d.args and isinstance(d.args[0], ast.Name):
                    names.add(d.args[0].id)
            # an overload's impl (a function defined inside a compiled one)
            names.update(sub.name for sub in ast.walk(node) if isinstance(sub, ast.FunctionDef))
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Call) and _is_jit(node.func):
            names.update(a.id for a in node.args if isinstance(a, ast.Name))  # cuda.jit(...)(kernel)
        if isinstance(node, ast.Call) and _is_jit(node):
            names.update(a.id for a in node.args if isinstance(a, ast.Name) and a.id in defs)  # njit(f)
    return {n: _arity(defs[n]) for n in names if n in defs}


def _modules():
    for folder in FOLDERS:
        for f in sorted((SRC / folder).glob("*.py")):
            yield f.relative_to(SRC).as_posix(), ast.parse(f.read_text())


def test_no_compiled_function_takes_more_than_twelve_arguments():
    over = []
    for rel, tree in _modules():
        for name, n in sorted(compiled_functions(tree).items()):
            if n > LIMIT and name not in PENDING.get(rel, ()):
                over.append(f"{rel}:{name} takes {n}")
    assert not over, (f"compiled functions above {LIMIT} arguments (put the values in a bundle of "
                      f"pdamper.kernels.bundles or pass vectors as (x, y, z) tuples): " + "; ".join(over))


def test_the_pending_gpu_kernels_are_still_there_and_still_above_the_limit():
    """The list of pending GPU kernels names only kernels that exist and still need it."""
    found = {rel: compiled_functions(tree) for rel, tree in _modules()}
    stale = [f"{rel}:{name}" for rel, names in PENDING.items() for name in names
             if found.get(rel, {}).get(name, 0) <= LIMIT]
    assert not stale, f"take these off PENDING (gone or within {LIMIT} arguments): {', '.join(stale)}"


def test_the_scan_sees_the_contact_function_and_what_it_compiles():
    """The scan finds the compiled functions of each kind: a decorated one, an overload's stub and
    impl, and a kernel compiled by a call (so it cannot pass by finding nothing)."""
    seen = {rel: compiled_functions(tree) for rel, tree in _modules()}
    contact = seen["kernels/contact.py"]
    assert {"contact", "friction", "impl", "scatter", "_spring_friction"} <= set(contact)
    assert "spring_force" in seen["contact/tangential_spring.py"]
    assert "wall_distance" in seen["geometry/walls.py"]
    assert "batch_verlet" in seen["kernels/gpu/verlet.py"] and "batch_gear" in seen["kernels/gpu/gear.py"]
    # and it counts: a 13-argument compiled function in a module's text is found
    tree = ast.parse("@njit\ndef f(" + ", ".join(f"a{k}" for k in range(13)) + "):\n    pass\n")
    assert compiled_functions(tree) == {"f": 13}
