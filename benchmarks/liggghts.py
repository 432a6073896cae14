"""The same damper in LIGGGHTS, for the side-by-side benchmark (``benchmarks/run.py``).

LIGGGHTS-PUBLIC 3.8 (Debian: ``apt-get install liggghts``) runs the paper's cuboid as a moving
triangle mesh: the six walls are an STL box (written here, in pdamper's container frame: floor
at y = 0, length along x, width along z), moved with ``fix move/mesh ... wiggle`` along the drive
direction; gravity carries the container tilt (the box stays axis-aligned, gravity and drive are
expressed in its frame exactly as pdamper does). Contacts: ``model hertz tangential history``
(Hertz with LIGGGHTS' restitution-based viscoelastic damping, Mindlin tangential spring with a
Coulomb limit), the same E, nu, eps and mu as the case. The spheres start from pdamper's own
initial positions for the case's seed and settle for the same time in the still box.

The force of the spheres on the box (``fix mesh/surface/stress``, global vector) is averaged
over every sample interval by ``fix ave/time`` (the same impulse / interval signal pdamper
records), so the complex-power analysis of both codes sees the same kind of signal.

This is a deck of our own for a cross-check, not a port of pdamper: the damping law differs
(LIGGGHTS' Tsuji-type damping vs pdamper's calibrated Hertz-Gonthier) and so does friction
(tangential spring vs regularised Coulomb), so eta* agrees within the seed spread, not bit for
bit.
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

LIGGGHTS = "liggghts"
INSTALL_HINT = "install it with `apt-get install liggghts` (Debian/Ubuntu), then re-run the benchmark"


def available() -> str | None:
    """Path of the LIGGGHTS executable, or None."""
    return shutil.which(LIGGGHTS)


def _box_stl(length, height, width) -> str:
    """ASCII STL of the cuboid's six walls (12 triangles) in the container frame [m]."""
    x0, x1, y0, y1, z0, z1 = -length / 2, length / 2, 0.0, height, -width / 2, width / 2
    v = {(i, j, k): (x, y, z) for i, x in enumerate((x0, x1)) for j, y in enumerate((y0, y1))
         for k, z in enumerate((z0, z1))}
    quads = [((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)),  # floor y = 0
             ((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)),  # lid
             ((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)),  # x = -L/2
             ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1)),  # x = +L/2
             ((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)),  # z = -w/2
             ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1))]  # z = +w/2
    out = ["solid box"]
    for q in quads:
        for tri in ((q[0], q[1], q[2]), (q[0], q[2], q[3])):
            a, b, c = (np.array(v[t]) for t in tri)
            n = np.cross(b - a, c - a)
            n /= np.linalg.norm(n)
            out.append(f"facet normal {n[0]:.6e} {n[1]:.6e} {n[2]:.6e}\n outer loop")
            out += [f"  vertex {p[0]:.9e} {p[1]:.9e} {p[2]:.9e}" for p in (a, b, c)]
            out.append(" endloop\nendfacet")
    out.append("endsolid box")
    return "\n".join(out) + "\n"


def write_deck(case, workdir: Path, *, dt: float) -> dict:
    """Write ``in.damper`` and ``box.stl`` for a cuboid ``case`` into ``workdir``."""
    from pdamper.geometry.tilt import container_vectors
    from pdamper.initial import initial_positions

    g = case.container.geometry
    if g.shape != "cuboid":
        raise ValueError("the LIGGGHTS deck models the cuboid only")
    if len(case.particles) != 1:
        raise ValueError("the LIGGGHTS deck models one particle set")
    p = case.particles[0]
    wall = case.container.material
    pos = initial_positions(case, np.random.default_rng(case.initial.seed))
    gvec, dvec = container_vectors(case.container.tilt, case.gravity, case.drive.lab_direction())
    gn = float(np.linalg.norm(gvec))
    eps = case.contact.restitution_for(p.material.name, p.material.name).value
    eps_w = case.contact.restitution_for(p.material.name, wall.name).value
    mu = case.contact.friction_for(p.material.name, p.material.name)
    mu_w = case.contact.friction_for(p.material.name, wall.name)
    fs = case.recording.sample_rate
    sub = int(round(1.0 / (fs * dt)))
    settle = int(math.ceil(case.initial.settle_time * fs)) * sub
    drive = int(round(case.duration * fs)) * sub
    X, period = case.drive.stroke, 1.0 / case.drive.frequency
    m = 2 * X + 4 * p.radius  # domain margin beyond the box's travel
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "box.stl").write_text(_box_stl(g.length, g.height, g.width))
    atoms = "\n".join(f"create_atoms 1 single {x:.12e} {y:.12e} {z:.12e} units box" for x, y, z in pos)
    deck = f"""# pdamper benchmark: {case.n_particles} spheres in the paper's cuboid, X = {X * 1e3:g} mm, f = {1 / period:g} Hz
atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
region domain block {-g.length / 2 - m} {g.length / 2 + m} {-m} {g.height + m} {-g.width / 2 - m} {g.width / 2 + m} units box
create_box 2 domain
neighbor {0.2 * p.radius} bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype {p.material.youngs_modulus} {wall.youngs_modulus}
fix m2 all property/global poissonsRatio peratomtype {p.material.poisson_ratio} {wall.poisson_ratio}
fix m3 all property/global coefficientRestitution peratomtypepair 2 {eps} {eps_w} {eps_w} {eps_w}
fix m4 all property/global coefficientFriction peratomtypepair 2 {mu} {mu_w} {mu_w} {mu_w}
hard_particles yes
pair_style gran model hertz tangential history
pair_coeff * *
timestep {dt}
fix gravi all gravity {gn} vector {gvec[0] / gn:.15e} {gvec[1] / gn:.15e} {gvec[2] / gn:.15e}
fix box all mesh/surface/stress file box.stl type 2
fix walls all wall/gran model hertz tangential history mesh n_meshes 1 meshes box
{atoms}
set group all diameter {2 * p.radius} density {p.material.density}
fix integr all nve/sphere
thermo_style custom step atoms ke
thermo {settle}
run {settle}
fix move all move/mesh mesh box wiggle amplitude {X * dvec[0]:.15e} {X * dvec[1]:.15e} {X * dvec[2]:.15e} period {period}
fix fav all ave/time 1 {sub} {sub} f_box[1] f_box[2] f_box[3] file force.txt
thermo {drive}
run {drive}
"""
    (workdir / "in.damper").write_text(deck)
    return {"settle_steps": settle, "drive_steps": drive, "sub": sub, "dvec": dvec}


def run(case, workdir: Path, *, dt: float = 1e-6, timeout: float | None = None) -> dict:
    """Run ``case`` in LIGGGHTS at the fixed step ``dt`` [s]; return its step cost and eta*.

    ``us_per_step`` is LIGGGHTS' own loop time of the driven phase over its steps (the bed in
    motion, forces averaged every step); ``eta_star`` and ``energy_per_cycle_J`` come from
    pdamper's complex-power analysis of the LIGGGHTS force record.
    """
    from pdamper.recorders.signals import Signals
    from pdamper.run import analyze_signals

    exe = available()
    if exe is None:
        raise FileNotFoundError(f"`{LIGGGHTS}` is not on PATH; {INSTALL_HINT}")
    workdir = Path(workdir)
    info = write_deck(case, workdir, dt=dt)
    t0 = time.perf_counter()
    proc = subprocess.run([exe, "-in", "in.damper", "-log", "log.liggghts", "-nocite"],
                          cwd=workdir, capture_output=True, text=True, timeout=timeout)
    wall = time.perf_counter() - t0
    log = (workdir / "log.liggghts").read_text() if (workdir / "log.liggghts").exists() else ""
    if proc.returncode != 0:
        tail = "\n".join((log or proc.stdout + proc.stderr).splitlines()[-15:])
        raise RuntimeError(f"LIGGGHTS failed (exit {proc.returncode}) in {workdir}:\n{tail}")
    loops = [(float(a), int(b)) for a, b in re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", log)]
    drive_time, drive_steps = loops[-1]
    rows = np.loadtxt(workdir / "force.txt", comments="#", ndmin=2)
    # the spheres push the box with f_mesh; the walls push the spheres with -f_mesh (along the drive)
    wall_force = -(rows[:, 1:4] @ info["dvec"])
    res = analyze_signals(case, Signals.from_run(case, 1.0 / case.recording.sample_rate, wall_force))
    return {"us_per_step": 1e6 * drive_time / drive_steps, "steps": drive_steps, "wall_time_s": wall,
            "eta_star": float(res.eta_star), "energy_per_cycle_J": float(res.energy_per_cycle_J)}
