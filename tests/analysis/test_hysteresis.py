"""The hysteresis loop (pdamper.analysis.hysteresis) against closed forms: a viscous force encloses
pi c Omega X^2 a cycle, an inertial one nothing, impacts at higher harmonics nothing under a harmonic
drive; on a DEM run the first-harmonic loop's area is the complex power's energy per cycle (eq. 4)."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.analysis.hysteresis import hysteresis_loop
from pdamper.errors import InputError

F_HZ, X, C, M = 2.0, 0.012, 3.0, 0.4
W = 2 * np.pi * F_HZ
T = np.arange(0.0, 6.0, 2e-4)  # 30 000 samples, each standing for its 0.2 ms: 12 cycles
POS = X * np.sin(W * T)
#: a viscous part, an inertial part and a train of impacts (a half-sine pulse each half cycle)
IMPACTS = 5.0 * np.clip(np.sin(2 * W * T), 0.9, None) - 5.0 * 0.9
FORCE = C * W * X * np.cos(W * T) - M * W**2 * X * np.sin(W * T) + IMPACTS


@pytest.mark.parametrize("harmonics", [1, 3, 10, 40])
def test_the_loop_encloses_the_viscous_energy_alone(harmonics):
    loop = hysteresis_loop(T, FORCE, POS, F_HZ, drop_cycles=2, harmonics=harmonics)
    assert loop.cycles == 10 and loop.window_s == pytest.approx((1.0, 6.0))  # 2 cycles of 0.5 s dropped
    assert loop.energy_per_cycle_J == pytest.approx(np.pi * C * W * X**2, rel=1e-5)  # 1.6e-6: linear resampling
    # the loop's own area (a polygon of its points) is the same energy
    area = np.trapezoid(loop.force, loop.position)
    assert area == pytest.approx(loop.energy_per_cycle_J, rel=2e-3)
    assert abs(loop.position_harmonics[1]) == pytest.approx(X, rel=1e-5)


def test_the_first_harmonic_is_an_ellipse_and_the_filtered_loop_keeps_the_impacts():
    first = hysteresis_loop(T, FORCE, POS, F_HZ, harmonics=1)
    filtered = hysteresis_loop(T, FORCE, POS, F_HZ, harmonics=10)
    # first harmonic: F = c W X cos - m W^2 X sin, so F_1 = c W X + i m W^2 X; x = X sin, so x_1 = -i X
    assert first.force_harmonics[1] == pytest.approx(C * W * X + 1j * M * W**2 * X, rel=1e-5)
    assert first.position_harmonics[1] == pytest.approx(-1j * X, rel=1e-5)
    assert np.ptp(filtered.force - first.force) > 0.3  # the impacts (pulses of 0.5 N, second harmonic and up)
    assert np.ptp(first.force) == pytest.approx(2 * abs(first.force_harmonics[1]), rel=1e-4)


def test_an_inertial_force_encloses_nothing():
    loop = hysteresis_loop(T, -M * W**2 * POS, POS, F_HZ, harmonics=5)
    assert abs(loop.energy_per_cycle_J) < 1e-9 * M * W**2 * X**2


def test_a_run_s_first_harmonic_loop_is_the_complex_power_energy():
    from dem_fixtures import TINY_CONFIG
    from pdamper.config import loads_case
    from pdamper.run import run_case

    res = run_case(loads_case(TINY_CONFIG))
    s = res.signals
    loop = hysteresis_loop(s.time, s.force, s.position, res.case.drive.frequency, drop_cycles=res.case.drop_cycles)
    assert loop.energy_per_cycle_J == pytest.approx(res.energy_per_cycle_J, rel=2e-3)
    filtered = hysteresis_loop(s.time, s.force, s.position, res.case.drive.frequency,
                               drop_cycles=res.case.drop_cycles, harmonics=10)
    assert filtered.energy_per_cycle_J == pytest.approx(loop.energy_per_cycle_J, rel=1e-3)


@pytest.mark.parametrize("kw, words", [({"frequency": 0.0}, "frequency = 0.0"), ({"harmonics": 0}, "harmonics = 0"),
                                       ({"drop_cycles": 50}, "no whole cycle")])
def test_bad_arguments_are_one_line(kw, words):
    args = dict(time=T, force=FORCE, position=POS, frequency=F_HZ)
    args.update({k: v for k, v in kw.items() if k in args})
    with pytest.raises(InputError, match=words):
        hysteresis_loop(**args, **{k: v for k, v in kw.items() if k not in args})

