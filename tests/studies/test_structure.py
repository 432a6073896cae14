"""The damper on a structure: the coupled run (negligible bed = the closed form; a real bed
closes the coupled ledger and damps), the free-decay and frequency-response studies."""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.excitation import HarmonicDrive
from pdamper.structure import CoupledStructure
from pdamper.params import Case, Numerics, ParticleSet
from pdamper.run import run_case
from pdamper.studies.structure import parse_frequencies, run_decay, run_response
from pdamper.theory import oscillator_response

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "structure_36.toml"


def _small(count=8, cycles=3, **over):
    return load_case(EXAMPLE, {"particles.count": count, "run.cycles": cycles, **over})


@pytest.mark.parametrize("integrator", ["verlet", "gear"])
def test_a_negligible_bed_leaves_the_closed_form_oscillator(integrator):
    # one 4 g sphere on a 7 t structure (mass ratio 6e-7): the whole coupled path (settling hold,
    # release, recording) must give the bare oscillator, with either integrator advancing it
    s = CoupledStructure(mass=7000.0, stiffness=7000.0 * (4 * math.pi) ** 2, damping_ratio=0.01, displacement=0.004)
    case = Case(particles=(ParticleSet(count=1),), drive=s, numerics=Numerics(integrator=integrator),
                cycles=2, drop_cycles=0)
    res = run_case(case)
    rec = res.structure
    x, _, _ = oscillator_response(rec.time, mass=s.mass, stiffness=s.stiffness, damping_ratio=0.01, displacement=0.004)
    assert np.max(np.abs(rec.displacement - x)) / 0.004 < 1e-5
    # the signals carry the recorded motion
    assert res.signals.velocity.size == rec.time.size
    assert res.signals.position[0] == pytest.approx(0.004, rel=1e-3)


@pytest.mark.parametrize("integrator", ["verlet", "gear"])
def test_the_coupled_ledger_closes_and_the_bed_damps(integrator):
    case = _small(count=16, cycles=3, **{"numerics.integrator": integrator})
    res = run_case(case)
    rec = res.structure
    # structure + bed: E_s + E_bed + losses - external work = const, to a small fraction of the energy
    assert rec.balance_error(res.energy) < 5e-3
    # without the bed's share the balance is far off: the bed took energy (Newton 3 is wired in)
    assert rec.balance_error() > 20 * rec.balance_error(res.energy)
    lost_to_bed = res.energy.damping[-1] + res.energy.friction[-1]
    assert lost_to_bed > 0.01 * rec.initial_energy  # 16 spheres, scattered at 20 mm: ~2 % in 3 cycles


@pytest.mark.slow
def test_decay_study_summary():
    res = run_decay(_small(count=36, cycles=4))
    s = res.summary
    assert s["bare_vs_closed_form_max_error"] < 2e-5
    assert s["zeta_bare_mean"] == pytest.approx(0.005, rel=0.01)
    # at 20 -> 14 mm the 36-sphere bed (X_opt 12.2 mm) at least doubles the damping
    assert s["zeta_damped_upper_half"] > 2 * 0.005
    assert s["energy_balance_error"] < 5e-3
    assert res.envelope_damped[1][-1] < res.envelope_bare[1][-1]


@pytest.mark.slow
def test_response_study_without_and_with_bed():
    case = _small(count=8, cycles=6)
    res = run_response(case, [1.9, 2.1], force_amplitude=0.2, measure_cycles=2, workers=1, progress=False)
    assert res.damped.shape == (2,) and np.all(res.damped > 0)
    # the solid-mass curve is the bare one shifted down in frequency: larger below f_n... here both
    # points are off resonance, so the closed forms are close to each other
    assert np.all(np.abs(res.solid / res.bare - 1) < 0.3)
    assert res.summary["energy_balance_error_max"] < 5e-3


def test_bare_response_run_matches_the_steady_closed_form_when_started_there():
    # the structure alone started on its steady orbit stays on it
    from pdamper.analysis import harmonic_amplitude
    from pdamper.simulation import run_bare_structure
    from pdamper.theory import steady_amplitude

    M, K, z, F0, f = 7.0, 1105.0, 0.005, 0.4, 2.0  # 500 samples per period: no leakage
    Xc = F0 / complex(K - M * (2 * math.pi * f) ** 2, 2 * z * math.sqrt(K * M) * 2 * math.pi * f)
    s = CoupledStructure(mass=M, stiffness=K, damping_ratio=z, force_amplitude=F0, force_frequency=f,
                         displacement=Xc.imag, velocity=(1j * 2 * math.pi * f * Xc).imag)
    rec = run_bare_structure(s, 10 / f)
    amp = harmonic_amplitude(rec.time, rec.displacement, f, cycles=8)
    assert amp == pytest.approx(steady_amplitude(f, mass=M, stiffness=K, damping_ratio=z, force_amplitude=F0), rel=1e-5)


def test_studies_need_a_structure_and_good_frequencies():
    case = dataclasses.replace(_small(), drive=HarmonicDrive(stroke=0.01),
                               numerics=Numerics(integrator="verlet"))
    with pytest.raises(InputError, match=r"\[structure\]"):
        run_decay(case)
    assert parse_frequencies("1Hz:2Hz:3").tolist() == [1.0, 1.5, 2.0]
    assert parse_frequencies("1.9Hz, 2Hz").tolist() == [1.9, 2.0]
    for bad in ("2Hz:1Hz:3", "1Hz:2Hz", "1Hz:2Hz:x", "-1Hz"):
        with pytest.raises(InputError, match="frequencies"):
            parse_frequencies(bad)
    with pytest.raises(InputError, match=r"2 measured cycles need at least 4 cycles \(2 of transient first\); "
                                         r"run --cycles 4 or more, or measure at most 1 \(--measure-cycles 1\)"):
        run_response(_small(cycles=3), [2.0], force_amplitude=0.1, measure_cycles=2)
    # issue 24: --cycles 2 --measure-cycles 1 said "no transient to discard" without saying how many are needed
    with pytest.raises(InputError, match=r"1 measured cycle need at least 3 cycles .*run --cycles 3 or more$"):
        run_response(_small(cycles=2), [2.0], force_amplitude=0.1, measure_cycles=1)


def test_a_locked_bed_in_a_forced_response_is_an_added_mass():
    """The numbers codes ask for and the TMD numbers of a forced response (run_response): on a locked
    bed (tests/dem_fixtures.locked_case) the floor's acceleration and drift over the measured periods
    are the structure's carrying the bed, forced from rest, exactly; the bed's fit is a mass m_bed
    without a dashpot and the mode's detuning 1 / sqrt(1 + mu) - 1."""
    from dem_fixtures import locked_case

    from pdamper.config import loads_case
    from pdamper.studies.structure import response_case
    from pdamper.theory.tmd import added_mass_detuning

    text = locked_case("", structure='mass = "2kg"\nnatural_frequency = "3Hz"\ndamping_ratio = 0.02\n'
                       'storey_height = "3m"\nforce_amplitude = "0.5N"\nforce_frequency = "2.9Hz"', text=True)
    case = loads_case(text[:text.index("[load]")] + "[run]\ncycles = 6\n")
    res = run_response(case, [2.9], force_amplitude=0.5, measure_cycles=2, progress=False)
    s = res.summary
    fs = case.recording.sample_rate
    t = np.arange(1, int(6 / 2.9 * fs) + 1) / fs
    x, _, a = response_case(case, 2.9, 0.5).running_drive.carrying(case.bed_mass).motion(t)
    last = slice(-int(round(2 / 2.9 * fs)), None)  # the measured periods
    assert s["codes"]["acceleration_peak_m_s2"][0] == pytest.approx(np.max(np.abs(a[last])), rel=1e-3)  # 2.8e-5
    assert s["codes"]["drift_ratio_peak"][0] == pytest.approx(np.max(np.abs(x[last])) / 3.0, rel=1e-4)  # 8e-7
    assert s["codes"]["acceleration_peak_m_s2_at_hz"] == [2.9]
    tm = s["tmd_equivalent"][0]
    assert s["damper_fits"]["mass_kg"][0] == pytest.approx(case.bed_mass, rel=1e-3)  # measured 5.1e-5
    assert tm["detuning"][0] == pytest.approx(float(added_mass_detuning(case.bed_mass / 2.0)), rel=1e-3)
    assert abs(tm["added_damping_ratio"][0]) < 1e-5 and tm["at_frequency_hz"] == 2.9
