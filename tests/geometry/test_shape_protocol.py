"""The shape protocol is complete: a toy shape defined in this file alone (a hexagonal prism) is
read from a config, filled, simulated, analysed and drawn, sized by ``pdamper theory`` and
``pdamper design``, with no change anywhere in pdamper. (That no module outside the shapes' and
drives' own switches on which one it has: tests/test_no_kind_switches.py.)"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.geometry import SHAPES, ShapeBase, register_shape
from pdamper.geometry.walls import PLANE, plane, wall_distances
from pdamper.schema import convert_fields, param

@dataclass(frozen=True, kw_only=True)
class HexPrism(ShapeBase):
    """A regular hexagonal prism, axis up, two flat sides across z: ``side`` a [m], ``height`` [m]."""

    side: float = param(0.035, dimension="length")
    height: float = param(0.02, dimension="length")
    shape: str = param("hexprism", kind="tag")

    def __post_init__(self):
        convert_fields(self, "container")
        if not (self.side > 0 and self.height > 0):
            raise InputError(f"container.side = {self.side!r}, height = {self.height!r}; must be > 0")

    def _normals(self):
        return [(math.cos(a), 0.0, math.sin(a)) for a in np.radians(np.arange(30, 360, 60))]

    def walls(self):
        apothem = self.side * math.sqrt(3) / 2
        rows = [plane((-nx, 0, -nz), -apothem) for nx, _, nz in self._normals()]
        rows += [plane((0, 1, 0), 0.0), plane((0, -1, 0), -self.height)]
        names = [f"side {k + 1}" for k in range(6)] + ["floor", "lid"]
        return np.full(8, PLANE, dtype=np.int64), np.array(rows), names

    def bounding_box(self):
        a = self.side * math.sqrt(3) / 2
        return np.array([-self.side, 0.0, -a]), np.array([self.side, self.height, a])

    def floor_sites(self, radius, spacing):
        row = spacing * math.sqrt(3) / 2
        n = int(self.side / min(spacing, row)) + 2
        pts = np.array([(i * spacing + 0.5 * spacing * (j % 2), j * row) for j in range(-n, n + 1)
                        for i in range(-n, n + 1)])
        kinds, data, _ = self.walls()
        p3 = np.column_stack([pts[:, 0], np.full(len(pts), radius), pts[:, 1]])
        s, _ = wall_distances(kinds[:6], np.ascontiguousarray(data[:6]), np.ascontiguousarray(p3))
        keep = pts[np.all(s >= radius, axis=1)]
        return keep[np.lexsort((keep[:, 1], keep[:, 0]))]

    def outline(self, view):
        if view == "top":
            th = np.radians(np.arange(0, 360, 60))
            return [np.column_stack([self.side * np.cos(th), self.side * np.sin(th)])]
        return super().outline(view)


@pytest.fixture(autouse=True, scope="module")
def _registered():
    """The registration line (here for this module's tests only: the other tests see the shipped shapes)."""
    register_shape(HexPrism)
    yield
    SHAPES.pop("hexprism")


TOY = """
[container]
shape = "hexprism"
side = "35mm"
height = "20mm"
[particles]
count = 7
[drive]
stroke = "8mm"
[run]
cycles = 3
drop_cycles = 1
[recording]
trajectory_fps = 50
"""


def test_the_toy_shape_is_registered_and_read_from_a_config():
    from pdamper.config import case_from_dict, case_to_dict, loads_case

    assert SHAPES["hexprism"] is HexPrism
    case = loads_case(TOY)
    assert isinstance(case.container.geometry, HexPrism)
    assert case.container.geometry.side == pytest.approx(0.035)
    assert case_from_dict(case_to_dict(case)) == case
    with pytest.raises(InputError, match="radius applies to shape = 'cylinder'"):
        loads_case(TOY.replace('side = "35mm"', 'radius = "35mm"'))


def test_a_case_runs_in_the_toy_shape_with_its_energy_ledger_closed(tmp_path):
    from pdamper.config import loads_case
    from pdamper.plotting.motion import animate, paths_figure
    from pdamper.run import run_case

    case = loads_case(TOY)
    res = run_case(case)
    # every sphere stays inside the hexagon (the walls' signed distances >= r less a resting overlap)
    kinds, data, _ = case.container.walls()
    pos = res.trajectory["position"].reshape(-1, 3)
    s, _ = wall_distances(kinds, np.ascontiguousarray(data), np.ascontiguousarray(pos))
    assert s.min() > 0.005 * (1 - 0.01)
    assert res.energy.balance_error() < 5e-3
    assert res.eta_star > 0.05  # the bed collides: the damper dissipates
    # the shape's outline is what the figures draw
    fig = paths_figure([("hex", res.trajectory, case)], tmp_path / "paths.png")
    assert (tmp_path / "paths.png").stat().st_size > 0
    drawn = fig.axes[0].patches[0].get_xy()
    assert np.ptp(drawn[:, 0]) == pytest.approx(70.0, rel=1e-6)  # corner to corner [mm]
    out = animate(res.trajectory, case, tmp_path / "hex.gif", max_frames=5)
    assert out.stat().st_size > 0


def test_the_toy_shape_answers_the_protocol_from_its_walls():
    hexa = HexPrism()
    assert hexa.length_along((1.0, 0.0, 0.0)) == pytest.approx(0.07, rel=1e-9)        # corner to corner
    assert hexa.length_along((0.0, 0.0, 1.0)) == pytest.approx(0.035 * math.sqrt(3), rel=1e-9)  # flat to flat
    sites, jx, jz = hexa.layer_sites(0.005, 1e-4)
    assert len(sites) == hexa.max_particles(0.005) - 0 or len(sites) <= hexa.max_particles(0.005)
    v, quads = hexa.mesh()
    assert v.shape == (12, 3) and quads.shape == (6, 4)
    assert "hexprism" in hexa.describe()


# ------------------------------------------------------------------ the theory and the design ask the shape

def test_the_toy_shape_answers_its_drive_length_from_the_protocol_alone():
    # HexPrism writes no drive_length: ShapeBase's (the chord along x) is its L, corner to corner
    hexa = HexPrism(side=0.035)
    assert hexa.drive_length == pytest.approx(0.07, rel=1e-9)
    assert hexa.with_drive_length(0.09).side == pytest.approx(0.045, rel=1e-12)
    assert hexa.row_capacity(0.005) >= 1


def test_pdamper_theory_and_design_take_the_toy_shape():
    import json

    from click.testing import CliRunner

    from pdamper import theory as th
    from pdamper.cli.common import main

    hexa = HexPrism(side=0.035)
    n_max = hexa.clearance_capacity(0.005)
    r = CliRunner().invoke(main, ["theory", "--shape", "hexprism", "--size", "side=35mm", "--particles", "7",
                                  "--max-particles", str(n_max), "--frequency", "2Hz", "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.stdout)
    assert out["length_m"] == pytest.approx(0.07, rel=1e-9)
    assert out["x_opt_m"] == pytest.approx(th.optimal_stroke(th.clearance(0.07, 7, n_max)), rel=1e-12)
    d = CliRunner().invoke(main, ["design", "--shape", "hexprism", "--size", "side=35mm", "--frequency", "2Hz",
                                  "--stroke", "8mm", "--sphere-radius", "5mm", "--json"])
    assert d.exit_code == 0, d.output
    design = json.loads(d.stdout)
    assert design["shape"] == "hexprism" and design["length_m"] == pytest.approx(0.07, rel=1e-9)
    assert design["x_opt_m"] <= 0.008 and design["max_particles"] == n_max
    missing = CliRunner().invoke(main, ["theory", "--shape", "hexprism", "--particles", "7", "--max-particles", "19",
                                        "--frequency", "2Hz"])
    assert missing.exit_code == 2 and "needs --size side=VALUE" in missing.output


def test_a_shape_without_the_protocol_is_refused_when_registered():
    @dataclass(frozen=True, kw_only=True)
    class Blob:
        shape: str = param("blob", kind="tag")

        def walls(self): ...

    with pytest.raises(TypeError, match="does not answer the shape protocol: missing .*drive_length"):
        register_shape(Blob)
    assert "blob" not in SHAPES
