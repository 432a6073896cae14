"""Motion modes of a vertically shaken bed: synthetic trajectories whose regime is known by
construction (a rigid block bouncing, a block flying between floor and lid, independent gas
particles, a bed at rest), the family a case asks for, and short DEM runs."""

import math
from pathlib import Path

import numpy as np
import pytest

from pdamper.analysis.fields import mode_family as field_family
from pdamper.analysis.modes import (COLLIDE_MODES, THRESHOLDS, VERTICAL_MODES, classify_features, family_of,
                                    vertical_clearance, vertical_features)

R = 0.005
H = 0.050                # floor to lid
F = 15.0
FPS = 600.0              # 40 frames a cycle
G = 9.81


def block(layers=2, cols=4, rows=3):
    """A packed block's sites (x, y above its bottom, z): ``layers`` square layers of cols x rows."""
    return np.array([((i - (cols - 1) / 2) * 2 * R, R + 2 * R * k, (j - (rows - 1) / 2) * 2 * R)
                     for k in range(layers) for i in range(cols) for j in range(rows)])


def frames(bottom, *, cycles=6, sites=None):
    """Trajectory of the rigid block lifted to ``bottom(t)`` [m] (its lowest sphere's bottom above the floor)."""
    t = np.arange(1, int(cycles * FPS / F) + 1) / FPS
    sites = block() if sites is None else sites
    pos = np.repeat(sites[None, :, :], t.size, axis=0)
    pos[:, :, 1] += bottom(t)[:, None]
    return t, pos


def drive(t, stroke):
    return stroke * np.sin(2 * math.pi * F * t)


def features(t, pos, stroke=0.004, clearance=H - 4 * R, **kw):
    return vertical_features(t, pos, R, height=H, clearance=clearance, frequency=F,
                             container_position=drive(t, stroke), **kw)


def ballistic(t, period, flight, phase=0.0):
    """Height of a ball leaving the floor at phase + k period and flying for ``flight`` [s]."""
    tau = np.mod(t - phase, period)
    v0 = G * flight / 2
    return np.where(tau < flight, v0 * tau - G * tau**2 / 2, 0.0)


def test_a_rigid_block_bouncing_once_a_cycle_is_a_bouncing_bed():
    # flies 60 % of each cycle, apex g (0.6 T)^2 / 8 = 1.96 mm: the lid (30 mm above it) never reached
    f = features(*frames(lambda t: ballistic(t, 1 / F, 0.6 / F)))
    assert f.coherence == pytest.approx(1.0) and f.lid_touch == 0.0
    apex = G * (0.6 / F) ** 2 / 8
    above_gap = 0.6 * math.sqrt(1 - THRESHOLDS["touch_gap"] * R / apex)    # the flight's part above 0.1 r
    assert 1 - f.floor_touch == pytest.approx(above_gap, abs=0.03) and f.floor_impacts == pytest.approx(1.0, abs=0.2)
    assert classify_features(f) == "bouncing-bed"


def test_a_block_bouncing_every_few_cycles_is_a_bouncing_bed_too():
    # period 3: flies 2.8 cycles (apex 80 mm: a taller container), out of step with the drive
    t, pos = frames(lambda t: ballistic(t, 3 / F, 2.8 / F), cycles=9)
    f = vertical_features(t, pos, R, height=0.2, clearance=0.2 - 4 * R, frequency=F,
                          container_position=drive(t, 0.001))
    assert f.sync < THRESHOLDS["sync_min"] and f.floor_impacts == pytest.approx(1 / 3, abs=0.1)
    assert classify_features(f) == "bouncing-bed"


def collect_and_collide(t):
    """The block's bottom: from the floor to under the lid (30 mm) and back once a cycle, resting at
    each for a while (a clipped sine)."""
    return 0.5 * (H - 4 * R) * (1 + np.clip(1.6 * np.sin(2 * math.pi * F * t - 2.0), -1, 1))


def test_a_block_flying_between_floor_and_lid_in_step_is_bouncing_collect_and_collide():
    f = features(*frames(collect_and_collide))
    assert f.floor_impacts == pytest.approx(1.0, abs=0.2) and f.lid_impacts == pytest.approx(1.0, abs=0.2)
    assert f.swing == pytest.approx(1.0, abs=0.02) and f.sync > 0.9 and f.coherence == pytest.approx(1.0)
    assert classify_features(f) == "bouncing-collect-and-collide"
    # the same travel out of step with the drive (a third of its frequency) is no collect-and-collide
    slow = features(*frames(lambda t: collect_and_collide(t / 3), cycles=9))
    assert slow.sync < THRESHOLDS["sync_min"] and classify_features(slow) == "bouncing-bed"


def gas(n=48, cycles=6, seed=3):
    """``n`` spheres, each bouncing on the floor on its own: random phase, flight time (0.5-3
    cycles) and place in the floor plane."""
    rng = np.random.default_rng(seed)
    t = np.arange(1, int(cycles * FPS / F) + 1) / FPS
    pos = np.zeros((t.size, n, 3))
    pos[:, :, 0] = rng.uniform(-0.05, 0.05, n)
    pos[:, :, 2] = rng.uniform(-0.015, 0.015, n)
    for i in range(n):
        flight = rng.uniform(0.5, 3.0) / F
        pos[:, i, 1] = R + ballistic(t, flight * 1.05, flight, rng.uniform(0, flight))
    return t, np.minimum(pos, H - R)


def test_independent_gas_particles_are_fluidised():
    t, pos = gas()
    f = features(t, pos)
    assert f.coherence < 0.1                  # ~1/N: the centre barely moves while each sphere flies
    assert f.floor_touch > 0.9                # some sphere is always at the floor: the bed never leaves it
    assert classify_features(f) == "fluidised"


def test_a_bed_at_rest_on_a_drive_below_1g_is_locked():
    # X = 0.5 mm at 15 Hz: A = 0.45 g; two layers resting, moving with the container
    t, pos = frames(lambda t: np.zeros_like(t))
    f = features(t, pos, stroke=0.0005)
    assert f.relative == 0.0 and classify_features(f) == "locked"
    # without the container's track the relative motion is unknown: nothing is locked
    assert classify_features(vertical_features(t, pos, R, height=H, clearance=H - 4 * R, frequency=F)) == "fluidised"


@pytest.mark.parametrize("key, value, mode", [
    ("coherence_min", 1.01, "fluidised"),          # a block that must move more as one than a rigid one
    ("flight_min", 0.7, "fluidised"),              # ... or fly longer than 60 % of the cycle
    ("coherence_min", 0.45, "bouncing-bed"),
])
def test_the_bouncing_bed_thresholds_are_parameters(key, value, mode):
    f = features(*frames(lambda t: ballistic(t, 1 / F, 0.6 / F)))
    assert classify_features(f, {key: value}) == mode


def test_the_vertical_names_are_their_own_and_the_efficient_one_is_in_the_collide_family():
    assert set(VERTICAL_MODES) == {"locked", "bouncing-collect-and-collide", "bouncing-bed", "fluidised"}
    assert "bouncing-collect-and-collide" in COLLIDE_MODES
    assert field_family("bouncing-collect-and-collide") == "collide"
    assert field_family("compartment-collect-and-collide") == "collide"
    assert field_family("bouncing-bed") == field_family("fluidised") == "other"


# --------------------------------------------------------------------------- the family a case asks for

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _case(name, **over):
    from pdamper import load_case

    return load_case(EXAMPLES / f"{name}.toml", over)


@pytest.mark.parametrize("name, over, family", [
    ("vertical_96", {}, "vertical"),
    ("vertical_96", {"drive.direction": [1, 1.2, 0]}, "vertical"),        # 50 deg from the floor plane
    ("vertical_96", {"drive.direction": [1, 0.8, 0]}, "horizontal"),      # 39 deg
    ("cuboid_36", {}, "horizontal"),
    ("cuboid_36", {"container.baffles": [{"position": "-20mm"}, {"position": "20mm"}]}, "compartments"),
    # a gap under the plates wider than a sphere: one floor, the plates do not split the bed
    ("cuboid_36", {"container.baffles": [{"position": "0mm", "gap_below": "12mm"}]}, "horizontal"),
    # driven along z, across the plates' planes: they do not stand between the bed and the walls it hits
    ("cuboid_36", {"container.baffles": [{"position": "0mm"}], "drive.angle": "90deg"}, "horizontal"),
])
def test_the_family_is_asked_of_the_drive_and_the_container(name, over, family):
    assert family_of(_case(name, **over)) == family


def test_the_free_height_above_two_layers():
    height, h_v = vertical_clearance(_case("vertical_96"))
    assert height == pytest.approx(0.050) and h_v == pytest.approx(0.050 - 4 * 0.005)


# --------------------------------------------------------------------------- short DEM runs

def _dem(stroke, cycles, **over):
    from pdamper import run_case

    res = run_case(_case("vertical_96", **{"drive.stroke": stroke, "run.cycles": cycles, "run.drop_cycles": 1,
                                           **over}))
    s = res.summary()
    return s["mode"], s["mode_features"]


def test_dem_two_layers_below_1g_rest_on_the_floor_and_are_locked():
    # X = 0.5 mm at 15 Hz (A = 0.45 g): was "lift-off" (the upper layer's centres are 3 r high)
    mode, f = _dem("0.5mm", 3)
    assert f["family"] == "vertical" and mode == "locked", f
    assert f["floor_touch"] == 1.0 and f["lid_touch"] == 0.0


@pytest.mark.slow
def test_dem_two_layers_at_12mm_collect_and_collide_between_floor_and_lid():
    # X = 12 mm at 15 Hz (11 g): the bed is thrown from the floor to the lid and back once a cycle
    # (docs/motion.md: 12 cycles, 4 dropped, seeds 0 and 1: floor and lid each reached 1.1-1.5 times
    # a cycle, sync 0.99)
    mode, f = _dem("12mm", 4)
    assert mode == "bouncing-collect-and-collide", f
    assert f["sync"] > 0.9 and min(f["floor_impacts"], f["lid_impacts"]) >= 0.5


def test_the_old_name_of_family_of_warns_and_gives_the_same_family():
    from pdamper.analysis import modes

    with pytest.warns(DeprecationWarning, match=r"mode_family is deprecated; use .*family_of"):
        assert modes.mode_family(_case("vertical_96")) == "vertical"
    assert "mode_family" not in modes.__all__
