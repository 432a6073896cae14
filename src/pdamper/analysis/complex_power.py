"""The complex power method: energy dissipated per cycle and reduced loss factor.

Paper Sect. 4.1 ("Energy dissipation in horizontally driven particle dampers of
low acceleration intensities", Nonlinear Dynamics), after Yang's complex power
method. With ``F*`` and ``V*`` the complex amplitudes of the driving force on the
container and of the container velocity at the drive frequency ``f``
(``Omega = 2 pi f``):

- complex power (3): ``P = 1/2 F* conj(V*)``                       [W]
- energy dissipated per cycle (4): ``E~_diss = 2 pi E_diss = (2 pi / Omega) Re(P)``  [J]
- reduced loss factor (5): ``eta* = E_diss / (1/2 m_bed |V*_Omega|^2)``  [-]

Beyond the paper, the same ``P`` gives the mass and the dashpot that, moved as the container
is, would take the same power at f (``PowerResult.effective_mass_kg``,
``PowerResult.equivalent_damping_N_s_per_m``):

- effective mass: ``m_eff = Im(P) / (1/2 Omega |V*|^2) - m_c``                 [kg]
- equivalent damping: ``c_eq = 2 Re(P) / |V*|^2``                              [N s/m]

with ``m_c`` the container's own mass (``container_mass``, 0 unless given), whose ``m_c x_c''``
is part of the force. A force ``F = m x'' + c x' + k x`` gives ``m - k/Omega^2`` and ``c``.

``E~_diss`` is the energy taken out of the drive in one cycle (a viscous damper
``F = c v`` driven at ``x = X sin(Omega t)`` gives ``pi c Omega X^2``); ``E_diss =
E~_diss / (2 pi)`` is the paper's scaled energy used in (5).

What happens to a record
------------------------
1. **Validation.** Time, force and motion must be 1-D, of equal length (at least
   3 samples), finite, and the time strictly increasing and uniformly sampled:
   every sample within ``time_tolerance`` (default 1e-3) sample intervals of the
   straight line from the first to the last time. Records that pass are treated
   as sampled exactly on that uniform grid. Every problem raises
   :class:`~pdamper.errors.InputError` with one message naming it and the fix.
2. **Drive frequency.** Given, or detected from the motion signal (see
   :func:`detect_frequency`): the largest non-DC peak of the Hann-windowed,
   zero-padded spectrum, refined by parabolic interpolation of the
   log-magnitude and then by a least-squares sinusoid fit (frequency, amplitude,
   phase, offset and linear drift), polished by Gauss-Newton steps. A 2 Hz drive sampled at 1 kHz over 20 cycles
   is found to ~1e-12 relative without noise. The drive must carry at least half
   of the (detrended) motion variance, otherwise "no clear drive peak".
3. **Whole cycles.** Cycle ``k`` spans ``[t0 + k T, t0 + (k+1) T)`` with ``T = 1/f``
   and ``t0`` the first sample. Each cycle is represented by ``m`` equally spaced
   points (rectangle rule, the FFT's own quadrature), so a cycle is complete when
   its last point, ``T/m`` before the cycle's end, lies inside the record (a
   20-cycle record of 10 000 samples at 1 kHz and 2 Hz holds 20 whole cycles).
   The first ``drop_cycles`` cycles are dropped, the FFT window is all the
   remaining whole cycles (the largest integer number), and the fraction of a
   cycle at the end of the record is not used.

   - *Integer samples per period* (``T/dt`` within 1e-9 of an integer ``m``, the
     paper's 1 kHz / 2 Hz): the samples themselves are used, ``m = T/dt``; the
     window holds exactly ``n m`` samples, the drive is exactly FFT bin ``n``, and
     no interpolation is involved.
   - *Otherwise* the window cannot consist of whole cycles on the sample grid.
     The record is then resampled, by an interpolating quintic spline through the
     samples, onto a grid of ``m = ceil(T/dt)`` points per period starting at
     ``t0``; the window is again exactly ``n`` periods long and the drive exactly
     bin ``n`` of its FFT (i.e. the DFT is evaluated at the exact frequency, not
     at the nearest bin of the original grid). For a smooth signal the error is
     that of the spline, ~``(Omega dt)^6``: 1e-15 at 2.37 Hz / 1 kHz, 1e-12 at
     9.3 Hz, 1e-8 at 47 Hz (22 samples per period). ``PowerResult.resampled`` says
     which path was taken.
4. **Complex amplitudes.** ``X* = (2/M) sum_j x_j exp(-i Omega tau_j)`` over the
   ``M = n m`` window points, ``tau_j`` the time since the window start (the
   phases refer to the window start; ``P`` does not depend on it). With this
   normalisation ``X sin(Omega t)`` has ``|X*| = X`` and ``x(t) = Re(X* e^{i Omega t})``.
   Motion given as position gives ``V* = i Omega X*``, as acceleration
   ``V* = A* / (i Omega)``: exact at the drive frequency, no numerical
   differentiation or integration.
5. **Velocity signal** (for the time-domain cross-check, the per-cycle energies
   and the plot): velocity as given; position: the fitted drive sinusoid is
   differentiated exactly and the remainder (harmonics, noise, encoder steps)
   low-passed at 20 f (zero-phase 4th-order Butterworth) and differentiated
   through its quintic spline, so a clean drive keeps its exact derivative and
   measurement noise is not amplified up to the Nyquist frequency;
   acceleration integrated through the antiderivative of its quintic spline, the
   unknown constant fixed so that the velocity has zero mean over the FFT window
   (a sensor offset in the acceleration would show as a linear drift here; it
   does not affect ``P``).
6. **Cross-checks.** ``mean_power_check_J = <F v> T`` over the window: equal to
   ``energy_per_cycle_J`` to rounding when the velocity is a pure sinusoid (then
   only the force's fundamental does work), different when the motion has
   harmonics. ``cycle_energies_J`` is ``int F v dt`` over every whole cycle of the
   record, dropped ones included (``cycle_used`` flags them), so one sees whether
   the record is steady; ``cycle_energy_spread`` is the relative standard
   deviation of the used ones.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError, shown
from .checks import (_as_1d, _check_bed_mass, _check_drop, _check_finite, _check_frequency, _check_lengths,
                     _check_tolerance, _uniform_grid)
from .frequency import TIME_TOLERANCE, detect_frequency
from .results import PowerResult, Signals
from .sinusoid import MIN_GIVEN_SHARE, detect_uniform
from ..units import quantities

# The method lives here; the result types (results.py), the input checks (checks.py) and the
# frequency detection (frequency.py) have their own modules and are re-exported for the names
# this module always had.
__all__ = [
    "PowerResult",
    "Signals",
    "complex_power",
    "analyze_record",
    "detect_frequency",
    "DEFAULT_DROP_CYCLES",
    "TIME_TOLERANCE",
    "MOTIONS",
]

#: Cycles dropped at the start of a record by default (paper Sect. 2: 2 of 20).
DEFAULT_DROP_CYCLES = 2
#: Motion signals a record may carry.
MOTIONS = ("position", "velocity", "acceleration")

# T/dt closer than this (relative) to an integer counts as integer samples per period.
_INTEGER_RATIO_TOL = 1e-9
# Order of the interpolating spline used for resampling, differentiation, integration.
_SPLINE_ORDER = 5
# Position-derived velocity keeps harmonics up to this multiple of the drive frequency.
_VELOCITY_HARMONICS = 20


# --------------------------------------------------------------------------- public API


@quantities(time="time", force="force", velocity="velocity", frequency="frequency", bed_mass="mass",
            time_tolerance="dimensionless", container_mass="mass")
def complex_power(
    time,
    force,
    velocity,
    *,
    frequency: float | None = None,
    drop_cycles: int = DEFAULT_DROP_CYCLES,
    bed_mass: float | None = None,
    time_tolerance: float = TIME_TOLERANCE,
    keep_signals: bool = True,
    container_mass: float = 0.0,
) -> PowerResult:
    """Complex power, energy per cycle and reduced loss factor of a force/velocity record.

    Implements eqs. (3)-(5) of the paper over the whole cycles left after
    dropping the first ``drop_cycles`` (see the module docstring for the exact
    procedure).

    Parameters
    ----------
    time : array_like
        Sample times [s], uniformly spaced.
    force : array_like
        Driving force on the container along the drive [N].
    velocity : array_like
        Container velocity along the drive [m/s].
    frequency : float, optional
        Drive frequency f [Hz]; detected from ``velocity`` if omitted.
    drop_cycles : int, default 2
        Whole cycles dropped at the start (the transient).
    bed_mass : float, optional
        Mass of the particle bed m_bed [kg]; without it ``eta_star`` is NaN.
    time_tolerance : float, default 1e-3
        Largest deviation of a time stamp from the uniform grid [sample intervals].
    keep_signals : bool, default True
        Keep the signals in ``PowerResult.signals`` (for plots).
    container_mass : float, default 0
        The container's own mass m_c [kg], whose ``m_c x_c''`` is part of ``force``; removed
        from the bed's effective mass ``PowerResult.effective_mass_kg``.

    Returns
    -------
    PowerResult

    Raises
    ------
    InputError
        For any malformed record or argument, with the problem and the fix.

    Examples
    --------
    A viscous damper ``F = c v`` dissipates ``pi c Omega X^2`` per cycle:

    >>> import numpy as np
    >>> t = np.arange(10_000) * 1e-3                      # 20 cycles at 2 Hz, 1 kHz
    >>> X, W, c = 0.01, 2 * np.pi * 2.0, 3.0
    >>> v = X * W * np.cos(W * t)
    >>> r = complex_power(t, c * v, v, bed_mass=0.149)
    >>> r.cycles_used, round(r.frequency_hz, 9)
    (18, 2.0)
    >>> bool(np.isclose(r.energy_per_cycle_J, np.pi * c * W * X**2, rtol=1e-12))
    True
    """
    return _with_container(_analyze(time, force, velocity, "velocity", frequency=frequency,
                                    drop_cycles=drop_cycles, bed_mass=bed_mass,
                                    time_tolerance=time_tolerance, keep_signals=keep_signals), container_mass)


@quantities(time="time", force="force", position="length", velocity="velocity", acceleration="acceleration",
            frequency="frequency", bed_mass="mass", time_tolerance="dimensionless", container_mass="mass")
def analyze_record(
    time,
    force,
    *,
    position=None,
    velocity=None,
    acceleration=None,
    frequency: float | None = None,
    drop_cycles: int = DEFAULT_DROP_CYCLES,
    bed_mass: float | None = None,
    time_tolerance: float = TIME_TOLERANCE,
    keep_signals: bool = True,
    container_mass: float = 0.0,
) -> PowerResult:
    """Complex power method on a record with any one motion signal.

    Exactly one of ``position`` [m], ``velocity`` [m/s] or ``acceleration``
    [m/s^2] must be given. At the drive frequency the velocity amplitude follows
    exactly: ``V* = i Omega X*`` from position, ``V* = A* / (i Omega)`` from
    acceleration. The other arguments are those of :func:`complex_power`.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(10_000) * 1e-3
    >>> X, W, c = 0.01, 2 * np.pi * 2.0, 3.0
    >>> r = analyze_record(t, c * X * W * np.cos(W * t), position=X * np.sin(W * t))
    >>> bool(np.isclose(r.energy_per_cycle_J, np.pi * c * W * X**2, rtol=1e-12))
    True
    """
    given = [(name, sig) for name, sig in
             (("position", position), ("velocity", velocity), ("acceleration", acceleration))
             if sig is not None]
    if len(given) != 1:
        names = ", ".join(n for n, _ in given) or "none"
        raise InputError(
            "give exactly one motion signal (position, velocity or acceleration); "
            f"got {names}")
    kind, motion = given[0]
    return _with_container(_analyze(time, force, motion, kind, frequency=frequency,
                                    drop_cycles=drop_cycles, bed_mass=bed_mass,
                                    time_tolerance=time_tolerance, keep_signals=keep_signals), container_mass)


# --------------------------------------------------------------------------- the method


def _with_container(result: PowerResult, container_mass) -> PowerResult:
    """``result`` with the container's own mass to remove from the bed's effective mass."""
    import numbers

    if isinstance(container_mass, bool) or not isinstance(container_mass, numbers.Real) \
            or not (math.isfinite(container_mass) and container_mass >= 0.0):
        raise InputError(f"container mass must be a number >= 0 in kg (the empty container's own mass); "
                         f"got {shown(container_mass)}")
    if container_mass == 0.0:
        return result
    from dataclasses import replace

    return replace(result, container_mass_kg=float(container_mass))


def _analyze(time, force, motion, kind, *, frequency, drop_cycles, bed_mass,
             time_tolerance, keep_signals) -> PowerResult:
    t = _as_1d("time", time)
    F = _as_1d("force", force)
    s = _as_1d(kind, motion)
    _check_lengths({"time": t, "force": F, kind: s})
    _check_finite("time", t, None)
    _check_finite("force", F, t)
    _check_finite(kind, s, t)
    drop = _check_drop(drop_cycles)
    bed = _check_bed_mass(bed_mass)
    _check_tolerance(time_tolerance)
    try:
        t0, dt = _uniform_grid(t, time_tolerance)
    except InputError as exc:
        if not np.all(np.diff(t) > 0):
            raise
        # jitter, rounded stamps or a dropped sample: the phasors at the true time stamps
        from .nonuniform import analyze_nonuniform

        return analyze_nonuniform(t, F, s, kind, frequency=frequency, drop=drop, bed=bed,
                                  keep_signals=keep_signals, uniform_error=str(exc))
    n_samples = t.size
    fs = 1.0 / dt

    if frequency is None:
        f, _ = detect_uniform(s, dt, kind)
        detected = True
    else:
        f = _check_frequency(frequency)
        detected = False
    if f >= 0.5 * fs:
        raise InputError(
            f"drive frequency {f:.6g} Hz is at or above the Nyquist frequency "
            f"{0.5 * fs:.6g} Hz of the record (sample rate {fs:.6g} Hz); give the "
            "right frequency or a record sampled faster")
    period = 1.0 / f
    omega = 2.0 * math.pi * f

    # ---- whole cycles: m points per period, n_total complete cycles from t0
    ratio = period / dt
    m_int = int(round(ratio))
    on_grid = m_int >= 2 and abs(ratio - m_int) <= _INTEGER_RATIO_TOL * ratio
    if on_grid:
        m = m_int
        h = dt
        n_total = n_samples // m
    else:
        m = int(math.ceil(ratio))
        h = period / m
        span = (n_samples - 1) * dt
        # The last window point may lie up to 0.1 h past the last sample (a detected
        # frequency a hair low must not cost the last cycle); the spline extrapolates.
        n_total = int(math.floor((span + 1.1 * h) / period))
    n_used = n_total - drop
    if n_used < 1:
        held = n_samples * dt / period
        raise InputError(
            f"the record holds {held:.3g} cycles of {f:.6g} Hz ({n_total} whole) and the "
            f"first {drop} are dropped, which leaves no whole cycle to analyse; use a "
            f"longer record or fewer dropped cycles (drop_cycles, --drop-cycles "
            f"{max(n_total - 1, 0)})")

    tk = np.arange(n_samples) * dt          # sample times relative to t0 (uniform grid)
    spline = _spline(tk, s) if (not on_grid or kind == "acceleration") else None
    if on_grid:
        F_g = F[: n_total * m]
        s_g = s[: n_total * m]
    else:
        tau = np.arange(n_total * m) * h
        F_g = _spline(tk, F)(tau)
        s_g = spline(tau)

    # velocity on the analysis grid and on the samples
    if kind == "velocity":
        v_g = s_g
        v_k = s
    elif kind == "position":
        d = _position_to_velocity(tk, s, f, fs)
        v_g = d(tau) if not on_grid else d(tk[: n_total * m])
        v_k = d(tk)
    else:  # acceleration
        a_int = spline.antiderivative()
        v_g = a_int(tau) if not on_grid else a_int(tk[: n_total * m])
        v_k = a_int(tk)
    i0, i1 = drop * m, n_total * m
    if kind == "acceleration":
        offset = float(np.mean(v_g[i0:i1]))
        v_g = v_g - offset
        v_k = v_k - offset

    # ---- complex amplitudes at the drive: bin n_used of the window's FFT (eq. 3)
    S_star = _amplitude(s_g[i0:i1], n_used)
    F_star = _amplitude(F_g[i0:i1], n_used)
    if kind == "velocity":
        V_star = S_star
    elif kind == "position":
        V_star = 1j * omega * S_star
    else:
        V_star = S_star / (1j * omega)

    s_win = s_g[i0:i1]
    var = float(np.mean((s_win - s_win.mean()) ** 2))
    share = 0.5 * abs(S_star) ** 2 / var if var > 0.0 else 0.0
    if not detected and share < MIN_GIVEN_SHARE:
        raise InputError(
            f"the {kind} signal has almost nothing at the given drive frequency "
            f"{f:.6g} Hz ({100 * share:.2g} % of its variance in the window); check the "
            "frequency, or omit it to detect the drive from the motion")

    P = 0.5 * F_star * np.conj(V_star)                                  # (3)
    energy = (2.0 * math.pi / omega) * P.real                           # (4)
    e_diss = energy / (2.0 * math.pi)
    v_amp = abs(V_star)
    if bed is None:
        eta = math.nan
    elif v_amp == 0.0:
        eta = math.nan
    else:
        eta = e_diss / (0.5 * bed * v_amp**2)                           # (5)

    # ---- time-domain cross-checks
    power = F_g * v_g
    mean_power = float(np.mean(power[i0:i1])) * period
    cycle_e = power.reshape(n_total, m).sum(axis=1) * h
    used = np.arange(n_total) >= drop
    spread = math.nan
    if n_used >= 2:
        e_used = cycle_e[used]
        apparent = math.pi * abs(F_star) * v_amp / omega
        scale = max(abs(float(e_used.mean())), 1e-9 * apparent)
        if scale > 0.0:
            spread = float(np.std(e_used, ddof=1)) / scale
    starts = t0 + np.arange(n_total) * period
    for arr in (cycle_e, starts, used):
        arr.setflags(write=False)

    signals = None
    if keep_signals:
        signals = Signals(time_s=t, force_N=F, velocity_m_s=np.asarray(v_k, dtype=float),
                          motion=kind)

    return PowerResult(
        frequency_hz=float(f),
        frequency_detected=detected,
        sample_rate_hz=float(fs),
        resampled=not on_grid,
        motion=kind,
        cycles_dropped=drop,
        cycles_used=n_used,
        window_s=(float(t0 + drop * period), float(t0 + n_total * period)),
        complex_power_W=complex(P),
        force_phasor_N=complex(F_star),
        velocity_phasor_m_s=complex(V_star),
        force_amplitude_N=float(abs(F_star)),
        velocity_amplitude_m_s=float(v_amp),
        energy_per_cycle_J=float(energy),
        dissipated_energy_J=float(e_diss),
        eta_star=float(eta),
        bed_mass_kg=math.nan if bed is None else float(bed),
        mean_power_check_J=mean_power,
        drive_share=float(min(share, 1.0)),
        cycle_energies_J=cycle_e,
        cycle_start_s=starts,
        cycle_used=used,
        cycle_energy_spread=spread,
        signals=signals,
        time_base=_time_base(t, True),
    )


def _time_base(t, uniform):
    from .nonuniform import time_base

    return time_base(t, uniform)


def _amplitude(x: np.ndarray, n_cycles: int) -> complex:
    """Complex amplitude at bin ``n_cycles`` of whole-cycle samples: ``(2/M) sum x_j e^{-2 pi i n j/M}``."""
    return complex(np.fft.rfft(x)[n_cycles] * (2.0 / x.size))


def _spline(tk: np.ndarray, y: np.ndarray):
    from scipy.interpolate import make_interp_spline

    k = min(_SPLINE_ORDER, tk.size - 1)
    return make_interp_spline(tk, y, k=k)


def _position_to_velocity(tk: np.ndarray, x: np.ndarray, f: float, fs: float):
    """Velocity [m/s] as a function of time since t0, from position samples [m].

    The drive sinusoid ``a cos(Omega t) + b sin(Omega t) + c`` (least-squares fit
    to all samples) is differentiated exactly; the rest (harmonics, noise, encoder
    steps) is low-passed at ``_VELOCITY_HARMONICS`` times f (4th-order
    Butterworth, forward and backward, so no phase shift) when that is below
    0.4 fs, and differentiated through its quintic spline. A clean sinusoid thus
    keeps its exact derivative, and differentiation does not blow up measurement
    noise (an encoder with 20 um steps at 1 kHz would otherwise add ~10 mm/s).
    """
    from scipy.signal import butter, sosfiltfilt

    w = 2.0 * math.pi * f
    basis = np.column_stack([np.cos(w * tk), np.sin(w * tk), np.ones(tk.size)])
    (a, b, _c), *_ = np.linalg.lstsq(basis, x, rcond=None)
    rest = x - basis @ np.array([a, b, _c])
    fc = _VELOCITY_HARMONICS * f
    if fc < 0.4 * fs and tk.size > 12:
        sos = butter(4, fc, fs=fs, output="sos")
        padlen = int(min(tk.size - 1, math.ceil(3.0 * fs / fc)))
        rest = sosfiltfilt(sos, rest, padtype="odd", padlen=padlen)
    d_rest = _spline(tk, rest).derivative()

    def velocity(t):
        return w * (b * np.cos(w * t) - a * np.sin(w * t)) + d_rest(t)

    return velocity
