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

import io
import math
import re
from pathlib import Path

import numpy as np

from ..errors import InputError, checked_file, shown, shown_path

__all__ = ["read_structure_matrices", "check_matrices", "rayleigh_coefficients", "modes_from_matrices",
           "nonproportional", "MATRIX_READERS"]

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
        raise InputError(f"structure.matrices.{name} = {shown(str(path))}: unknown file type {shown(p.suffix)}; give a Matrix "
                         f"Market (.mtx), Harwell-Boeing ({', '.join(k for k, r in _MATRIX_READERS.items() if r == 'hb_read')}) "
                         "or .npy file, or one .npz with arrays M, K (and C)")
    try:
        p = checked_file(p, "matrix file", missing="file not found: {path}")
    except InputError as exc:
        raise InputError(f"structure.matrices.{name}: {exc}") from None
    try:
        if reader == "npy":
            a = np.load(p, allow_pickle=False)
        else:
            data = p.read_bytes()
            if reader == "mmread":
                _check_matrix_market(p, data)
            # a file object, not the name: scipy's readers take only names that are UTF-8 text
            stream = io.BytesIO(data) if reader == "mmread" else io.TextIOWrapper(io.BytesIO(data), encoding="latin-1")
            a = getattr(scipy.io, reader)(stream)
        if getattr(a, "ndim", 0) != 2 or max(a.shape) > MAX_DOFS:
            raise InputError(f"structure.matrices.{name}: {shown_path(p)} holds a matrix of shape "
                             f"{' x '.join(map(str, getattr(a, 'shape', ())))}; give a square matrix of at most "
                             f"{MAX_DOFS:,} dofs (the modes are found from dense matrices)")
        return np.asarray(a.toarray() if hasattr(a, "toarray") else a, dtype=float)
    except InputError as exc:
        text = str(exc)
        raise InputError(text if text.startswith("structure.") else f"structure.matrices.{name}: {text}") from None
    except Exception as exc:  # the readers raise many kinds of error on a bad file
        raise InputError(f"structure.matrices.{name}: cannot read {shown_path(p)}: "
                         f"{shown(' '.join(str(exc).split()) or type(exc).__name__, 200)}") from None


#: Most dofs a structure's matrices may have: the modes are found from dense matrices (8 n^2 bytes each).
MAX_DOFS = 5_000
_MM_NUMBER = re.compile(rb"^[ \t]*(?:[-+]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eEdD][-+]?[0-9]+)?[ \t]*)+\r?$")


def _check_matrix_market(p: Path, data: bytes) -> None:
    """The lines of a Matrix Market file as the format writes them, before scipy reads it: scipy's
    reader (fast_matrix_market) crashes the process on a NUL byte in a data line and skips what is
    not a number; here every line after the banner and the ``%`` comments is numbers only, and the
    size line at most :data:`MAX_DOFS` rows and columns."""
    lines = data.split(b"\n")
    if not lines[0].startswith(b"%%MatrixMarket"):
        raise InputError(f"{shown_path(p)}, line 1: {shown(lines[0][:60].decode('latin-1'))} is not a Matrix Market banner; expected "
                         "'%%MatrixMarket matrix coordinate real symmetric' (or general, or array)")
    size = None
    for no, line in enumerate(lines[1:], start=2):
        if line.startswith(b"%") or not line.strip():
            continue
        if not _MM_NUMBER.match(line):
            raise InputError(f"{shown_path(p)}, line {no}: {shown(line.decode('latin-1'))} is not a row of numbers (a Matrix Market "
                             "file holds the size line, then one entry a line)")
        if size is None:
            size = [float(x) for x in line.split()]
            if len(size) not in (2, 3) or any(x != int(x) or x < 0 for x in size) or max(size[:2]) > MAX_DOFS:
                raise InputError(f"{shown_path(p)}, line {no}: size {shown(line.strip().decode('ascii'))}; give rows, "
                                 f"columns (and entries) as whole numbers, at most {MAX_DOFS:,} rows and columns")


def read_structure_matrices(matrices) -> dict:
    """``{"M": ..., "K": ..., "C": ... or None}`` from ``matrices``: the path of an .npz with arrays
    ``M``, ``K`` (and optionally ``C``), or a table ``{M = path, K = path, C = path}`` of Matrix
    Market / Harwell-Boeing / .npy files (read by scipy)."""
    if isinstance(matrices, (str, Path)):
        p = Path(matrices)
        if p.suffix.lower() != ".npz":
            raise InputError(f"structure.matrices = {shown(str(matrices))}; one file must be an .npz with arrays M, K "
                             "(and C); for Matrix Market or Harwell-Boeing files give a table, "
                             "matrices = {M = 'frame_M.mtx', K = 'frame_K.mtx'}")
        try:
            p = checked_file(p, "matrix file (.npz)", missing="file not found: {path}")
        except InputError as exc:
            raise InputError(f"structure.matrices: {exc}") from None
        try:
            with np.load(p, allow_pickle=False) as z:
                missing = [k for k in ("M", "K") if k not in z.files]
                if missing:
                    raise InputError(f"structure.matrices = {shown(str(matrices))} has no array {shown(missing[0])} "
                                     f"(it has {shown(z.files)}); it needs M and K, optionally C")
                return {k: (np.asarray(z[k], dtype=float) if k in z.files else None) for k in ("M", "K", "C")}
        except InputError:
            raise
        except Exception as exc:  # numpy/zipfile raise BadZipFile, EOFError, ValueError ... for a damaged file
            raise InputError(f"structure.matrices: cannot read {shown_path(p)} as an .npz of arrays M, K (and C): "
                             f"{shown(' '.join(str(exc).split()) or type(exc).__name__, 200)}") from None
    if isinstance(matrices, dict):
        unknown = [k for k in matrices if k not in ("M", "K", "C")]
        if unknown:
            raise InputError(f"structure.matrices: unknown key {shown(unknown[0])}; give M, K and optionally C")
        for k in ("M", "K"):
            if k not in matrices:
                raise InputError(f"structure.matrices.{k} is missing; give M = 'file' and K = 'file' (and C)")
        return {k: (_load_matrix(matrices[k], k) if k in matrices else None) for k in ("M", "K", "C")}
    raise InputError(f"structure.matrices = {shown(matrices)}; give the path of an .npz file (arrays M, K, C) or a "
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
        raise InputError(f"structure.rayleigh_modes = {shown(list(modes))}; give two different mode numbers from 1 to "
                         f"{n} (1 the lowest), e.g. [1, 3]")
    if z.shape != (2,) or not np.all(np.isfinite(z)) or np.any(z < 0) or np.any(z >= 1):
        raise InputError(f"structure.rayleigh_ratios = {shown(list(ratios))}; give two damping ratios in [0, 1), "
                         "e.g. [0.02, 0.02]")
    return [int(v) - 1 for v in m], z


def modes_from_matrices(s, mats: dict | None = None, dofs: dict | None = None, labels=None) -> dict:
    """The modal data of the :class:`~pdamper.structure.ModalStructure` ``s`` from its
    ``matrices`` (or the matrices ``mats`` in hand: ``{"M", "K", "C"}``, an OpenSees model's): the
    lowest ``modes_kept`` modes (mass-normalised), their damping, the mode shapes at the damper,
    force and response dofs and the truncation error (see the module docstring); ``shapes`` (dofs
    x modes) every dof's, ``mass_shapes`` = Phi^T M (a ground acceleration's participation),
    ``dampers`` (dampers x modes) the shapes at every damper dof (``damper_dof = [2, 1]``: a damper
    at each). ``dofs``: the damper dofs (a list), the force and the response dof as indices, instead
    of the structure's ``damper_dof``, ``force_dof``, ``response_dof`` (checked there); ``labels``
    the dofs' labels (default 0 .. n - 1)."""
    from scipy.linalg import eigh

    if mats is None:
        mats = read_structure_matrices(s.matrices)
    n = check_matrices(mats)
    if dofs is None:
        dofs = _dof_indices(s, n)
    kept = n if s.modes_kept is None else s.modes_kept
    if isinstance(kept, bool) or not isinstance(kept, (int, np.integer)) or not 1 <= kept <= n:
        raise InputError(f"structure.modes_kept = {shown(s.modes_kept)}; must be from 1 to the number of dofs, {n}")
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
    coupling = 0.0
    if s.rayleigh is not None:
        r = np.asarray(s.rayleigh, dtype=float)
        if r.shape != (2,) or not np.all(np.isfinite(r)) or np.any(r < 0):
            raise InputError(f"structure.rayleigh = {shown(s.rayleigh)}; give [alpha, beta] >= 0 "
                             "(C = alpha M + beta K)")
        c = r[0] + r[1] * w2
    elif pair is not None:
        alpha, beta = rayleigh_coefficients(w[pair[0]], pair[1])
        c = alpha + beta * w2
        if np.any(c[:kept] < 0):
            k = int(np.argmax(c[:kept] < 0))
            raise InputError(f"structure.rayleigh_ratios = {shown(list(s.rayleigh_ratios))} at modes "
                             f"{shown(list(s.rayleigh_modes))} give alpha = {alpha:.4g} 1/s, beta = {beta:.4g} s: mode "
                             f"{k + 1} ({w[k] / (2 * math.pi):.4g} Hz) would have a negative damping ratio; give "
                             "ratios that grow less steeply with frequency, or modes further apart")
    elif s.damping_ratio is not None:
        z = s.damping_ratio
        if isinstance(z, bool) or not isinstance(z, (int, float)) or not 0.0 <= z < 1.0:
            raise InputError(f"structure.damping_ratio = {shown(z)}; must be in [0, 1), e.g. 0.005 (0.5 %)")
        c = 2.0 * z * w
    else:
        c = np.einsum("ik,ij,jk->k", phi, mats["C"], phi)
        coupling = nonproportional(phi[:, :kept].T @ mats["C"] @ phi[:, :kept])
    w2, w, phi, c = w2[:kept], w[:kept], phi[:, :kept], c[:kept]
    zeta = c / (2.0 * w)
    if np.any(zeta >= 1.0):
        k = int(np.argmax(zeta >= 1.0))
        raise InputError(f"structure: mode {k + 1} ({w[k] / (2 * math.pi):.4g} Hz) has damping ratio {zeta[k]:.3g} "
                         ">= 1 with this damping (rayleigh or C); the modal model needs underdamped modes")
    ds, f, r = dofs["damper_dof"], dofs["force_dof"], dofs["response_dof"]
    d = ds[0]
    for dd in ds:
        if not np.any(np.abs(phi[dd]) > 1e-12 * np.max(np.abs(phi))):
            raise InputError(f"structure.{dofs.get('damper_key', 'damper_dof')} = {_shown(labels, dd)}: every kept "
                             "mode shape is zero there; the damper would act on none of them (choose the dof the "
                             "container moves with, or keep more modes)")
    pd = phi[d]
    full = float(np.linalg.solve(mats["K"], np.eye(n)[:, d])[d])
    kept_c = float(np.sum(pd**2 / w2))
    return {"frequency": w / (2.0 * math.pi), "damping_ratio": zeta, "modal_mass": np.ones(kept),
            "damper": pd.copy(), "force": phi[f].copy(), "response": phi[r].copy(),
            "dampers": phi[list(ds)].copy(), "damper_index": list(ds),
            "truncation_error": (full - kept_c) / full, "dofs": n,
            "shapes": phi.copy(), "mass_shapes": phi.T @ mats["M"], "nonproportional": coupling,
            "labels": list(range(n)) if labels is None else list(labels)}


def _shown(labels, index):
    return index if labels is None else labels[index]


def nonproportional(P) -> float:
    """How far the modal projection ``P = Phi^T C Phi`` of a damping matrix is from diagonal: the
    largest |P_ij| / sqrt(P_ii P_jj) over i != j (0: classically damped, as Rayleigh damping of the
    whole model is; the modal model keeps the diagonal only)."""
    P = np.asarray(P, dtype=float)
    if P.shape[0] < 2:
        return 0.0
    d = np.sqrt(np.maximum(np.abs(np.diag(P)), 1e-300))
    R = np.abs(P) / np.outer(d, d)
    np.fill_diagonal(R, 0.0)
    return float(np.max(R))


def _dof_indices(s, n: int) -> dict:
    """The damper dofs (a list: ``damper_dof`` one index or several), the force and the response dof
    of ``s`` as checked indices of ``n`` dofs."""
    dofs = {}
    for key in ("damper_dof", "force_dof", "response_dof"):
        v = getattr(s, key)
        if v is None:
            if key == "damper_dof":
                raise InputError("structure.damper_dof is missing: give the index (0-based) of the dof the "
                                 f"container sits on, along the drive direction (0 to {n - 1}), or a list of them "
                                 "(a damper at each)")
            v = dofs["damper_dof"][0]
        many = list(v) if key == "damper_dof" and isinstance(v, (list, tuple)) else [v]
        if not many:
            raise InputError(f"structure.{key} = []; give at least one dof index (0 to {n - 1})")
        for x in many:
            if isinstance(x, bool) or not isinstance(x, (int, np.integer)) or not 0 <= x < n:
                raise InputError(f"structure.{key} = {shown(list(v)) if len(many) > 1 else shown(v)}; must be a dof "
                                 f"index from 0 to {n - 1} (0-based; the matrices have {n} dofs)")
        dofs[key] = [int(x) for x in many] if key == "damper_dof" else int(many[0])
    return dofs
