"""The one schema (pdamper.schema): every parameter field is a config key read and written from
its own spec, and the one override mechanism (pdamper.config.with_overrides) reaches every key."""

import dataclasses
import math
from pathlib import Path

import pytest

from pdamper.config import SECTIONS, _fields_to, _Reader, case_to_dict, with_overrides
from pdamper.contact.cor_thornton import ThorntonRestitution
from pdamper.errors import InputError
from pdamper.excitation import HarmonicDrive
from pdamper.structure import CoupledStructure
from pdamper.geometry.cuboid import Cuboid
from pdamper.materials import Material
from pdamper.params import Case, Container, ContactModel, InitialState, Numerics, ParticleSet, Recording
from pdamper.schema import Spec, check_choice, config_keys, param, plain_fields, spec_of
from pdamper.units import DIMENSIONS

BASE = Case(particles=(ParticleSet(count=3),))
STRUCTURE = dataclasses.replace(BASE, drive=CoupledStructure(
    mass=7.0, stiffness=1105.0, displacement=0.01, force_amplitude=0.5, force_frequency=2.0))

# (section, class, the object of BASE/STRUCTURE holding the class's fields)
HOLDERS = [
    ("container", Cuboid, lambda c: c.container.geometry),
    ("container", Container, lambda c: c.container),
    ("particles", ParticleSet, lambda c: c.particles[0]),
    ("drive", HarmonicDrive, lambda c: c.drive),
    ("contact", ContactModel, lambda c: c.contact),
    ("numerics", Numerics, lambda c: c.numerics),
    ("recording", Recording, lambda c: c.recording),
    ("initial", InitialState, lambda c: c.initial),
    ("run", Case, lambda c: c),
    ("structure", CoupledStructure, lambda c: c.drive),
]
SCALARS = [(section, cls, get, f, s) for section, cls, get in HOLDERS for f, s in plain_fields(cls)
           if s.kind in ("number", "whole") and s.choices is None]


#: The Case field that holds the dataclass of a section with optional (None) scalar keys.
_FIELD = {"structure": "drive"}


def _base(cls):
    return STRUCTURE if cls is CoupledStructure else BASE


def test_every_section_key_comes_from_a_field_or_is_named_structure():
    """The sections are the dataclasses' fields; the few keys that are not fields are structure."""
    # ([[damper]] node: where a damper sits on an OpenSees model, the structure's damper_nodes)
    structural = {"shape", "kind", "samples", "pair", "natural_frequency", "node"}
    fields = {s.key or f.name for _, cls, _ in HOLDERS for f in dataclasses.fields(cls) for s in (spec_of(f),)}
    fields |= {s.key or f.name for cls in (Material,) for f in dataclasses.fields(cls) for s in (spec_of(f),)}
    from pdamper.excitation import SampledDrive, Still
    from pdamper.structure import ModalStructure, OpenSeesStructure
    from pdamper.geometry.cylinder import Cylinder
    from pdamper.params import Damper
    fields |= (set(config_keys(SampledDrive)) | set(config_keys(Still)) | set(config_keys(Cylinder))
               | set(config_keys(ModalStructure)) | set(OpenSeesStructure.table_keys()) | set(config_keys(Damper)))
    from pdamper.structure.loads import LOADS
    fields |= {k for cls in LOADS.values() for k in cls.table_keys()}
    for section, keys in SECTIONS.items():
        for key in keys:
            assert key in fields or key in structural, f"[{section}] {key} is neither a field nor structure"


@pytest.mark.parametrize("section, cls, get, f, s", SCALARS, ids=[f"{x[0]}.{x[3].name}" for x in SCALARS])
def test_every_scalar_field_is_overridden_with_its_unit_and_written_back(section, cls, get, f, s):
    base = _base(cls)
    key = f"{section}.{s.key or f.name}"
    old = getattr(get(base), f.name)
    new = 2 * old if old else (3 if s.kind == "whole" else 0.25)
    if s.kind == "whole" or s.dimension is None:
        text = new
    else:
        text = f"{new!r} {DIMENSIONS[s.dimension]}".strip()
    case = with_overrides(base, {key: text})
    assert getattr(get(case), f.name) == new
    # nothing else moved, bit for bit
    if old is None and section in _FIELD:  # an optional key (structure.storey_height): left out is the way back
        holder = dataclasses.replace(get(case), **{f.name: None})
        back = dataclasses.replace(case, **{_FIELD[section]: holder})
        assert back == base
    else:
        assert with_overrides(case, {key: old}) == base
    # the writer uses the same key
    table = case_to_dict(case)[section]
    assert (table if isinstance(table, dict) else table[0])[s.key or f.name] == new


def test_overrides_take_parameter_objects_and_equal_dataclasses_replace():
    steel_mod = Material(name="steel-mod", youngs_modulus=405e9, poisson_ratio=0.3, density=7900.0)
    tilt = (math.radians(0.1), math.radians(3.0), math.radians(0.1))
    case = with_overrides(BASE, {"particles.material": steel_mod, "container.tilt": tilt,
                                 "contact.restitution": ThorntonRestitution(yield_pressure=2e9),
                                 "contact.friction": 1.0})
    expected = dataclasses.replace(
        BASE, particles=(dataclasses.replace(BASE.particles[0], material=steel_mod),),
        container=dataclasses.replace(BASE.container, tilt=tilt),
        contact=dataclasses.replace(BASE.contact, restitution=ThorntonRestitution(yield_pressure=2e9), friction=1.0))
    assert case == expected


def test_override_errors_name_the_key_and_a_fix():
    with pytest.raises(InputError, match=r"\[numerics\] integrator = 'verlett' is not allowed; did you mean 'verlet'"):
        with_overrides(BASE, {"numerics.integrator": "verlett"})
    with pytest.raises(InputError, match=r"unknown key 'stroek' in \[drive\]; did you mean 'stroke'"):
        with_overrides(BASE, {"drive.stroek": 0.01})
    with pytest.raises(InputError, match=r"\[drive\] stroke.*\(paper: 3-50 mm\)"):
        with_overrides(BASE, {"drive.stroke": "3s"})
    with pytest.raises(InputError, match=r"\[particles\] radius.*a length.*\(paper: 5 mm\)"):
        with_overrides(BASE, {"particles.radius": "5kg"})


@dataclasses.dataclass(frozen=True, kw_only=True)
class _Demo:
    """A parameter class a contributor might add: every kind of field, declared once."""

    gap: float = param(0.001, dimension="length")
    rate: float | None = param(None, dimension="frequency", auto=True)
    count: int = 4
    law: str = param("a", choices=("alpha", "beta", "a"))
    times: tuple = param((), kind="list", dimension="time")
    points: tuple | None = param(None, kind="rows", dimension="length", example="'5mm'")
    label: str = param("x", kind="text")
    ratio: float = 0.5
    tag: str = param("demo", kind="tag")
    other: object = param(None, kind="custom")


def test_a_new_field_is_read_written_and_checked_from_its_spec_alone():
    reader = _Reader(Path.cwd())
    table = {"gap": "2mm", "rate": "auto", "count": 7, "law": "beta", "times": ["1ms", 0.5],
             "points": [["1mm", 0, 0]], "label": "y", "ratio": 0.25}
    demo = _Demo(**reader.fields(table, "demo", _Demo))
    assert demo == _Demo(gap=0.002, rate=None, count=7, law="beta", times=(0.001, 0.5), points=((0.001, 0.0, 0.0),),
                         label="y", ratio=0.25)
    written = _fields_to(demo)
    assert written["tag"] == "demo" and "other" not in written and written["rate"] == "auto"
    assert _Demo(**reader.fields(written, "demo", _Demo)) == demo
    with pytest.raises(InputError, match=r"\[demo\] gap = '2s'"):
        reader.fields({"gap": "2s"}, "demo", _Demo)
    with pytest.raises(InputError, match=r"did you mean 'alpha'"):
        reader.fields({"law": "alpah"}, "demo", _Demo)
    with pytest.raises(InputError, match=r"\[demo\] count = 2.5 must be a whole number"):
        reader.fields({"count": 2.5}, "demo", _Demo)


def test_spec_kinds_and_choice_messages():
    kinds = {f.name: spec_of(f).kind for f in dataclasses.fields(_Demo)}
    assert kinds == {"gap": "number", "rate": "number", "count": "whole", "law": "text", "times": "list",
                     "points": "rows", "label": "text", "ratio": "number", "tag": "tag", "other": "custom"}
    with pytest.raises(ValueError, match="Spec kind"):
        Spec(kind="vector")
    with pytest.raises(InputError, match=r"demo.law = 'bta'; did you mean 'beta'\? choose 'alpha', 'beta' or 'a'"):
        check_choice(_Demo(law="bta"), "law", "demo")
    check_choice(_Demo(law="beta"), "law", "demo")  # allowed: no error


def test_every_number_field_of_a_parameter_class_says_its_unit_or_is_a_ratio():
    """A physical quantity must declare its dimension (or unit) so configs can give it with units."""
    ratios = {"friction", "poisson_ratio", "damping_ratio", "overlap_limit", "cycles"}
    for _, cls, _ in HOLDERS + [(None, Material, None)]:
        for f, s in plain_fields(cls):
            if s.kind == "number" and s.dimension is None and s.unit is None:
                assert f.name in ratios, f"{cls.__name__}.{f.name}: give param(dimension=...) or unit=..."


def test_docs_name_every_key_and_every_choice():
    """docs/config.md documents each section's keys and each allowed value (they come from the fields)."""
    import re

    text = (Path(__file__).parents[1] / "docs" / "config.md").read_text(encoding="utf-8")
    for section, keys in SECTIONS.items():
        start = text.index(f"### `[{section}]")
        end = text.find("\n### ", start + 4)
        body = text[start:end if end > 0 else None]
        for key in keys:
            assert re.search(r"`(\[\[contact\.)?%s\b" % re.escape(key), body), f"[{section}] {key} is not in docs/config.md"
    for section, cls, _ in HOLDERS:
        for f, s in plain_fields(cls):
            for choice in s.choices or ():
                assert f'"{choice}"' in text, f"{section}.{f.name} = {choice!r} is not in docs/config.md"
