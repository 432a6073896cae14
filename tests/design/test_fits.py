"""One rule for what fits (issue 39, item 4): the design's largest filling and the run's initial
packing come from one function, :func:`pdamper.initial.floor_capacity`.

Before, ``design --length 160mm --width 60mm`` offered "82 of 96" (the floor lattice counted
floor(W / 2r) = 6 spheres across) while ``run`` refused more than 80 (its packing put 5 across a
width of exactly 6 diameters); and the paper's cylinder was offered up to 47 spheres of which a
run places 44.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from pdamper.cli.common import main
from pdamper.design import design_filling
from pdamper.design.filling import most_spheres
from pdamper.design.search import _candidates
from pdamper.errors import InputError
from pdamper.geometry import Cuboid, Cylinder
from pdamper.initial import floor_capacity, initial_positions
from pdamper.params import Case, Container, ParticleSet

R = 0.005
SPHERE = 7900.0 * 4.0 / 3.0 * math.pi * R**3
SHAPES = [Cuboid(length=0.16, width=0.06), Cuboid(), Cuboid(length=0.12, width=0.04), Cuboid(length=0.125, width=0.045),
          Cylinder()]


def _placed(geo, n):
    case = Case(particles=(ParticleSet(count=n, radius=R),), container=Container(geometry=geo), cycles=1,
                drop_cycles=0)
    return initial_positions(case, np.random.default_rng(0))


@pytest.mark.parametrize("geo", SHAPES, ids=lambda g: g.describe())
def test_the_design_offers_no_filling_that_a_run_refuses(geo):
    fits = floor_capacity(Container(geometry=geo), R)
    n_max = geo.clearance_capacity(R)
    # the run: the whole floor is placed in one layer, one sphere more is refused naming the count
    assert len(_placed(geo, fits)) == fits
    with pytest.raises(InputError, match=f"at most {fits}"):
        _placed(geo, fits + 1)
    top = most_spheres(geo, R, n_max)
    assert top == min(fits, n_max - 1)
    # the design for a stroke: the smallest stroke asks for the most spheres, and gets what fits
    d = design_filling(frequency=2.0, stroke=1e-5, sphere_radius=R, container=geo)
    assert d.particles == top and any("too small" in w for w in d.warnings)
    with pytest.raises(InputError, match=f"only {fits} spheres fit" if fits < n_max - 1 else "give a filling"):
        design_filling(frequency=2.0, stroke=0.01, sphere_radius=R, container=geo, particles=top + 1)
    # the design for a structure: its candidates stop there too
    cands = _candidates(geo, np.array([geo.drive_length]), R, SPHERE, math.inf, (1, math.inf))
    assert max(c.particles for c in cands) == top
    assert len(_placed(geo, top)) == top


def test_the_issue_s_container_holds_six_spheres_across_in_design_and_run():
    # 160 x 60 mm: exactly 6 diameters across, as exactly 16 along: the packing fits both
    geo = Cuboid(length=0.16, width=0.06)
    assert floor_capacity(Container(geometry=geo), R) == 96 == geo.clearance_capacity(R)
    assert geo.row_capacity(R) == 6
    out = CliRunner().invoke(main, ["design", "--length", "160mm", "--width", "60mm", "--frequency", "2Hz",
                                    "--stroke", "2mm", "--sphere-radius", "5mm", "--json"])
    assert out.exit_code == 0, out.output
    offered = json.loads(out.stdout)["particles"]
    assert offered > 80  # what the run refused before
    pos = _placed(geo, offered)
    assert len(np.unique(np.round(pos[:, 2], 6))) == 6  # six rows across the width


def test_the_cylinder_is_offered_what_its_floor_holds_not_the_paper_s_area_count():
    cyl = Cylinder()
    assert cyl.clearance_capacity(R) == 48 and floor_capacity(Container(geometry=cyl), R) == 44
    d = design_filling(frequency=2.0, stroke=1e-4, sphere_radius=R, container=cyl)
    assert (d.particles, d.max_particles) == (44, 48)
