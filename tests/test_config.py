"""TOML config files: every key read, an exact round trip Case -> TOML -> Case, errors that help."""

import math
from pathlib import Path

import pytest

from pdamper.config import case_from_dict, case_to_dict, dump_case, dumps_case, load_case, loads_case
from pdamper.contact.cor_constant import ConstantRestitution
from pdamper.contact.cor_table import TabulatedRestitution
from pdamper.contact.cor_thornton import ThorntonRestitution
from pdamper.errors import InputError
from pdamper.excitation import HarmonicDrive, SampledDrive
from pdamper.geometry.cylinder import Cylinder
from pdamper.materials import PVC, STEEL_S235, TUNGSTEN, Material
from pdamper.params import Case, Container, ContactModel, InitialState, Numerics, ParticleSet, Recording

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
MIN = "[particles]\ncount = 3\n"


def rich_case():
    """A case with a non-default value for every field the config can hold."""
    glass = Material(name="glass", youngs_modulus=63e9, poisson_ratio=0.2, density=2500.0)
    return Case(
        particles=(ParticleSet(count=3, radius=0.004, material=glass), ParticleSet(count=2, material=TUNGSTEN)),
        container=Container(geometry=Cylinder(radius=0.05, height=0.02), material=STEEL_S235,
                            tilt=(0.01, 0.0, -math.radians(0.3)), mass=0.3),
        drive=SampledDrive(time=(0.0, 0.1, 0.2, 0.3, 0.4), position=(0.0, 1e-3, 0.0, -1e-3, 0.0),
                           velocity=(0.1, 0.0, -0.1, 0.0, 0.1), frequency=2.5, angle=0.3),
        contact=ContactModel(friction=0.2, restitution=TabulatedRestitution(speeds=(0.1, 1.0), values=(0.95, 0.8)),
                             tau=500.0, v_in_floor=2e-3, damping="gonthier",
                             pair_friction={("glass", "steel"): 0.3},
                             pair_restitution={("glass", "steel"): ThorntonRestitution(yield_pressure=1e9),
                                               ("tungsten", "glass"): ConstantRestitution(value=0.7)}),
        numerics=Numerics(integrator="gear", time_step=1e-6, steps_per_contact=20, max_impact_speed=0.5,
                          max_time_step=2e-5, gear_tolerance=1e-9, neighbour_search="cells", skin=1e-3,
                          overlap_limit=0.1),
        recording=Recording(sample_rate=2000.0, trajectory_fps=50.0),
        initial=InitialState(arrangement="scatter", jitter=0.0, seed=7, settle_time=0.0, layers="auto",
                             positions=((0.0, 0.005, 0.0),) * 5, velocities=((0.1, 0.0, 0.0),) * 5,
                             spins=((0.0, 0.0, 1.0),) * 5),
        cycles=3.5, drop_cycles=1, gravity=9.0)


# --------------------------------------------------------------------------- round trip

@pytest.mark.parametrize("case", [
    Case(particles=(ParticleSet(count=36),)),
    Case(particles=(ParticleSet(count=8),), drive=HarmonicDrive(stroke=math.radians(0.7) / 3, frequency=2.7,
                                                                 angle=math.pi / 7), cycles=3, drop_cycles=1),
    rich_case(),
], ids=["paper-defaults", "odd-floats", "every-field"])
def test_round_trip_case_dict_toml_case_is_exact(case, tmp_path):
    assert case_from_dict(case_to_dict(case)) == case
    path = dump_case(case, tmp_path / "config.toml")
    assert load_case(path) == case
    # and writing the re-read case gives the same text again
    assert dumps_case(load_case(path)) == path.read_text(encoding="utf-8")


def test_dump_is_atomic_and_commented(tmp_path):
    path = dump_case(Case(particles=(ParticleSet(count=4),)), tmp_path / "c.toml")
    text = path.read_text(encoding="utf-8")
    assert text.startswith("# pdamper case configuration")
    assert "SI units" in text
    assert [p.name for p in tmp_path.iterdir()] == ["c.toml"]  # no temporary file left behind


# --------------------------------------------------------------------------- reading

def test_minimal_config_gives_the_paper_defaults():
    assert loads_case(MIN) == Case(particles=(ParticleSet(count=3),))


def test_units_and_plain_si_read_the_same():
    with_units = loads_case(MIN + '[drive]\nstroke = "12mm"\nfrequency = "120/min"\nangle = "90deg"\n'
                                  '[container]\nlength = "12cm"\nmass = "149g"\ntilt = "0.5deg"\n'
                                  '[run]\ngravity = "981cm/s^2"\n')
    plain = loads_case(MIN + "[drive]\nstroke = 0.012\nfrequency = 2\nangle = 1.5707963267948966\n"
                             "[container]\nlength = 0.12\nmass = 0.149\ntilt = [0.008726646259971648, "
                             "0.008726646259971648, 0.008726646259971648]\n[run]\ngravity = 9.81\n")
    assert with_units.drive.stroke == pytest.approx(plain.drive.stroke, rel=1e-14)
    assert with_units.drive.frequency == pytest.approx(2.0, rel=1e-14)
    assert with_units.drive.angle == pytest.approx(math.pi / 2, rel=1e-14)
    assert with_units.container.geometry.length == pytest.approx(0.12, rel=1e-14)
    assert with_units.container.mass == pytest.approx(0.149, rel=1e-14)
    assert with_units.container.tilt == pytest.approx(plain.container.tilt, rel=1e-14)
    assert with_units.gravity == pytest.approx(9.81, rel=1e-14)


def test_every_key_is_read():
    text = """
[container]
shape = "cylinder"
radius = "39mm"
height = "11mm"
material = {name = "acrylic", youngs_modulus = "3.2GPa", poisson_ratio = 0.37, density = "1190kg/m^3"}
tilt = ["0.1deg", "0deg", "-0.2deg"]
mass = "0.5kg"

[[particles]]
count = 10
radius = "4mm"
material = "tungsten"

[[particles]]
count = 5

[drive]
stroke = "7mm"
frequency = "3Hz"
angle = "30deg"

[contact]
friction = 0.15
restitution = {law = "thornton", yield_pressure = "1.5GPa"}
tau = 2000
v_in_floor = "2mm/s"
damping = "gonthier"

[[contact.pair]]
materials = ["steel", "acrylic"]
friction = 0.2
restitution = 0.8

[[contact.pair]]
materials = ["tungsten", "steel"]
restitution = {law = "table", speeds = ["10mm/s", "1m/s"], values = [0.95, 0.85]}

[numerics]
integrator = "gear"
time_step = "2us"
steps_per_contact = 20
max_impact_speed = "0.5m/s"
max_time_step = "5us"
gear_tolerance = "1nm"
neighbour_search = "cells"
skin = "1mm"
overlap_limit = 0.1

[recording]
sample_rate = "2kHz"
trajectory_fps = "25Hz"

[initial]
arrangement = "scatter"
jitter = "0.2mm"
seed = 4
settle_time = "50ms"
layers = "auto"

[run]
cycles = 6
drop_cycles = 1
gravity = "9.80665m/s^2"
"""
    c = loads_case(text)
    g = c.container.geometry
    assert (g.shape, g.radius, g.height) == ("cylinder", pytest.approx(0.039), pytest.approx(0.011))
    assert c.container.material.name == "acrylic"
    assert c.container.material.youngs_modulus == pytest.approx(3.2e9)
    assert c.container.material.density == pytest.approx(1190)
    assert c.container.tilt == pytest.approx((math.radians(0.1), 0.0, math.radians(-0.2)))
    assert c.container.mass == pytest.approx(0.5)
    assert [p.count for p in c.particles] == [10, 5]
    assert c.particles[0].material == TUNGSTEN and c.particles[0].radius == pytest.approx(0.004)
    assert c.particles[1].material == STEEL_S235 and c.particles[1].radius == 0.005
    d = c.drive
    assert isinstance(d, HarmonicDrive)
    assert (d.stroke, d.frequency, d.angle) == (pytest.approx(0.007), 3.0, pytest.approx(math.pi / 6))
    ct = c.contact
    assert ct.friction == 0.15 and ct.tau == 2000 and ct.v_in_floor == pytest.approx(2e-3)
    assert ct.damping == "gonthier"
    assert isinstance(ct.restitution, ThorntonRestitution)
    assert ct.restitution.yield_pressure == pytest.approx(1.5e9)
    assert ct.friction_for("acrylic", "steel") == 0.2
    assert ct.restitution_for("acrylic", "steel") == ConstantRestitution(value=0.8)
    assert ct.friction_for("tungsten", "steel") == 0.15
    law = ct.restitution_for("steel", "tungsten")
    assert isinstance(law, TabulatedRestitution) and law.speeds == pytest.approx((0.01, 1.0))
    n = c.numerics
    assert (n.integrator, n.steps_per_contact, n.neighbour_search, n.overlap_limit) == ("gear", 20, "cells", 0.1)
    assert n.time_step == pytest.approx(2e-6) and n.max_time_step == pytest.approx(5e-6)
    assert n.max_impact_speed == pytest.approx(0.5) and n.gear_tolerance == pytest.approx(1e-9)
    assert n.skin == pytest.approx(1e-3)
    assert c.recording == Recording(sample_rate=2000.0, trajectory_fps=25.0)
    i = c.initial
    assert (i.arrangement, i.seed, i.layers) == ("scatter", 4, "auto")
    assert i.jitter == pytest.approx(2e-4) and i.settle_time == pytest.approx(0.05)
    assert (c.cycles, c.drop_cycles) == (6, 1) and c.gravity == pytest.approx(9.80665)


def test_auto_values_and_explicit_positions():
    c = loads_case(MIN + '[numerics]\ntime_step = "auto"\nskin = "auto"\nmax_impact_speed = "auto"\n'
                         '[initial]\npositions = [[0, "5.001mm", 0], ["20mm", "5.001mm", 0], [-0.02, 0.005001, 0]]\n'
                         'velocities = [["1cm/s", 0, 0], [0, 0, 0], [0, 0, 0]]\nspins = [[0, 0, "10rad/s"], '
                         '[0, 0, 0], [0, 0, 0]]\n')
    assert c.numerics.time_step is None and c.numerics.skin is None and c.numerics.max_impact_speed is None
    assert c.initial.positions[1] == pytest.approx((0.02, 0.005001, 0.0))
    assert c.initial.velocities[0] == pytest.approx((0.01, 0.0, 0.0))
    assert c.initial.spins[0] == (0.0, 0.0, 10.0)


def test_sampled_drive_from_inline_arrays_and_from_a_csv_file(tmp_path):
    inline = loads_case(MIN + '[drive]\ntime = ["0ms", "10ms", "20ms", "30ms", "40ms"]\n'
                              'position = ["0mm", "1mm", "0mm", "-1mm", "0mm"]\nfrequency = "25Hz"\n')
    assert isinstance(inline.drive, SampledDrive)
    assert inline.drive.time == pytest.approx((0.0, 0.01, 0.02, 0.03, 0.04))
    assert inline.drive.position == pytest.approx((0.0, 1e-3, 0.0, -1e-3, 0.0))
    (tmp_path / "motion.csv").write_text("# a measured motion\ntime [ms],position [mm],velocity [mm/s]\n"
                                         "0,0,100\n10,1,0\n20,0,-100\n30,-1,0\n40,0,100\n")
    (tmp_path / "case.toml").write_text(MIN + '[drive]\nsamples = "motion.csv"\nfrequency = "25Hz"\n')
    from_file = load_case(tmp_path / "case.toml")  # the path is relative to the config file
    assert from_file.drive.time == pytest.approx(inline.drive.time)
    assert from_file.drive.position == pytest.approx(inline.drive.position)
    assert from_file.drive.velocity == pytest.approx((0.1, 0.0, -0.1, 0.0, 0.1))
    assert from_file.drive.frequency == 25.0
    # the dumped config holds the samples themselves, so a run directory needs no other file
    assert load_case(dump_case(from_file, tmp_path / "again.toml")) == from_file


def test_overrides_replace_and_add_values():
    text = MIN + '[drive]\nstroke = "12mm"\n[run]\ncycles = 20\n'
    c = loads_case(text, {"drive.stroke": 0.004, "drive.frequency": "3Hz", "run.cycles": 5, "initial.seed": 3,
                          "numerics.integrator": "gear", "particles.count": 8})
    assert c.drive.stroke == 0.004 and c.drive.frequency == pytest.approx(3.0)
    assert (c.cycles, c.initial.seed, c.numerics.integrator, c.n_particles) == (5, 3, "gear", 8)
    assert loads_case(text) == Case(particles=(ParticleSet(count=3),))  # the overrides did not leak


@pytest.mark.parametrize("name", ["cuboid_36", "cuboid_44", "cylinder_30", "cylinder_42"])
def test_examples_load_with_the_papers_values(name):
    c = load_case(EXAMPLES / f"{name}.toml")
    shape, n = name.split("_")
    assert c.n_particles == int(n)
    assert c.container.geometry.shape == shape
    g = c.container.geometry
    if shape == "cuboid":
        assert (g.length, g.width, g.height) == pytest.approx((0.12, 0.0404, 0.04))
    else:
        assert (g.radius, g.height) == pytest.approx((0.039, 0.011))
    assert c.container.material == PVC
    assert c.particles[0].material == STEEL_S235 and c.particles[0].radius == pytest.approx(0.005)
    assert c.container.tilt == pytest.approx((math.radians(0.1),) * 3)
    assert c.contact.friction == 0.1 and c.contact.restitution == ConstantRestitution(value=0.9)
    assert c.drive.frequency == 2.0
    assert c.drive.stroke == pytest.approx(0.013 if n in ("36", "30") else 0.0045)
    assert (c.cycles, c.drop_cycles, c.gravity) == (20, 2, pytest.approx(9.81))


def test_examples_starting_positions_are_valid():
    import numpy as np

    from pdamper.initial import initial_positions

    from pdamper.structure.opensees import available

    for path in sorted(EXAMPLES.glob("*.toml")):
        if "opensees" in path.read_text() and available() is not None:
            continue  # an OpenSees model: tests/structure/test_opensees.py, where openseespy loads
        c = load_case(path)
        assert initial_positions(c, np.random.default_rng(0)).shape == (c.n_particles, 3), path.name


# --------------------------------------------------------------------------- errors

@pytest.mark.parametrize("text, words", [
    (MIN + '[drive]\nstroek = "12mm"\n', ["unknown key 'stroek' in [drive]", "did you mean 'stroke'?"]),
    (MIN + '[drvie]\nstroke = "12mm"\n', ["unknown section [drvie]", "did you mean [drive]?"]),
    (MIN + '[numerics]\nintergrator = "gear"\n', ["unknown key 'intergrator' in [numerics]", "'integrator'"]),
    (MIN + '[drive]\nwhatever = 1\n', ["unknown key 'whatever' in [drive]", "allowed keys", "stroke"]),
    (MIN + '[drive]\nstroke = "2Hz"\n', ["[drive] stroke = '2Hz' is not a length"]),
    (MIN + '[container]\ntilt = ["1deg", "2mm", 0]\n', ["[container] tilt[1] = '2mm' is not an angle"]),
    (MIN + '[run]\ngravity = "fast"\n', ["[run] gravity", "cannot read 'fast'"]),
    (MIN + "[drive]\nstroke = [1, 2]\n", ["[drive] stroke", "not a list"]),
    ('[particles]\ncount = "many"\n', ["[particles] count = 'many' must be a whole number"]),
    ("[particles]\ncount = 3.5\n", ["[particles] count = 3.5 must be a whole number"]),
    ('[particles]\nradius = "5mm"\n', ["[particles] count is missing"]),
    ('[drive]\nstroke = "5mm"\n', ["missing section [particles]"]),
    ("drive = 3\n" + MIN, ["[drive] must be a table"]),
    (MIN + '[numerics]\nintegrator = "verlett"\n', ["[numerics] integrator = 'verlett'", "did you mean 'verlet'?"]),
    (MIN + "[numerics]\nintegrator = 3\n", ["[numerics] integrator = 3 must be a string"]),
    (MIN + 'material = "steal"\n', ["[particles] material = 'steal' is not a known material",
                                    "did you mean 'steel'?"]),
    (MIN + 'material = {youngs_modulus = "1GPa", density = 1000}\n', ["[particles.material] poisson_ratio is missing"]),
    (MIN + '[container]\nradius = "3cm"\n', ["[container] radius applies to shape = 'cylinder'"]),
    (MIN + '[container]\ntilt = ["1deg", "2deg"]\n', ["[container] tilt", "three angles"]),
    (MIN + '[contact]\nrestitution = {law = "thorton", yield_pressure = "1GPa"}\n',
     ["law = 'thorton' is unknown", "did you mean 'thornton'?"]),
    (MIN + "[contact]\nrestitution = {law = \"table\", speeds = [1, 2]}\n", ["law = 'table' needs 'values'"]),
    (MIN + "[contact]\nrestitution = 1.5\n", ["[contact] restitution = 1.5", "(0, 1]"]),
    (MIN + '[[contact.pair]]\nmaterials = ["steel", "pcv"]\nfriction = 0.2\n',
     ["'pcv' is not a material of this case", "did you mean 'pvc'?"]),
    (MIN + '[[contact.pair]]\nmaterials = ["steel", "pvc"]\nfricton = 0.2\n',
     ["unknown key 'fricton' in [contact.pair #1]", "did you mean 'friction'?"]),
    (MIN + '[[contact.pair]]\nmaterials = ["steel", "pvc"]\nfriction = 0.2\n[[contact.pair]]\n'
           'materials = ["pvc", "steel"]\nfriction = 0.3\n', ["given twice"]),
    (MIN + '[drive]\nstroke = "1mm"\ntime = [0, 1, 2, 3]\nposition = [0, 1, 0, 1]\n', ["not a mix"]),
    (MIN + '[drive]\ntime = [0, 1, 2, 3]\n', ["needs 'position'"]),
    (MIN + '[drive]\nsamples = "no_such_file.csv"\n', ["[drive] samples", "file not found", "no_such_file.csv"]),
    (MIN + '[drive]\nstroke = "-1mm"\n', ["[drive] stroke", "must be > 0"]),
    (MIN + "[run]\ncycles = 2\n", ["[run] cycles", "nothing after dropping 2 cycles"]),
    (MIN + "[run]\ngravity = true\n", ["[run] gravity", "expected an acceleration"]),
    (MIN + 'material = {name = "pvc", youngs_modulus = "1GPa", poisson_ratio = 0.3, density = 1000}\n',
     ["two different materials are both named 'pvc'"]),
    ("[particles]\ncount = \n", ["invalid TOML", "line 2"]),
    ("[particles\ncount = 3\n", ["invalid TOML", "line 1"]),
])
def test_errors_name_the_file_section_key_and_a_fix(text, words):
    with pytest.raises(InputError) as info:
        loads_case(text, source="case.toml")
    msg = str(info.value)
    assert msg.startswith("case.toml: ")
    assert "\n" not in msg
    for w in words:
        assert w in msg, f"{w!r} not in {msg!r}"


@pytest.mark.parametrize("overrides, words", [
    ({"drive.stroek": 0.01}, ["unknown key 'stroek' in [drive]", "did you mean 'stroke'?"]),
    ({"drve.stroke": 0.01}, ["unknown section [drve]", "did you mean [drive]?"]),
    ({"stroke": 0.01}, ["'section.key'"]),
    ({"drive.stroke": "2Hz"}, ["[drive] stroke = '2Hz' is not a length"]),
])
def test_override_errors(overrides, words):
    with pytest.raises(InputError) as info:
        loads_case(MIN, overrides)
    for w in words:
        assert w in str(info.value)


def test_stroke_override_on_a_sampled_drive_is_refused():
    text = MIN + "[drive]\ntime = [0, 0.1, 0.2, 0.3]\nposition = [0, 0.001, 0, -0.001]\n"
    with pytest.raises(InputError, match="harmonic drive only"):
        loads_case(text, {"drive.stroke": 0.01})


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(InputError, match="config file not found"):
        load_case(tmp_path / "nope.toml")
    with pytest.raises(InputError, match="is a directory"):
        load_case(tmp_path)


def test_syntax_error_names_the_file(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text("[particles]\ncount = 3\n[drive]\nstroke = 12mm\n")
    with pytest.raises(InputError) as info:
        load_case(p)
    assert str(p) in str(info.value) and "line 4" in str(info.value)
