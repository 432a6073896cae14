"""Messages quote a value as the user wrote it, never a numpy repr (issue 42 item 4; pdamper.errors.shown).

A value that reaches a check as a numpy scalar -- from an array, a computed grid, a notebook -- must be
said in plain digits (``force = 0.0 N``), not as ``np.float64(0.0)``; a long text is cut. Each case below
feeds a numpy value through one refusal of the contact laws, the recorders, run.py, the design and the
structure's studies, and asserts what the message shows. Nothing runs: every refusal comes before a
simulation starts.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
#: What a numpy repr prints that a value as written never does.
NUMPY_WORDS = ("np.", "float64", "int64", "numpy")


def _structure():
    from pdamper.structure import CoupledStructure

    return CoupledStructure(mass=25.0, stiffness=25.0 * (6 * math.pi) ** 2, damping_ratio=0.003, displacement=0.001)


def _frame_case():
    from pdamper.config import load_case

    return load_case(ROOT / "examples" / "frame_3hz.toml")


class _Recorder:
    name = "mine"
    channels = frozenset()
    every = np.int64(-2)

    def start(self, run): ...

    def record(self, state): ...

    def finalize(self, data): ...


def _restitution():
    from pdamper.contact import ConstantRestitution

    ConstantRestitution(value=np.float64(1.5))


def _thornton():
    from pdamper.contact import ThorntonRestitution

    ThorntonRestitution(yield_pressure=np.float64(-2.5))


def _trajectory():
    from pdamper.recorders import TrajectoryRecorder

    TrajectoryRecorder(np.float64(-4.0))


def _every():
    from pdamper.recorders.base import check_recorders

    check_recorders([_Recorder()])


def _until_steady():
    from pdamper import Case, ParticleSet, run_case

    run_case(Case(particles=(ParticleSet(count=2),)), until_steady=np.float64(-0.01))


def _design_force():
    from pdamper.design import design_for_structure

    design_for_structure(_structure(), force=np.float64(0.0))


def _design_target():
    from pdamper.design import design_for_structure

    design_for_structure(_structure(), force=1.5, target_ratio=np.float64(1.25))


def _design_margin():
    from pdamper.design import design_for_structure

    design_for_structure(_structure(), force=1.5, margin=np.float64(0.75))


def _design_container_mass():
    from pdamper.design import design_for_structure

    design_for_structure(_structure(), force=1.5, container_mass=np.float64(-0.5))


def _filling_particles():
    from pdamper.design import design_filling

    design_filling(frequency=2.0, stroke=0.012, sphere_radius=0.005, length=0.12, particles=np.int64(7))


def _response_force():
    from pdamper.studies.structure import run_response

    run_response(_frame_case(), [3.0], force_amplitude=np.float64(-1.5))


def _stepped_sine_force():
    from pdamper.studies.transient import run_stepped_sine

    run_stepped_sine(_frame_case(), [3.0], force_amplitude=np.float64(-1.5))


def _samples():
    from pdamper.studies.unknowns import sample

    sample(None, np.int64(0))


CASES = {
    "contact restitution": (_restitution, "restitution = 1.5"),
    "contact thornton": (_thornton, "yield_pressure = -2.5 Pa"),
    "recorders fps": (_trajectory, "fps = -4.0"),
    "recorders every": (_every, "every = -2"),
    "run until_steady": (_until_steady, "until_steady = -0.01"),
    "design force": (_design_force, "= 0.0 N"),
    "design target ratio": (_design_target, "= 1.25"),
    "design margin": (_design_margin, "= 0.75"),
    "design container mass": (_design_container_mass, "container mass = -0.5 kg"),
    "design filling particles": (_filling_particles, "particles = 7"),
    "studies response force": (_response_force, "--force = -1.5 N"),
    "studies stepped sine force": (_stepped_sine_force, "--force = -1.5 N"),
    "studies samples": (_samples, "--samples 0"),
}


@pytest.mark.parametrize("call, says", CASES.values(), ids=list(CASES))
def test_a_numpy_value_is_said_as_written(call, says):
    with pytest.raises((InputError, ValueError)) as info:
        call()
    msg = str(info.value)
    assert says in msg, msg
    assert not any(w in msg for w in NUMPY_WORDS), msg
    assert "\n" not in msg


def test_a_long_value_is_cut_not_quoted_whole():
    from pdamper.studies.structure import parse_frequencies

    with pytest.raises(InputError) as info:
        parse_frequencies("1Hz:" * 2000)
    msg = str(info.value)
    assert msg.startswith("--frequencies '1Hz:1Hz:") and "(8000 characters)" in msg and len(msg) < 300, msg


def test_a_missing_load_file_is_named_by_its_path_not_its_repr(tmp_path):
    """The design's --load reader names a file as shown_path does (a 5,000-character name cut)."""
    from pdamper.design.case import load_structure

    long = tmp_path / ("x" * 200 + ".csv")
    with pytest.raises(InputError) as info:
        load_structure(ROOT / "examples" / "frame_3hz.toml", load=long)
    msg = str(info.value)
    assert "..." in msg and "characters)" in msg and "'" + str(long) not in msg, msg
