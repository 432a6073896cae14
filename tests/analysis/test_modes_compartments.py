"""Motion modes of a baffled bed: each compartment's bed measured on its own (synthetic beds whose
motion is known by construction), the container's floor sections, and a short DEM run."""

import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.analysis.modes import (THRESHOLDS, classify_features, compartment_features, mode_features)
from pdamper.geometry import Baffle
from pdamper.params import Container

R = 0.005
L = 0.120
F = 2.0
FPS = 100.0
#: the paper's cuboid with two full-height plates 2 mm thick at -20 and +20 mm
SECTIONS = [(-0.060, -0.021), (-0.019, 0.019), (0.021, 0.060)]
PER_LENGTH = 48 / L      # N_p,max / L: spheres a metre of floor holds in one layer


def section_block(a, b, n_cols=3, n_rows=4):
    """A compact block of n_cols x n_rows spheres centred in the section (a, b): (x, z) sites."""
    xs = 0.5 * (a + b) + (np.arange(n_cols) - (n_cols - 1) / 2) * 2 * R
    zs = (np.arange(n_rows) - (n_rows - 1) / 2) * 2 * R
    return np.array([(x, z) for x in xs for z in zs])


def baffled_frames(motions, cycles=4):
    """Trajectory of one 3 x 4 block per section, each moved along x by ``motions[k](t, h)`` (h the
    section's clearance: its length less the block's 30 mm)."""
    t = np.arange(1, int(cycles * FPS / F) + 1) / FPS
    parts = []
    for (a, b), move in zip(SECTIONS, motions):
        sites = section_block(a, b)
        p = np.zeros((t.size, len(sites), 3))
        p[:, :, 0] = sites[:, 0] + move(t, (b - a) - 0.030)[:, None]
        p[:, :, 1] = R
        p[:, :, 2] = sites[:, 1]
        parts.append(p)
    return t, np.concatenate(parts, axis=1)


def collide(t, h):
    """Wall to wall once a cycle in step with the drive, resting against each wall a while."""
    return h / 2 * np.clip(1.6 * np.sin(2 * math.pi * F * t - 2.0), -1, 1)


def wander(t, h):
    """In the middle, never reaching a wall, at a third of the drive frequency."""
    return 0.3 * h * np.sin(2 * math.pi * F / 3 * t)


def features(t, pos, **kw):
    return compartment_features(t, pos, R, sections=SECTIONS, spheres_per_length=PER_LENGTH, frequency=F, **kw)


def test_each_compartment_collecting_and_colliding_is_compartment_collect_and_collide():
    t, pos = baffled_frames([collide] * 3)
    f = features(t, pos)
    assert f.spheres == (12, 12, 12)
    for c, (a, b) in zip(f.compartments, SECTIONS):
        # the clearance per compartment: eq. (6) with N_p,max / L of the whole floor (9 and 8 mm)
        assert c.swing == pytest.approx(1.0, abs=0.05) and c.sync > 0.9
        assert c.impacts_lo == pytest.approx(1.0, abs=0.3) and c.impacts_hi == pytest.approx(1.0, abs=0.3)
    assert f.modes() == ["rolling-collect-and-collide"] * 3
    assert classify_features(f) == "compartment-collect-and-collide"
    # the same bed judged as one bed against the container's end walls (the classifier before):
    # the middle block never touches an end wall, the bed centre hardly moves: scattered
    whole = mode_features(t, pos, R, length=L, clearance=0.030, frequency=F)
    assert classify_features(whole) == "scattered"


def test_the_baffle_faces_are_walls_of_the_compartments_beside_them():
    t, pos = baffled_frames([collide] * 3)
    f = features(t, pos)
    # the middle section's both walls are baffle faces; they are reached as often as end walls
    middle = f.compartments[1]
    assert middle.touch_lo > 0.2 and middle.touch_hi > 0.2


def test_the_mode_of_most_spheres_names_the_bed():
    t, pos = baffled_frames([collide, collide, wander], cycles=6)
    f = features(t, pos)
    assert f.modes() == ["rolling-collect-and-collide", "rolling-collect-and-collide", "scattered"]
    assert classify_features(f) == "compartment-collect-and-collide"
    t, pos = baffled_frames([collide, wander, wander], cycles=6)
    assert classify_features(features(t, pos)) == "scattered"


def test_a_baffled_bed_thrown_up_is_lift_off():
    t, pos = baffled_frames([collide] * 3)
    tau = np.mod(t - t[0], 1 / F)
    flight = 0.5 / F
    pos[:, :, 1] += np.where(tau < flight, 9.81 * flight / 2 * tau - 9.81 * tau**2 / 2, 0.0)[:, None]
    f = features(t, pos)
    assert f.airborne > THRESHOLDS["lift_fraction"] and classify_features(f) == "lift-off"


def test_an_empty_compartment_is_left_out():
    t, pos = baffled_frames([collide] * 3)
    f = features(t, pos[:, :24])           # the +x section holds nobody
    assert f.spheres == (12, 12, 0) and f.modes()[2] == "" and classify_features(f) == \
        "compartment-collect-and-collide"
    assert f.to_dict()["compartments"][2] == {}


def test_the_container_says_its_floor_sections():
    plates = (Baffle(position=-0.02), Baffle(position=0.02))
    # as arrays: pytest >= 9.2 refuses approx over nested sequences (a list of pairs)
    np.testing.assert_allclose(Container(baffles=plates).compartments(R), SECTIONS, rtol=1e-6, atol=1e-12)
    assert Container().compartments(R) == [(-0.06, 0.06)]
    # a gap under a plate that a sphere passes: no split there
    gapped = (Baffle(position=-0.02), Baffle(position=0.02, gap_below=0.012))
    np.testing.assert_allclose(Container(baffles=gapped).compartments(R), [(-0.06, -0.021), (-0.019, 0.06)],
                               rtol=1e-6, atol=1e-12)


# --------------------------------------------------------------------------- a short DEM run

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def test_dem_36_spheres_in_three_compartments_collect_and_collide_in_each():
    # docs/robust.md's baffled container at 3.28 mm (X_opt of a compartment, h ~ 9 mm: 3.7 mm): it was
    # "scattered" (the classifier looked for the container's end walls only)
    from pdamper import load_case, run_case

    case = load_case(EXAMPLES / "cuboid_36.toml", {"drive.stroke": "3.28mm", "run.cycles": 4, "run.drop_cycles": 1,
                                                   "container.baffles": [{"position": "-20mm"}, {"position": "20mm"}]})
    s = run_case(case).summary()
    f = s["mode_features"]
    assert f["family"] == "compartments" and f["spheres"] == [12, 12, 12], f
    assert s["mode"] == "compartment-collect-and-collide", f
