"""Progress bars of the Python API: shown on a terminal and in Jupyter, never asked of a pipe."""

from __future__ import annotations

import io
import sys
import types

from pdamper.studies import _progress


def test_not_shown_on_a_pipe_outside_jupyter(monkeypatch):
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert not _progress.in_jupyter()
    assert _progress.show_progress(None) is False
    assert _progress.show_progress(True) is True


def _ipython_shell(monkeypatch, app: str):
    """Pretend to run inside an IPython shell whose application is ``app``."""
    shell = types.SimpleNamespace(config={app: {}})
    monkeypatch.setitem(sys.modules, "ipykernel", types.ModuleType("ipykernel"))
    monkeypatch.setitem(sys.modules, "IPython", types.SimpleNamespace(get_ipython=lambda: shell))


def test_shown_in_a_jupyter_kernel(monkeypatch):
    _ipython_shell(monkeypatch, "IPKernelApp")
    monkeypatch.setattr(sys, "stderr", io.StringIO())
    assert _progress.in_jupyter()
    assert _progress.show_progress(None) is True
    assert _progress.show_progress(False) is False


def test_a_plain_ipython_shell_is_not_jupyter(monkeypatch):
    _ipython_shell(monkeypatch, "TerminalIPythonApp")
    assert not _progress.in_jupyter()


def test_text_bar_without_ipywidgets_writes_to_stderr(monkeypatch):
    err = io.StringIO()
    monkeypatch.setattr(sys, "stderr", err)
    monkeypatch.setattr(_progress, "in_jupyter", lambda: True)
    monkeypatch.setattr(_progress.importlib.util, "find_spec", lambda name: None)
    bar = _progress.progress_bar(total=3, desc="sweep", unit="case")
    bar.update(3)
    bar.close()
    assert "sweep: 100%" in err.getvalue() and "3/3" in err.getvalue()
