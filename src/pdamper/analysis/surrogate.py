"""The polynomial response surface of the calibration (:mod:`pdamper.studies.calibrate`): a pure
function, so the calibration figure can evaluate the surrogate it fitted."""

from __future__ import annotations

import numpy as np

__all__ = ["poly_basis"]


def poly_basis(z) -> np.ndarray:
    """Polynomial basis in the scaled parameters ``z`` (points, k): cubic for one parameter, the
    full quadratic for more.

    >>> poly_basis([[0.5]]).tolist()
    [[1.0, 0.5, 0.25, 0.125]]
    """
    z = np.atleast_2d(np.asarray(z, dtype=float))
    k = z.shape[1]
    if k == 1:
        return np.column_stack([np.ones(len(z)), z[:, 0], z[:, 0] ** 2, z[:, 0] ** 3])
    cols = [np.ones(len(z))] + [z[:, i] for i in range(k)] + [z[:, i] * z[:, j] for i in range(k) for j in range(i, k)]
    return np.column_stack(cols)
