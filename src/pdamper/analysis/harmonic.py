"""The forced response and the free decay of a modal structure with the damper's fields at its node.

The structure (modal data, :meth:`pdamper.excitation.ModalStructure.modal_arrays`; one mode for
the single-degree-of-freedom :class:`~pdamper.excitation.CoupledStructure`) obeys, per mode k,

    m_k q_k'' + c_k q_k' + k_k q_k = phi_k(f) F0 sin(Omega t) - phi_k(d) F_w,

with F_w the force of the container on the bed along the drive. In one harmonic (complex
amplitudes, ``x(t) = Im(x^ e^{i Omega t})``) the damper acts on its node as a mass m_eff and a
dashpot c_eq, read from the fields at the damper's amplitude X = |x^_d| and the frequency f
(docs/fields.md): ``F^_w = Z x^_d``, ``Z(X, f) = -Omega^2 m_eff + i Omega c_eq``. With the
receptances of the bare structure

    H_ab(Omega) = sum_k phi_k(a) phi_k(b) / (m_k (omega_k^2 - Omega^2) + i Omega c_k)

the damper node is ``x^_d = H_df F0 - H_dd Z x^_d``, hence

    x^_d = H_df F0 / (1 + H_dd Z(X, f)),      x^_r = H_rf F0 - H_rd Z x^_d,

and the damper amplitude is a fixed point ``X = G(X) = F0 |H_df| / |1 + H_dd Z(X, f)|``
(one mode, a rigid mass m_a: ``Z = -Omega^2 m_a`` and ``x^_d = F0 / (k - Omega^2 (m + m_a) + i
Omega c)``, the closed form). :func:`solve_frequency` finds every fixed point: it scans the
residual ``R(X) = ln X - ln G(X)`` on a log grid over the fields' amplitude range (and their
nodes), on each branch of the fields (:meth:`~pdamper.analysis.fields.DamperFields.branches`: in
a jump interval the segment below and the one above both exist), refines each sign change with
Brent's method and drops those that are the fields' jump rather than a root (``|R| > 1e-6``
after refinement). Where no segment has a root inside a jump interval and R changes sign across
the jump itself, the bed switches between its modes: that solution is reported at the jump (the
interval's geometric midpoint), branch ``"jump"``, with the two sides' impedances mixed to meet
X = G(X). A jump frequency is where the stable solutions change in number or in mode family.

**Stability** is the slope criterion of the amplitude equation: a fixed point is stable when
``dR/d ln X > 0`` (equivalently ``dG/dX < 1``: G crosses the identity from above). Its sign
changes where the frequency-response curve has a vertical tangent (the saddle-node fold where a
branch ends and the response jumps); it says nothing of instabilities of the phase (a Hopf
bifurcation of the slow flow), which a single-harmonic amplitude balance cannot see.

Below the smallest amplitude of the box R goes to -inf (G stays finite); above the largest to
+inf. So ``R > 0`` at the box's lower end means a solution below it, ``R < 0`` at the upper end
one above it: then :func:`solve_frequency` raises an :class:`~pdamper.errors.InputError` naming
the amplitude and the frequency, unless ``extrapolate=True`` (the box widened tenfold at a time,
the fields' end values continued).

:func:`decay_envelope` is the free decay from the same fields, by averaging (slow-flow energy
balance over a cycle of the first mode, docs/structure.md).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, shown

__all__ = ["receptances", "Solution", "FrequencyResponse", "solve_frequency", "solve_response",
           "decay_envelope", "RESIDUAL_TOLERANCE", "SeveralSolution", "solve_several", "solve_response_several"]

#: |ln X - ln G(X)| above which a sign change refined by Brent's method is the fields' jump, not a root.
RESIDUAL_TOLERANCE = 1e-6
_WIDEN = 10.0  # extrapolate: the box widened by this factor at a time
_MAX_WIDEN = 6


def receptances(modal, frequency: float) -> tuple[complex, complex, complex, complex]:
    """(H_dd, H_df, H_rd, H_rf) [m/N] of the bare structure at ``frequency`` [Hz]; ``modal`` =
    (mass, stiffness, damping, phi_damper, phi_force, phi_response), arrays over the modes.

    >>> h = receptances(([1.0], [4.0], [0.0], [1.0], [1.0], [1.0]), 0.0)
    >>> h[0]
    (0.25+0j)
    """
    m, k, c, pd, pf, pr = (np.asarray(a, dtype=float) for a in modal)
    w = 2.0 * math.pi * float(frequency)
    den = m * (k / m - w * w) + 1j * w * c
    return (complex(np.sum(pd * pd / den)), complex(np.sum(pd * pf / den)), complex(np.sum(pr * pd / den)),
            complex(np.sum(pr * pf / den)))


@dataclass(frozen=True)
class Solution:
    """One fixed point at one frequency: amplitudes [m] of the damper node and the response point,
    their complex amplitudes (``x(t) = Im(x^ e^{i Omega t})``), the fields there, the branch of the
    fields (``"below"``/``"above"`` in a jump interval, else ``""``), ``stable`` (slope criterion)
    and ``slope`` = dR/d ln X."""

    damper_amplitude_m: float
    response_amplitude_m: float
    damper_phasor: complex
    response_phasor: complex
    effective_mass_kg: float
    equivalent_damping_N_s_per_m: float
    branch: str
    family: str
    stable: bool
    slope: float
    extrapolated: bool

    def to_dict(self) -> dict:
        out = dict(self.__dict__)
        for key in ("damper_phasor", "response_phasor"):
            z = out.pop(key)
            out[key.replace("phasor", "phase_rad")] = float(np.angle(z)) if z != 0 else 0.0
        return out


@dataclass(frozen=True)
class FrequencyResponse:
    """The solutions at each of ``frequencies`` [Hz] (``solutions[i]``: every fixed point, stable
    or not, by increasing amplitude), ``jumps``: the frequencies [Hz] where the stable solutions
    change in number or in mode family (a fold, or the response moving to another mode or onto the
    fields' jump: it jumps there on a slow sweep), ``time_s``: the wall
    time [s] of each frequency's solve."""

    frequencies: np.ndarray
    force_amplitude: float
    solutions: list
    jumps: list = field(default_factory=list)
    time_s: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def stable(self, what: str = "damper_amplitude_m") -> list:
        """Per frequency the stable solutions' ``what`` (a list, by increasing damper amplitude)."""
        return [[getattr(s, what) for s in sols if s.stable] for sols in self.solutions]


def _impedance(fields, X, f, branch, extrapolate):
    v = fields.at(X, f, branch=branch, extrapolate=extrapolate)
    m, c = v.effective_mass_kg, v.equivalent_damping_N_s_per_m
    if not (math.isfinite(m) and math.isfinite(c)):
        raise InputError(f"the fields have no effective mass or equivalent damping at X = {X * 1e3:.4g} mm, "
                         f"f = {f:g} Hz (NaN); rebuild them with 'pdamper fields' from a store that has them")
    w = 2.0 * math.pi * f
    return complex(-w * w * m, w * c), v


def solve_frequency(modal, fields, frequency: float, force_amplitude: float, *, extrapolate: bool = False,
                    points: int = 48) -> list[Solution]:
    """Every fixed point of the harmonic balance at ``frequency`` [Hz] under ``force_amplitude``
    [N] (module docstring), by increasing damper amplitude."""
    f = float(frequency)
    F0 = float(force_amplitude)
    if not (F0 > 0 and math.isfinite(F0)):
        raise InputError(f"force amplitude = {shown(force_amplitude)} N; must be > 0")
    Hdd, Hdf, Hrd, Hrf = receptances(modal, f)
    if Hdf == 0:
        return [Solution(damper_amplitude_m=0.0, response_amplitude_m=abs(Hrf) * F0, damper_phasor=0j,
                         response_phasor=Hrf * F0, effective_mass_kg=math.nan, equivalent_damping_N_s_per_m=math.nan,
                         branch="", family="", stable=True, slope=math.inf, extrapolated=False)]
    fs = fields.frequencies
    lo, hi = fields.amplitude_box(f)
    if not math.isfinite(lo):
        if not extrapolate:
            raise InputError(f"f = {f:g} Hz is outside the frequencies of the fields ({fs[0]:g}-{fs[-1]:g} Hz); "
                             "choose --frequencies inside them, widen the sweep over drive.frequency, or allow "
                             "--extrapolate (the end frequency's fields continued)")
        lo, hi = fields.amplitude_box(fs[0] if f < fs[0] else fs[-1])
    logG0 = math.log(F0 * abs(Hdf))

    def residual(X, branch):
        Z, v = _impedance(fields, X, f, branch, extrapolate)
        return math.log(X) - logG0 + math.log(abs(1.0 + Hdd * Z)), v

    # the box must hold every solution: R(lo) < 0 < R(hi) on every branch (the ends have one)
    for _ in range(_MAX_WIDEN + 1):
        r_lo, r_hi = residual(lo, None)[0], residual(hi, None)[0]
        if r_lo <= 0 and r_hi >= 0:
            break
        if not extrapolate:
            if r_lo > 0:
                raise InputError(f"at f = {f:g} Hz and F0 = {F0:g} N the damper amplitude lies below X = "
                                 f"{lo * 1e3:.4g} mm, the smallest amplitude of the fields there ({fields.box()}); "
                                 "extend the sweep to smaller strokes or allow --extrapolate")
            raise InputError(f"at f = {f:g} Hz and F0 = {F0:g} N the damper amplitude lies above X = "
                             f"{hi * 1e3:.4g} mm, the largest amplitude of the fields there ({fields.box()}); "
                             "extend the sweep to larger strokes, lower the force, or allow --extrapolate")
        lo, hi = (lo / _WIDEN if r_lo > 0 else lo), (hi * _WIDEN if r_hi < 0 else hi)
    else:
        raise InputError(f"at f = {f:g} Hz no solution within X = {lo * 1e3:.4g}-{hi * 1e3:.4g} mm even with the "
                         "fields extrapolated; check the force")
    nodes = fields.amplitudes
    grid = np.unique(np.concatenate([np.geomspace(lo, hi, int(points)), nodes[(nodes > lo) & (nodes < hi)]]))
    jumpy = any(residual(X, "below")[1].branch for X in grid) if fields.jumps() else False
    roots: list[Solution] = []
    for branch in (("below", "above", None) if jumpy else (None,)):
        if jumpy and branch is None and any(s.branch for s in roots):
            break  # a mode holds in the jump interval: the bed does not switch there
        r = np.array([residual(X, branch)[0] for X in grid])
        for i in np.flatnonzero(np.sign(r[:-1]) * np.sign(r[1:]) <= 0):
            if r[i] == 0 and i > 0 and r[i - 1] == 0:
                continue
            X, v, is_root = _refine(residual, grid[i], grid[i + 1], branch, r[i], r[i + 1])
            if any(abs(X - s.damper_amplitude_m) <= 1e-7 * X for s in roots):
                continue
            if is_root:
                roots.append(_solution(X, v, branch, residual, f, F0, Hdd, Hdf, Hrd, Hrf))
            elif jumpy and branch is None:  # the fields' jump itself, at the interval's geometric midpoint
                sol = _at_jump(X, residual, f, F0, Hdd, Hdf, Hrd, Hrf, fields, extrapolate, rising=r[i] < r[i + 1])
                if sol is not None:
                    roots.append(sol)
    return sorted(roots, key=lambda s: s.damper_amplitude_m)


def _refine(residual, a, b, branch, ra, rb):
    """(X, fields at X, True) at a root of the residual between a and b, or (X, fields, False) where
    Brent's method closed on a jump of the fields instead."""
    from scipy.optimize import brentq

    if ra == 0:
        X = a
    elif rb == 0:
        X = b
    else:
        g = lambda u: residual(math.exp(u), branch)[0]  # noqa: E731
        la, lb = math.log(a), math.log(b)
        if g(la) * g(lb) > 0:  # a jump on a grid node: exp(log a) fell on its other side
            X = a if abs(ra) < abs(rb) else b
        else:
            X = math.exp(brentq(g, la, lb, xtol=1e-13, rtol=1e-15))
    rx, v = residual(X, branch)
    return X, v, abs(rx) <= RESIDUAL_TOLERANCE


def _at_jump(X, residual, f, F0, Hdd, Hdf, Hrd, Hrf, fields, extrapolate, *, rising: bool):
    """A solution held at the fields' jump X [m]: neither branch has a fixed point there, the
    residual changes sign across the jump; the bed's impedance a mixture (1 - s) Z_- + s Z_+ of the
    two sides with the s in [0, 1] that makes X = G(X) (the bed switching between its modes).
    ``rising``: the residual rises across the jump (stable by the slope criterion)."""
    from scipy.optimize import brentq

    w = 2.0 * math.pi * f
    (Zm, vm), (Zp, vp) = (_impedance(fields, X * (1.0 + d), f, None, extrapolate) for d in (-1e-9, 1e-9))
    g = lambda s: math.log(X) - math.log(F0 * abs(Hdf) / abs(1.0 + Hdd * ((1 - s) * Zm + s * Zp)))  # noqa: E731
    if g(0.0) * g(1.0) > 0:
        return None
    s = brentq(g, 0.0, 1.0, xtol=1e-14)
    Z = (1 - s) * Zm + s * Zp
    xd = Hdf * F0 / (1.0 + Hdd * Z)
    xr = Hrf * F0 - Hrd * Z * xd
    return Solution(damper_amplitude_m=float(abs(xd)), response_amplitude_m=float(abs(xr)), damper_phasor=complex(xd),
                    response_phasor=complex(xr), effective_mass_kg=float(-Z.real / (w * w)),
                    equivalent_damping_N_s_per_m=float(Z.imag / w), branch="jump", family=f"{vm.family}/{vp.family}",
                    stable=bool(rising), slope=math.inf if rising else -math.inf, extrapolated=vm.extrapolated)


def _solution(X, v, branch, residual, f, F0, Hdd, Hdf, Hrd, Hrf) -> Solution:
    h = 1e-4
    slope = (residual(X * math.exp(h), branch)[0] - residual(X * math.exp(-h), branch)[0]) / (2 * h)
    w = 2.0 * math.pi * f
    Z = complex(-w * w * v.effective_mass_kg, w * v.equivalent_damping_N_s_per_m)
    xd = Hdf * F0 / (1.0 + Hdd * Z)
    xr = Hrf * F0 - Hrd * Z * xd
    return Solution(damper_amplitude_m=float(abs(xd)), response_amplitude_m=float(abs(xr)), damper_phasor=complex(xd),
                    response_phasor=complex(xr), effective_mass_kg=v.effective_mass_kg,
                    equivalent_damping_N_s_per_m=v.equivalent_damping_N_s_per_m, branch=v.branch, family=v.family,
                    stable=bool(slope > 0), slope=float(slope), extrapolated=v.extrapolated)


def _signature(solutions) -> tuple:
    """The mode families of the stable solutions, sorted: a change of it between two frequencies is
    a jump (a branch ends, or the response moves to another mode or to the jump)."""
    return tuple(sorted(s.family for s in solutions if s.stable))


def solve_response(modal, fields, frequencies, force_amplitude: float, *, extrapolate: bool = False,
                   points: int = 48, jump_tolerance: float = 1e-4) -> FrequencyResponse:
    """:func:`solve_frequency` at each of ``frequencies`` [Hz]; between two neighbours whose stable
    solutions differ in number or in mode family (:func:`_signature`), the jump frequency found by
    bisection to ``jump_tolerance`` (relative)."""
    freqs = np.asarray(frequencies, dtype=float)
    sols, times = [], []
    for f in freqs:
        t0 = time.perf_counter()
        sols.append(solve_frequency(modal, fields, f, force_amplitude, extrapolate=extrapolate, points=points))
        times.append(time.perf_counter() - t0)
    order = np.argsort(freqs)
    jumps = []
    for a, b in zip(order[:-1], order[1:]):
        sa, sb = _signature(sols[a]), _signature(sols[b])
        if sa == sb:
            continue
        lo, hi = float(freqs[a]), float(freqs[b])
        while hi - lo > jump_tolerance * hi:
            mid = 0.5 * (lo + hi)
            if _signature(solve_frequency(modal, fields, mid, force_amplitude, extrapolate=extrapolate,
                                          points=points)) == sa:
                lo = mid
            else:
                hi = mid
        jumps.append({"frequency_hz": 0.5 * (lo + hi), "stable_below": len(sa), "stable_above": len(sb),
                      "families_below": list(sa), "families_above": list(sb)})
    return FrequencyResponse(frequencies=freqs, force_amplitude=float(force_amplitude), solutions=sols, jumps=jumps,
                             time_s=np.asarray(times))


# --------------------------------------------------------------------------- several dampers

@dataclass(frozen=True)
class SeveralSolution:
    """One fixed point of the harmonic balance with several dampers at one frequency: each damper
    point's amplitude [m] and complex amplitude, the response point's, each damper's fields there,
    ``stable`` (the amplitudes' slow flow, see :func:`solve_several`) and the Jacobian's eigenvalue of
    smallest real part (``slope``; one damper: dR/d ln X)."""

    damper_amplitudes_m: tuple
    damper_phasors: tuple
    response_amplitude_m: float
    response_phasor: complex
    effective_masses_kg: tuple
    equivalent_dampings_N_s_per_m: tuple
    families: tuple
    stable: bool
    slope: float
    extrapolated: bool

    @property
    def damper_amplitude_m(self) -> float:
        """The first damper point's amplitude [m]."""
        return float(self.damper_amplitudes_m[0])

    def to_dict(self) -> dict:
        return {"damper_amplitudes_m": list(self.damper_amplitudes_m),
                "damper_phases_rad": [float(np.angle(z)) for z in self.damper_phasors],
                "response_amplitude_m": self.response_amplitude_m,
                "response_phase_rad": float(np.angle(self.response_phasor)),
                "effective_masses_kg": list(self.effective_masses_kg),
                "equivalent_dampings_N_s_per_m": list(self.equivalent_dampings_N_s_per_m),
                "families": list(self.families), "stable": self.stable, "slope": self.slope,
                "extrapolated": self.extrapolated}


def _receptance_matrices(modal, shapes, frequency: float):
    """(H_DD (n x n), H_Df (n), H_rD (n), H_rf) of the bare structure at ``frequency`` [Hz] with the
    damper points' mode ``shapes`` (n x modes)."""
    m, k, c, pd, pf, pr = (np.asarray(a, dtype=float) for a in modal)
    P = np.asarray(shapes, dtype=float)
    w = 2.0 * math.pi * float(frequency)
    den = m * (k / m - w * w) + 1j * w * c
    return (P / den) @ P.T, (P / den) @ pf, (P / den) @ pr, complex(np.sum(pr * pf / den))


def solve_several(modal, shapes, fields, frequency: float, force_amplitude: float, *, extrapolate: bool = False,
                  starts: int = 6) -> list:
    """The fixed points of the harmonic balance with a damper at each of several points (mode
    ``shapes``: points x modes), damper j as its ``fields[j]`` (a
    :class:`~pdamper.analysis.fields.DamperFields`): the damper points' complex amplitudes solve

        (I + H_DD Z(X)) x^ = H_Df F0,     Z = diag(Z_j(|x^_j|, f)),

    so their amplitudes are a fixed point ``ln X = ln |x^(X)|`` in n dimensions. Found by Powell's
    hybrid method (scipy ``root``) from ``starts`` starting points (the bare amplitudes, the solid-mass
    ones and fractions of them), the distinct converged ones kept, by increasing first amplitude.
    Each damper's fields as :meth:`~pdamper.analysis.fields.DamperFields.at` gives them (in a jump
    interval: the jump at its geometric midpoint; the one-damper solver, :func:`solve_frequency`,
    follows both segments and the bed switching between them).

    **Stability**: the slow flow of the amplitudes, ``d(ln X)/dt = -(ln X - ln |x^(X)|)`` linearised at
    the fixed point, is stable when every eigenvalue of its Jacobian has a positive real part -- for one
    damper the slope criterion of :func:`solve_frequency`; for several a heuristic (the amplitudes'
    phases are slaved to them here)."""
    from scipy.optimize import root

    f = float(frequency)
    F0 = float(force_amplitude)
    if not (F0 > 0 and math.isfinite(F0)):
        raise InputError(f"force amplitude = {force_amplitude!r} N; must be > 0")
    P = np.asarray(shapes, dtype=float)
    n = P.shape[0]
    if len(fields) != n:
        raise InputError(f"{len(fields)} fields for {n} dampers: give one fields file a damper (or one for all)")
    HDD, HDf, HrD, Hrf = _receptance_matrices(modal, P, f)
    w = 2.0 * math.pi * f
    boxes = [fl.amplitude_box(min(max(f, fl.frequencies[0]), fl.frequencies[-1])) for fl in fields]
    for j, fl in enumerate(fields):
        if not (fl.frequencies[0] <= f <= fl.frequencies[-1]) and not extrapolate:
            raise InputError(f"f = {f:g} Hz is outside the frequencies of damper {j + 1}'s fields "
                             f"({fl.frequencies[0]:g}-{fl.frequencies[-1]:g} Hz); choose --frequencies inside them "
                             "or allow --extrapolate")

    def state(u):
        X = np.exp(u)
        vals = [fl.at(float(X[j]), f, extrapolate=True) for j, fl in enumerate(fields)]
        Z = np.array([complex(-w * w * v.effective_mass_kg, w * v.equivalent_damping_N_s_per_m) for v in vals])
        x = np.linalg.solve(np.eye(n) + HDD * Z[None, :], HDf * F0)
        return x, Z, vals

    def residual(u):
        x, _, _ = state(u)
        return u - np.log(np.maximum(np.abs(x), 1e-300))

    bare = np.abs(HDf * F0)
    x0 = [bare, 0.5 * bare, 0.25 * bare, 2.0 * bare, np.array([math.sqrt(lo * hi) for lo, hi in boxes]),
          np.array([hi for lo, hi in boxes])][:max(1, int(starts))]
    found = []
    for start in x0:
        u0 = np.log(np.maximum(start, 1e-12))
        sol = root(residual, u0, method="hybr", options={"xtol": 1e-12})
        if not sol.success or not np.all(np.abs(residual(sol.x)) <= RESIDUAL_TOLERANCE):
            continue
        if any(np.max(np.abs(sol.x - g)) <= 1e-6 for g in found):
            continue
        found.append(sol.x)
    out = []
    for u in found:
        X = np.exp(u)
        outside = [j for j, (lo, hi) in enumerate(boxes) if not lo * (1 - 1e-9) <= X[j] <= hi * (1 + 1e-9)]
        if outside and not extrapolate:
            j = outside[0]
            raise InputError(f"at f = {f:g} Hz and F0 = {F0:g} N damper {j + 1}'s amplitude {X[j] * 1e3:.4g} mm lies "
                             f"outside its fields ({fields[j].box()}); extend that sweep or allow --extrapolate")
        x, Z, vals = state(u)
        h = 1e-5
        J = np.column_stack([(residual(u + h * e) - residual(u - h * e)) / (2 * h) for e in np.eye(n)])
        eig = np.linalg.eigvals(J)
        xr = Hrf * F0 - HrD @ (Z * x)
        out.append(SeveralSolution(damper_amplitudes_m=tuple(float(v) for v in np.abs(x)),
                                   damper_phasors=tuple(complex(v) for v in x), response_amplitude_m=float(abs(xr)),
                                   response_phasor=complex(xr),
                                   effective_masses_kg=tuple(float(v.effective_mass_kg) for v in vals),
                                   equivalent_dampings_N_s_per_m=tuple(float(v.equivalent_damping_N_s_per_m)
                                                                       for v in vals),
                                   families=tuple(v.family for v in vals), stable=bool(np.all(eig.real > 0)),
                                   slope=float(np.min(eig.real)), extrapolated=bool(outside)))
    return sorted(out, key=lambda s: s.damper_amplitudes_m[0])


def solve_response_several(modal, shapes, fields, frequencies, force_amplitude: float, *,
                           extrapolate: bool = False) -> FrequencyResponse:
    """:func:`solve_several` at each of ``frequencies`` [Hz] (no jump search: the several dampers'
    solutions are listed per frequency)."""
    freqs = np.asarray(frequencies, dtype=float)
    sols, times = [], []
    for f in freqs:
        t0 = time.perf_counter()
        sols.append(solve_several(modal, shapes, fields, f, force_amplitude, extrapolate=extrapolate))
        times.append(time.perf_counter() - t0)
    return FrequencyResponse(frequencies=freqs, force_amplitude=float(force_amplitude), solutions=sols, jumps=[],
                             time_s=np.asarray(times))


def decay_envelope(fields, *, mass: float, stiffness: float, damping: float, amplitude: float, duration: float,
                   extrapolate: bool = False, points: int = 400):
    """The free decay's envelope A(t) [m] of a mode with the damper at its node, by averaging.

    Over a cycle of the mode at amplitude A, the structure's energy ``E = K A^2 / 2`` (at an
    extreme every velocity, the bed's effective share included, is zero) loses the bed's energy
    per cycle ``E_d(A, f)`` (the fields) and the structure's own ``pi c Omega A^2``, so

        dA/dt = -f (E_d(A, f) + pi c Omega A^2) / (K A),     Omega = 2 pi f,

    with f the mode's frequency with the bed's effective mass, ``2 pi f = sqrt(K / (M + m_eff(A,
    f)))`` (three fixed-point steps). The bed's energy per cycle is taken as ``E_d = pi c_eq Omega
    A^2`` (the same quantity; c_eq is the smoother field to interpolate in amplitude), so ``d ln A /
    dt = -f pi Omega (c_eq + c) / K``. Without a bed it is ``A0 e^{-zeta omega t}``. In a jump
    interval the decay stays on the segment it comes from (the upper one) down to its end.

    ``mass``, ``stiffness``, ``damping``: M [kg], K [N/m], c [N s/m] of the mode at the damper;
    ``amplitude``: A(0) [m]; ``duration`` [s]. Returns (t [s], A [m], f [Hz]); it stops at the
    fields' smallest amplitude unless ``extrapolate``.
    """
    from scipy.integrate import solve_ivp

    M, K, c = float(mass), float(stiffness), float(damping)
    f_n = math.sqrt(K / M) / (2.0 * math.pi)

    def frequency(A):
        f = f_n
        for _ in range(3):
            f = math.sqrt(K / (M + fields.at(A, f, branch="above", extrapolate=extrapolate).effective_mass_kg)) / (
                2.0 * math.pi)
        return f

    def rate(t, y):
        A = math.exp(y[0])
        f = frequency(A)
        c_eq = fields.at(A, f, branch="above", extrapolate=extrapolate).equivalent_damping_N_s_per_m
        W = 2.0 * math.pi * f
        return [-f * math.pi * W * (c_eq + c) / K]  # d ln A / dt

    lo = min(fields.amplitude_box(_frequency_nearest(fields, f_n))[0], amplitude)

    def floor(t, y):
        return y[0] - math.log(lo * (1.0 + 1e-9))

    floor.terminal = True
    t_eval = np.linspace(0.0, float(duration), int(points))
    sol = solve_ivp(rate, (0.0, float(duration)), [math.log(float(amplitude))], t_eval=t_eval, rtol=1e-6,
                    atol=1e-9, events=None if extrapolate else floor)
    A = np.exp(sol.y[0])
    return sol.t, A, np.array([frequency(a) for a in A])


def _frequency_nearest(fields, f: float) -> float:
    """The fields' frequency node nearest ``f`` [Hz] when f is outside their range, else f."""
    fs = fields.frequencies
    return float(min(max(f, fs[0]), fs[-1]))
