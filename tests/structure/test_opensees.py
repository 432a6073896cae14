"""An OpenSees model as the structure (pdamper.structure.opensees): read linearly it is the same
frame as its matrices; a bad model file gives one line; co-simulated, a locked bed on it is the
frame carrying the bed's mass; a model that does not converge says so.

Skipped, in one line, where openseespy does not load (pip install "pdamper[opensees]"; on Linux it
needs the system's libblas3 and liblapack3).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np
import pytest

from pdamper.structure.opensees import available

REASON = available()
pytestmark = pytest.mark.skipif(REASON is not None, reason=f"openseespy does not load here: {REASON}")

from pdamper.config import loads_case  # noqa: E402
from pdamper.errors import InputError, SimulationError  # noqa: E402
from pdamper.structure.linear import dof_response  # noqa: E402

DATA = Path(__file__).parent / "data"
EXAMPLES = Path(__file__).parents[2] / "examples"
MASSES = [25.0, 25.0, 25.0, 20.0]
STIFF = [4.0e4, 3.6e4, 3.2e4, 2.8e4]
ALPHA, BETA = 0.2, 0.001

SHEAR4 = f"""
import openseespy.opensees as ops

ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.node(0, 0.0)
ops.fix(0, 1)
for i, (m, k) in enumerate(zip({MASSES!r}, {STIFF!r}), start=1):
    ops.node(i, 0.0)
    ops.mass(i, m)
    ops.uniaxialMaterial("Elastic", i, k)
    ops.element("zeroLength", i, i - 1, i, "-mat", i, "-dir", 1, "-doRayleigh", 1)
ops.rayleigh({ALPHA}, 0.0, 0.0, {BETA})
"""

LOADS = {
    "ground": 'kind = "ground_acceleration"\ntime = [0, 0.05, 0.1, 0.2, 0.3, 0.4]\nacceleration = [0, 2.0, -3.0, 1.5, '
              '-0.5, 0]\nduration = 2.0',
    "force": 'kind = "force_history"\ntime = [0, 0.01, 0.02, 0.0201]\nforce = [0, 300.0, 0, 0]\nduration = 2.0',
}


def _matrices():
    n = len(MASSES)
    M = np.diag(MASSES)
    K = np.zeros((n, n))
    for i, k in enumerate(STIFF):
        K[i, i] += k
        if i > 0:
            K[i - 1, i - 1] += k
            K[i - 1, i] -= k
            K[i, i - 1] -= k
    return M, K


def _case(tmp_path, structure: str, load: str, model: str = SHEAR4):
    (tmp_path / "frame.py").write_text(textwrap.dedent(model))
    return loads_case(f'[particles]\ncount = 4\n[structure]\n{structure}\n[load]\n{load}\n', base_dir=tmp_path)


@pytest.mark.parametrize("load", sorted(LOADS))
def test_a_linear_model_is_the_same_frame_as_its_matrices(tmp_path, load):
    """The model read linearly (M, K, C from OpenSees) and the same frame given as matrices with
    C = alpha M + beta K: the same bare peaks and RMS at every dof, within 1e-6."""
    M, K = _matrices()
    np.savez(tmp_path / "frame.npz", M=M, K=K)
    ours = _case(tmp_path, 'opensees = "frame.py"\ndamper_node = 4', LOADS[load]).running_drive
    given = loads_case(f'[particles]\ncount = 4\n[structure]\nmatrices = "frame.npz"\ndamper_dof = 3\n'
                       f'rayleigh = [{ALPHA}, {BETA}]\n[load]\n{LOADS[load]}\n', base_dir=tmp_path).running_drive
    assert not ours.cosimulated and ours.nonlinear == ()
    np.testing.assert_allclose(ours.mode_frequencies, given.mode_frequencies, rtol=1e-9)
    np.testing.assert_allclose(ours.mode_damping_ratios, given.mode_damping_ratios, rtol=1e-9)
    t = np.linspace(0.0, 2.0, 4001)
    _, a = dof_response(ours, t)
    _, b = dof_response(given, t)
    peak_a, peak_b = np.max(np.abs(a), axis=0), np.max(np.abs(b), axis=0)
    rms_a, rms_b = np.sqrt(np.mean(a * a, axis=0)), np.sqrt(np.mean(b * b, axis=0))
    assert np.max(np.abs(peak_a / peak_b - 1)) < 1e-6
    assert np.max(np.abs(rms_a / rms_b - 1)) < 1e-6
    assert ours.dof_shapes()[0] == [1, 2, 3, 4]  # the dofs are the nodes


def test_a_nonlinear_model_is_cosimulated_and_its_bare_run_is_opensees_own(tmp_path):
    """Steel01 storeys make the model nonlinear: coupling "auto" co-simulates it. A linear model
    forced into the co-simulation: OpenSees' Newmark run without the beds against the exact
    response, within 2e-3 of the peak (average acceleration at 1 ms: its period error (w h)^2/12)."""
    from pdamper.cosim import run_bare

    yielding = SHEAR4.replace('"Elastic", i, k)', '"Steel01", i, 0.01 * k, k, 0.05)')
    s = _case(tmp_path, 'opensees = "frame.py"\ndamper_node = 4', LOADS["ground"], yielding).drive
    assert s.cosimulated and s.nonlinear == ("uniaxialMaterial Steel01 (tags 1, 2, 3, 4)",)
    case = _case(tmp_path, 'opensees = "frame.py"\ndamper_node = 4\ncoupling = "opensees"', LOADS["ground"])
    assert case.in_loop
    run = run_bare(case)
    _, exact = dof_response(case.running_drive, run.time)
    assert np.max(np.abs(run.displacements - exact)) < 2e-3 * np.max(np.abs(exact))


def test_a_locked_bed_on_a_cosimulated_frame_is_the_frame_carrying_its_mass(tmp_path):
    """The co-simulation with a locked bed (a row of spheres wall to wall: its force is its mass
    times the container's acceleration) on the roof of a linear frame advanced by OpenSees: the
    frame carrying the bed's mass exactly, within 2e-3 of the peak (Newmark's error, as above); the
    interface energy mismatch within 1 % of the work through the walls."""
    import sys

    sys.path.insert(0, str(Path(__file__).parents[1]))
    from dem_fixtures import locked_case

    from pdamper.cosim import run_coupled

    (tmp_path / "frame.py").write_text(textwrap.dedent(SHEAR4))
    case = locked_case(LOADS["force"].replace("300.0", "600.0").replace("duration = 2.0", "duration = 0.5"),
                       structure=f'opensees = "{tmp_path / "frame.py"}"\ndamper_node = 4\ncoupling = "opensees"')
    run = run_coupled(case)
    solid = case.running_drive.carrying(case.bed_mass)
    _, exact = dof_response(solid, run.time)
    assert np.max(np.abs(run.displacements - exact)) < 2e-3 * np.max(np.abs(exact))
    assert run.summary["interface_energy_error"] < 1e-2
    assert run.summary["coupling"] == "opensees" and run.summary["coupled_energy_balance_error"] is None


def test_a_model_that_does_not_converge_gives_one_line(tmp_path):
    """A spring whose post-yield stiffness is negative on a light mass: Newton and the fallbacks
    fail; one SimulationError line with the step's times and what to try."""
    from pdamper.cosim import run_bare

    model = (DATA / "opensees_snap.py").read_text()
    case = _case(tmp_path, 'opensees = "frame.py"\ndamper_node = 1',
                 'kind = "force_history"\ntime = [0, 0.01, 0.3, 0.31]\nforce = [0, 400.0, 400.0, 0]\nduration = 0.5',
                 model)
    with pytest.raises(SimulationError) as err:
        run_bare(case)
    msg = str(err.value)
    assert "\n" not in msg and "did not converge in the step from t = " in msg and "coupling_step" in msg


BAD = {
    "raises": ("x = 1 / 0\n", "ZeroDivisionError (line 1)"),
    "syntax": ("def (\n", "SyntaxError"),
    "exits": ("import sys\nsys.exit(3)\n", "SystemExit (line 2): 3"),
    "dies": ("import os\nos._exit(7)\n", "OpenSees stopped during building the model (exit status 7)"),
    "no node": (SHEAR4, "structure.damper_node = 9: the model has no node 9 (its nodes: 0, 1, 2, 3, 4)"),
    "no mass": (SHEAR4.replace("ops.mass(i, m)", "ops.mass(i, m if i < 4 else 0.0)"),
                "the node has no mass along dof 1"),
    "fixed": (SHEAR4 + "\nops.fix(4, 1)\n", "its dof 1 is fixed"),
    "analysis": (SHEAR4 + "\nops.analyze(1, 0.01)\n", "the model file calls ops.analyze(...), which runs an analysis"),
    "pattern": (SHEAR4 + "\nops.pattern('Plain', 1, 1)\n", "which defines loads"),
    "opensees": (SHEAR4.replace('"-mat", i', '"-mat", 99'), "OpenSees says"),
    "no nodes": ("import openseespy.opensees as ops\nops.wipe()\nops.model('basic', '-ndm', 1, '-ndf', 1)\n",
                 "defines no nodes"),
}


@pytest.mark.parametrize("what", sorted(BAD))
def test_a_bad_model_file_gives_one_line(tmp_path, capfd, what):
    """Each bad model file: one InputError line that names structure.opensees and says what is wrong;
    the model file's output and OpenSees' stay out of pdamper's (captured in the child's log)."""
    model, said = BAD[what]
    node = 9 if what == "no node" else (1 if what == "dies" else 4)
    (tmp_path / "frame.py").write_text(model + "\nprint('the model file prints')\n")
    with pytest.raises(InputError) as err:
        loads_case(f'[particles]\ncount = 4\n[structure]\nopensees = "frame.py"\ndamper_node = {node}\n'
                   'displacement = "1mm"\n', base_dir=tmp_path)
    msg = str(err.value)
    assert "\n" not in msg and "[structure] opensees" in msg, msg
    assert said in msg, msg
    out = capfd.readouterr()
    assert "the model file prints" not in out.out + out.err


@pytest.mark.slow
def test_a_model_file_that_loops_is_stopped(tmp_path):
    """A file that never ends: stopped at the time limit, one line."""
    from pdamper.structure.opensees import read_model

    (tmp_path / "frame.py").write_text("while True:\n    pass\n")
    with pytest.raises(InputError) as err:
        read_model(tmp_path / "frame.py", damper_nodes=[1], timeout=2.0)
    assert "took longer than 2 s and was stopped" in str(err.value)


def test_the_missing_file_and_a_folder_say_so(tmp_path):
    for path, said in ((tmp_path / "none.py", "not found"), (tmp_path, "is a directory")):
        with pytest.raises(InputError, match=said):
            loads_case(f'[particles]\ncount = 4\n[structure]\nopensees = "{path}"\ndamper_node = 1\n'
                       'displacement = "1mm"\n')


def test_the_dorayleigh_trap_is_warned_about(tmp_path):
    """Without '-doRayleigh', 1 the zeroLength storeys take no stiffness-proportional damping: the
    damping is not the Rayleigh damping the model asks for, and pdamper says so (with the fix); with
    it, no warning."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _case(tmp_path, 'opensees = "frame.py"\ndamper_node = 4', LOADS["force"])
    model = SHEAR4.replace(', "-doRayleigh", 1', "")
    with pytest.warns(UserWarning, match="-doRayleigh"):
        _case(tmp_path, 'opensees = "frame.py"\ndamper_node = 4', LOADS["force"], model)


def test_the_example_frames_read(tmp_path):
    """examples/frame4_linear.py: 2 % at modes 1 and 3 (its Rayleigh pair), linear; frame4_yield.py:
    the same modes (the initial tangent), nonlinear, co-simulated."""
    lin = loads_case(f'[particles]\ncount = 4\n[structure]\nopensees = "{EXAMPLES / "frame4_linear.py"}"\n'
                     'damper_node = 4\ndisplacement = "1mm"\n').drive
    assert lin.mode_damping_ratios[0] == pytest.approx(0.02, rel=1e-3)
    assert lin.mode_damping_ratios[2] == pytest.approx(0.02, rel=1e-3)
    assert not lin.cosimulated
    case = loads_case((EXAMPLES / "frame4_two_dampers.toml").read_text(), base_dir=EXAMPLES)
    assert case.drive.cosimulated and case.damper_count == 2 and case.in_loop
    np.testing.assert_allclose(case.drive.mode_frequencies, lin.mode_frequencies, rtol=1e-12)
    assert math.isclose(case.drive.mode_frequencies[0], 2.078, rel_tol=1e-3)
