"""The recorder protocol: a Python recorder sees the state where it is due, reads what the kernel
channel reads, and changes nothing about the run; bad recorders are refused clearly."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pdamper.config import load_case
from pdamper.recorders import EnergyRecorder, SignalsRecorder, TrajectoryRecorder
from pdamper.run import run_case
from pdamper.simulation import Simulation
from script_loader import load_script

ROOT = Path(__file__).resolve().parents[2]


def _example_recorder():
    return load_script("examples/kinetic_energy_recorder.py").BedKineticEnergy


def _case(**over):
    return load_case(ROOT / "examples" / "cuboid_36.toml", {"drive.stroke": "14mm", "run.cycles": 0.6,
                                                              "run.drop_cycles": 0, **over})


@pytest.mark.parametrize("integrator", ["gear", "verlet"])
def test_the_example_recorder_reads_what_the_energy_channel_reads(integrator):
    case = _case(**{"numerics.integrator": integrator})
    ke = _example_recorder()(every=7)  # 7 does not divide the quarter-second segments
    res = run_case(case, recorders=[ke], analyze=False)
    ds = res.recorded["bed_kinetic_energy"]
    n = res.signals.force.size  # 300 samples
    assert ds.sizes["time"] == n // 7
    k = (np.arange(n // 7) + 1) * 7 - 1  # the samples it was called at
    np.testing.assert_allclose(ds["time"].values, (k + 1) * 1e-3, rtol=1e-12)
    np.testing.assert_allclose(ds["kinetic_energy"].values, res.energy.kinetic[k], rtol=1e-10)


def test_a_python_recorder_changes_nothing_about_the_run():
    case = _case()
    plain = run_case(case, analyze=False)
    with_rec = run_case(case, recorders=[_example_recorder()(every=3)], analyze=False)
    assert np.array_equal(plain.signals.force, with_rec.signals.force)
    assert np.array_equal(plain.energy.friction, with_rec.energy.friction)
    assert plain.steps == with_rec.steps


def test_a_simulation_records_only_what_its_recorders_ask_for():
    sim = Simulation(_case(), [SignalsRecorder()])
    assert sim.samples.energy.shape[0] == 0 and sim.samples.frames.shape[0] == 0
    record = sim.run()
    assert set(record.outputs) == {"signals"} and record.energy is None
    assert record.signals.force.size == sim.n_samples
    with pytest.raises(AttributeError, match="run_case"):
        record.eta_star  # noqa: B018


def test_a_simulation_can_be_advanced_in_parts():
    case = _case()
    whole = Simulation(case, [SignalsRecorder(), EnergyRecorder()]).run()
    sim = Simulation(case, [SignalsRecorder(), EnergyRecorder()])
    sim.settle()
    assert sim.time == 0.0
    sim.advance(123)
    assert sim.sample == 123 and sim.time == pytest.approx(0.123)
    sim.advance()
    parts = sim.finalize()
    assert np.array_equal(parts.signals.force, whole.signals.force)
    assert np.array_equal(parts.energy.work, whole.energy.work)


def test_bad_recorders_are_refused_with_what_is_wrong():
    class NoFinalize:
        name, channels, every = "x", frozenset(), 1

        def start(self, run): ...

        def record(self, state): ...

    with pytest.raises(TypeError, match="lacks finalize"):
        Simulation(_case(), [NoFinalize()])
    with pytest.raises(ValueError, match="unknown channels.*velocity_field"):
        bad = SignalsRecorder()
        bad.channels = frozenset({"velocity_field"})
        Simulation(_case(), [bad])
    with pytest.raises(ValueError, match="two recorders are named 'signals'"):
        Simulation(_case(), [SignalsRecorder(), SignalsRecorder()])
    with pytest.raises(ValueError, match="one frame rate per run"):
        Simulation(_case(), [TrajectoryRecorder(50), TrajectoryRecorder(25, name="coarse")])
