"""A damper per mode (pdamper.design.several): each mode's damper designed at its point as one
damper is; the designs written as one case with a [[damper]] each, which reads back and runs."""

from __future__ import annotations

import numpy as np
import pytest

from pdamper.config import dumps_case, load_case, loads_case
from pdamper.design import design_case_several, design_for_case, design_for_modes, load_structure
from pdamper.errors import InputError

#: the 4-storey frame of examples/frame4_linear.py as matrices (floors 3, 3, 3, 2.5 kg; storeys 4.4, 4.0,
#: 3.4, 2.6 kN/m), 2 % damping at modes 1 and 3
MASSES = [3.0, 3.0, 3.0, 2.5]
STIFF = [4400.0, 4000.0, 3400.0, 2600.0]


@pytest.fixture()
def structure_file(tmp_path):
    n = len(MASSES)
    K = np.zeros((n, n))
    for i, k in enumerate(STIFF):
        K[i, i] += k
        if i:
            K[i - 1, i - 1] += k
            K[i - 1, i] -= k
            K[i, i - 1] -= k
    np.savez(tmp_path / "frame.npz", M=np.diag(MASSES), K=K)
    p = tmp_path / "frame.toml"
    p.write_text('[structure]\nmatrices = "frame.npz"\ndamper_dof = [3, 1]\nrayleigh_modes = [1, 3]\n'
                 "rayleigh_ratios = [0.02, 0.02]\n")
    return p


def test_each_mode_is_designed_at_its_point_as_one_damper_is(structure_file):
    case = load_structure(structure_file)
    sd = design_for_modes(case, force=1.0, modes=(1, 2))
    assert [d.mode for d in sd.designs] == [1, 2]
    import dataclasses

    for k, d in enumerate(sd.designs):
        one = design_for_case(dataclasses.replace(case, drive=case.drive.at_damper(k)), force=1.0, mode=d.mode)
        assert d.to_dict() == one.to_dict()
    assert sd.designs[0].natural_frequency_hz == pytest.approx(2.078, rel=1e-3)
    assert all(d.reduction < 1 for d in sd.designs)


def test_the_written_case_reads_back_and_runs(structure_file, tmp_path):
    from pdamper.studies.transient import run_transient

    case = load_structure(structure_file)
    sd = design_for_modes(case, force=1.0, modes=(1, 2))
    written = design_case_several(sd, case)
    path = tmp_path / "two.toml"
    path.write_text(dumps_case(written, name="two.toml"))
    back = load_case(path)
    assert back == written and back.damper_count == 2 and back.in_loop
    assert [d.n_particles for d in back.damper_beds()] == [d.filling.particles for d in sd.designs]
    s = run_transient(load_case(path, {"run.cycles": 1})).summary
    assert s["dampers"] == 2 and np.all(np.isfinite(s["peak_m"])) and s["energy_balance_error"] < 1e-3


def test_it_needs_a_point_a_mode(structure_file, tmp_path):
    one = tmp_path / "one.toml"
    one.write_text(structure_file.read_text().replace("damper_dof = [3, 1]", "damper_dof = 3"))
    with pytest.raises(InputError, match="2 modes need a damper point each: the structure has 1"):
        design_for_modes(load_structure(one), force=1.0, modes=(1, 2))
    with pytest.raises(InputError, match="two or more different modes"):
        design_for_modes(load_structure(structure_file), force=1.0, modes=(1, 1))
