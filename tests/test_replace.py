"""pdamper.schema.replace: a case changed by config keys, each value read by its field's spec and
every object rebuilt through its __post_init__; the road every sweep point takes."""

import dataclasses
import math
import re
from pathlib import Path

import pint
import pytest

from pdamper.config import case_from_dict, case_to_dict, dumps_case
from pdamper.contact.cor_constant import ConstantRestitution
from pdamper.errors import InputError
from pdamper.excitation import SampledDrive, Still
from pdamper.structure import CoupledStructure
from pdamper.materials import LIBRARY, Material
from pdamper.params import Case, ParticleSet
from pdamper.schema import param, replace

U = pint.UnitRegistry()
BASE = Case(particles=(ParticleSet(count=36),))
SRC = Path(__file__).parents[1] / "src" / "pdamper"


def test_values_with_units_quantities_and_si_numbers():
    case = replace(BASE, {"drive.stroke": "13mm", "drive.frequency": 3 * U.Hz, "contact.friction": 0.2,
                          "container.length": "100mm", "container.mass": "0.5kg", "run.cycles": 30,
                          "numerics.time_step": "auto", "numerics.skin": "1mm", "initial.seed": 3.0})
    assert case.drive.stroke == 0.013 and case.drive.frequency == 3.0 and case.contact.friction == 0.2
    assert case.container.geometry.length == 0.1 and case.container.mass == 0.5 and case.cycles == 30
    assert case.numerics.time_step is None and case.numerics.skin == 0.001
    assert case.initial.seed == 3 and isinstance(case.initial.seed, int)
    # what was not given is the same object
    assert case.recording is BASE.recording and case.particles is BASE.particles
    assert replace(BASE, {}) is BASE


def test_custom_fields_take_config_values_or_built_objects():
    steel_mod = Material(name="steel-mod", youngs_modulus=405e9, poisson_ratio=0.3, density=7900.0)
    case = replace(BASE, {"particles.material": "tungsten", "container.material": steel_mod,
                          "contact.restitution": 0.8, "container.tilt": "0.2deg"})
    assert case.particles[0].material == LIBRARY["tungsten"] and case.container.material is steel_mod
    assert case.contact.restitution == ConstantRestitution(value=0.8)
    assert case.container.tilt == pytest.approx((math.radians(0.2),) * 3, rel=1e-14)
    law = {"law": "thornton", "yield_pressure": "1.5GPa"}
    assert replace(BASE, {"contact.restitution": law}).contact.restitution.yield_pressure == 1.5e9
    still = Still(duration_s=1.0)
    assert replace(BASE, {"drive": still}).drive is still


def test_the_structure_is_its_own_section():
    case = dataclasses.replace(BASE, drive=CoupledStructure(mass=7.0, stiffness=1105.0, displacement=0.01))
    assert replace(case, {"structure.mass": "8kg"}).drive.mass == 8.0
    with pytest.raises(InputError, match=r"'drive.stroke': this case's drive is a \[structure\]"):
        replace(case, {"drive.stroke": 0.01})


@pytest.mark.parametrize("changes, message", [
    ({"drive.stroek": 0.01}, r"'drive.stroek': unknown key 'stroek' in \[drive\]; did you mean 'stroke'"),
    ({"drvie.stroke": 0.01}, r"unknown section \[drvie\]; did you mean \[drive\]"),
    ({"run.cyclse": 3}, r"'run.cyclse': unknown key 'cyclse' in \[run\]; did you mean 'cycles'"),
    ({"container.radius": 0.01}, r"unknown key 'radius' in \[container\]; .*shape = 'cuboid'"),
    ({"drive.stroke": "3s"}, r"\[drive\] stroke = '3s' is not a length.*\(paper: 3-50 mm\)"),
    ({"numerics.integrator": "verlett"}, r"\[numerics\] integrator = 'verlett' is not allowed; did you mean 'verlet'"),
    ({"particles.material": "steal"}, r"\[particles\] material = 'steal' is not a known material; did you mean 'steel'"),
    ({"drive.kind": "still"}, r"'drive.kind': kind = 'harmonic' cannot be changed key by key"),
    ({"stroke": 0.01}, r"unknown section \[stroke\]"),
    ({"drive.stroke.x": 0.01}, r"write a key as 'section.key'"),
])
def test_bad_keys_and_values_name_the_key(changes, message):
    with pytest.raises(InputError, match=message):
        replace(BASE, changes)


def test_post_init_checks_the_new_values():
    with pytest.raises(InputError, match=r"drive.stroke = -0.001 m; must be > 0"):
        replace(BASE, {"drive.stroke": "-1mm"})
    with pytest.raises(InputError, match=r"run.cycles = 2 leaves nothing"):
        replace(BASE, {"run.cycles": 2})
    with pytest.raises(InputError, match="trajectory_fps"):
        replace(BASE, {"recording.trajectory_fps": "2kHz"})


def test_several_particle_sets_are_refused_key_by_key():
    mixed = dataclasses.replace(BASE, particles=(ParticleSet(count=3), ParticleSet(count=4, radius=0.004)))
    with pytest.raises(InputError, match=r"'particles.radius': the case has 2 \[\[particles\]\] sets"):
        replace(mixed, {"particles.radius": 0.003})


def test_a_sampled_drive_has_no_stroke():
    sampled = dataclasses.replace(BASE, drive=SampledDrive(time=(0.0, 0.1, 0.2, 0.3), position=(0.0, 0.001, 0.0, -0.001)))
    with pytest.raises(InputError, match=r"unknown key 'stroke' in \[drive\].*kind = 'samples'"):
        replace(sampled, {"drive.stroke": 0.01})


POINTS = [{"drive.stroke": 0.013}, {"drive.stroke": 1.0}, {"contact.friction": 0.3, "drive.stroke": 0.004},
          {"particles.count": 30}, {"drive.frequency": 2.5, "particles.radius": 0.004}, {"initial.seed": 7},
          {"run.cycles": 12.0}, {"numerics.integrator": "verlet"}, {"container.width": 0.05},
          {"contact.restitution": 0.6}]


@pytest.mark.parametrize("point", POINTS, ids=[",".join(p) for p in POINTS])
def test_a_sweep_point_by_replace_is_the_one_the_config_reader_made(point):
    """The old road (Case -> config -> overrides -> reader -> Case) and replace give the same case,
    and the same config text (a store's fingerprint is taken of it)."""
    old = case_from_dict(case_to_dict(BASE), point)
    new = replace(BASE, point)
    assert new == old
    assert dumps_case(new) == dumps_case(old)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["cuboid_36", "cylinder_30", "structure_36"])
def test_every_scalar_key_of_the_examples_as_the_config_reader_read_it(name):
    """Every single-value key of each example, at a few values: replace makes the case (or the
    error) the old road made, and the same config text."""
    from pdamper.config import SECTIONS, key_spec, load_case

    base = load_case(Path(__file__).parents[1] / "examples" / f"{name}.toml")
    for section, keys in SECTIONS.items():
        for k in keys:
            try:
                spec = key_spec(f"{section}.{k}")
            except InputError:
                continue  # a table or a list: no sweep axis
            values = (list(spec.choices) if spec.choices else [3, 40] if spec.kind == "whole"
                      else [] if spec.kind == "text" else [0.0123, 1.0])
            for v in values:
                point = {f"{section}.{k}": v}
                try:
                    old = case_from_dict(case_to_dict(base), point)
                except InputError:
                    old = None
                try:
                    new = replace(base, point)
                except InputError:
                    new = None
                assert (old is None) == (new is None), point
                if old is not None:
                    assert new == old and dumps_case(new) == dumps_case(old), point


def test_a_stroke_point_is_the_one_the_stroke_road_made():
    for x in (0.5e-3, 0.013, 1.0):
        old = dataclasses.replace(BASE, drive=dataclasses.replace(BASE.drive, stroke=x))
        assert replace(BASE, {"drive.stroke": x}) == old
        assert dumps_case(replace(BASE, {"drive.stroke": x})) == dumps_case(old)


def test_with_stroke_is_a_deprecated_alias():
    from pdamper.params import with_stroke

    with pytest.deprecated_call():
        assert with_stroke(BASE, "13mm") == replace(BASE, {"drive.stroke": 0.013})


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Inner:
    gap: float = param(0.001, dimension="length")
    tag: str = param("toy", kind="tag")


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Part:
    inner: _Inner = param(default_factory=_Inner, kind="custom", inline=True)
    rate: float | None = param(None, dimension="frequency", auto=True)
    size: int = 2

    def __post_init__(self):
        if self.size < 1:
            raise InputError(f"part.size = {self.size!r}; must be >= 1")


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Root:
    part: _Part = param(default_factory=_Part, kind="custom", section="part")
    steps: int = param(5, section="run")


def test_the_walker_knows_only_the_specs():
    """A parameter tree replace has never seen: sections from the root's specs, inline keys, checks."""
    root = replace(_Root(), {"part.gap": "2mm", "part.rate": "3Hz", "part.size": 4, "run.steps": 6})
    assert root == _Root(part=_Part(inner=_Inner(gap=0.002), rate=3.0, size=4), steps=6)
    assert replace(root, {"part.rate": None}).part.rate is None
    with pytest.raises(InputError, match=r"part.size = 0; must be >= 1"):
        replace(root, {"part.size": 0})
    with pytest.raises(InputError, match=r"unknown key 'gpa' in \[part\]; did you mean 'gap'"):
        replace(root, {"part.gpa": 1})


def test_no_sweep_code_goes_through_the_config_reader():
    """Sweep points, stores, re-analysis and named studies change a case with schema.replace only."""
    reader = re.compile(r"\b(with_overrides|case_from_dict|_Reader|_apply_overrides|with_stroke)\b")
    for path in sorted((SRC / "studies").glob("*.py")):
        text = path.read_text(encoding="utf-8")
        assert not reader.search(text), f"{path.name} builds a case through the config reader"
    assert not re.search(r"\bwith_stroke\(", (SRC / "cli").joinpath("sweep.py").read_text(encoding="utf-8"))
