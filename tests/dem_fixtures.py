"""Small DEM set-ups shared by the physics tests (one or two spheres, still container)."""

from __future__ import annotations

import math

import numpy as np

from pdamper.contact import ConstantRestitution
from pdamper.excitation import Still
from pdamper.geometry import Cuboid
from pdamper.materials import PVC, STEEL_S235
from pdamper.params import Case, ContactModel, Container, InitialState, Numerics, ParticleSet, Recording
from pdamper.simulation import Simulation
from pdamper.config import loads_case

R = 0.005
BOX = Cuboid(length=0.2, width=0.1, height=0.1)


def still_case(positions, velocities, *, duration, eps=0.9, mu=0.0, gravity=0.0, dt=None, sample_rate=None,
               tilt=(0.0, 0.0, 0.0), spins=None, container=BOX, tau=1000.0, steps_per_contact=15, drive=None,
               integrator="verlet", material=STEEL_S235, wall=PVC, baffles=(), wall_materials=None):
    pos = np.asarray(positions, dtype=float)
    n = len(pos)
    rec = Recording(sample_rate=sample_rate) if sample_rate else Recording(sample_rate=max(1000.0, 10.0 / duration))
    num = Numerics(time_step=dt, steps_per_contact=steps_per_contact, max_impact_speed=1.0, integrator=integrator)
    return Case(
        particles=(ParticleSet(count=n, radius=R, material=material),),
        container=Container(geometry=container, material=wall, tilt=tilt, baffles=baffles,
                            wall_materials=wall_materials or {}),
        drive=drive if drive is not None else Still(duration_s=duration),
        contact=ContactModel(friction=mu, restitution=ConstantRestitution(value=eps), tau=tau),
        numerics=num, recording=rec,
        initial=InitialState(positions=tuple(map(tuple, pos)), velocities=tuple(map(tuple, velocities)),
                             spins=None if spins is None else tuple(map(tuple, spins)), settle_time=0.0, jitter=0.0),
        cycles=1, drop_cycles=0, gravity=gravity)


def run(case):
    """Simulate ``case`` (its recorders' results, no analysis); the simulation keeps the end state."""
    sim = Simulation(case)
    res = sim.run()
    return sim, res


def sphere_mass(material=STEEL_S235, r=R):
    return material.density * 4.0 / 3.0 * math.pi * r**3


#: A tiny damper case (8 spheres, 3 cycles, 1 dropped) for CLI and sweep tests: a few seconds a run.
TINY_CONFIG = """\
# a tiny case for the CLI and sweep tests
[particles]
count = 8

[drive]
stroke = "13mm"
frequency = "2Hz"

[initial]
settle_time = "50ms"

[run]
cycles = 3
drop_cycles = 1
"""


ROW = 6  # spheres in the row


def locked_case(load: str, *, structure: str = 'mass = "2kg"\nnatural_frequency = "3Hz"\ndamping_ratio = 0.02',
                text: bool = False):
    """A locked bed on a structure under ``load`` (the lines of a ``[load]`` table): a row of ROW
    spheres wall to wall along the drive, touching at rest (tests/studies/test_transient.py); the
    case, or with ``text`` its config text."""
    length = 2 * 0.005 * ROW
    pos = [[-length / 2 + 0.005 + 0.01 * i, 0.005, 0.0] for i in range(ROW)]
    toml = f"""
[container]
shape = "cuboid"
length = {length!r}
width = 0.0101
height = 0.011
material = "pvc"
tilt = 0.0
[particles]
count = {ROW}
radius = "5mm"
material = "steel"
[contact]
friction = 0.5
[initial]
positions = {pos!r}
settle_time = 0.05
jitter = 0
[structure]
{structure}
[load]
{load}
"""
    return toml if text else loads_case(toml)
