"""A script of the repository (``benchmarks/``, ``examples/``, ``tools/``: files, not modules of the
package) loaded as a module, for the tests of its functions."""

import importlib.util
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def load_script(relative):
    """The script at ``relative`` (to the repository's root), executed as a module of its own."""
    path = ROOT / relative
    spec = importlib.util.spec_from_file_location(f"script_{path.stem}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod
