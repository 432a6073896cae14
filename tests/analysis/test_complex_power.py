"""Complex power method (paper Sect. 4.1, eqs. 3-5) against closed forms and invariants."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from pdamper.analysis import (
    PowerResult,
    analyze_record,
    complex_power,
    detect_frequency,
)
from pdamper.errors import InputError

FS = 1000.0  # the paper's sample rate [Hz]


def drive(f, *, cycles=20.0, fs=FS, X=0.01, phase=0.0, t0=0.0):
    """Samples of x = X sin(Omega t + phase): time [s], x [m], v [m/s], a [m/s^2]."""
    n = int(round(cycles * fs / f))
    t = t0 + np.arange(n) / fs
    w = 2 * np.pi * f
    arg = w * (t - t0) + phase
    return t, X * np.sin(arg), X * w * np.cos(arg), -X * w**2 * np.sin(arg)


def viscous_energy(c, f, X):
    """Energy per cycle of a viscous damper F = c v at x = X sin(Omega t) [J]."""
    return np.pi * c * (2 * np.pi * f) * X**2


def apparent(r: PowerResult) -> float:
    return np.pi * r.force_amplitude_N * r.velocity_amplitude_m_s / r.angular_frequency_rad_s


# --------------------------------------------------------------------------- closed forms


def test_viscous_damper_gives_pi_c_omega_x2_to_fft_precision():
    c, X, f = 12.5, 0.015, 2.0
    t, x, v, a = drive(f, X=X)
    r = complex_power(t, c * v, v, frequency=f)
    exact = viscous_energy(c, f, X)
    assert not r.resampled
    assert r.cycles_used == 18 and r.cycles_dropped == 2
    assert r.energy_per_cycle_J == pytest.approx(exact, rel=1e-12)
    assert r.dissipated_energy_J == pytest.approx(exact / (2 * np.pi), rel=1e-12)
    assert r.mean_power_check_J == pytest.approx(exact, rel=1e-12)
    # P = 1/2 c |V|^2 is real: no reactive part for a pure damper
    assert r.complex_power_W.real == pytest.approx(0.5 * c * (X * 2 * np.pi * f) ** 2, rel=1e-12)
    assert abs(r.complex_power_W.imag) < 1e-12 * abs(r.complex_power_W)


def test_spring_and_mass_dissipate_nothing():
    t, x, v, a = drive(2.0)
    for force in (4000.0 * x, 0.7 * a, 4000.0 * x + 0.7 * a):
        r = complex_power(t, force, v)
        assert abs(r.energy_per_cycle_J) < 1e-13 * apparent(r)
        assert abs(r.mean_power_check_J) < 1e-13 * apparent(r)
        assert np.all(np.abs(r.cycle_energies_J) < 1e-12 * apparent(r))


def test_reduced_loss_factor_eq5():
    c, X, f, m_bed = 3.0, 0.01, 2.0, 0.149
    t, x, v, a = drive(f, X=X)
    r = complex_power(t, c * v, v, bed_mass=m_bed)
    # E_diss = c Omega X^2 / 2, E_kin = m (X Omega)^2 / 2  ->  eta* = c / (m Omega)
    assert r.eta_star == pytest.approx(c / (m_bed * 2 * np.pi * f), rel=1e-12)
    assert r.bed_mass_kg == m_bed
    assert math.isnan(complex_power(t, c * v, v).eta_star)


def test_complex_amplitude_normalisation_and_phase():
    """X sin(Omega t) has |X*| = X; with the window starting at phase 0, V* = i Omega X* is real."""
    X, f = 0.02, 2.0
    t, x, v, a = drive(f, X=X)
    r = analyze_record(t, 5.0 * np.sin(2 * np.pi * f * t), position=x)
    assert r.force_amplitude_N == pytest.approx(5.0, rel=1e-13)
    assert r.velocity_amplitude_m_s == pytest.approx(X * 2 * np.pi * f, rel=1e-13)
    assert r.force_phasor_N == pytest.approx(-5.0j, abs=1e-12)
    assert r.velocity_phasor_m_s == pytest.approx(X * 2 * np.pi * f, abs=1e-13)


def test_nonlinear_damper_fundamental_only_and_mean_power_check():
    """Cubic damping puts harmonics in F; with a sinusoidal v only the fundamental does work."""
    c, c3, X, f = 2.0, 40.0, 0.01, 2.0
    t, x, v, a = drive(f, X=X)
    force = c * v + c3 * v**3 + 300 * x + 0.4 * a
    r = complex_power(t, force, v)
    V = X * 2 * np.pi * f
    exact = np.pi / (2 * np.pi * f) * (c * V**2 + 0.75 * c3 * V**4)
    assert r.energy_per_cycle_J == pytest.approx(exact, rel=1e-12)
    assert r.mean_power_check_J == pytest.approx(r.energy_per_cycle_J, rel=1e-12)
    assert r.check_relative_difference < 1e-12


# --------------------------------------------------------------------------- whole cycles


@pytest.mark.parametrize("n, whole", [(10_000, 20), (10_001, 20), (9_999, 19), (10_499, 20)])
def test_whole_cycles_on_the_sample_grid(n, whole):
    """Each cycle is 500 samples at 1 kHz / 2 Hz; a cycle counts when all its samples exist."""
    t = np.arange(n) / FS
    v = np.cos(4 * np.pi * t)
    r = complex_power(t, v, v, frequency=2.0)
    assert r.cycle_energies_J.size == whole
    assert r.cycles_used == whole - 2
    assert r.window_s == pytest.approx((1.0, whole * 0.5))
    assert list(r.cycle_used) == [False, False] + [True] * (whole - 2)
    assert r.cycle_start_s == pytest.approx(np.arange(whole) * 0.5)


@pytest.mark.parametrize("f", [2.37, 0.731, 9.3])
def test_non_integer_samples_per_period_is_resampled_to_whole_cycles(f):
    """fs/f not an integer: resampled onto m = ceil(fs/f) points per period, still exact."""
    c, X = 7.0, 0.012
    t, x, v, a = drive(f, X=X, cycles=19.37, t0=3.21, phase=0.4)
    r = complex_power(t, c * v, v, frequency=f)
    assert r.resampled
    assert r.cycle_energies_J.size == 19 and r.cycles_used == 17
    assert r.window_s == pytest.approx((3.21 + 2 / f, 3.21 + 19 / f))
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(c, f, X), rel=1e-10)
    assert r.mean_power_check_J == pytest.approx(viscous_energy(c, f, X), rel=1e-10)
    assert np.allclose(r.cycle_energies_J, viscous_energy(c, f, X), rtol=1e-9)


def test_resampling_accuracy_documented_for_few_samples_per_period():
    """At 47.1 Hz (21 samples per period) the quintic spline is still good to ~1e-7."""
    c, X, f = 7.0, 0.001, 47.1
    t, x, v, a = drive(f, X=X, cycles=30)
    r = complex_power(t, c * v + 0.1 * a, v, frequency=f)
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(c, f, X), rel=1e-6)


def test_naive_nearest_window_would_leak_but_method_does_not():
    """The plain DFT over the nearest-integer sample window leaks the reactive power into Re(P).

    A spring-mass force with 10^4 times more reactive than real power: the method
    gets Re(P) to 1e-9, a single-frequency DFT over the nearest whole-sample
    window is off by ~1e-3.
    """
    f, X = 2.37, 0.01
    t, x, v, a = drive(f, X=X, cycles=20.3)
    force = 5e4 * x + 2.0 * v
    r = complex_power(t, force, v, frequency=f, drop_cycles=0)
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(2.0, f, X), rel=1e-9)
    # the naive estimate, for contrast
    n = int(round(20 * FS / f))
    w = np.exp(-2j * np.pi * f * t[:n])
    Fs, Vs = 2 / n * force[:n] @ w, 2 / n * v[:n] @ w
    naive = np.pi / (2 * np.pi * f) * (Fs * np.conj(Vs)).real
    assert abs(naive / viscous_energy(2.0, f, X) - 1) > 1e-4


def test_noisy_record_with_non_integer_length_within_predicted_scatter():
    """White noise on force and velocity: unbiased, with the scatter the DFT predicts.

    Std of Re(P) from noise: 1/2 sqrt(2/M) sqrt(|V|^2 s_F^2 + |F|^2 s_v^2), M window samples.
    """
    c, X, f = 5.0, 0.01, 2.0
    t, x, v, a = drive(f, X=X, cycles=17.6)
    sF, sv = 0.05, 0.002
    exact = viscous_energy(c, f, X)
    errs = []
    rng = np.random.default_rng(7)
    for _ in range(40):
        r = complex_power(t, c * v + rng.normal(0, sF, t.size), v + rng.normal(0, sv, t.size),
                          frequency=f)
        errs.append(r.energy_per_cycle_J - exact)
    assert r.cycles_used == 15
    M = r.cycles_used * 500
    V, F = X * 2 * np.pi * f, c * X * 2 * np.pi * f
    sigma = 0.5 * math.sqrt(2 / M) * math.hypot(V * sF, F * sv) / f
    errs = np.array(errs)
    assert abs(errs.mean()) < 4 * sigma / math.sqrt(errs.size)
    assert 0.6 * sigma < errs.std() < 1.5 * sigma
    assert np.all(np.abs(errs) < 5 * sigma)


def test_detected_frequency_with_noise_still_accurate():
    c, X, f = 5.0, 0.01, 2.0
    t, x, v, a = drive(f, X=X, cycles=19.6)
    rng = np.random.default_rng(3)
    r = analyze_record(t, c * v + rng.normal(0, 0.02, t.size),
                       position=x + rng.normal(0, 5e-6, t.size))
    assert r.frequency_detected
    assert r.frequency_hz == pytest.approx(f, rel=1e-4)
    assert r.cycles_used == 17
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(c, f, X), rel=2e-3)
    assert r.mean_power_check_J == pytest.approx(r.energy_per_cycle_J, rel=2e-3)


def test_encoder_steps_do_not_blow_up_the_derived_velocity():
    """Position quantised to 20 um (the paper's encoder): derived velocity stays clean."""
    c, X, f = 5.0, 0.01, 2.0
    t, x, v, a = drive(f, X=X)
    xq = np.round(x / 20e-6) * 20e-6
    r = analyze_record(t, c * v, position=xq, frequency=f)
    vd = r.signals.velocity_m_s
    assert np.std(vd - v) < 2e-3 * X * 2 * np.pi * f
    assert r.cycle_energy_spread < 1e-3
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(c, f, X), rel=1e-3)


# --------------------------------------------------------------------------- motion inputs


@pytest.mark.parametrize("f", [2.0, 2.37])
def test_position_velocity_acceleration_give_the_same_answer(f):
    c, X = 4.0, 0.01
    t, x, v, a = drive(f, X=X, phase=0.9, t0=1.3)
    force = c * v + 800 * x + 0.3 * a + 10 * c * v**3
    results = [analyze_record(t, force, **{k: s}, frequency=f)
               for k, s in (("position", x), ("velocity", v), ("acceleration", a))]
    ref = results[1]
    for r in results:
        assert r.complex_power_W == pytest.approx(ref.complex_power_W, rel=1e-10)
        assert r.energy_per_cycle_J == pytest.approx(ref.energy_per_cycle_J, rel=1e-10)
        assert r.velocity_amplitude_m_s == pytest.approx(X * 2 * np.pi * f, rel=1e-10)
        assert r.mean_power_check_J == pytest.approx(ref.energy_per_cycle_J, rel=1e-9)
        assert r.signals.velocity_m_s == pytest.approx(v, abs=1e-9)
        assert np.allclose(r.cycle_energies_J, ref.cycle_energies_J, rtol=1e-8)
    assert [r.motion for r in results] == ["position", "velocity", "acceleration"]


def test_acceleration_offset_does_not_change_the_complex_power():
    c, X, f = 4.0, 0.01, 2.0
    t, x, v, a = drive(f, X=X)
    r0 = analyze_record(t, c * v, acceleration=a)
    r1 = analyze_record(t, c * v, acceleration=a + 0.05)   # sensor offset
    assert r1.energy_per_cycle_J == pytest.approx(r0.energy_per_cycle_J, rel=1e-12)


def test_position_offset_and_drift_do_not_change_detection():
    t, x, v, a = drive(2.0)
    assert detect_frequency(t, x + 0.3 + 0.001 * t) == pytest.approx(2.0, rel=1e-6)


# --------------------------------------------------------------------------- frequency detection


@pytest.mark.parametrize("f", [2.0, 2.37, 0.5, 11.3])
def test_detect_frequency_clean(f):
    t, x, v, a = drive(f, phase=0.3)
    assert detect_frequency(t, x) == pytest.approx(f, rel=1e-9)


def test_detect_2hz_at_1khz_over_20_cycles_with_noise_and_harmonics():
    t, x, v, a = drive(2.0)
    rng = np.random.default_rng(0)
    sig = v + 0.1 * v.max() * np.cos(3 * 4 * np.pi * t) + rng.normal(0, 0.05 * v.max(), t.size)
    assert detect_frequency(t, sig) == pytest.approx(2.0, rel=1e-4)


def test_detected_frequency_lands_on_the_sample_grid():
    """A clean 2 Hz drive at 1 kHz is detected precisely enough to use the samples as they are."""
    t, x, v, a = drive(2.0)
    r = complex_power(t, 3 * v, v)
    assert r.frequency_detected and not r.resampled
    assert r.frequency_hz == pytest.approx(2.0, rel=1e-11)
    assert r.cycles_used == 18


def test_no_clear_peak_is_an_input_error():
    rng = np.random.default_rng(1)
    t = np.arange(5000) / FS
    with pytest.raises(InputError, match="no clear drive peak.*--frequency"):
        detect_frequency(t, rng.normal(size=t.size))
    with pytest.raises(InputError, match="no clear drive peak.*constant"):
        complex_power(t, np.ones(t.size), np.zeros(t.size))


def test_given_frequency_with_nothing_there_is_an_input_error():
    t, x, v, a = drive(2.0)
    with pytest.raises(InputError, match="almost nothing at the given drive frequency 7"):
        complex_power(t, v, v, frequency=7.0)


# --------------------------------------------------------------------------- invariants (hypothesis)

SETTINGS = settings(max_examples=40, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])


@SETTINGS
@given(c=st.floats(1e-3, 1e4), X=st.floats(1e-4, 0.1), f=st.floats(0.5, 20.0),
       phase=st.floats(0, 2 * np.pi), t0=st.floats(-100.0, 100.0))
def test_viscous_damper_property(c, X, f, phase, t0):
    t, x, v, a = drive(f, X=X, phase=phase, t0=t0, cycles=12.5)
    r = complex_power(t, c * v, v, frequency=f)
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(c, f, X), rel=1e-8)
    assert r.mean_power_check_J == pytest.approx(r.energy_per_cycle_J, rel=1e-8)


@SETTINGS
@given(k=st.floats(-1e6, 1e6), m=st.floats(-100.0, 100.0), f=st.floats(0.5, 20.0),
       phase=st.floats(0, 2 * np.pi))
def test_spring_and_mass_terms_leave_real_power_unchanged(k, m, f, phase):
    c, X = 3.0, 0.01
    t, x, v, a = drive(f, X=X, phase=phase, cycles=10.2)
    base = complex_power(t, c * v, v, frequency=f)
    more = complex_power(t, c * v + k * x + m * a, v, frequency=f)
    scale = abs(more.complex_power_W) + abs(base.complex_power_W)
    assert abs(more.complex_power_W.real - base.complex_power_W.real) <= 1e-9 * scale
    assert more.velocity_phasor_m_s == pytest.approx(base.velocity_phasor_m_s, rel=1e-12)


@SETTINGS
@given(f=st.sampled_from([1.0, 2.0, 2.5, 4.0, 5.0, 8.0, 2.37, 3.3]),
       phase=st.floats(0, 2 * np.pi), t0=st.floats(-1e3, 1e3))
def test_time_shift_changes_nothing(f, phase, t0):
    """Start time and drive phase: a periodic nonlinear record gives the same result."""
    c, c3, X = 2.0, 30.0, 0.01
    ref_t, ref_x, ref_v, ref_a = drive(f, X=X)
    force = lambda x, v, a: c * v + c3 * v**3 + 500 * x + 0.2 * a + 0.5 * np.tanh(v / 0.1)  # noqa: E731
    ref = complex_power(ref_t, force(ref_x, ref_v, ref_a), ref_v, frequency=f)
    t, x, v, a = drive(f, X=X, phase=phase, t0=t0)
    r = complex_power(t, force(x, v, a), v, frequency=f)
    tol = 1e-9 if not r.resampled else 1e-6
    assert r.energy_per_cycle_J == pytest.approx(ref.energy_per_cycle_J, rel=tol)
    assert r.velocity_amplitude_m_s == pytest.approx(ref.velocity_amplitude_m_s, rel=1e-9)
    assert r.window_s[0] == pytest.approx(t0 + 2 / f)


# --------------------------------------------------------------------------- per-cycle energies


def test_cycle_energies_flag_a_transient():
    c, X, f = 3.0, 0.01, 2.0
    t, x, v, a = drive(f, X=X)
    ramp = np.clip(t / 1.0, 0, 1)              # damping builds up over the first 2 cycles
    r = complex_power(t, c * ramp * v, v)
    e = r.cycle_energies_J
    assert e[0] < e[1] < e[2] == pytest.approx(viscous_energy(c, f, X), rel=1e-12)
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(c, f, X), rel=1e-12)
    assert r.cycle_energy_spread < 1e-10
    r0 = complex_power(t, c * ramp * v, v, drop_cycles=0)
    assert r0.cycle_energy_spread > 0.1
    assert r0.energy_per_cycle_J < r.energy_per_cycle_J


def test_result_is_frozen_and_json_ready():
    t, x, v, a = drive(2.0)
    r = complex_power(t, 3 * v, v)
    with pytest.raises(AttributeError):
        r.energy_per_cycle_J = 1.0
    with pytest.raises(ValueError):
        r.cycle_energies_J[0] = 1.0
    d = r.to_dict()
    text = json.dumps(d, allow_nan=False)
    assert json.loads(text)["eta_star"] is None
    for key in ("frequency_hz", "cycles_used", "window_s", "complex_power_W", "energy_per_cycle_J",
                "eta_star", "velocity_amplitude_m_s", "force_amplitude_N", "mean_power_check_J",
                "cycle_energies_J"):
        assert key in d
    assert d["complex_power_W"] == [r.complex_power_W.real, r.complex_power_W.imag]
    assert "signals" not in d
    assert complex_power(t, 3 * v, v, keep_signals=False).signals is None


def test_time_jitter_below_tolerance_is_accepted():
    t, x, v, a = drive(2.0)
    jitter = np.random.default_rng(0).uniform(-1e-7, 1e-7, t.size)   # 1e-4 sample intervals
    r = complex_power(t + jitter, 3 * v, v)
    # samples are taken as on the uniform grid: the error is of order Omega * jitter
    assert r.energy_per_cycle_J == pytest.approx(viscous_energy(3, 2.0, 0.01), rel=1e-6)


# --------------------------------------------------------------------------- input errors


def _record(n=10_000):
    t, x, v, a = drive(2.0, cycles=n * 2.0 / FS)
    return t, 3 * v, v


@pytest.mark.parametrize("mutate, pattern", [
    (lambda t, F, v: (t, F[:-1], v), "same number of samples.*force 9999"),
    (lambda t, F, v: (t[:2], F[:2], v[:2]), "2 samples; at least 3"),
    (lambda t, F, v: (t, np.where(np.arange(t.size) == 17, np.nan, F), v),
     "force has 1 non-finite value.*index 17"),
    (lambda t, F, v: (t, F, np.where(np.arange(t.size) >= 40, np.inf, v)),
     "velocity has 9960 non-finite values.*index 40"),
    (lambda t, F, v: (np.where(np.arange(t.size) == 5, np.nan, t), F, v), "time has 1 non-finite"),
    (lambda t, F, v: (np.concatenate([t[:100], t[99:-1]]), F, v), "increase strictly.*index 100"),
    (lambda t, F, v: (t[::-1], F, v), "increase strictly"),
    (lambda t, F, v: (np.concatenate([t[:500], t[700:], t[-1] + 1e-3 * np.arange(1, 201)]), F, v),
     "gap of 0.201 s after t = 0.499 s.*not observed"),
    (lambda t, F, v: (t, F.reshape(-1, 2), v), "1-D"),
])
def test_bad_records(mutate, pattern):
    t, F, v = mutate(*_record())
    with pytest.raises(InputError, match=pattern):
        complex_power(t, F, v, frequency=2.0)


def test_too_few_cycles_says_how_many_and_suggests_drop_cycles():
    t, x, v, a = drive(2.0, cycles=2.7)
    with pytest.raises(InputError, match=r"holds 2\.7 cycles.*\(2 whole\).*--drop-cycles 1"):
        complex_power(t, v, v, frequency=2.0)
    assert complex_power(t, v, v, frequency=2.0, drop_cycles=1).cycles_used == 1


@pytest.mark.parametrize("kwargs, pattern", [
    (dict(frequency=600.0), "above the Nyquist frequency 500 Hz"),
    (dict(frequency=500.0), "Nyquist"),
    (dict(frequency=0.0), "positive"),
    (dict(frequency=-2.0), "positive"),
    (dict(frequency=float("nan")), "positive"),
    (dict(frequency="2mm"), "is not a frequency"),
    (dict(bed_mass=0.0), "bed mass must be positive"),
    (dict(bed_mass=-1.0), "bed mass must be positive"),
    (dict(drop_cycles=-1), "0 or more"),
    (dict(drop_cycles=1.5), "whole number"),
])
def test_bad_arguments(kwargs, pattern):
    t, F, v = _record()
    with pytest.raises(InputError, match=pattern):
        complex_power(t, F, v, **kwargs)


def test_analyze_record_needs_exactly_one_motion():
    t, x, v, a = drive(2.0)
    with pytest.raises(InputError, match="exactly one motion signal.*none"):
        analyze_record(t, v)
    with pytest.raises(InputError, match="exactly one motion signal.*position, velocity"):
        analyze_record(t, v, position=x, velocity=v)


def test_docstring_examples_run():
    import doctest
    import importlib

    # the package re-exports the function under the module's name; fetch the module itself
    mod = importlib.import_module("pdamper.analysis.complex_power")

    failures, tried = doctest.testmod(mod, optionflags=doctest.NORMALIZE_WHITESPACE)
    assert tried >= 5 and failures == 0


def test_input_error_is_a_value_error():
    with pytest.raises(ValueError):
        complex_power([0, 1], [0, 1], [0, 1])


def test_records_and_arguments_with_units():
    import pint

    u = pint.UnitRegistry()
    t, F, v = _record()
    si = complex_power(t, F, v, frequency=2.0, bed_mass=0.149)
    q = complex_power(t * u.s, F * u.N, v * u.m / u.s, frequency="2Hz", bed_mass=149 * u.g)
    assert q.energy_per_cycle_J == si.energy_per_cycle_J and q.eta_star == si.eta_star
    with pytest.raises(InputError, match="force: .* is not a force"):
        complex_power(t, F * u.m, v, frequency=2.0)
