"""Finite-element matrices of a structure: reading M, K (and C) from files, checking them, and
the modes of the generalised problem K phi = omega^2 M phi with their damping (``[structure]
matrices = ...``; docs/structure.md, "Structures with several modes").

The damping of the modes is one of:

- ``damping_ratio = zeta``: every kept mode has zeta;
- ``rayleigh = [alpha, beta]``: C = alpha M + beta K, so mode k has c_k = alpha + beta omega_k^2
  (mass-normalised) and zeta_k = alpha / (2 omega_k) + beta omega_k / 2;
- ``rayleigh_modes = [i, j]`` with ``rayleigh_ratios = [zeta_i, zeta_j]``: the Rayleigh damping
  that gives modes i and j (1-based) those ratios, alpha and beta from the two equations above
  (:func:`rayleigh_coefficients`); every other mode's ratio follows (printed by ``pdamper decay``,
  ``run`` and ``response`` as ``mode_damping_ratios``);
- a ``C`` matrix in the file: the diagonal of its modal projection Phi^T C Phi.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from ..errors import InputError

__all__ = ["read_structure_matrices", "check_matrices", "rayleigh_coefficients", "modes_from_matrices",
           "MATRIX_READERS"]

#: File endings of a matrix that scipy reads: Matrix Market and Harwell-Boeing (and numpy's own).
MATRIX_READERS = {".mtx": "mmread", ".mm": "mmread", ".rb": "hb_read", ".rua": "hb_read", ".rsa": "hb_read",
                  ".hb": "hb_read", ".npy": "npy"}
_MATRIX_READERS = MATRIX_READERS


def _load_matrix(path, name: str):
    """A matrix [SI] from ``path`` (Matrix Market, Harwell-Boeing or .npy), dense."""
    import scipy.io

    p = Path(path)
    reader = _MATRIX_READERS.get(p.suffix.lower())
    if reader is None:
        raise InputError(f"structure.matrices.{name} = {str(path)!r}: unknown file type {p.suffix!r}; give a Matrix "
                         f"Market (.mtx), Harwell-Boeing ({', '.join(k for k, r in _MATRIX_READERS.items() if r == 'hb_read')}) "
                         "or .npy file, or one .npz with arrays M, K (and C)")
    if not p.is_file():
        raise InputError(f"structure.matrices.{name}: file not found: {p}")
    try:
        a = np.load(p) if reader == "npy" else getattr(scipy.io, reader)(str(p))
    except Exception as exc:  # the readers raise many kinds of error on a bad file
        raise InputError(f"structure.matrices.{name}: cannot read {p}: {exc}") from None
    return np.asarray(a.toarray() if hasattr(a, "toarray") else a, dtype=float)


def read_structure_matrices(matrices) -> dict:
    """``{"M": ..., "K": ..., "C": ... or None}`` from ``matrices``: the path of an .npz with arrays
    ``M``, ``K`` (and optionally ``C``), or a table ``{M = path, K = path, C = path}`` of Matrix
    Market / Harwell-Boeing / .npy files (read by scipy)."""
    if isinstance(matrices, (str, Path)):
        p = Path(matrices)
        if p.suffix.lower() != ".npz":
            raise InputError(f"structure.matrices = {str(matrices)!r}; one file must be an .npz with arrays M, K "
                             "(and C); for Matrix Market or Harwell-Boeing files give a table, "
                             "matrices = {M = 'frame_M.mtx', K = 'frame_K.mtx'}")
        if not p.is_file():
            raise InputError(f"structure.matrices: file not found: {p}")
        with np.load(p) as z:
            missing = [k for k in ("M", "K") if k not in z.files]
            if missing:
                raise InputError(f"structure.matrices = {str(matrices)!r} has no array {missing[0]!r} (it has "
                                 f"{', '.join(z.files) or 'none'}); it needs M and K, optionally C")
            return {k: (np.asarray(z[k], dtype=float) if k in z.files else None) for k in ("M", "K", "C")}
    if isinstance(matrices, dict):
        unknown = [k for k in matrices if k not in ("M", "K", "C")]
        if unknown:
            raise InputError(f"structure.matrices: unknown key {unknown[0]!r}; give M, K and optionally C")
        for k in ("M", "K"):
            if k not in matrices:
                raise InputError(f"structure.matrices.{k} is missing; give M = 'file' and K = 'file' (and C)")
        return {k: (_load_matrix(matrices[k], k) if k in matrices else None) for k in ("M", "K", "C")}
    raise InputError(f"structure.matrices = {matrices!r}; give the path of an .npz file (arrays M, K, C) or a "
                     "table {M = 'M.mtx', K = 'K.mtx'}")


def check_matrices(mats: dict) -> int:
    """Shapes, symmetry and definiteness of M, K (and C); returns the number of dofs."""
    M, K, C = mats["M"], mats["K"], mats["C"]
    if M.ndim != 2 or M.shape[0] != M.shape[1] or M.shape[0] == 0:
        raise InputError(f"structure.matrices: M must be square, got shape {M.shape}")
    n = M.shape[0]
    for name, A in (("K", K), ("C", C)):
        if A is not None and A.shape != (n, n):
            raise InputError(f"structure.matrices: {name} has shape {A.shape}; M is {n} x {n}, they must match")
    for name, A in (("M", M), ("K", K), ("C", C)):
        if A is None:
            continue
        if not np.all(np.isfinite(A)):
            raise InputError(f"structure.matrices: {name} has NaN or infinite entries")
        asym = float(np.max(np.abs(A - A.T))) / max(float(np.max(np.abs(A))), 1e-300)
        if asym > 1e-9:
            raise InputError(f"structure.matrices: {name} is not symmetric (largest |{name} - {name}^T| is {asym:.2g} "
                             f"of its largest entry); give the symmetric {name} of the FE model")
    for name, A, what in (("M", M, "a mass matrix"),
                          ("K", K, "a supported structure (one with rigid-body modes has a singular K: clamp it)")):
        try:
            np.linalg.cholesky(A)
        except np.linalg.LinAlgError:
            raise InputError(f"structure.matrices: {name} is not positive definite; {what} must be") from None
    return n


def rayleigh_coefficients(omegas, ratios) -> tuple[float, float]:
    """(alpha [1/s], beta [s]) of the Rayleigh damping C = alpha M + beta K that gives the modes
    of angular frequencies ``omegas`` = (omega_i, omega_j) [rad/s] the damping ratios ``ratios`` =
    (zeta_i, zeta_j): zeta = alpha / (2 omega) + beta omega / 2 at both.

    >>> a, b = rayleigh_coefficients((2.0, 20.0), (0.05, 0.05))
    >>> round(a, 6), round(b, 6)
    (0.181818, 0.004545)
    """
    wi, wj = (float(w) for w in omegas)
    zi, zj = (float(z) for z in ratios)
    A = np.array([[1.0 / (2.0 * wi), wi / 2.0], [1.0 / (2.0 * wj), wj / 2.0]])
    alpha, beta = np.linalg.solve(A, [zi, zj])
    return float(alpha), float(beta)


def _rayleigh_pair(modes, ratios, n: int):
    """The checked ``rayleigh_modes`` (0-based indices) and ``rayleigh_ratios``."""
    m = np.asarray(modes, dtype=float) if modes is not None else np.zeros(0)
    z = np.asarray(ratios, dtype=float) if ratios is not None else np.zeros(0)
    if modes is None or ratios is None:
        missing = "rayleigh_ratios" if ratios is None else "rayleigh_modes"
        raise InputError(f"structure.{missing} is missing: Rayleigh damping by two modes takes rayleigh_modes = "
                         "[i, j] (1-based) and rayleigh_ratios = [zeta_i, zeta_j], e.g. [1, 3] and [0.02, 0.02]")
    if m.shape != (2,) or not np.all(np.isfinite(m)) or np.any(m != np.round(m)) or not (1 <= m.min()) \
            or m[0] == m[1] or m.max() > n:
        raise InputError(f"structure.rayleigh_modes = {list(modes)!r}; give two different mode numbers from 1 to "
                         f"{n} (1 the lowest), e.g. [1, 3]")
    if z.shape != (2,) or not np.all(np.isfinite(z)) or np.any(z < 0) or np.any(z >= 1):
        raise InputError(f"structure.rayleigh_ratios = {list(ratios)!r}; give two damping ratios in [0, 1), "
                         "e.g. [0.02, 0.02]")
    return [int(v) - 1 for v in m], z


def modes_from_matrices(s) -> dict:
    """The modal data of the :class:`~pdamper.structure.ModalStructure` ``s`` from its
    ``matrices``: the lowest ``modes_kept`` modes (mass-normalised), their damping, the mode
    shapes at the damper, force and response dofs and the truncation error (see the module
    docstring)."""
    from scipy.linalg import eigh

    mats = read_structure_matrices(s.matrices)
    n = check_matrices(mats)
    dofs = {}
    for key in ("damper_dof", "force_dof", "response_dof"):
        v = getattr(s, key)
        if v is None:
            if key == "damper_dof":
                raise InputError("structure.damper_dof is missing: give the index (0-based) of the dof the "
                                 f"container sits on, along the drive direction (0 to {n - 1})")
            v = dofs["damper_dof"]
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 0 <= v < n:
            raise InputError(f"structure.{key} = {v!r}; must be a dof index from 0 to {n - 1} (0-based; the "
                             f"matrices have {n} dofs)")
        dofs[key] = int(v)
    kept = n if s.modes_kept is None else s.modes_kept
    if isinstance(kept, bool) or not isinstance(kept, (int, np.integer)) or not 1 <= kept <= n:
        raise InputError(f"structure.modes_kept = {s.modes_kept!r}; must be from 1 to the number of dofs, {n}")
    damping = [k for k in ("rayleigh", "damping_ratio") if getattr(s, k) is not None]
    if s.rayleigh_modes is not None or s.rayleigh_ratios is not None:
        damping.append("rayleigh_modes with rayleigh_ratios")
    if mats["C"] is not None:
        damping.append("C (in the matrices)")
    if len(damping) != 1:
        raise InputError("structure: give exactly one damping: rayleigh = [alpha, beta], rayleigh_modes = [i, j] with "
                         "rayleigh_ratios = [zeta_i, zeta_j], damping_ratio = 0.005 or a C matrix in the matrices "
                         "file" + (f" (given: {', '.join(damping)})" if damping else ""))
    pair = None
    top = kept
    if s.rayleigh_modes is not None or s.rayleigh_ratios is not None:
        pair = _rayleigh_pair(s.rayleigh_modes, s.rayleigh_ratios, n)
        top = max(kept, max(pair[0]) + 1)
    w2, phi = eigh(mats["K"], mats["M"], subset_by_index=[0, top - 1])
    w = np.sqrt(w2)
    if s.rayleigh is not None:
        r = np.asarray(s.rayleigh, dtype=float)
        if r.shape != (2,) or not np.all(np.isfinite(r)) or np.any(r < 0):
            raise InputError(f"structure.rayleigh = {s.rayleigh!r}; give [alpha, beta] >= 0 "
                             "(C = alpha M + beta K)")
        c = r[0] + r[1] * w2
    elif pair is not None:
        alpha, beta = rayleigh_coefficients(w[pair[0]], pair[1])
        c = alpha + beta * w2
        if np.any(c[:kept] < 0):
            k = int(np.argmax(c[:kept] < 0))
            raise InputError(f"structure.rayleigh_ratios = {list(s.rayleigh_ratios)!r} at modes "
                             f"{list(s.rayleigh_modes)!r} give alpha = {alpha:.4g} 1/s, beta = {beta:.4g} s: mode "
                             f"{k + 1} ({w[k] / (2 * math.pi):.4g} Hz) would have a negative damping ratio; give "
                             "ratios that grow less steeply with frequency, or modes further apart")
    elif s.damping_ratio is not None:
        z = s.damping_ratio
        if isinstance(z, bool) or not isinstance(z, (int, float)) or not 0.0 <= z < 1.0:
            raise InputError(f"structure.damping_ratio = {z!r}; must be in [0, 1), e.g. 0.005 (0.5 %)")
        c = 2.0 * z * w
    else:
        c = np.einsum("ik,ij,jk->k", phi, mats["C"], phi)
    w2, w, phi, c = w2[:kept], w[:kept], phi[:, :kept], c[:kept]
    zeta = c / (2.0 * w)
    if np.any(zeta >= 1.0):
        k = int(np.argmax(zeta >= 1.0))
        raise InputError(f"structure: mode {k + 1} ({w[k] / (2 * math.pi):.4g} Hz) has damping ratio {zeta[k]:.3g} "
                         ">= 1 with this damping (rayleigh or C); the modal model needs underdamped modes")
    d, f, r = dofs["damper_dof"], dofs["force_dof"], dofs["response_dof"]
    pd = phi[d]
    if not np.any(np.abs(pd) > 1e-12 * np.max(np.abs(phi))):
        raise InputError(f"structure.damper_dof = {d}: every kept mode shape is zero there; the damper would act "
                         "on none of them (choose the dof the container moves with, or keep more modes)")
    full = float(np.linalg.solve(mats["K"], np.eye(n)[:, d])[d])
    kept_c = float(np.sum(pd**2 / w2))
    return {"frequency": w / (2.0 * math.pi), "damping_ratio": zeta, "modal_mass": np.ones(kept),
            "damper": pd.copy(), "force": phi[f].copy(), "response": phi[r].copy(),
            "truncation_error": (full - kept_c) / full, "dofs": n}
