"""The loads of a ``[load]`` section (pdamper.structure.loads): read, written back, refused, and their
functions of time as the kernels take them; the readers of their files (pdamper.io.records)."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.config import dumps_case, load_case, loads_case
from pdamper.errors import InputError
from pdamper.io.records import read_at2, read_signal
from pdamper.structure import CoupledStructure
from pdamper.structure.loads import (LOADS, ForceHistory, GroundAcceleration, HarmonicLoad, RandomLoad,
                                     SteppedSine)
from pdamper.structure.loads.base import FORM_LINEAR, FORM_SINE, table_values

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
LOADED = ["frame_quake", "mast_quake", "mast_hammer", "structure_random"]

SDOF = """
[particles]
count = 4
[structure]
mass = "7kg"
natural_frequency = "2Hz"
damping_ratio = 0.01
"""


def test_the_registry_has_one_class_a_kind():
    assert set(LOADS) == {"harmonic", "force_history", "ground_acceleration", "random", "stepped_sine"}
    what = {k: (c.in_time, c.stationary, c.stepped) for k, c in LOADS.items()}
    assert what["harmonic"] == (False, False, False) and what["random"] == (True, True, False)
    assert what["stepped_sine"] == (True, False, True) and GroundAcceleration.ground and not ForceHistory.ground


@pytest.mark.parametrize("name", LOADED)
def test_each_loaded_example_reads_and_is_written_back_as_it_was(name):
    case = load_case(EXAMPLES / f"{name}.toml")
    load = case.drive.load
    assert load is not None and load.in_time and case.duration == pytest.approx(load.duration)
    again = loads_case(dumps_case(case))
    assert again == case and again.drive.load.config_table() == load.config_table()


def test_a_harmonic_load_is_the_structures_own_force():
    a = loads_case(SDOF + '[load]\nkind = "harmonic"\namplitude = "0.4N"\nfrequency = "2.1Hz"\n')
    b = loads_case(SDOF.replace('damping_ratio = 0.01', 'damping_ratio = 0.01\nforce_amplitude = "0.4N"\n'
                                'force_frequency = "2.1Hz"'))
    assert a == b and a.drive.load is None and "[load]" not in dumps_case(a)
    # a file made for decay and response (force 0) takes a [load] too
    c = loads_case(SDOF.replace('damping_ratio = 0.01', 'damping_ratio = 0.01\nforce_amplitude = "0N"')
                   + '[load]\nkind = "harmonic"\namplitude = "0.4N"\nfrequency = "2.1Hz"\n')
    assert c == a
    assert HarmonicLoad(amplitude=0.4, frequency=2.1).config_table() == {"kind": "harmonic", "amplitude": 0.4,
                                                                         "frequency": 2.1}


@pytest.mark.parametrize("extra, words", [
    ('[load]\nkind = "harmonic"\namplitude = "0.4N"\nfrequency = "2Hz"\n', "force_amplitude both load"),
    ('[load]\nkind = "force_history"\ntime = [0, 0.1]\nforce = [0, 1]\n', "force_amplitude both"),
])
def test_a_load_given_twice_is_refused(extra, words):
    text = SDOF.replace('damping_ratio = 0.01', 'damping_ratio = 0.01\nforce_amplitude = "0.2N"\n'
                        'force_frequency = "2Hz"') + extra
    with pytest.raises(InputError, match=words):
        loads_case(text)


@pytest.mark.parametrize("table, words", [
    ('kind = "sine"', r"\[load\] kind = 'sine' is not allowed"),
    ('file = "x.csv"', r"\[load\] kind is missing"),
    ('kind = "force_history"\nfile = "nowhere.csv"', r"\[load\] file: force file not found"),
    ('kind = "force_history"\nfile = "h.csv"\ntime = [0, 1]', "either file"),
    ('kind = "force_history"\ntime = [0, 1]', "needs 'force'"),
    ('kind = "force_history"\ntime = [0, 1, 1]\nforce = [0, 1, 0]', r"\[load\] time: must increase strictly; it does not at sample 2 \(t = 1.0 s\)"),
    ('kind = "force_history"\ntime = [0, 1]\nforce = [0, 1]\nlevel = 3', r"\[load\] level does not apply to a force"),
    ('kind = "random"\nlevel = 0.1\nduration = "10s"', r"\[load\] band is missing"),
    ('kind = "random"\nlevel = 0.1\nband = [0, "600Hz"]\nduration = "10s"\ntime_step = "2ms"', "time_step"),
    ('kind = "random"\nlevel = -1\nband = [0, 10]\nduration = "10s"', r"\[load\] level = -1"),
    ('kind = "random"\nexcitation = "force"\nlevel = 1\nband = [0, 10]\nduration = "1s"\ninfluence = [1]',
     "influence belongs to excitation = 'ground'"),
    ('kind = "stepped_sine"\namplitude = "1N"\nfrequencies = []', r"\[load\] frequencies = \(\); give one or more"),
    ('kind = "ground_acceleration"\ntime = [0, 1]\nacceleration = [0, 1]\ninfluence = [1]\nparticipation = [1]',
     "both given"),
])
def test_a_bad_load_table_is_refused_naming_the_key(tmp_path, table, words):
    (tmp_path / "h.csv").write_text("time [s],force [N]\n0,0\n1,1\n")
    (tmp_path / "c.toml").write_text(SDOF + "[load]\n" + table + "\n")
    with pytest.raises(InputError, match=words) as info:
        load_case(tmp_path / "c.toml")
    assert "\n" not in str(info.value)


def test_a_load_needs_a_structure():
    with pytest.raises(InputError, match=r"\[load\] loads a structure; this case's \[drive\]"):
        loads_case('[particles]\ncount = 4\n[drive]\nstroke = "5mm"\n[load]\nkind = "force_history"\n'
                   'time = [0, 1]\nforce = [0, 1]\n')


def test_a_load_beside_the_rig_drive_loads_the_structure():
    """A [drive] beside a [structure] is the damper's rig (pdamper design --write-case): a [load] then
    loads the structure, not the rig, and the three sections are written back as read."""
    text = SDOF + '[drive]\nstroke = "10mm"\nfrequency = "2Hz"\n[load]\nkind = "force_history"\ntime = [0, 1]\n' \
                  'force = [0, 1]\n'
    case = loads_case(text)
    assert case.drive.load == ForceHistory(time=(0.0, 1.0), force=(0.0, 1.0)) and case.rig.stroke == 0.01
    written = dumps_case(case)
    assert written.index("[drive]") < written.index("[structure]") < written.index("[load]")
    assert loads_case(written) == case


def test_pdamper_transient_needs_a_load_in_time():
    from pdamper.studies.transient import run_transient

    case = loads_case(SDOF.replace('damping_ratio = 0.01', 'damping_ratio = 0.01\ndisplacement = "5mm"'))
    with pytest.raises(InputError, match="needs a load in time"):
        run_transient(case)


# ----------------------------------------------------------------------------- files

def test_read_signal_takes_units_from_the_header_or_a_row_of_units(tmp_path):
    p = tmp_path / "a.csv"
    p.write_text("# a logger's note\ntime [ms];acceleration [g]\n0;0\n10;0,5\n20;-1\n")
    s = read_signal(p, "acceleration")
    assert s.time.tolist() == pytest.approx([0.0, 0.01, 0.02]) and s.values.tolist() == pytest.approx(
        [0.0, 0.5 * 9.80665, -9.80665])
    p.write_text("time,F_x\ns,kN\n0,0\n0.5,2\n")
    s = read_signal(p, "force", column="F_x")
    assert s.values.tolist() == [0.0, 2000.0]
    p.write_text("time [s],force [N]\n0,0\n0.5,2\n0.5,3\n")
    with pytest.raises(InputError, match="a.csv: the time must increase strictly"):
        read_signal(p, "force")
    p.write_text("time [s],acceleration [furlong]\n0,0\n1,1\n")
    with pytest.raises(InputError, match="not a known unit of acceleration"):
        read_signal(p, "acceleration")


def test_the_at2_reader_reads_both_header_layouts_and_names_what_is_wrong(tmp_path):
    body = "  .1000000E-01  .2000000E-01 -.1000000E-01\n  .0000000E+00\n"
    p = tmp_path / "q.AT2"
    p.write_text("PEER\nevent\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT=   .0050 SEC\n" + body)
    s = read_at2(p)
    assert s.time.tolist() == pytest.approx([0, 0.005, 0.01, 0.015])
    assert s.values.tolist() == pytest.approx([0.0981, 0.1961, -0.0981, 0.0], rel=1e-3)
    p.write_text("PEER\nevent\nACCELERATION TIME SERIES IN UNITS OF CM/S/S\n    4    .0050    NPTS, DT\n" + body)
    assert read_signal(p, "acceleration").values[1] == pytest.approx(0.0002)
    for head, words in (("NPTS=    5, DT=   .0050 SEC", "NPTS = 5 but the file has 4"),
                        ("NPTS=    4, DT=  -.0050 SEC", "DT = -.0050 s; must be a time step > 0"),
                        ("NPTS=    4", "line 4"),
                        ("NPTS=  4.5, DT= .005", "NPTS = 4.5")):
        p.write_text("PEER\nevent\nACCELERATION TIME SERIES IN UNITS OF G\n" + head + "\n" + body)
        with pytest.raises(InputError, match=words):
            read_at2(p)
    with pytest.raises(InputError, match="holds a ground acceleration, not a force"):
        read_signal(p, "force")


def test_a_merged_field_at2_file_reads_to_the_values_of_its_spaced_twin(tmp_path):
    """Issue 42: fixed-width .AT2 fields that touch (``.1000000E-01-.2000000E-01``, older PEER and COSMOS
    files) are split by their width, which NPTS and the line length give; the same values as the file
    with blanks between its fields, bit for bit, and both within the 7 written digits of the record."""
    from fuzz_helpers import at2_text

    a = np.random.default_rng(3).normal(0.0, 0.05, 1003)  # a ragged last line (1003 = 200 x 5 + 3)
    spaced, merged = tmp_path / "spaced.AT2", tmp_path / "merged.AT2"
    spaced.write_text(at2_text(a, dt=0.005, width=15))
    merged.write_text(at2_text(a, dt=0.005, width=13))
    rows = merged.read_text().splitlines()[4:]
    touching = sum("E-01-." in r or "E-02-." in r for r in rows)
    assert touching > 100 and all(len(r) == 65 for r in rows[:-1]) and len(rows[-1]) == 39  # they touch
    s, m = read_at2(spaced), read_at2(merged)
    assert np.array_equal(s.values, m.values) and np.array_equal(s.time, m.time) and m.values.size == 1003
    assert np.max(np.abs(m.values / 9.80665 - a)) <= 5e-8 * 1.0  # 7 digits of |a| < 1
    with_d = tmp_path / "fortran_d.AT2"  # a Fortran D exponent, fields touching
    with_d.write_text(merged.read_text().replace("E-", "D-").replace("E+", "D+"))
    assert np.array_equal(read_at2(with_d).values, m.values)


@pytest.mark.parametrize("line, words", [
    (" .1000000E-01-.2000000E-01 .1000000E-0x .0000000E+00", r"line 5, field 3 \(columns 27-39 of fixed width 13\)"),
    (" .1000000E-01-.2000000E-01 .1000000E-01", r"NPTS = 4 but the file has 3|cannot read"),
])
def test_a_merged_field_at2_line_that_is_wrong_is_named(tmp_path, line, words):
    p = tmp_path / "bad.AT2"
    p.write_text("PEER\nevent\nACCELERATION TIME SERIES IN UNITS OF G\nNPTS=    4, DT=   .0050 SEC\n" + line + "\n")
    with pytest.raises(InputError, match=words):
        read_at2(p)


def test_the_example_accelerogram_reads_the_same_from_csv_and_at2():
    a, b = read_signal(EXAMPLES / "quake_synthetic.csv", "acceleration"), read_at2(EXAMPLES / "quake_synthetic.AT2")
    assert np.allclose(a.time, b.time) and np.max(np.abs(a.values - b.values)) < 1e-5 * np.max(np.abs(a.values))


# ----------------------------------------------------------------------------- functions of time

def test_the_kernels_load_value_is_the_tables_function():
    """The compiled f(t) (kernels.structure.load_value) against the numpy one of the load, both forms."""
    from pdamper.kernels.structure import LOAD_LINEAR, LOAD_SINE, load_value

    assert (LOAD_LINEAR, LOAD_SINE) == (FORM_LINEAR, FORM_SINE)
    t = np.linspace(-0.1, 2.5, 2001)
    for load in (ForceHistory(time=(0.0, 0.3, 0.5, 1.2), force=(1.0, -2.0, 0.5, 3.0)),
                 SteppedSine(amplitude=0.4, frequencies=(2.0, 3.0), cycles=2.5)):
        form, rows = load.kernel_table()
        compiled = np.array([load_value(rows, float(form), float(x)) for x in t])
        assert np.allclose(compiled, table_values(form, rows, t), rtol=1e-13, atol=1e-15)  # (an FMA: 1 ulp)
    f = ForceHistory(time=(0.0, 0.3, 0.5, 1.2), force=(1.0, -2.0, 0.5, 3.0)).values
    assert f([0.15, 0.3, 1.1999999, 1.2, 2.0]) == pytest.approx([-0.5, -2.0, 3.0, 0.0, 0.0], abs=1e-5)


def test_a_stepped_sine_is_continuous_and_orders_its_steps():
    up = SteppedSine(amplitude=1.0, frequencies=(1.9, 2.0, 2.13), cycles=7.3)
    assert up.direction == "up" and SteppedSine(amplitude=1.0, frequencies=(2.1, 2.0)).direction == "down"
    edges = up.step_times()[1:-1]
    assert np.allclose(up.values(edges - 1e-10), up.values(edges + 1e-10), atol=1e-8)
    assert up.duration == pytest.approx(7.3 * (1 / 1.9 + 1 / 2.0 + 1 / 2.13))
    assert up.values([up.duration + 0.1]) == [0.0]


def test_a_random_load_is_seeded_and_has_its_spectrum():
    kw = dict(level=0.5, band=(1.0, 8.0), duration_s=400.0)
    a, b, c = RandomLoad(seed=1, **kw), RandomLoad(seed=1, **kw), RandomLoad(seed=2, **kw)
    assert np.array_equal(a.samples()[1], b.samples()[1]) and not np.array_equal(a.samples()[1], c.samples()[1])
    assert a.target_variance == pytest.approx(0.5 * 7.0, rel=1e-6)
    # the realisation's variance: a sum of 2800 independent exponential terms, relative sigma 1.9 %
    assert np.var(a.samples()[1]) / a.target_variance == pytest.approx(1.0, abs=4 / math.sqrt(7.0 * 400.0))
    kt = RandomLoad(spectrum="kanai_tajimi", level=1.0, ground_frequency=2.5, ground_damping=0.6, duration_s=10.0,
                    excitation="ground")
    g = kt.psd(np.array([0.0, 2.5, 25.0, 30.0]))
    assert g[0] == pytest.approx(1.0) and g[1] == pytest.approx(1 + 1 / (4 * 0.36)) and g[3] == 0.0
    assert kt.ground and kt.band == (0.0, 25.0)


def test_the_sdof_takes_its_whole_mass_in_a_ground_acceleration():
    load = GroundAcceleration(time=(0.0, 1.0), acceleration=(0.0, 0.0))
    s = CoupledStructure(mass=7.0, stiffness=1105.0, load=load).carrying(0.3)
    assert s.ground_participation() == pytest.approx([7.3]) and s.dof_shapes() == ([0], [[1.0]])
    assert load.modal_coefficients(s) == pytest.approx([-7.3])
    with pytest.raises(InputError, match="one mode and one dof"):
        s.ground_participation(participation=(1.0, 2.0))
    g = dataclasses.replace(load, participation=(0.5,))
    assert g.modal_coefficients(s) == pytest.approx([-0.5 * 7.3])
