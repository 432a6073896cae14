"""The drive protocol: a drive kind is one class that reads its own config table and answers what it
can do; a kind registered after ``pdamper.config`` was imported is read and run like the shipped
ones; the kernels' drive kinds are named constants, reached by name."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

import pdamper.config as config
from pdamper.errors import InputError
from pdamper.excitation import DRIVES, DriveBase, HarmonicDrive, SampledDrive, Still, register_drive
from pdamper.kernels import drive as kdrive
from pdamper.schema import param
from pdamper.structure import CoupledStructure, ModalStructure


@dataclass(frozen=True, kw_only=True)
class PhasedDrive(DriveBase):
    """x_c = X sin(Omega t + phi): a harmonic drive started at a phase (the kernels' harmonic
    motion with its phase parameter)."""

    stroke: float = param(0.008, dimension="length")
    frequency: float = param(2.0, dimension="frequency")
    phase: float = param(0.0, dimension="angle")
    angle: float = param(0.0, dimension="angle")
    direction: tuple | None = param(None, kind="list")
    kind: str = param("phased", kind="tag")
    analysable = True
    counts_cycles = True
    config_marks = ("phase",)
    config_label = "a phased drive"
    config_summary = "phase (phased)"

    def __post_init__(self):
        self._prepare()
        self._check_direction()

    def duration(self, cycles):
        return cycles / self.frequency

    def motion(self, t):
        t = np.asarray(t, dtype=float)
        w = 2 * math.pi * self.frequency
        s, c = np.sin(w * t + self.phase), np.cos(w * t + self.phase)
        return self.stroke * s, self.stroke * w * c, -self.stroke * w * w * s

    def kernel_args(self):
        return "harmonic", np.array([self.stroke, 2 * math.pi * self.frequency, self.phase]), np.zeros((1, 5))


@pytest.fixture
def phased():
    register_drive(PhasedDrive)
    yield PhasedDrive
    DRIVES.pop("phased")


CASE = """
[particles]
count = 6
[drive]
kind = "phased"
stroke = "8mm"
phase = "90deg"
[run]
cycles = 3
drop_cycles = 1
"""


def test_a_drive_registered_after_the_config_reader_is_read_written_and_run(phased):
    from pdamper.run import run_case

    case = config.loads_case(CASE)
    d = case.drive
    assert isinstance(d, PhasedDrive) and d.phase == pytest.approx(math.pi / 2)
    assert "phase" in config.SECTIONS["drive"]
    assert config.case_from_dict(config.case_to_dict(case)) == case
    # a table without kind = ... is the phased drive's by its own key
    assert isinstance(config.loads_case(CASE.replace('kind = "phased"\n', "")).drive, PhasedDrive)
    res = run_case(case)
    # the container moved as the drive says: the recorded velocity (interval means) against the
    # closed form's mean over each interval
    sig = res.signals
    t0, t1 = sig.time - 0.5 / case.recording.sample_rate, sig.time + 0.5 / case.recording.sample_rate
    mean_v = (d.motion(t1)[0] - d.motion(t0)[0]) * case.recording.sample_rate
    assert np.max(np.abs(sig.velocity - mean_v)) < 1e-9 * d.stroke * 2 * math.pi * d.frequency
    assert math.isfinite(res.eta_star)  # analysable: the complex power was taken


def test_a_key_of_another_kind_is_refused_with_both_kinds_named(phased):
    with pytest.raises(InputError, match=r"duration is a key of a drive at rest, but this \[drive\] is a phased "
                                         r"drive; give .*phase \(phased\), not a mix") as err:
        config.loads_case(CASE.replace('kind = "phased"\n', 'kind = "phased"\nduration = "1s"\n'))
    assert "\n" not in str(err.value)
    with pytest.raises(InputError, match="are given together"):
        config.loads_case(CASE.replace('kind = "phased"\n', 'duration = "1s"\n'))


def test_each_kind_answers_what_it_can_do():
    h = HarmonicDrive(stroke=0.01)
    sampled = SampledDrive(time=(0.0, 0.1, 0.2, 0.3), position=(0.0, 0.001, 0.0, -0.001))
    still = Still()
    sdof = CoupledStructure(mass=7.0, stiffness=1105.0, displacement=0.01)
    modal = ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.005, "modal_mass": 7.0, "damper": 1.0},),
                           displacement=0.01)
    table = {d.kind: (d.periodic, d.sweepable, d.analysable, d.coupled, d.counts_cycles)
             for d in (h, sampled, still, sdof, modal)}
    assert table == {"harmonic": (True, True, True, False, True), "samples": (False, False, True, False, False),
                     "still": (False, False, False, False, False), "structure": (False, False, False, True, True),
                     "modal": (False, False, False, True, True)}


def test_every_kernel_drive_names_a_compiled_motion_and_the_numbers_are_named():
    from pdamper.engine.build import drive_bundle

    drives = [HarmonicDrive(stroke=0.01), Still(),
              SampledDrive(time=(0.0, 0.1, 0.2, 0.3), position=(0.0, 0.001, 0.0, -0.001)),
              CoupledStructure(mass=7.0, stiffness=1105.0, displacement=0.01),
              ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.005, "modal_mass": 7.0, "damper": 1.0},),
                             displacement=0.01)]
    kinds = {drive_bundle(d).kind for d in drives}
    assert kinds == {kdrive.DRIVE_STILL, kdrive.DRIVE_HARMONIC, kdrive.DRIVE_SAMPLED, kdrive.DRIVE_STRUCTURE,
                     kdrive.DRIVE_MODAL}
    assert {drive_bundle(d).coupling.__class__.__name__ for d in drives[3:]} == {"CoupledMotion"}
    assert set(kdrive.DRIVE_KINDS.values()) == kinds  # one name for each compiled motion

    class Unknown(Still):
        def kernel_args(self):
            return "teleport", np.zeros(3), np.zeros((1, 5))

    with pytest.raises(InputError, match="names the compiled motion 'teleport'"):
        drive_bundle(Unknown())


def test_the_old_import_path_of_the_structures_still_works_and_warns():
    import pdamper.excitation as exc

    with pytest.warns(DeprecationWarning, match="pdamper.structure.CoupledStructure"):
        old = exc.CoupledStructure
    assert old is CoupledStructure
    with pytest.warns(DeprecationWarning):
        assert exc.read_structure_matrices is __import__("pdamper.structure", fromlist=["x"]).read_structure_matrices
    with pytest.raises(AttributeError):
        exc.NoSuchDrive
