"""Coated walls: a material per wall, its stiffness in the contact table, its own restitution."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.config import case_from_dict, case_to_dict, loads_case
from pdamper.engine.build import build
from pdamper.errors import InputError
from pdamper.geometry import Cuboid
from pdamper.materials import LIBRARY, PVC, SILICONE, STEEL_S235, Material, effective_modulus
from pdamper.params import Container

from .dem_fixtures import R, run, still_case


def test_each_wall_gets_the_stiffness_of_its_own_material():
    case = still_case([(0.0, 0.05, 0.0)], [(0.0, 0.0, 0.0)], duration=0.01, wall_materials={"x_min": SILICONE})
    e = build(case)
    names = list(e.wall_names)
    k_coated = e.walls.stiffness[0, names.index("x_min")]
    k_plain = e.walls.stiffness[0, names.index("x_max")]
    assert k_coated == pytest.approx(4 / 3 * effective_modulus(STEEL_S235, SILICONE) * math.sqrt(R), rel=1e-12)
    assert k_plain == pytest.approx(4 / 3 * effective_modulus(STEEL_S235, PVC) * math.sqrt(R), rel=1e-12)


@pytest.mark.parametrize("coating_eps", [0.5, 0.7])
def test_a_coating_with_its_own_restitution_sends_the_sphere_back_slower(coating_eps):
    # weightless, frictionless: a sphere flies at 0.2 m/s into the x_min wall (box 200 mm long)
    coat = Material(name="coat", youngs_modulus=50e6, poisson_ratio=0.45, density=1200.0, restitution=coating_eps)
    case = still_case([(-0.06, 0.05, 0.0)], [(-0.2, 0.0, 0.0)], duration=0.4, eps=0.9, wall_materials={"x_min": coat})
    sim, res = run(case)
    v_back = sim.bodies.velocity[0, 0]
    assert v_back == pytest.approx(0.2 * coating_eps, rel=0.02)
    assert res.energy.balance_error() < 1e-3


def test_wall_materials_are_read_by_wall_name_and_checked():
    case = loads_case("""
[container]
wall_materials = {x_min = "silicone", x_max = {name = "pu60", youngs_modulus = "60MPa", poisson_ratio = 0.47, density = "1200kg/m^3", restitution = 0.6}}
[particles]
count = 12
""")
    wm = case.container.wall_materials
    assert wm["x_min"] == LIBRARY["silicone"] and wm["x_max"].restitution == 0.6
    assert case_from_dict(case_to_dict(case)) == case
    with pytest.raises(InputError, match="did you mean 'x_min'"):
        Container(geometry=Cuboid(), wall_materials={"xmin": SILICONE})
    with pytest.raises(InputError, match="restitution"):
        Material(name="bad", youngs_modulus=1e6, poisson_ratio=0.4, density=1000.0, restitution=1.5)


def test_the_automatic_step_follows_the_stiffest_wall():
    from pdamper.engine.build import auto_time_step
    import dataclasses

    # soft (PVC) spheres: the sphere pair limits the step in a PVC box, a steel floor limits it more
    base = still_case([(0.0, 0.05, 0.0)], [(0.1, 0.0, 0.0)], duration=0.01, material=PVC)
    base = dataclasses.replace(base, numerics=dataclasses.replace(base.numerics, time_step=None))
    steel_wall = dataclasses.replace(base, container=dataclasses.replace(base.container,
                                                                         wall_materials={"floor": STEEL_S235}))
    assert auto_time_step(steel_wall) < auto_time_step(base)
    assert np.isfinite(auto_time_step(steel_wall))
