"""The structure's compiled step without a bed against the closed-form oscillator, and its ledger."""

import math

import numpy as np
import pytest

from pdamper.structure import CoupledStructure
from pdamper.simulation import run_bare_structure
from pdamper.theory import oscillator_response

M, FN, Z = 7.0, 2.0, 0.005
K = M * (2 * math.pi * FN) ** 2


def _exact(rec, s):
    return oscillator_response(rec.time, mass=s.mass, stiffness=s.stiffness, damping_ratio=s.damping_ratio,
                               force_amplitude=s.force_amplitude, force_frequency=s.force_frequency or 0.0,
                               displacement=s.displacement, velocity=s.velocity)


def test_free_decay_matches_the_closed_form():
    s = CoupledStructure(mass=M, stiffness=K, damping_ratio=Z, displacement=0.02)
    rec = run_bare_structure(s, 15.0)  # 30 periods
    x, v, _ = _exact(rec, s)
    assert np.max(np.abs(rec.displacement - x)) / 0.02 < 2e-5
    assert np.max(np.abs(rec.velocity - v)) / (0.02 * 2 * math.pi * FN) < 2e-5
    assert rec.balance_error() < 1e-5


def test_forced_response_from_any_start_matches_the_closed_form():
    s = CoupledStructure(mass=M, stiffness=K, damping_ratio=0.02, force_amplitude=0.4, force_frequency=1.9,
                         displacement=0.003, velocity=-0.01)
    rec = run_bare_structure(s, 10.0)
    x, _, _ = _exact(rec, s)
    assert np.max(np.abs(rec.displacement - x)) / np.max(np.abs(x)) < 2e-5
    assert rec.balance_error() < 1e-5
    assert rec.external_work[-1] > 0 and rec.damping_loss[-1] > 0


def test_the_step_size_matters_second_order():
    s = CoupledStructure(mass=M, stiffness=K, damping_ratio=Z, displacement=0.02)
    err = []
    for dt in (2e-3, 1e-3):
        rec = run_bare_structure(s, 5.0, sample_rate=100.0, time_step=dt)
        err.append(np.max(np.abs(rec.displacement - _exact(rec, s)[0])))
    assert 3.0 < err[0] / err[1] < 5.0
