"""The structure without the bed under a load in time (pdamper.structure.linear) against independent
solutions: scipy's ``lsim`` on the full matrices (a force history, a ground acceleration), the white
noise variance of random-vibration theory, the steady closed form under a stepped sine, the FRF."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy import signal

from pdamper.structure import CoupledStructure, ModalStructure
from pdamper.structure.linear import damper_motion, dof_response, frequency_response, modal_response
from pdamper.structure.loads import ForceHistory, GroundAcceleration, RandomLoad, SteppedSine
from pdamper.structure.matrices import rayleigh_coefficients


def shear_frame(tmp_path, n=4):
    """A shear frame of ``n`` storeys (masses 900 .. 600 kg, storey stiffnesses 2.4 .. 1.2 MN/m):
    M, K in an .npz; its file."""
    m = np.linspace(900.0, 600.0, n)
    k = np.linspace(2.4e6, 1.2e6, n)
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] += k[i]
        if i + 1 < n:
            K[i, i] += k[i + 1]
            K[i, i + 1] = K[i + 1, i] = -k[i + 1]
    path = tmp_path / "frame.npz"
    np.savez(path, M=np.diag(m), K=K)
    return path, np.diag(m), K


def full_lsim(M, C, K, load_vector, f, t):
    """Every dof of ``M x'' + C x' + K x = load_vector f(t)`` from rest by scipy's lsim (linear
    interpolation of the input between the samples ``t``)."""
    n = M.shape[0]
    Mi = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ K, -Mi @ C]])
    B = np.concatenate([np.zeros(n), Mi @ load_vector])[:, None]
    Cout = np.hstack([np.eye(n), np.zeros((n, n))])
    _, y, _ = signal.lsim(signal.StateSpace(A, B, Cout, np.zeros((n, 1))), f, t)
    return y


def pulse(duration=0.3, dt=0.002, peak=5e3):
    """A hammer-like force: a half sine of 20 ms, a smaller rebound, samples every ``dt``, ending at 0."""
    t = np.arange(0.0, duration + dt / 2, dt)
    f = peak * np.where(t < 0.02, np.sin(np.pi * t / 0.02), 0.0) - 0.2 * peak * np.where(
        (t > 0.05) & (t < 0.09), np.sin(np.pi * (t - 0.05) / 0.04), 0.0)
    return t, f


def test_a_force_history_on_fe_matrices_is_scipy_lsim_on_the_full_matrices(tmp_path):
    path, M, K = shear_frame(tmp_path)
    s = ModalStructure(matrices=str(path), damper_dof=3, force_dof=2, response_dof=0, rayleigh_modes=(1, 3),
                       rayleigh_ratios=(0.02, 0.04), load=ForceHistory(time=tuple(pulse()[0]), force=tuple(pulse()[1]),
                                                                      duration_s=2.0))
    w = 2 * math.pi * s.mode_frequencies
    a, b = rayleigh_coefficients((w[0], w[2]), (0.02, 0.04))
    t = np.linspace(0.0, 2.0, 4001)  # the load's samples (2 ms) are every fourth output time
    labels, x = dof_response(s, t)
    ref = full_lsim(M, a * M + b * K, K, np.eye(4)[2], s.load.values(t), t)
    assert labels == [0, 1, 2, 3]
    assert np.max(np.abs(x - ref)) / np.max(np.abs(ref)) < 1e-6  # measured 1.7e-14
    # the damper point's motion is its dof's
    assert np.allclose(damper_motion(s, t)[0], x[:, 3], rtol=0, atol=1e-12 * np.max(np.abs(x)))


def test_a_ground_acceleration_on_fe_matrices_is_scipy_lsim_with_the_container_carried(tmp_path):
    """-M r a_g on every dof, the displacements relative to the ground; the empty container's mass at
    the damper (stiffness-proportional damping: the carried modes keep it diagonal, so the modal
    model is the full one exactly) is in the ground's load too."""
    path, M, K = shear_frame(tmp_path)
    tg = np.arange(0.0, 3.0 + 1e-9, 0.01)
    ag = 2.0 * np.sin(2 * np.pi * 1.7 * tg) * np.sin(np.pi * tg / 3.0) ** 2  # ends at 0: no jump after it
    load = GroundAcceleration(time=tuple(tg), acceleration=tuple(ag), duration_s=4.0)
    beta = 0.002
    s = ModalStructure(matrices=str(path), damper_dof=3, rayleigh=(0.0, beta), load=load).carrying(150.0)
    t = np.linspace(0.0, 4.0, 4001)
    _, x = dof_response(s, t)
    Mc = M + 150.0 * np.outer(np.eye(4)[3], np.eye(4)[3])
    ref = full_lsim(Mc, beta * K, K, -Mc @ np.ones(4), load.values(t), t)
    assert np.max(np.abs(x - ref)) / np.max(np.abs(ref)) < 1e-6  # measured 1.6e-14


def test_the_influence_vector_repeats_one_nodes_pattern_and_participation_can_be_given(tmp_path):
    path, M, K = shear_frame(tmp_path)
    base = ModalStructure(matrices=str(path), damper_dof=3, damping_ratio=0.02, displacement=0.001)
    phi = base.dof_shapes()[1]
    assert np.allclose(base.ground_participation(), phi.T @ M @ np.ones(4))
    assert np.allclose(base.ground_participation(influence=(1.0, 0.0)), phi.T @ M @ np.array([1.0, 0, 1, 0]))
    gamma = (1.2, -0.4, 0.2, 0.1)
    assert np.allclose(base.ground_participation(participation=gamma), gamma)  # mass-normalised modes
    from pdamper.errors import InputError

    with pytest.raises(InputError, match="influence has 3 values"):
        base.ground_participation(influence=(1.0, 0.0, 1.0))
    data = ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.01, "modal_mass": 7.0, "damper": 1.0},),
                          displacement=0.001)
    with pytest.raises(InputError, match="participation is missing"):
        data.ground_participation()
    assert data.ground_participation(participation=(1.5,)) == pytest.approx([1.5 * 7.0])


def test_the_frf_is_the_steady_phasor():
    s = ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.01, "modal_mass": 7.0, "damper": 1.0,
                               "force": 0.5, "response": 0.3},
                              {"frequency": 9.0, "damping_ratio": 0.02, "modal_mass": 3.0, "damper": -0.4,
                               "force": 0.9, "response": 1.0}), displacement=0.001)
    f = np.array([0.5, 1.9, 2.0, 8.7, 15.0])
    load = ForceHistory(time=(0.0, 1.0), force=(0.0, 0.0))
    H = frequency_response(s, f, load)
    assert np.allclose(H[:, 0] * 0.4, s.steady_phasor(f, 0.4), rtol=1e-12)
    assert np.allclose(H[:, 2] * 0.4, s.steady_phasor(f, 0.4, point="response"), rtol=1e-12)
    assert np.allclose(H * 0.4, s.dof_phasors(f, 0.4), rtol=1e-12)


@pytest.mark.slow
def test_white_noise_on_a_sdof_has_the_variance_of_random_vibration_theory():
    """sigma^2 = pi S0 / (2 zeta omega^3 m^2) for two-sided white noise S0 per rad/s (Crandall & Mark,
    Random Vibration, 1963; S0 = G / 4 pi for the one-sided G per Hz), against the mean square of
    the exact response over one record (from rest; the first 20 decay times dropped).

    The sampling error: the record is periodic over its length T (FFT synthesis) and each Fourier
    coefficient an independent complex Gaussian, so its mean square over the record is a sum of
    independent exponential terms: var(s^2) / s^4 = sum_j (|H_j|^2 G_j)^2 / (sum_j |H_j|^2 G_j)^2 --
    about 1 / (zeta omega_n T) for a narrow resonance (sigma 0.64 % here). The check allows 4 of it plus the
    band's cut (the integral of |H|^2 G beyond 10 Hz, 1e-4) and the linear interpolation between the
    samples (1e-3 at 2 Hz, 200 samples a second)."""
    m, fn, zeta, G = 7.0, 2.0, 0.1, 0.04
    load = RandomLoad(level=G, band=(0.0, 10.0), duration_s=20000.0, seed=3)
    w = 2 * math.pi * fn
    s = CoupledStructure(mass=m, stiffness=m * w * w, damping_ratio=zeta, load=load)
    t, _ = load.samples()
    q, _ = modal_response(s, t)
    keep = t > 20.0 / (zeta * w)
    measured = float(np.mean(q[keep, 0] ** 2))
    theory = math.pi * (G / (4 * math.pi)) / (2 * zeta * w**3 * m**2)
    fj = np.fft.rfftfreq(t.size - 1, t[1] - t[0])
    h2 = np.abs(frequency_response(s, fj)[:, 0]) ** 2 * load.psd(fj)
    sampling = math.sqrt(np.sum(h2**2)) / np.sum(h2)
    assert sampling < 0.01
    assert measured / theory - 1 == pytest.approx(0.0, abs=4 * sampling + 2e-3)  # measured -0.34 %, sigma 0.64 %
    # the realisation's own spectrum: its load variance is the target's within its own sampling error
    tv = load.target_variance
    assert np.var(load.samples()[1]) / tv - 1 == pytest.approx(0.0, abs=4 * math.sqrt(2 / (t.size * 0.5)) + 1e-3)


def test_the_stepped_sine_of_the_bare_structure_is_the_steady_closed_form():
    """Each step's amplitude over its last 10 periods (60 a step: the transient after a step has
    decayed to e^-19 at zeta = 5 %), exactly and by the compiled step."""
    from pdamper.simulation import run_bare_structure
    from pdamper.studies.transient import fit_sine

    load = SteppedSine(amplitude=0.4, frequencies=(1.8, 1.9, 2.0, 2.1, 2.2), cycles=60.0)
    s = CoupledStructure(mass=7.0, stiffness=1105.0, damping_ratio=0.05, load=load)
    starts = load.step_times()
    closed = s.steady_amplitude(load.frequencies, 0.4)
    exact = []
    for j, f in enumerate(load.frequencies):
        tt = np.linspace(starts[j + 1] - 10 / f, starts[j + 1], 1001)
        exact.append(abs(fit_sine(tt, modal_response(s, tt)[0][:, 0], f)))
    assert np.allclose(exact, closed, rtol=1e-6)  # measured 4.0e-8
    rec = run_bare_structure(s, load.duration, sample_rate=200.0)
    compiled = []
    for j, f in enumerate(load.frequencies):
        sel = (rec.time > starts[j + 1] - 10 / f) & (rec.time <= starts[j + 1] + 1e-9)
        compiled.append(abs(fit_sine(rec.time[sel], rec.displacement[sel], f)))
    assert np.allclose(compiled, closed, rtol=1e-4)  # the structure's step: measured 4.7e-6
    # the phase goes on from step to step: the force is continuous
    f_at = load.values(starts[1:-1] - 1e-9), load.values(starts[1:-1] + 1e-9)
    assert np.allclose(*f_at, atol=1e-6)
