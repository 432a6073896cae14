"""The toolbox every figure uses: where a figure may be written, writing it, and the log stroke axis.

* :func:`check_path` -- a figure's file name checked before anything is computed (format from the
  extension, :data:`FORMATS`; the folder must exist);
* :func:`save` -- write the figure, an unwritable file an :class:`~pdamper.errors.InputError`;
* :func:`log_ticks`, :func:`stroke_axis` -- labelled ticks on a log axis, and the stroke axis in
  mm over a sweep's strokes.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import InputError, shown

__all__ = ["FORMATS", "MM", "check_path", "save", "log_ticks", "stroke_axis"]

#: File formats the figures are written in, by extension.
FORMATS = (".png", ".svg", ".pdf")

#: Metres -> millimetres on a stroke axis.
MM = 1e3


def check_path(path, *, create_folder: bool = False) -> Path | None:
    """``path`` as a :class:`~pathlib.Path` (None stays None) once its extension is one of
    :data:`FORMATS` and its folder exists (``create_folder``: made when missing)."""
    if path is None:
        return None
    target = Path(path)
    if target.suffix.lower() not in FORMATS:
        raise InputError(f"plot file {shown(str(target))}: unknown format "
                         f"{shown(target.suffix or '(no extension)')}; end the name with one of "
                         f"{', '.join(FORMATS)}")
    if create_folder:
        target.parent.mkdir(parents=True, exist_ok=True)
    if not target.parent.is_dir():
        raise InputError(f"plot file {shown(str(target))}: folder {shown(str(target.parent))} does not "
                         "exist; create it or choose another path")
    return target


def save(fig, target: Path, dpi: int = 200) -> None:
    """Write ``fig`` to ``target`` (a :func:`check_path` result) at ``dpi`` (raster formats), whole
    or not at all: to a temporary file beside it, then renamed (a failure leaves no half figure)."""
    import os
    import tempfile

    target = Path(target)
    tmp = None
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{target.stem}.", suffix=target.suffix, dir=target.parent)
        os.close(fd)
        fig.savefig(tmp, dpi=dpi)
        mask = os.umask(0)
        os.umask(mask)
        os.chmod(tmp, 0o666 & ~mask)  # as a file written directly (mkstemp's is private)
        os.replace(tmp, target)
        tmp = None
    except OSError as exc:
        raise InputError(f"plot file {shown(str(target))} cannot be written: "
                         f"{exc.strerror or exc}") from None
    finally:
        if tmp is not None and os.path.exists(tmp):
            os.remove(tmp)


def stroke_axis(ax, strokes_m) -> None:
    """The x axis of ``ax`` over the strokes ``strokes_m`` [m], in mm on a log scale, a little
    padded, with at least three labelled ticks."""
    lo, hi = float(strokes_m.min()) * MM, float(strokes_m.max()) * MM
    pad = (hi / lo) ** 0.04 if hi > lo else 1.5
    ax.set_xlim(lo / pad, hi * pad)
    log_ticks(ax.xaxis, lo / pad, hi * pad)


def log_ticks(axis, lo: float, hi: float, least: int = 3) -> None:
    """Labelled ticks on a log ``axis`` spanning ``lo`` .. ``hi`` (data units, > 0): decades, or
    1-2-5, or every 1..9 x 10^n, the sparsest that labels at least ``least`` ticks (a narrow
    range below that: evenly spaced round numbers); labels as plain numbers (0.5, 10, 200)."""
    from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullFormatter

    lo, hi = sorted((float(lo), float(hi)))
    for subs in ((1.0,), (1.0, 2.0, 5.0), tuple(np.arange(1.0, 10.0))):
        locator = LogLocator(base=10.0, subs=subs, numticks=30)
        ticks = [v for v in locator.tick_values(lo, hi) if lo <= v <= hi]
        if len(ticks) >= least and (len(subs) > 1 or math.log10(hi / lo) > 3.5):
            break
    else:
        locator = MaxNLocator(nbins=4, steps=[1, 2, 2.5, 5, 10])
    axis.set_major_locator(locator)
    axis.set_major_formatter(FuncFormatter(lambda v, _pos: f"{v:.4g}"))
    axis.set_minor_locator(LogLocator(base=10.0, subs=np.arange(1.0, 10.0), numticks=30))
    axis.set_minor_formatter(NullFormatter())
