"""Reading measured force/motion records (CSV with units in the header)."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.io.records import Record, read_record


def write(path, text):
    path.write_text(text, encoding="utf-8")
    return path


@pytest.fixture
def signals():
    t = np.arange(50) * 1e-3
    w = 2 * np.pi * 2.0
    return t, 0.01 * np.sin(w * t), 0.01 * w * np.cos(w * t), 3.0 * np.cos(w * t)


def test_units_in_brackets_are_converted_to_si(tmp_path, signals):
    t, x, v, F = signals
    p = tmp_path / "r.csv"
    np.savetxt(p, np.column_stack([t * 1e3, F / 1e3, x * 1e3]), delimiter=",",
               header="time [ms], force [kN], position [mm]", comments="")
    rec = read_record(p)
    assert isinstance(rec, Record)
    assert rec.motion_kind == "position" and rec.velocity is None and rec.acceleration is None
    assert rec.time == pytest.approx(t, rel=1e-15, abs=1e-18)
    assert rec.force == pytest.approx(F, rel=1e-14)
    assert rec.position == pytest.approx(x, rel=1e-14, abs=1e-18)
    assert rec.motion is rec.position
    assert rec.source == str(p)
    assert rec.headers == {"time": "time [ms]", "force": "force [kN]", "position": "position [mm]"}
    assert len(rec) == t.size


@pytest.mark.parametrize("header, factor", [
    ("velocity [m/s]", 1.0), ("velocity [mm/s]", 1e-3), ("Velocity (mm/s)", 1e-3),
    ("  VELOCITY  ", 1.0), ("velocity[km/h]", 1 / 3.6),
])
def test_velocity_units_and_name_matching(tmp_path, header, factor):
    p = write(tmp_path / "r.csv", f"time [s],force [N],{header}\n0,1,2\n0.001,1,4\n0.002,1,6\n")
    rec = read_record(p)
    assert rec.velocity == pytest.approx(np.array([2, 4, 6]) * factor)


@pytest.mark.parametrize("header, factor", [
    ("acceleration [m/s^2]", 1.0), ("acceleration [mm/s^2]", 1e-3), ("acceleration [g0]", 9.80665),
])
def test_acceleration_units(tmp_path, header, factor):
    p = write(tmp_path / "r.csv", f"time,force,{header}\n0,1,2\n0.001,1,4\n0.002,1,6\n")
    assert read_record(p).acceleration == pytest.approx(np.array([2, 4, 6]) * factor)


def test_semicolon_and_tab_delimiters_with_decimal_comma(tmp_path):
    p = write(tmp_path / "s.csv", "time [s];force [N];position [mm]\n0,000;1,5;2\n0,001;2,5;3\n")
    rec = read_record(p)
    assert rec.force == pytest.approx([1.5, 2.5]) and rec.position == pytest.approx([2e-3, 3e-3])
    p = write(tmp_path / "t.tsv", "time\tforce\tvelocity\n0\t1\t2\n1\t3\t4\n")
    rec = read_record(p)
    assert rec.velocity == pytest.approx([2, 4])


def test_comments_blank_lines_bom_and_extra_columns(tmp_path):
    text = "\ufeff# exported by the rig\n\ntime [s],comment,force [N],velocity [m/s]\n" \
           "0,start,1,2\n\n0.001,,3,4\n"
    rec = read_record(write(tmp_path / "r.csv", text))
    assert rec.time == pytest.approx([0, 1e-3]) and rec.force == pytest.approx([1, 3])


def test_column_map(tmp_path):
    p = write(tmp_path / "r.csv", "t [ms],F_x [kN],x [mm],v [m/s]\n0,1,2,0\n1,2,3,0\n")
    rec = read_record(p, columns={"time": "t", "force": "F_x", "position": "x"})
    assert rec.time == pytest.approx([0, 1e-3])
    assert rec.force == pytest.approx([1e3, 2e3])
    assert rec.position == pytest.approx([2e-3, 3e-3])
    # the full header text works too, case-insensitively
    rec = read_record(p, columns={"time": "T [MS]", "force": "f_x [kN]", "velocity": "v"})
    assert rec.motion_kind == "velocity"


def test_two_motion_columns_need_a_choice(tmp_path):
    p = write(tmp_path / "r.csv", "time,force,position [mm],velocity [mm/s]\n0,1,2,3\n1,1,2,3\n")
    with pytest.raises(InputError, match="'position \\[mm\\]' and 'velocity \\[mm/s\\]'.*choose"):
        read_record(p)
    assert read_record(p, motion="velocity").velocity == pytest.approx([3e-3, 3e-3])
    assert read_record(p, columns={"position": "position"}).motion_kind == "position"
    with pytest.raises(InputError, match="several motion columns"):
        read_record(p, columns={"position": "position", "velocity": "velocity"})


@pytest.mark.parametrize("text, pattern", [
    ("", "empty"),
    ("# only a comment\n\n", "empty"),
    ("time,force,position\n", "no data rows"),
    ("time,position\n0,1\n", "no force column \\('force'\\).*--force-column"),
    ("t,force,position\n0,1,2\n", "no time column"),
    ("time,force,temperature\n0,1,2\n", "no motion column.*position, velocity, acceleration"),
    ("time,force,position\n0,1,2\n0.001,x1,2\n", "line 3, column 'force': cannot read 'x1'"),
    ("time,force,position\n0,1,2\n0.001,,2\n", "line 3, column 'force': empty cell"),
    ("time,force,position\n0,1,2\n0.001,2\n", "line 3: 2 fields but the header has 3"),
    ("time,force,position\n0,1,2\n0.001,nan,2\n", "line 3, column 'force': 'nan' is not a finite"),
    ("time,force,position [furlong/s]\n0,1,2\n", "'furlong/s' is not a known unit of length"),
    ("time [kg],force,position\n0,1,2\n", "'kg' is not a known unit of time"),
    ("time,force,position [%]\n0,1,2\n", "'%' is not a unit of length"),
    ("time [fortnight/s],force,position\n0,1,2\n", "'fortnight/s' is not a unit of time"),
    ("time,force [N],position,force [kN]\n0,1,2,3\n", "2 columns match force"),
    ("time force position\n0 1 2\n", "cannot find the column delimiter"),
])
def test_bad_files(tmp_path, text, pattern):
    p = write(tmp_path / "bad.csv", text)
    with pytest.raises(InputError, match=pattern):
        read_record(p)


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_record(tmp_path / "nope.csv")
    with pytest.raises(InputError, match="directory"):
        read_record(tmp_path)


def test_bad_options(tmp_path):
    p = write(tmp_path / "r.csv", "time,force,position\n0,1,2\n")
    with pytest.raises(InputError, match="unknown column role 'speed'"):
        read_record(p, columns={"speed": "v"})
    with pytest.raises(InputError, match="motion must be one of"):
        read_record(p, motion="jerk")
    with pytest.raises(InputError, match="no velocity column"):
        read_record(p, motion="velocity")


def test_record_needs_exactly_one_motion():
    with pytest.raises(InputError, match="exactly one motion"):
        Record(time=np.zeros(3), force=np.zeros(3))


# --------------------------------------------------------------------------- files as loggers write them

def _logger_text(t, F, a_g, *, decimal_comma=True):
    rows = "\n".join(f'{ti:.4f};"{Fi:.6f}";{ai:.6f}'.replace(".", ",") if decimal_comma else f"{ti},{Fi},{ai}"
                     for ti, Fi, ai in zip(t, F, a_g))
    return ("Device: NI-9234\nOperator: J. Doe\nRate: 1000 Hz\n\n"
            "Time;Force;Accel\ns;N;g\n" + rows + "\n")


def test_a_logger_file_with_preamble_units_row_semicolons_decimal_commas_and_g(tmp_path, signals):
    t, x, v, F = signals
    a = -(2 * np.pi * 2.0) ** 2 * x
    p = write(tmp_path / "log.txt", _logger_text(t, F, a / 9.80665))
    rec = read_record(p, columns={"acceleration": "Accel"})
    assert rec.meta == {"Device": "NI-9234", "Operator": "J. Doe", "Rate": "1000 Hz"}
    assert rec.headers == {"time": "Time [s]", "force": "Force [N]", "acceleration": "Accel [g]"}
    assert rec.time == pytest.approx(np.round(t, 4), abs=1e-12)
    assert rec.acceleration == pytest.approx(a, abs=1e-5)  # 'g' is the standard gravity (6 digits in g)
    assert rec.force == pytest.approx(F, abs=1e-6)


def test_standard_input_and_a_bad_cell_is_named_with_its_line(tmp_path, signals, monkeypatch):
    import io

    t, x, v, F = signals
    text = "time,force,position\n" + "\n".join(f"{a},{b},{c}" for a, b, c in zip(t, F, x)) + "\n"
    monkeypatch.setattr("sys.stdin", io.StringIO(text))
    rec = read_record("-")
    assert rec.source == "<stdin>" and rec.position == pytest.approx(x)
    bad = text.replace(f"{F[7]}", "oops", 1)
    with pytest.raises(InputError, match=r"line 9, column 'force': cannot read 'oops' as a number"):
        read_record(write(tmp_path / "b.csv", bad))


def test_hdf5_mat_and_tdms_files_with_a_channel_map(tmp_path, signals):
    import h5py
    import scipy.io
    from nptdms import ChannelObject, TdmsWriter

    t, x, v, F = signals
    with h5py.File(tmp_path / "r.h5", "w") as f:
        g = f.create_group("daq")
        g["t"] = t
        g["F_x"] = F / 1e3
        g["F_x"].attrs["units"] = "kN"
        g["x"] = x * 1e3
        g["x"].attrs["units"] = "mm"
    rec = read_record(tmp_path / "r.h5", columns={"time": "t", "force": "F_x", "position": "x"})
    assert rec.force == pytest.approx(F) and rec.position == pytest.approx(x) and rec.time == pytest.approx(t)
    scipy.io.savemat(tmp_path / "r.mat", {"time": t, "force": F, "velocity": v})
    rec = read_record(tmp_path / "r.mat")
    assert rec.motion_kind == "velocity" and rec.velocity == pytest.approx(v)
    with TdmsWriter(tmp_path / "r.tdms") as w:
        w.write_segment([ChannelObject("rig", "force", F, properties={"wf_increment": 1e-3, "unit_string": "N"}),
                         ChannelObject("rig", "position", x * 1e3, properties={"wf_increment": 1e-3,
                                                                                 "unit_string": "mm"})])
    rec = read_record(tmp_path / "r.tdms")
    assert rec.time == pytest.approx(t) and rec.position == pytest.approx(x) and rec.force == pytest.approx(F)
    with pytest.raises(InputError, match="no force column"):
        read_record(tmp_path / "r.h5", columns={"time": "t"})


def test_pdamper_run_output_is_a_record(tmp_path):
    from pdamper.rundir import write_run
    from pdamper.run import run_case
    from dem_fixtures import TINY_CONFIG
    from pdamper.config import loads_case

    res = run_case(loads_case(TINY_CONFIG))
    write_run(res, tmp_path / "run")
    for target in (tmp_path / "run", tmp_path / "run" / "signals.csv"):
        rec = read_record(target)
        assert rec.motion_kind == "velocity"
        np.testing.assert_array_equal(rec.velocity, res.signals.velocity)
        np.testing.assert_array_equal(rec.force, res.signals.force)


def test_a_field_over_128_kB_is_named_with_its_line_not_a_csv_traceback(tmp_path, signals):
    # issue 24: a binary dump pasted into a logger file ended in "_csv.Error: field larger than field limit"
    t, x, _, F = signals
    rows = [f"{a:.6g},{b:.6g},{c:.6g}" for a, b, c in zip(t, F, x)]
    rows[7] = f"{t[7]:.6g},{F[7]:.6g}," + "A" * 140_000
    p = write(tmp_path / "dump.csv", "time,force,position\n" + "\n".join(rows) + "\n")
    with pytest.raises(InputError, match=r"dump.csv, line 9, column 'position': cannot read 'AAAA.*'\.\.\. "
                                         r"\(140000 characters\) as a number") as info:
        read_record(p)
    assert len(str(info.value)) < 400  # the message quotes the start of the cell, not 140 kB of it
    # a huge quoted header cell: the header is still found, the motion column named
    q = write(tmp_path / "header.csv", 'time,force,"' + "B" * 140_000 + '"\n0,1,2\n0.001,1,2\n')
    with pytest.raises(InputError, match=r"no motion column.*characters\)"):
        read_record(q)


def test_a_record_too_large_to_analyse_is_not_called_constant(tmp_path, signals):
    # issue 24: values of 1e200 overflowed the spectrum, and the signal was said to be "constant"
    from pdamper.analysis import analyze_record

    t = np.arange(4000) * 1e-3
    x = 1e200 * np.sin(2 * np.pi * 2.0 * t)
    with pytest.raises(InputError, match=r"position has values up to 1e\+200: too large to analyse") as info:
        analyze_record(t, np.cos(2 * np.pi * 2.0 * t), position=x)
    assert "constant" not in str(info.value)
