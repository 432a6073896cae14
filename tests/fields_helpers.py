"""Synthetic sweep-like results for the damper-fields tests (tests/analysis, tests/plotting)."""

from __future__ import annotations

import numpy as np
import xarray as xr

M_BED = 0.149
COLLIDE, OTHER = "rolling-collect-and-collide", "scattered"


def results(strokes, freqs, eta, *, modes=None, m_eff=None, seeds=1, frequency_attr=None):
    """A sweep-like dataset (stroke, frequency, seed) whose fields obey E = pi m_bed (Omega X)^2 eta*,
    c_eq = eta* m_bed Omega; ``eta``, ``modes``, ``m_eff``: (stroke, frequency[, seed]) arrays."""
    X = np.asarray(strokes, float)[:, None, None]
    w = 2 * np.pi * np.asarray(freqs, float)[None, :, None]
    shape = (len(strokes), len(freqs), seeds)
    eta = _grid(eta, shape, float)
    m = _grid(0.3 * M_BED if m_eff is None else m_eff, shape, float)
    md = _grid("" if modes is None else modes, shape, object).astype(str)
    dims = ("stroke", "frequency", "seed")
    ds = xr.Dataset({"eta_star": (dims, eta), "energy_per_cycle": (dims, np.pi * M_BED * (w * X) ** 2 * eta),
                     "effective_mass": (dims, m), "equivalent_damping": (dims, eta * M_BED * w), "mode": (dims, md)},
                    coords={"stroke": np.asarray(strokes, float), "frequency": np.asarray(freqs, float),
                            "seed": np.arange(seeds)},
                    attrs={"bed_mass_kg": M_BED, "title": "synthetic"})
    if frequency_attr is not None:
        ds = ds.isel(frequency=0, drop=True)
        ds.attrs["frequency_hz"] = frequency_attr
    return ds


def _grid(a, shape, dtype):
    """``a`` (a scalar, a column over the strokes, a (stroke, frequency) or a full array) on ``shape``."""
    a = np.asarray(a, dtype=dtype)
    if a.ndim == 1:
        a = a[:, None]
    if a.ndim == 2:
        a = a[:, :, None]
    return np.broadcast_to(a, shape).copy()


STROKES = [0.005, 0.007, 0.010, 0.020, 0.030]
FREQS = [1.5, 2.0, 3.0]


def constant_fields(m_a, c_a, strokes, freqs):
    """Fields of a rigid mass m_a [kg] and a dashpot c_a [N s/m] (c_eq = eta* m_bed Omega) over
    ``strokes`` [m] and ``freqs`` [Hz]."""
    from pdamper.analysis.fields import DamperFields

    w = 2 * np.pi * np.asarray(freqs)
    eta = np.broadcast_to(c_a / (M_BED * w), (len(strokes), len(freqs)))
    return DamperFields.from_results(results(strokes, freqs, eta, m_eff=m_a))
