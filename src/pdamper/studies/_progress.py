"""Progress bars of the Python API that show on a terminal and in Jupyter.

Sweeps, studies and frequency responses show a bar by default when stderr is a terminal or the
code runs in a Jupyter kernel (where stderr is not a terminal but a bar still shows). In Jupyter
the bar is a widget when ipywidgets is installed (``tqdm.auto``), else a text bar in the cell's
output; without ipywidgets ``tqdm.auto`` would add a warning, so the text bar is chosen directly.
"""

from __future__ import annotations

import importlib.util
import sys

__all__ = ["in_jupyter", "show_progress", "progress_bar"]


def in_jupyter() -> bool:
    """True inside a Jupyter kernel (notebook, JupyterLab, VS Code), not in a plain IPython shell."""
    if "ipykernel" not in sys.modules:
        return False
    try:
        shell = sys.modules["IPython"].get_ipython()
    except (KeyError, AttributeError):
        return False
    return shell is not None and "IPKernelApp" in getattr(shell, "config", {})


def show_progress(progress: bool | None) -> bool:
    """Whether to show a bar: ``progress`` if given, else on a terminal or in Jupyter."""
    if progress is not None:
        return bool(progress)
    return sys.stderr.isatty() or in_jupyter()


def progress_bar(*args, **kwargs):
    """A tqdm bar on stderr: a widget in Jupyter with ipywidgets, else the text bar."""
    kwargs.setdefault("file", sys.stderr)
    if in_jupyter() and importlib.util.find_spec("ipywidgets") is not None:
        from tqdm.auto import tqdm
    else:
        from tqdm.std import tqdm
    return tqdm(*args, **kwargs)
