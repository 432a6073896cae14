"""What the structure's studies share (pdamper.studies.structure_base): the bed's X_opt, the dofs,
the bare resonance; and the forced case of a structure file (pdamper.studies.structure.load_forced)."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies.structure import load_forced
from pdamper.studies.structure_base import bare_resonance, bed_x_opt, parse_dofs, select_dofs

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_x_opt_of_a_run_uses_the_clearance_count_of_the_studies():
    """`pdamper run` reports X_opt with the same N_p,max as the studies' store (48 for the paper's
    cylinder, not the 44 its floor packing holds)."""
    from pdamper import theory
    from pdamper.analysis.modes import case_clearance
    from pdamper.config import load_case

    root = Path(__file__).resolve().parents[2] / "examples"
    for name, h_paper in (("cylinder_30", 0.02925), ("cylinder_42", 0.00975), ("cuboid_36", 0.030)):
        case = load_case(root / f"{name}.toml")
        assert case_clearance(case)[1] == pytest.approx(h_paper, rel=1e-9)
        assert bed_x_opt(case) == pytest.approx(theory.optimal_stroke(h_paper), rel=1e-9)


def test_bed_x_opt_is_none_for_a_full_or_mixed_bed():
    case = load_case(EXAMPLES / "cuboid_36.toml", {"particles.count": 48})
    assert bed_x_opt(case) is None  # 48 of 48: no clearance


def test_the_bare_resonance_is_the_closed_form_peak():
    s = load_case(EXAMPLES / "structure_36.toml").drive
    fn, z = float(s.mode_frequencies[0]), float(s.mode_damping_ratios[0])
    r = bare_resonance(s, 0.4, fn)
    # the peak of a damped oscillator: at fn sqrt(1 - 2 zeta^2), F0 / (2 zeta sqrt(1 - zeta^2) K)
    assert r["resonance_bare_frequency_hz"] == pytest.approx(fn * math.sqrt(1 - 2 * z * z), rel=1e-7)
    assert r["resonance_bare_m"] == pytest.approx(0.4 / (2 * z * math.sqrt(1 - z * z) * s.stiffness), rel=1e-9)


def test_dofs_are_chosen_by_label_and_refused_by_name():
    s = load_case(EXAMPLES / "mast_fe.toml").drive
    labels, idx = select_dofs(s, parse_dofs("0:6:2"))
    assert labels == [0, 2, 4] and idx.tolist() == [0, 2, 4]
    with pytest.raises(InputError, match="is not a dof of this structure"):
        select_dofs(s, ["nope"])


def test_a_forced_case_reads_a_file_that_nothing_moves(tmp_path):
    p = tmp_path / "still.toml"
    p.write_text('[particles]\ncount = 36\n[structure]\nmass = "25kg"\nnatural_frequency = "3Hz"\n'
                 'damping_ratio = 0.003\n')
    with pytest.raises(InputError, match="still.toml: .*nothing moves it"):
        load_forced(p)  # as it is: nothing moves the structure
    case = load_forced(p, force=1.5)
    assert case.drive.force_amplitude == 1.5 and case.drive.force_frequency == pytest.approx(3.0)
    assert case.drive.load is None
    given = load_forced(p, {"structure.force_amplitude": 0.4, "structure.force_frequency": "2.9Hz"}, force=1.5)
    assert given.drive.force_amplitude == 0.4  # the file's own force, set by the overrides, wins
