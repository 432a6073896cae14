"""The tuned mass damper's closed forms (pdamper.theory.tmd) against the two-degree-of-freedom system
itself: Den Hartog's optimum under a harmonic force (its peak the fixed points' height, and detuning
it raises the peak), Warburton's under a white-noise ground acceleration (the least variance, found
numerically from the Lyapunov equation), and a mass fixed at the damper."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_continuous_lyapunov
from scipy.optimize import minimize

from pdamper.theory import tmd


def two_dof(mu, f, zeta):
    """M, C, K of a mode (m = 1 kg, omega = 1 rad/s, undamped) with a TMD of mass ratio ``mu``,
    tuning ``f`` and damping ratio ``zeta``."""
    ka, ca = mu * f**2, 2 * zeta * mu * f
    return (np.diag([1.0, mu]), np.array([[ca, -ca], [-ca, ca]]), np.array([[1 + ka, -ka], [-ka, ka]]))


def peak_amplification(mu, f, zeta):
    """max over the forcing frequency of |X_1| k / F."""
    M, C, K = two_dof(mu, f, zeta)
    w = np.linspace(0.5, 1.5, 20001)[:, None, None]
    A = K - w * w * M + 1j * w * C  # the dynamic stiffness at each frequency, solved for F = (1, 0)
    det = A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
    return float(np.max(np.abs(A[:, 1, 1] / det)))


@pytest.mark.parametrize("mu, within", [(0.01, 2e-3), (0.05, 1e-2)])
def test_den_hartog_s_optimum_peaks_at_the_fixed_points_height(mu, within):
    f, z = tmd.den_hartog_tuning(mu), tmd.den_hartog_damping(mu)
    peak = peak_amplification(mu, f, z)
    # the fixed points' height; zeta_opt (an average of the two points' flat-top values) lets the
    # curve rise a little above them: measured 0.055 % (mu = 0.01), 0.67 % (mu = 0.05)
    assert peak == pytest.approx(tmd.den_hartog_peak(mu), rel=within)
    assert peak >= tmd.den_hartog_peak(mu) * (1 - 1e-9)
    for detuned in (0.98 * f, 1.02 * f):  # off the optimal tuning one fixed point rises
        assert peak_amplification(mu, detuned, z) > 1.1 * peak
    # a mode alone with the equivalent damping ratio peaks as high: 1 / (2 zeta_eq)
    assert 1 / (2 * tmd.den_hartog_equivalent_damping(mu)) == pytest.approx(tmd.den_hartog_peak(mu), rel=1e-12)


@pytest.mark.parametrize("mu", [0.01, 0.05, 0.2])
def test_warburton_s_optimum_is_the_least_variance_under_white_noise_at_the_ground(mu):
    def variance(p):
        M, C, K = two_dof(mu, *p)
        Mi = np.linalg.inv(M)
        A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Mi @ K, -Mi @ C]])
        B = np.concatenate([np.zeros(2), -np.ones(2)])[:, None]  # -r a_g on both masses
        return solve_continuous_lyapunov(A, -B @ B.T)[0, 0]

    best = minimize(lambda p: np.log(variance(p)), [1.0, 0.05], method="Nelder-Mead",
                    options=dict(xatol=1e-8, fatol=1e-13, maxiter=4000)).x
    assert best == pytest.approx([tmd.warburton_tuning(mu), tmd.warburton_damping(mu)], rel=1e-5)  # measured 1e-7


def test_a_mass_fixed_at_the_damper_only_detunes_the_mode():
    """The structure carrying a mass at the damper (its modal equations diagonalised again) against the
    closed form with mu = m phi_d^2 / m_k."""
    from pdamper.structure import ModalStructure

    s = ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.01, "modal_mass": 7.0, "damper": 0.5},),
                       displacement=0.001)
    carried = s.carrying(0.35)
    mu = 0.35 * 0.5**2 / 7.0
    assert carried.natural_frequency / 2.0 - 1 == pytest.approx(float(tmd.added_mass_detuning(mu)), rel=1e-10)
    assert float(tmd.den_hartog_equivalent_damping(0.0)) == 0.0
