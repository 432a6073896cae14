"""The structure without the bed under a load in time: its exact linear response, and its
frequency response function.

Each mode k (``m q'' + c q' + k q = b_k f(t)``, :meth:`~pdamper.structure.StructureBase.modal_arrays`,
``b_k`` the load's :meth:`~pdamper.structure.loads.base.LoadBase.modal_coefficients`) is solved
exactly on each piece of the load's table (:mod:`pdamper.kernels.structure`): on a piece where
``f = f_j + s_j tau`` the response is the particular ``q_p = alpha + beta tau`` (``beta = b s_j /
k``, ``alpha = (b f_j - c beta) / k``) plus the free vibration from what is left,

    q_h(tau) = e^{-zeta omega tau} (a cos omega_d tau + (v + zeta omega a) / omega_d sin omega_d tau),

(``omega_d = omega sqrt(1 - zeta^2)``); on a piece where ``f = A sin(Omega tau + phi)`` the
particular is the steady phasor ``Q = b A / (k - m Omega^2 + i c Omega)``. This is the
piecewise-exact integration of Nigam & Jennings (BSSA 59, 1969) for a piecewise-linear load: no
time step, no error but rounding. The states at the pieces' ends follow one another through the
free vibration's complex coordinate ``w = (v - conj(mu) q) / (2 i omega_d)``, ``mu = -zeta omega + i
omega_d``, which a piece of length Delta multiplies by ``e^{mu Delta}``: on pieces of one length
a first-order recursion, run by :func:`scipy.signal.lfilter`. The response at any time comes
from the state at the start of its piece.

Every dof is the modes' superposition with the shapes of
:meth:`~pdamper.structure.StructureBase.dof_shapes`; the FRF of dof i per unit f is ``H_i(f) =
sum_k phi_k(i) b_k / (k_k - m_k Omega^2 + i c_k Omega)``.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .loads.base import FORM_SINE

__all__ = ["modal_response", "damper_motion", "dof_response", "dof_motion", "frequency_response", "ground_velocity"]


def _modes(structure):
    mass, k, c, pd, pf, pr = (np.asarray(a, dtype=float) for a in structure.modal_arrays())
    w = np.sqrt(k / mass)
    zeta = c / (2.0 * mass * w)
    if np.any(zeta >= 1.0):
        raise InputError("the exact linear response needs underdamped modes (zeta < 1)")
    wd = w * np.sqrt(1.0 - zeta * zeta)
    return mass, k, c, w, zeta, wd


def _free(a, v, tau, w, zeta, wd):
    """(q, q') after ``tau`` of free vibration from (a, v) (broadcast over modes and times)."""
    e = np.exp(-zeta * w * tau)
    co, si = np.cos(wd * tau), np.sin(wd * tau)
    q = e * (a * co + (v + zeta * w * a) / wd * si)
    qd = e * (v * co - (w * w * a + zeta * w * v) / wd * si)
    return q, qd


def _particular(form, rows, j, tau, b, mass, k, c):
    """(q_p, q_p') of piece ``j`` (rows[j]) after ``tau`` (broadcast: j, tau of shape (P, 1))."""
    if form == FORM_SINE:
        A, W, ph = rows[j, 1], rows[j, 2], rows[j, 3]
        Q = b * A / (k - mass * W * W + 1j * c * W)
        e = np.exp(1j * (W * tau + ph))
        return np.imag(Q * e), np.imag(1j * W * Q * e)
    f, s = rows[j, 1], rows[j, 2]
    beta = b * s / k
    alpha = (b * f - c * beta) / k
    return alpha + beta * tau, beta + 0.0 * tau


def _piece_states(form, rows, q0, v0, b, mass, k, c, w, zeta, wd, t_end):
    """(q, q') [pieces, modes] at the start of every piece of the table starting at or before
    ``t_end``, from (q0, v0) at t = rows[0, 0]."""
    t = rows[:, 0]
    npieces = int(np.searchsorted(t, t_end, side="right"))
    npieces = max(1, min(npieces, t.size))
    Q = np.zeros((npieces, q0.size))
    V = np.zeros((npieces, q0.size))
    Q[0], V[0] = q0, v0
    if npieces == 1:
        return Q, V
    delta = np.diff(t[:npieces])
    j = np.arange(npieces - 1)[:, None]
    # the input of each piece: its particular solution's share, u_j = p_j(Delta) - Phi(Delta) p_j(0)
    p0, pd0 = _particular(form, rows, j, 0.0 * delta[:, None], b, mass, k, c)
    p1, pd1 = _particular(form, rows, j, delta[:, None], b, mass, k, c)
    f0, fd0 = _free(p0, pd0, delta[:, None], w, zeta, wd)
    uq, uv = p1 - f0, pd1 - fd0
    mu = -zeta * w + 1j * wd
    # runs of pieces of one length: a first-order complex recursion each
    breaks = np.flatnonzero(np.abs(np.diff(delta)) > 1e-9 * delta[1:]) + 1
    starts = np.concatenate([[0], breaks])
    ends = np.concatenate([breaks, [delta.size]])
    from scipy.signal import lfilter

    for a, z in zip(starts, ends):
        d = float(np.mean(delta[a:z]))
        lam = np.exp(mu * d)
        U = (uv[a:z] - np.conj(mu) * uq[a:z]) / (2j * wd)
        w0 = (V[a] - np.conj(mu) * Q[a]) / (2j * wd)
        for m in range(q0.size):
            y = lfilter([1.0], [1.0, -lam[m]], U[:, m], zi=[lam[m] * w0[m]])[0]
            Q[a + 1:z + 1, m] = 2.0 * np.real(y)
            V[a + 1:z + 1, m] = 2.0 * np.real(mu[m] * y)
    return Q, V


def modal_response(structure, times, load=None):
    """(q, q') [len(times), modes] of ``structure`` (as it runs: its modal arrays) without the bed
    under ``load`` (default its own load in time), from its initial state at t = 0, exactly (module
    docstring); ``times`` [s] >= 0."""
    load = structure.load if load is None else load
    if load is None:
        raise InputError("the structure has no load in time; give a [load] section")
    mass, k, c, w, zeta, wd = _modes(structure)
    b = np.asarray(load.modal_coefficients(structure), dtype=float)
    form, rows = load.kernel_table()
    rows = np.asarray(rows, dtype=float)
    t = np.asarray(times, dtype=float)
    if t.size == 0:
        return np.zeros((0, mass.size)), np.zeros((0, mass.size))
    if np.any(t < 0) or not np.all(np.isfinite(t)):
        raise InputError("times must be finite and >= 0 (the load starts at 0)")
    q0, v0 = (np.asarray(a, dtype=float) for a in structure.initial_modal_state())
    if rows[0, 0] > 0:  # free vibration up to the first row
        rows = np.vstack([[0.0, 0.0, 0.0, 0.0], rows])
    Qs, Vs = _piece_states(form, rows, q0, v0, b, mass, k, c, w, zeta, wd, float(np.max(t)))
    j = np.clip(np.searchsorted(rows[:, 0], t, side="right") - 1, 0, Qs.shape[0] - 1)
    tau = (t - rows[j, 0])[:, None]
    jj = j[:, None]
    p0, pd0 = _particular(form, rows, jj, 0.0 * tau, b, mass, k, c)
    p, pd = _particular(form, rows, jj, tau, b, mass, k, c)
    h, hd = _free(Qs[j] - p0, Vs[j] - pd0, tau, w, zeta, wd)
    return h + p, hd + pd


def damper_motion(structure, times):
    """(x, v, a) of the damper point [m, m/s, m/s^2] without the bed under its load in time
    (relative to the ground under a ground acceleration), exactly."""
    mass, k, c, pd_, pf, pr = (np.asarray(a, dtype=float) for a in structure.modal_arrays())
    t = np.asarray(times, dtype=float)
    q, qd = modal_response(structure, np.atleast_1d(t))
    b = np.asarray(structure.load.modal_coefficients(structure), dtype=float)
    f = structure.load.values(np.atleast_1d(t))[:, None]
    qdd = (b * f - c * qd - k * q) / mass
    out = tuple(z @ pd_ for z in (q, qd, qdd))
    return out if np.ndim(t) else tuple(float(z[0]) for z in out)


def dof_motion(structure, times):
    """(labels, x, v, a): every dof's displacement [m], velocity [m/s] and acceleration [m/s^2],
    arrays (times x dofs), without the bed under its load in time, exactly (relative to the ground
    under a ground acceleration: the absolute acceleration adds the ground's, ``load.values(t)``)."""
    mass, k, c, _, _, _ = (np.asarray(a, dtype=float) for a in structure.modal_arrays())
    labels, shapes = structure.dof_shapes()
    t = np.atleast_1d(np.asarray(times, dtype=float))
    q, qd = modal_response(structure, t)
    b = np.asarray(structure.load.modal_coefficients(structure), dtype=float)
    qdd = (b * structure.load.values(t)[:, None] - c * qd - k * q) / mass
    sh = np.asarray(shapes).T
    return labels, q @ sh, qd @ sh, qdd @ sh


def dof_response(structure, times, load=None):
    """(labels, x [len(times), dofs]): every dof's displacement [m] without the bed, exactly."""
    labels, shapes = structure.dof_shapes()
    q, _ = modal_response(structure, times, load)
    return labels, q @ np.asarray(shapes).T


def frequency_response(structure, frequencies, load=None) -> np.ndarray:
    """H [frequencies, dofs]: every dof's complex amplitude per unit load f (a force [m/N], a
    ground acceleration [m / (m/s^2)], relative to the ground) without the bed."""
    load = structure.load if load is None else load
    mass, k, c, pd, pf, pr = (np.asarray(a, dtype=float) for a in structure.modal_arrays())
    b = np.asarray(load.modal_coefficients(structure), dtype=float)
    _, shapes = structure.dof_shapes()
    W = 2.0 * math.pi * np.asarray(frequencies, dtype=float)[:, None]
    return (b / (k - mass * W * W + 1j * c * W)) @ np.asarray(shapes).T


def ground_velocity(load, times) -> np.ndarray:
    """The ground's velocity [m/s] at ``times`` [s] from rest at t = 0: the integral of the load's
    acceleration (trapezoidal on ``times`` and the load's samples)."""
    t = np.asarray(times, dtype=float)
    form, rows = load.kernel_table()
    grid = np.union1d(t, rows[:, 0][rows[:, 0] <= (t.max() if t.size else 0.0)])
    a = load.values(grid)
    v = np.concatenate([[0.0], np.cumsum(0.5 * (a[1:] + a[:-1]) * np.diff(grid))])
    return np.interp(t, grid, v)
