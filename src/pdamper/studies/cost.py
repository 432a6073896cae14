"""How long a case is expected to take, before it runs: the order in which a study's cases start.

A study finishes when its last case does. With the cases started longest first (the "longest
processing time" rule), a worker that frees up takes the next-longest case and the last cases to
start are the short ones, so no worker idles long while another works through a long case. The
ranking needs only relative costs, so :func:`expected_cost` is a model in arbitrary units:

    cost = (driven + settling time) x spheres x layers x steps per simulated second

- spheres x layers: the work of one step (each sphere and its contacts); a bed deeper than the
  floor holds (spheres over the floor's capacity, :func:`pdamper.analysis.modes.floor_capacity`)
  has more contacts per sphere;
- steps per simulated second: Gear's step is capped by the resting Hertz contacts (their
  vibration at the static load m g: omega = sqrt(k/m), k = 3/2 m g / delta, which is stiffer for
  small and light spheres and a stiffer material), and shortened by impacts as the drive's speed
  bound V grows (1 + ln(1 + V / 0.04 m/s): the step counts of the 36-sphere cuboid at 3, 14, 30 mm
  grow as the log of V, docs/integrators.md) and by friction (mu = 1 takes ~2.6x the steps of
  mu = 0.1; CHANGELOG.md, "Performance history").

Its exponents come from the benchmark's sample of every DEM curve of the paper (27 curves x 5
strokes, CPU seconds per curve; CHANGELOG.md, "Performance history", "Cases scheduled by their cost"). A resumed
study can do better than the model: :func:`learned_costs` scales it by the wall time its finished
cases took (per setting). The order changes no number of any case (each case is independent and
seeded, tests/studies/test_cost.py).
"""

from __future__ import annotations

import math

from ..errors import InputError

__all__ = ["expected_cost", "learned_costs", "finished", "ranked"]

#: The drive speed [m/s] at which impacts start to shorten Gear's steps (fit; see the module text).
V_REF = 0.04
#: Steps per second grow as omega_rest ** ALPHA (fit over the modulus, density and radius curves).
ALPHA = 0.35
#: mu above the paper's 0.1 adds this many times (mu - 0.1) to the step rate (friction: 36 and 44, mu = 1).
FRICTION = 1.2
#: A tilt of the container adds TILT x sin(largest tilt) to the work of a step (the bed piles against a
#: wall: more resting pair contacts; the 3-degree tilt curves take 1.1-1.75x their untilted ones).
TILT = 8.0
#: Impacts of smaller spheres are shorter (the Hertz contact time goes as the radius): the impact part of
#: the step rate scales as R_REF / r.
R_REF = 0.005


def _rest_omega(case) -> float:
    """The largest vibration frequency [rad/s] of a sphere resting on the floor (Hertz at m g)."""
    g = max(case.gravity, 0.1)  # a weightless bed still touches now and then: any finite scale
    best = 0.0
    for p in case.particles:
        mat = p.material
        e_star = mat.youngs_modulus / (2.0 * (1.0 - mat.poisson_ratio**2))
        weight = p.mass * g
        delta = (weight / (4.0 / 3.0 * e_star * math.sqrt(p.radius))) ** (2.0 / 3.0)
        best = max(best, math.sqrt(1.5 * weight / delta / p.mass))
    return best


def expected_cost(case) -> float:
    """A case's expected cost in arbitrary units (only ratios between cases mean anything)."""
    from ..analysis.modes import floor_capacity

    n = case.n_particles
    layers = max(1.0, n / max(floor_capacity(case), 1))
    t = case.drive.duration(case.cycles) + case.initial.settle_time
    speed = max(float(case.drive.speed_bound()), 0.0)
    mu = max([case.contact.friction, *case.contact.pair_friction.values()])
    r_min = min(p.radius for p in case.particles)
    tilt = max(abs(math.sin(a)) for a in case.container.tilt) if case.container.tilt else 0.0
    rate = (_rest_omega(case) ** ALPHA * (1.0 + R_REF / r_min * math.log1p(speed / V_REF))
            * (1.0 + FRICTION * max(mu - 0.1, 0.0)))
    return t * n * layers * (1.0 + TILT * tilt) * rate


def learned_costs(items, group_of: dict, measured: dict) -> dict:
    """``{key: cost}`` for ``items`` (``(key, point, seed, case)``): the model's cost, scaled per group
    (``group_of[key]``, e.g. a study's setting) by the median ratio of measured wall time to model
    cost over that group's finished cases (``measured``: ``{group: [(case, wall_time_s), ...]}``,
    from the store of a resumed study); a group with nothing finished is scaled by the median
    ratio over all groups. Without finished cases this is the model alone."""
    import statistics

    ratios = {}
    for group, done in measured.items():
        r = [w / expected_cost(c) for c, w in done if isinstance(w, (int, float)) and math.isfinite(w) and w > 0]
        if r:
            ratios[group] = statistics.median(r)
    overall = statistics.median(ratios.values()) if ratios else 1.0
    return {it[0]: expected_cost(it[3]) * ratios.get(group_of.get(it[0]), overall) for it in items}


def finished(store, spec) -> list:
    """``[(case, wall_time_s), ...]`` of the cases ``store`` holds (failed ones left out)."""
    out = []
    for rec in store.records():
        w = rec.get("wall_time_s")
        if "failed" in rec or not isinstance(w, (int, float)):
            continue
        try:
            out.append((spec.case(rec["point"], rec["seed"]), float(w)))
        except (InputError, KeyError, TypeError):  # a record this grid cannot place: no help for the estimate
            continue
    return out


def ranked(items, costs: dict | None = None) -> list:
    """``items`` (``(key, point, seed, case, ...)``) longest first: by ``costs[key]`` when given, else by
    :func:`expected_cost`; ties keep the given order."""
    cost = costs if costs is not None else {it[0]: expected_cost(it[3]) for it in items}
    return sorted(items, key=lambda it: -cost[it[0]])
