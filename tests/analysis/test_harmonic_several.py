"""The harmonic balance with several dampers (pdamper.analysis.harmonic.solve_several): constant
fields (a rigid mass and a dashpot at each point) give the coupled modal equations' closed form;
one damper gives the one-damper solver's fixed point."""

from __future__ import annotations

import math

import numpy as np
import pytest

import fields_helpers as fh
from pdamper.analysis.fields import DamperFields
from pdamper.analysis.harmonic import solve_frequency, solve_response_several, solve_several
from pdamper.structure import ModalStructure

STROKES = np.geomspace(1e-4, 0.1, 12)
FREQS = [1.5, 1.8, 2.0, 2.2, 2.5]
MAST = ModalStructure(modes=({"frequency": 2.0146, "damping_ratio": 0.005, "modal_mass": 7.984, "damper": 1.0,
                              "force": 1.0, "response": 0.3395},
                             {"frequency": 12.625, "damping_ratio": 0.005, "modal_mass": 7.984, "damper": 1.0,
                              "force": 1.0, "response": -0.7137}), displacement=0.01)


def constant_fields(m_a, c_a, freqs):
    return fh.constant_fields(m_a, c_a, STROKES, freqs)


#: a frame of three modes, a damper point at the top (shapes 1, 1, 1) and one lower (0.6, -0.5, 0.9)
FRAME = ModalStructure(modes=tuple({"frequency": f, "damping_ratio": 0.01, "modal_mass": m, "damper": 1.0, "force": 1.0,
                                    "response": r} for f, m, r in ((2.0, 8.0, 0.4), (5.5, 6.0, -0.6),
                                                                   (9.0, 5.0, 0.3))), displacement=0.01)
SHAPES = np.array([[1.0, 1.0, 1.0], [0.6, -0.5, 0.9]])


def closed_form(s, shapes, f, F0, dampers):
    m, k, c, pd, pf, pr = s.modal_arrays()
    w = 2 * math.pi * f
    A = np.diag(k - w * w * m + 1j * w * c)
    for (m_a, c_a), p in zip(dampers, shapes):
        A = A + complex(-w * w * m_a, w * c_a) * np.outer(p, p)
    q = np.linalg.solve(A, pf * F0)
    return np.abs(shapes @ q), abs(pr @ q)


def test_two_dampers_of_constant_fields_give_the_closed_form():
    dampers = [(0.12, 0.9), (0.3, 2.5)]
    fields = [constant_fields(m, c, [1.5, 2.0, 2.5, 5.0, 6.0]) for m, c in dampers]
    for f in (1.9, 2.0, 5.4):
        sols = solve_several(FRAME.modal_arrays(), SHAPES, fields, f, 0.5)
        assert len(sols) == 1 and sols[0].stable
        xd, xr = closed_form(FRAME, SHAPES, f, 0.5, dampers)
        np.testing.assert_allclose(sols[0].damper_amplitudes_m, xd, rtol=1e-9)
        assert sols[0].response_amplitude_m == pytest.approx(xr, rel=1e-9)


def test_one_damper_is_the_one_damper_solvers_fixed_point():
    """Fields whose eta* and effective mass change with the amplitude: at each frequency the
    several-damper solver with one damper finds the one-damper solver's stable fixed point."""
    X = STROKES[:, None]
    eta = 0.2 + 0.5 * np.exp(-((np.log(X / 0.01)) ** 2)) * np.ones((1, len(FREQS)))
    F = DamperFields.from_results(fh.results(STROKES, FREQS, eta, m_eff=0.05 + 0.5 * X * np.ones((1, len(FREQS)))))
    for f in (1.9, 2.0, 2.1):
        one = [s for s in solve_frequency(MAST.modal_arrays(), F, f, 0.3) if s.stable]
        several = [s for s in solve_several(MAST.modal_arrays(), MAST.modal_arrays()[3][None, :], [F], f, 0.3)
                   if s.stable]
        assert len(one) == 1 and len(several) >= 1
        assert several[0].damper_amplitude_m == pytest.approx(one[0].damper_amplitude_m, rel=1e-7)
        assert several[0].response_amplitude_m == pytest.approx(one[0].response_amplitude_m, rel=1e-7)


def test_the_response_over_frequencies_and_a_count_mismatch():
    fields = [constant_fields(0.1, 0.5, [1.5, 2.0, 2.5])] * 2
    res = solve_response_several(FRAME.modal_arrays(), SHAPES, fields, [1.8, 2.0, 2.2], 0.5)
    assert [len(s) for s in res.solutions] == [1, 1, 1] and res.jumps == []
    with pytest.raises(Exception, match="3 fields for 2 dampers"):
        solve_several(FRAME.modal_arrays(), SHAPES, fields + fields[:1], 2.0, 0.5)
