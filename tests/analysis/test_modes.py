"""Motion modes: the classifier on synthetic trajectories with known answers, and on short DEM runs."""

import math

import numpy as np
import pytest

from pdamper.geometry import Cylinder

from pdamper.analysis.modes import (COMPARTMENT_MODES, HORIZONTAL_MODES, MODES, THRESHOLDS, VERTICAL_MODES,
                                    bed_centre, case_clearance, classify_features, classify_trajectory, mode_features)

R = 0.005
L = 0.120
H_CLEAR = 0.030          # 36 of 48 spheres: h = 30 mm
F = 2.0
FPS = 100.0


def block(n_cols=9, n_rows=4):
    """A compact block's (x, z) sites centred on x = 0: 9 x 4 spheres, 90 mm = L - h long."""
    xs = (np.arange(n_cols) - (n_cols - 1) / 2) * 2 * R
    zs = (np.arange(n_rows) - (n_rows - 1) / 2) * 2 * R
    return np.array([(x, z) for x in xs for z in zs])


def frames(centre, *, jitter=None, height=None, cycles=4):
    """Trajectory of the block moved to ``centre(t)`` [m] along x, with optional per-sphere
    offsets ``jitter(t)`` (F, N) along x and heights ``height(t)`` (F, N) above y = r."""
    t = np.arange(1, int(cycles * FPS / F) + 1) / FPS
    sites = block()
    n = len(sites)
    pos = np.zeros((len(t), n, 3))
    pos[:, :, 0] = sites[:, 0] + centre(t)[:, None]
    if jitter is not None:
        pos[:, :, 0] += jitter(t)
    pos[:, :, 1] = R + (height(t) if height is not None else 0.0)
    pos[:, :, 2] = sites[:, 1]
    return t, pos


def features(t, pos, **kw):
    return mode_features(t, pos, R, length=L, clearance=H_CLEAR, frequency=F, **kw)


def tilted(t, stroke, g_s):
    """Keyword arguments for a container driven at ``stroke`` [m] with gravity ``g_s`` [m/s^2]
    along the drive (a tilt about z; < 0 pulls towards the -x wall)."""
    return dict(gravity_along=g_s, container_position=stroke * np.sin(2 * np.pi * F * t))


G_TAN_3 = 9.81 * math.sin(math.radians(3.0))


def rolling_centre(t):
    # wall to wall once per cycle, pressed against each wall for a while (clipped sine)
    return H_CLEAR / 2 * np.clip(1.6 * np.sin(2 * np.pi * F * t - 2.0), -1, 1)


def test_rolling_collect_and_collide():
    f = features(*frames(rolling_centre))
    assert f.impacts_lo == pytest.approx(1.0, abs=0.3) and f.impacts_hi == pytest.approx(1.0, abs=0.3)
    assert f.swing == pytest.approx(1.0, abs=0.05)
    assert f.sync > 0.9
    assert f.spread == pytest.approx(1.0, abs=0.05)
    assert classify_features(f) == "rolling-collect-and-collide"


def test_single_sided_bed_resting_on_the_low_wall():
    t, pos = frames(lambda t: np.full_like(t, -H_CLEAR / 2))
    # 3 deg tilt towards -x, X = 2 mm at 2 Hz: A = 0.32 m/s^2 < g sin 3 deg = 0.51 m/s^2
    f = features(t, pos, **tilted(t, 0.002, -G_TAN_3))
    assert f.touch_lo == 1.0 and f.touch_hi == 0.0 and f.swing == pytest.approx(0.0, abs=1e-9)
    assert f.tilt_pull == pytest.approx(G_TAN_3 / (0.002 * (2 * np.pi * F) ** 2), rel=0.01) and f.downhill == -1
    assert classify_features(f) == "single-sided"
    # the mirror image: tilted the other way, resting on the +x wall
    t, pos = frames(lambda t: np.full_like(t, H_CLEAR / 2))
    assert classify_features(features(t, pos, **tilted(t, 0.002, G_TAN_3))) == "single-sided"


def test_a_bed_at_one_wall_without_a_tilt_holding_it_there_is_not_single_sided():
    t, pos = frames(lambda t: np.full_like(t, -H_CLEAR / 2))
    assert classify_features(features(t, pos)) == "scattered"           # no tilt, no container track
    untilted = features(t, pos, **tilted(t, 0.001, -9.81 * math.sin(math.radians(0.1))))      # 0.1 deg
    assert untilted.tilt_pull == pytest.approx(0.108, abs=0.005)
    # it does not move in the container while the container moves: it moves with it (issue 24)
    assert classify_features(untilted) == "locked"
    assert classify_features(features(t, pos, **tilted(t, 0.002, +G_TAN_3))) == "locked"       # the high wall


def test_single_sided_bed_leaving_and_returning_to_one_wall():
    # leaves the -x wall for a third of each cycle, never reaches the other
    centre = lambda t: -H_CLEAR / 2 + 0.3 * H_CLEAR * np.clip(2 * np.sin(2 * np.pi * F * t) - 1, 0, 1)  # noqa: E731
    t, pos = frames(centre)
    f = features(t, pos, **tilted(t, 0.005, -G_TAN_3))     # A = 0.79 m/s^2: pull 0.65
    assert f.impacts_lo == pytest.approx(1.0, abs=0.3) and f.touch_hi == 0.0
    assert classify_features(f) == "single-sided"


def test_scattered_spheres_each_their_own_way():
    rng = np.random.default_rng(1)
    phases = rng.uniform(0, 2 * np.pi, 36)
    amps = rng.uniform(0, 0.4 * H_CLEAR, 36)
    freqs = rng.uniform(0.3, 1.7, 36) * F

    def jitter(t):
        return amps * np.sin(2 * np.pi * freqs * t[:, None] + phases) * 0.5

    f = features(*frames(lambda t: np.zeros_like(t), jitter=jitter))
    assert f.touch_lo < 0.5 and f.touch_hi < 0.5
    assert classify_features(f) == "scattered"


def test_in_step_in_the_middle_without_reaching_the_walls_is_scattered():
    # in step with the drive, but never reaching the walls (unlike the swaying bed near X_opt)
    f = features(*frames(lambda t: 0.3 * H_CLEAR * np.sin(2 * np.pi * F * t)))
    assert f.sync > 0.95 and f.impacts_lo == 0 and f.impacts_hi == 0
    assert classify_features(f) == "scattered"


def swaying_frames(amplitude=0.010, stretch=1.125, cycles=4):
    """A bed at rest in the lab while the container moves by ``amplitude`` about it: in the container
    frame its centre moves as -amplitude sin(Omega t). The bed lies ``stretch`` times longer than a
    compact block, so its leading spheres just touch each end wall at the container's turning points."""
    t, pos = frames(lambda t: -amplitude * np.sin(2 * np.pi * F * t), cycles=cycles)
    sites_x = np.tile(block()[:, 0], (len(t), 1))
    pos[:, :, 0] += (stretch - 1.0) * sites_x
    return t, pos


def test_swaying_bed_touches_both_walls_in_step_but_in_antiphase():
    t, pos = swaying_frames()
    f = features(t, pos)
    front = pos[:, :, 0].max(axis=1) + R
    assert front.max() == pytest.approx(L / 2, abs=1e-4)        # the leading spheres reach the wall, no deeper
    assert f.impacts_lo == pytest.approx(1.0, abs=0.3) and f.impacts_hi == pytest.approx(1.0, abs=0.3)
    assert f.sync > 0.99 and f.swing > THRESHOLDS["swing_min"]
    assert abs(f.phase_deg) == pytest.approx(180.0, abs=1.0)
    assert classify_features(f) == "swaying"


def _rolling_features():
    f = features(*frames(rolling_centre))
    assert classify_features(f) == "rolling-collect-and-collide" and abs(f.phase_deg) < 120
    return f


ROLLING = "rolling-collect-and-collide"


@pytest.mark.parametrize("phase, mode", [(-100.0, ROLLING), (-139.0, ROLLING), (-141.0, "swaying"), (-179.0, "swaying"),
                                         (179.0, "swaying"), (141.0, "swaying"), (139.0, ROLLING)])
def test_the_phase_separates_swaying_from_rolling_collect_and_collide(phase, mode):
    import dataclasses

    f = dataclasses.replace(_rolling_features(), phase_deg=phase)
    assert THRESHOLDS["phase_max"] == 140.0
    assert classify_features(f) == mode


def test_swaying_needs_both_walls_and_the_drive_frequency():
    import dataclasses

    sway = features(*swaying_frames())
    assert classify_features(dataclasses.replace(sway, impacts_hi=0.0)) == "scattered"      # one wall only
    assert classify_features(dataclasses.replace(sway, sync=0.69)) == "scattered"           # not in step
    assert classify_features(dataclasses.replace(sway, swing=0.4)) == "scattered"           # barely moves
    assert classify_features(dataclasses.replace(sway, airborne=0.1)) == "lift-off"
    # the phase threshold is a parameter like the others
    assert classify_features(sway, {"phase_max": 180.0}) == "rolling-collect-and-collide"


def test_wall_to_wall_out_of_step_with_the_drive_is_not_rolling():
    # reaches both walls, but at a third of the drive frequency: no synchrony
    f = features(*frames(lambda t: H_CLEAR / 2 * np.clip(1.6 * np.sin(2 * np.pi * F / 3 * t), -1, 1), cycles=6))
    assert f.touch_lo > 0.1 and f.touch_hi > 0.1 and f.sync < THRESHOLDS["sync_min"]
    assert classify_features(f) == "scattered"


def ballistic(t, period, flight, phase=0.0):
    """Height [m] of a ball that leaves the floor at times phase + k period and flies for ``flight``
    [s] under gravity (0 on the floor)."""
    tau = np.mod(t - phase, period)
    v0 = 9.81 * flight / 2
    return np.where(tau < flight, v0 * tau - 9.81 * tau**2 / 2, 0.0)


def test_lift_off_is_the_bed_leaving_the_floor():
    # every sphere leaves the floor once a cycle, from the first frame on, and flies for half of it
    # (apex g T^2 / 32 = 77 mm): half the sphere-frames but those within 0.2 r of the floor
    f = features(*frames(rolling_centre, height=lambda t: np.tile(ballistic(t, 1 / F, 0.5 / F, t[0]), (36, 1)).T))
    assert f.airborne == pytest.approx(0.5, abs=0.03) and f.max_height > 1.5
    assert classify_features(f) == "lift-off"


def riding(t, pos, spheres):
    """``pos`` with ``spheres`` more spheres each in a hollow on top of the block (centre sqrt(2) r
    above the layer's: touching the four below it), moving with the block."""
    top = np.zeros((len(t), spheres, 3))
    for k in range(spheres):
        top[:, k, 0] = pos[:, 4 * k, 0] + R                  # between columns k and k+1 ...
        top[:, k, 2] = pos[:, 4 * k, 2] + R                  # ... and rows 0 and 1
        top[:, k, 1] = R + math.sqrt(2) * R
    return np.concatenate([pos, top], axis=1)


def test_spheres_riding_on_the_layer_have_not_left_the_floor():
    # issue 28: 36 spheres at 24 mm, 2.4 Hz (0.56 g) were called lift-off: spheres squeezed up onto
    # their neighbours at the wall impacts ride on the layer, their centres above 1.2 r
    t, pos = frames(rolling_centre)
    pos = riding(t, pos, 4)
    f = mode_features(t, pos, R, length=L, clearance=H_CLEAR, frequency=F)
    assert f.raised == pytest.approx(4 / 40) and f.raised >= THRESHOLDS["lift_fraction"]   # the old measure
    assert f.airborne == 0.0
    assert classify_features(f) == "rolling-collect-and-collide"


def test_a_sphere_pushed_over_a_neighbour_briefly_on_a_056_g_drive_is_not_lift_off():
    # a resting layer in a container driven at X = 24 mm, f = 2.4 Hz (A = 0.56 g); once a cycle one
    # sphere is pushed up over its neighbour for a tenth of a cycle, touching it all the while
    f_drive = 2.4
    t = np.arange(1, 401) / FPS
    sites = block()
    pos = np.zeros((t.size, len(sites), 3))
    pos[:, :, 0], pos[:, :, 1], pos[:, :, 2] = sites[:, 0], R, sites[:, 1]
    tau = np.mod(t, 1 / f_drive) * f_drive
    over = tau < 0.1
    dx = 2 * R * (1 - np.sin(np.pi * tau / 0.1) * 0.5)         # from side by side (2 r) to r over it
    pos[over, 0, 0] = pos[over, 4, 0] - dx[over]               # sphere 0 climbs its +x neighbour (4)
    pos[over, 0, 1] = R + np.sqrt((2 * R) ** 2 - dx[over] ** 2)
    xc = 0.024 * np.sin(2 * np.pi * f_drive * t)
    assert (2 * np.pi * f_drive) ** 2 * 0.024 / 9.81 == pytest.approx(0.56, abs=0.01)
    f = mode_features(t, pos, R, length=L, clearance=H_CLEAR, frequency=f_drive, container_position=xc)
    assert f.max_height > 0.5 and f.raised > 0 and f.airborne == 0.0
    assert classify_features(f) == "locked"
    # the same sphere hopping free of it for one frame (shorter than lift_time) has not flown either
    hop = pos.copy()
    k = np.flatnonzero(over)[::max(1, int(np.sum(over) / 4))]
    hop[k, 0, 1] += 0.5 * R
    assert mode_features(t, hop, R, length=L, clearance=H_CLEAR, frequency=f_drive).airborne == 0.0


def test_a_flight_counts_from_the_floor_for_at_least_lift_time():
    # one sphere of 36 leaves the floor and flies for 0.3 cycle every cycle: about 0.3 / 36 of the
    # sphere-frames (less the frames within 0.2 r of the floor)
    t, pos = frames(rolling_centre)
    pos[:, 7, 1] += ballistic(t, 1 / F, 0.3 / F, t[0])
    f = features(t, pos)
    assert f.airborne == pytest.approx(0.3 / 36, rel=0.25)
    # a sphere that hops off a sphere under it did not leave the floor: the same flights atop a rider
    t, pos = frames(rolling_centre)
    pos = riding(t, pos, 1)
    pos[:, -1, 1] += ballistic(t, 1 / F, 0.3 / F, t[0])
    assert features(t, pos).airborne == 0.0
    # off the floor by 2 mm in one frame a cycle (0.02 cycle, under lift_time): not a flight
    t, pos = frames(rolling_centre)
    pos[10::int(FPS / F), 7, 1] += 0.4 * R
    assert THRESHOLDS["lift_time"] > 1 / (FPS / F) and features(t, pos).airborne == 0.0
    pos[11::int(FPS / F), 7, 1] += 0.4 * R          # two frames: 0.04 cycle, still under it
    pos[12::int(FPS / F), 7, 1] += 0.4 * R          # three: 0.06 cycle, a flight
    assert features(t, pos).airborne == pytest.approx(3 * 4 / (200 * 36))


def test_features_ignore_the_transient_and_follow_the_drive_direction():
    t, pos = frames(rolling_centre)
    # a drive along z of a container turned by 90 deg: swap x and z
    turned = pos[:, :, [2, 1, 0]]
    f = mode_features(t, turned, R, length=L, clearance=H_CLEAR, frequency=F, drive_dir=(0, 0, 1), start_time=1.0)
    assert f.cycles == pytest.approx(2.0, abs=0.05)
    assert classify_features(f) == "rolling-collect-and-collide"
    assert bed_centre(turned, (0, 0, 1)) == pytest.approx(pos[:, :, 0].mean(axis=1))


def test_rolling_in_a_cylinder_touches_the_curved_wall_off_the_axis():
    # 2 rows of 4 spheres at z = +-8.5 mm in a cylinder of R = 39 mm: the front spheres touch the
    # curved wall at x = sqrt((R - r)^2 - z^2) < R - r, where a flat end wall would not be
    big_r, z = 0.039, 0.0085
    x_front = math.sqrt((big_r - R) ** 2 - z**2)
    c = x_front - 3 * R                   # the block centre when it rests on the +x side
    t = np.arange(1, 201) / FPS
    centre = c * np.clip(1.6 * np.sin(2 * np.pi * F * t - 2.0), -1, 1)
    xs = (np.arange(4) - 1.5) * 2 * R
    sites = np.array([(x, zz) for x in xs for zz in (-z, z)])
    pos = np.zeros((t.size, 8, 3))
    pos[:, :, 0] = sites[:, 0] + centre[:, None]
    pos[:, :, 1] = R
    pos[:, :, 2] = sites[:, 1]
    kw = dict(length=2 * big_r, clearance=2 * c, frequency=F)
    round_ = mode_features(t, pos, R, shape=Cylinder(radius=big_r, height=0.011), **kw)
    flat = mode_features(t, pos, R, shape=None, **kw)
    assert round_.impacts_lo == pytest.approx(1.0, abs=0.3) and flat.touch_lo == 0.0
    assert classify_features(round_) == "rolling-collect-and-collide"
    assert classify_features(flat) == "scattered"


def test_bad_shapes_and_too_few_frames_are_refused():
    with pytest.raises(ValueError, match="frames, N, 3"):
        mode_features(np.arange(3.0), np.zeros((3, 4)), R, length=L, clearance=H_CLEAR, frequency=F)
    with pytest.raises(ValueError, match="at least 2 trajectory frames"):
        mode_features(np.zeros(1), np.zeros((1, 4, 3)), R, length=L, clearance=H_CLEAR, frequency=F)


def test_modes_listed():
    assert set(MODES) == {"scattered", "rolling-collect-and-collide", "swaying", "single-sided", "lift-off", "locked",
                          "bouncing-collect-and-collide", "bouncing-bed", "fluidised", "compartment-collect-and-collide"}
    assert set(HORIZONTAL_MODES) | set(VERTICAL_MODES) | set(COMPARTMENT_MODES) == set(MODES)


def test_case_clearance_of_the_paper_cases():
    from pdamper.params import Case, Container, ParticleSet
    from pdamper.geometry import Cylinder

    assert case_clearance(Case(particles=(ParticleSet(count=36),))) == pytest.approx((0.12, 0.03))
    assert case_clearance(Case(particles=(ParticleSet(count=44),)))[1] == pytest.approx(0.01)
    length, h = case_clearance(Case(particles=(ParticleSet(count=42),), container=Container(geometry=Cylinder())))
    assert length == pytest.approx(0.078) and h == pytest.approx(0.078 * 6 / 48)


# --------------------------------------------------------------------------- short DEM runs
# 4 cycles (the first dropped) of the paper's cases: about 1-6 s each. The numbers behind the
# thresholds (more strokes, seeds and cycles) are in docs/motion.md.

from pathlib import Path  # noqa: E402

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


def _dem_mode(name, stroke, **over):
    from pdamper import load_case, run_case

    from pdamper.plausible import LiftOffWarning

    case = load_case(EXAMPLES / f"{name}.toml", {"drive.stroke": stroke, "run.cycles": 4, "run.drop_cycles": 1,
                                                 **over})
    import contextlib
    import math

    lifts = case.drive.stroke * (2 * math.pi * case.drive.frequency) ** 2 > case.gravity
    with pytest.warns(LiftOffWarning, match="lifts off") if lifts else contextlib.nullcontext():  # said before
        res = run_case(case)
    s = res.summary()
    assert res.trajectory is None  # recorded for the mode only, not returned
    return s["mode"], s["mode_features"]


@pytest.mark.parametrize("stroke, mode", [("4mm", "scattered"), ("15mm", "rolling-collect-and-collide")])
def test_dem_36_spheres_scattered_below_and_rolling_above_x_opt(stroke, mode):
    got, feats = _dem_mode("cuboid_36", stroke)
    assert got == mode, feats


def test_dem_36_spheres_just_below_x_opt_sway():
    # 10 mm = 0.82 X_opt: the bed touches both walls in step with the drive but stays nearly at rest
    # in the lab (docs/motion.md: 4/1 cycles, seeds 0-2, phase -152 to -156 deg, eta* 0.28-0.38)
    got, feats = _dem_mode("cuboid_36", "10mm")
    assert got == "swaying", feats
    assert abs(feats["phase_deg"]) > THRESHOLDS["phase_max"] and min(feats["impacts_lo"], feats["impacts_hi"]) >= 0.5


def test_dem_44_spheres_tilted_3deg_below_g_tan_alpha_is_single_sided():
    # X = 2 mm at 2 Hz: A = 0.32 m/s^2 < g tan 3 deg = 0.51 m/s^2; the bed stays on the low wall
    got, feats = _dem_mode("cuboid_44", "2mm", **{"container.tilt": ["0.1deg", "0.1deg", "3deg"]})
    assert got == "single-sided", feats
    assert feats["touch_lo"] == 1.0 and feats["touch_hi"] == 0.0


def test_dem_36_spheres_thrown_up_are_lift_off():
    # the bed thrown up at 0.6 m/s from the floor (flight height v^2/2g = 18 mm = 3.7 r), then
    # bouncing with eps = 0.9, while driven at 5 Hz, 15 mm. (Whether the wall impacts alone throw
    # spheres up at this drive, A = 1.5 g, depends on the seed and on the integrator's tolerance:
    # docs/motion.md; a test cannot rest on it.)
    got, feats = _dem_mode("cuboid_36", "15mm", **{"drive.frequency": "5Hz", "initial.settle_time": 0.0,
                                                   "initial.velocities": [[0.0, 0.6, 0.0]] * 36})
    assert got == "lift-off", feats
    # flights from the floor in 13 % of the sphere-frames (measured), the rest of the time bouncing low
    assert feats["airborne"] > 2 * THRESHOLDS["lift_fraction"] and feats["raised"] > feats["airborne"]


@pytest.mark.slow
def test_dem_spheres_riding_on_the_layer_below_1g_are_not_lift_off():
    # 36 spheres at 24 mm, 2.4 Hz (A = 0.56 g), seed 5 (docs/motion.md): spheres squeezed onto their
    # neighbours at the wall impacts ride on the layer; the old rule (centres above 1.2 r in 5 % of the
    # sphere-frames: 13 % here) said lift-off. Flights from the floor (spheres that fall off the layer
    # and bounce): 2 % of the sphere-frames.
    got, feats = _dem_mode("cuboid_36", "24mm", **{"drive.frequency": "2.4Hz", "initial.seed": 5, "run.cycles": 20,
                                                   "run.drop_cycles": 2})
    assert feats["raised"] >= THRESHOLDS["lift_fraction"] > feats["airborne"], feats
    assert got == "rolling-collect-and-collide", feats


@pytest.mark.parametrize("airborne", [0.0, 0.2])
@pytest.mark.parametrize("sync", [0.1, 0.95])
@pytest.mark.parametrize("relative", [0.01, 1.0, math.nan])
def test_a_bed_on_the_floor_gets_a_horizontal_name_only(airborne, sync, relative):
    # the vertical and compartment names never come out of the horizontal rules: they cannot split
    # the effective fields of a horizontal sweep
    import dataclasses

    f = dataclasses.replace(_rolling_features(), airborne=airborne, sync=sync, relative=relative)
    mode = classify_features(f)
    assert mode in HORIZONTAL_MODES and (mode == "lift-off") == (airborne >= THRESHOLDS["lift_fraction"])


def test_dem_48_spheres_filling_the_floor_are_locked():
    # issue 24: 48 spheres fill the paper's 120 x 40.4 mm floor wall to wall (clearance 0): the bed
    # moves with the container and was labelled "scattered"
    got, feats = _dem_mode("cuboid_36", "13mm", **{"particles.count": 48})
    assert got == "locked", feats
    assert feats["relative"] <= THRESHOLDS["locked_max"] and feats["airborne"] == 0.0


def test_dem_a_moving_bed_is_not_locked():
    # the same container with 36 spheres at 4 mm (scattered) moves about the container: its centre
    # travels in the container frame by a good part of the container's own travel
    got, feats = _dem_mode("cuboid_36", "4mm")
    assert got != "locked" and feats["relative"] > 10 * THRESHOLDS["locked_max"], feats


def test_locked_needs_the_container_track():
    # without the container's positions the relative motion is unknown (NaN) and nothing is "locked"
    t, pos = frames(lambda t: np.zeros_like(t))  # a bed at rest in the container
    f = features(t, pos)
    assert math.isnan(f.relative) and classify_features(f) == "scattered"
    locked = features(t, pos, container_position=0.013 * np.sin(2 * np.pi * F * t))
    assert locked.relative == 0.0 and classify_features(locked) == "locked"
    # the rolling bed with the container's track: it moves, so the track changes nothing
    t, pos = frames(rolling_centre)
    rolling = features(t, pos, container_position=0.013 * np.sin(2 * np.pi * F * t))
    assert rolling.relative > 1.0 and classify_features(rolling) == "rolling-collect-and-collide"


def test_each_family_holds_its_names_and_thresholds_in_one_table():
    """The lists of the classifier are made from the families' tables (one module a family): every
    name once, the collide names of each family, every threshold given by exactly one table."""
    import pytest as _pytest

    from pdamper.analysis import modes
    from pdamper.analysis.modes.common import ModeFamily, register_family

    assert list(modes.FAMILIES) == ["horizontal", "vertical", "compartments"]
    assert modes.MODES == tuple(dict.fromkeys(m for f in modes.FAMILIES.values() for m in f.modes))
    assert modes.COLLIDE_MODES == tuple(m for f in modes.FAMILIES.values() for m in f.collide)
    own = [k for f in modes.FAMILIES.values() for k in f.thresholds]
    assert len(own) == len(set(own)) and set(own) <= set(modes.THRESHOLDS)
    assert modes.HORIZONTAL_MODES == modes.FAMILIES["horizontal"].modes
    # a family that gives a threshold another family gives is refused
    twice = ModeFamily(name="other", modes=("x",), collide=(), thresholds={"sync_min": 0.5},
                       applies=lambda case, th: False, measure=None, describe=None)
    with _pytest.raises(ValueError, match="already given"):
        register_family(twice)
    assert "other" not in modes.FAMILIES and modes.THRESHOLDS["sync_min"] == 0.7
