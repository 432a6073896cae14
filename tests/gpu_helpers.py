"""Shared pieces of the GPU engine's simulator tests (tests/kernels/gpu): tiny, violent cases and
running them on both engines."""

import math

import numpy as np

from pdamper.excitation import HarmonicDrive
from pdamper.geometry import Cylinder
from pdamper.materials import Material
from pdamper.params import Case, Container, ContactModel, InitialState, Numerics, ParticleSet, Recording
from pdamper.simulation import Simulation

STEEL_COATED = Material(name="coated", youngs_modulus=5e9, poisson_ratio=0.35, density=1200.0, restitution=0.6)


def tiny_case(shape="cuboid", n=4, damping="calibrated", direction=None, tilt=(0.02, 0.0, 0.05), baffles=(),
              coated=False, seed=0, time_step=None, cycles=0.02):
    """A short, violent case: a 30 mm, 20 Hz drive (48 g: the spheres fly), 1 ms of it sampled at
    10 kHz after 0.2 ms of settling; about 900 Verlet steps."""
    geometry = Cylinder() if shape == "cylinder" else None
    kw = {"geometry": geometry} if geometry is not None else {}
    walls = {"floor": STEEL_COATED} if coated else {}
    container = Container(tilt=tilt, baffles=baffles, wall_materials=walls, **kw)
    drive = HarmonicDrive(stroke=0.03, frequency=20.0, **({"direction": direction} if direction else {}))
    return Case(particles=(ParticleSet(count=n),), container=container, drive=drive, cycles=cycles, drop_cycles=0,
                contact=ContactModel(damping=damping), recording=Recording(sample_rate=10000.0),
                numerics=Numerics(integrator="verlet", time_step=time_step),
                initial=InitialState(settle_time=2e-4, seed=seed))


def on_both(cases, threads=None):
    """Each case on the CPU engine and, all together, on the GPU engine (simulator)."""
    import warnings

    from pdamper.engine.cuda import run_jobs

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # lift-off: intended
        cpu = [Simulation(c) for c in cases]
        gpu = [Simulation(c) for c in cases]
    for s in cpu:
        s.run()
    jobs = [s._gpu_job()[0] for s in gpu]
    outcomes = run_jobs(jobs, threads=threads)
    for s, o in zip(gpu, outcomes):
        s._gpu_done(o)
    return cpu, gpu, outcomes


def close(a, b, rel=1e-12):
    scale = max(float(np.max(np.abs(a))), 1e-300)
    return float(np.max(np.abs(a - b))) <= rel * scale


def pile_case(columns=3, rows=3, seed=0, cycles=0.004):
    """A resting pile under :func:`tiny_case`'s drive: a square layer of ``columns x rows`` spheres
    on the floor, each touching its neighbours, and a second layer in its hollows, each sphere of it
    touching the four below it and its neighbours; every sphere moving and spinning a little
    (seeded), so that every contact slips. Many touching pairs from the first step (a 3 x 3 layer:
    13 spheres, 32 pairs)."""
    import dataclasses

    r = 0.005
    s = 2 * r * (1 - 1e-6)  # centres 10 nm closer than touching: within check_positions' tolerance
    lo = [(-s * (columns - 1) / 2 + s * a, r * (1 - 1e-6), -s * (rows - 1) / 2 + s * b)
          for a in range(columns) for b in range(rows)]
    up = r * (1 - 1e-6) + math.sqrt(s * s - s * s / 2)
    hi = [(-s * (columns - 2) / 2 + s * a, up, -s * (rows - 2) / 2 + s * b)
          for a in range(columns - 1) for b in range(rows - 1)]
    pos = tuple(lo + hi)
    rng = np.random.default_rng(seed)
    vel = tuple(map(tuple, rng.normal(0.0, 0.05, (len(pos), 3))))
    spin = tuple(map(tuple, rng.normal(0.0, 10.0, (len(pos), 3))))
    case = tiny_case("cuboid", n=len(pos), direction=(1.0, 0.3, 0.2), cycles=cycles)
    return dataclasses.replace(case, initial=dataclasses.replace(case.initial, positions=pos, velocities=vel,
                                                                 spins=spin))
