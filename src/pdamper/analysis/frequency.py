"""Detection of the drive frequency in a motion signal: the largest spectral peak, refined by a
sinusoid fit (see :func:`detect_frequency`)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from .checks import _as_1d, _check_finite, _check_lengths, _check_tolerance, _uniform_grid
from .sinusoid import detect_uniform

__all__ = ["detect_frequency", "TIME_TOLERANCE"]

#: Largest allowed deviation of a time stamp from the uniform grid [sample intervals].
TIME_TOLERANCE = 1e-3


def detect_frequency(time, signal, *, name: str = "motion",
                     time_tolerance: float = TIME_TOLERANCE) -> float:
    """Drive frequency [Hz] of a motion signal: its largest non-DC spectral peak, refined.

    The signal is detrended (offset and linear drift), Hann-windowed and
    zero-padded 4x; the largest peak above 1.5 cycles per record is located and
    refined by parabolic interpolation of the log-magnitude, then by a bounded
    least-squares fit of ``a cos(2 pi f t) + b sin(2 pi f t) + c + d t`` over f
    within half a frequency bin, polished by Gauss-Newton steps (a clean drive is
    found to ~1e-13 relative; with noise the error is the fit's statistical one,
    e.g. ~1e-5 for 5 % noise over 20 cycles at 500 samples per cycle). The fitted
    sinusoid must carry at least half of the detrended variance ("a clear drive
    peak"), else :class:`InputError`.

    Parameters
    ----------
    time : array_like
        Sample times [s], uniformly spaced.
    signal : array_like
        Position, velocity or acceleration of the drive (any unit).
    name : str
        Name of the signal in error messages.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(10_000) * 1e-3
    >>> round(detect_frequency(t, np.sin(2 * np.pi * 2.0 * t + 0.4)), 9)
    2.0
    """
    t = _as_1d("time", time)
    s = _as_1d(name, signal)
    _check_lengths({"time": t, name: s})
    _check_finite("time", t, None)
    _check_finite(name, s, t)
    _check_tolerance(time_tolerance)
    try:
        _t0, dt = _uniform_grid(t, time_tolerance)
    except InputError:
        if not np.all(np.diff(t) > 0):
            raise
        from .nonuniform import detect_nonuniform

        return detect_nonuniform(t, s, name)[0]
    f, _share = detect_uniform(s, dt, name)
    return f
