"""The same damper in LIGGGHTS, for the side-by-side benchmark (``benchmarks/run.py``) and the
cross-code check (``benchmarks/crosscheck.py``, docs/crosscheck.md).

LIGGGHTS-PUBLIC 3.8 (Debian: ``apt-get install liggghts``). This is a deck of our own for a
cross-check, not a port of pdamper. What it models of a pdamper case:

- **Container**: a cuboid (``container.geometry``) in pdamper's container frame (floor at y = 0,
  length along x, width along z), its walls as triangle meshes (ASCII STL written here). Walls of
  one material share one mesh; ``per_wall=True`` gives every wall a mesh of its own (then the
  force on each wall is recorded apart). **Inner baffles** (``container.baffles``) are the faces
  of their solid plates: both x faces across the whole width from ``gap_below`` to
  ``height - gap_above``, and the lower and upper edge faces where a gap leaves room (faces that
  lie on a container wall are left out: no sphere reaches them). **Coated walls**
  (``container.wall_materials``) and baffles of their own material are meshes with an atom type
  of their own, so their E, nu (Hertz and Mindlin stiffness) and their restitution and friction
  pairs are their own.
- **Drive**: every mesh moves with ``fix move/mesh ... wiggle amplitude X*d period 1/f``, d the
  drive direction in the container frame, from the end of the settling on (x = X sin(Omega t),
  as pdamper's harmonic drive, started with the same jump to the velocity X Omega). Any drive
  direction: the case's ``drive.direction`` or ``drive.angle``.
- **Tilt**: as pdamper applies it (``pdamper.geometry.tilt.container_vectors``): the box stays
  axis-aligned, gravity (``fix gravity ... vector``) and the drive direction are the lab vectors
  seen from the container frame.
- **Spheres**: one particle set; the initial centres are pdamper's own
  (``pdamper.initial.initial_positions`` with ``numpy.random.default_rng(case.initial.seed)``,
  so ``initial.layers = "auto"`` stacks them as pdamper does), at rest; they settle for
  ``case.initial.settle_time`` in the still box before the drive starts.
- **Contact model** (sphere-sphere and sphere-wall alike): ``pair_style gran model hertz
  tangential history`` and ``fix wall/gran model hertz tangential history mesh``. Normal: Hertz,
  k_n = 4/3 E* sqrt(R* delta), with LIGGGHTS' viscoelastic damping gamma_n = -2 sqrt(5/6) beta
  sqrt(S_n m*), beta = ln e / sqrt(ln^2 e + pi^2), S_n = 2 E* sqrt(R* delta) (the law of
  pdamper's ``contact.damping = "tsuji"``; pdamper's default is the calibrated Hertz-Gonthier
  law); ``limitForce`` off (LIGGGHTS' default: the damped normal force may pull at the end of an
  impact). Tangential (LIGGGHTS' ``tangential_model_history.h``): the tangential displacement s
  is summed per contact while it lasts (s += v_t dt, then projected onto the new contact plane;
  set to zero when the contact opens), the force is F_t = -k_t s with the current Mindlin
  stiffness k_t = 8 G* sqrt(R* delta), G_i = E_i / (2 (1 + nu_i)), 1/G* = (2 - nu_1)/G_1 +
  (2 - nu_2)/G_2; where |k_t s| > mu |F_n| the contact slides: F_t and s are scaled back to
  mu |F_n| (no damping); otherwise it sticks and the tangential damping -gamma_t v_t is added,
  gamma_t = -2 sqrt(5/6) beta sqrt(S_t m*), S_t = k_t (``tangential_damping on``, LIGGGHTS'
  default; ``model_options="tangential_damping off"`` removes it, and on the two-layer vertical
  bed that changes eta* by a quarter: docs/crosscheck.md). No rolling friction, no cohesion.
  With mu = 0 (``contact.friction = 0``: the frictionless variant) the tangential force is zero.
  E, nu per atom type (``youngsModulus``, ``poissonsRatio``); e and mu per type pair
  (``coefficientRestitution``, ``coefficientFriction``) from the case: ``contact.friction_for``
  and pdamper's rule for the COR (a ``[[contact.pair]]`` law, else a coating's own
  ``restitution`` -- the lower where both have one --, else ``contact.restitution``; only a
  constant COR can be written). ``hard_particles yes`` (E above 1e9 Pa allowed). Particle density
  ``rho`` of the case.
- **Numerics**: ``units si``, fixed step ``dt`` (1 us by default), ``fix nve/sphere``
  (velocity Verlet with rotation), ``neighbor 0.2 r bin``, ``neigh_modify delay 0``,
  ``boundary f f f`` with a margin of 2 X + 4 r around the box's travel, one process.
- **Record**: the force of the spheres on every mesh (``fix mesh/surface/stress``, global vector
  f_mesh[1..3]) averaged over every sample interval of ``case.recording.sample_rate`` by
  ``fix ave/time 1 n n`` (n steps an interval: the mean force over the interval, the impulse /
  interval signal pdamper records). The container's driving force along the drive is
  -(sum over meshes of f_mesh) . d (the walls push the spheres with -f_mesh), analysed by
  pdamper's own complex power (``pdamper.run.analyze_signals``): eta* = E / (pi m_bed X^2
  Omega^2) the same way for both codes. Optionally (``dump_fps``) the spheres' positions and
  velocities every 1/dump_fps s of the drive (``dump custom``), in the inertial frame in which
  the box moves (subtract x_c d for the container frame: :func:`read_dump` does).

The two codes differ on purpose in the tangential law (this deck's spring against pdamper's
regularised Coulomb, or pdamper's own ``contact.tangential`` law where there is one) and in the
normal damping law unless pdamper runs with ``contact.damping = "tsuji"``; eta* agrees within the
seed spread where those do not decide it, not bit for bit.
"""

from __future__ import annotations

import math
import re
import resource
import shutil
import subprocess
import time
from pathlib import Path

import numpy as np

LIGGGHTS = "liggghts"
INSTALL_HINT = "install it with `apt-get install liggghts` (Debian/Ubuntu), then re-run the benchmark"

#: LIGGGHTS' contact model, written into the deck for the spheres and for the walls.
MODEL = "model hertz tangential history"


def available() -> str | None:
    """Path of the LIGGGHTS executable, or None."""
    return shutil.which(LIGGGHTS)


# --- geometry: the walls as quadrilaterals ---------------------------------------------------------

def _rect(axis: int, at: float, lo, hi, inward: float):
    """A rectangle in the plane ``coordinate[axis] = at`` spanning ``lo``..``hi`` in the other two
    coordinates (in axis order), its normal along ``inward`` * e_axis (+1 or -1): four corners."""
    a, b = [k for k in range(3) if k != axis]
    corners = []
    for u, v in ((lo[0], lo[1]), (hi[0], lo[1]), (hi[0], hi[1]), (lo[0], hi[1])):
        p = [0.0, 0.0, 0.0]
        p[axis], p[a], p[b] = at, u, v
        corners.append(np.array(p))
    n = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    if n[axis] * inward < 0:
        corners = corners[::-1]
    return corners


def wall_quads(case) -> dict[str, list]:
    """{wall name: [quad, ...]} of the cuboid's walls (pdamper's names: x_min, x_max, floor, lid,
    z_min, z_max) and of the baffles ("baffle 1", ...), in the container frame [m]; each quad's
    normal points to where the spheres are."""
    g = case.container.geometry
    L, W, H = g.length, g.width, g.height
    x0, x1, z0, z1 = -L / 2, L / 2, -W / 2, W / 2
    out = {"x_min": [_rect(0, x0, (0, z0), (H, z1), +1)], "x_max": [_rect(0, x1, (0, z0), (H, z1), -1)],
           "floor": [_rect(1, 0.0, (x0, z0), (x1, z1), +1)], "lid": [_rect(1, H, (x0, z0), (x1, z1), -1)],
           "z_min": [_rect(2, z0, (x0, 0), (x1, H), +1)], "z_max": [_rect(2, z1, (x0, 0), (x1, H), -1)]}
    for k, b in enumerate(case.container.baffles, 1):
        xa, xb = b.position - b.thickness / 2, b.position + b.thickness / 2
        ya, yb = b.gap_below, H - b.gap_above
        quads = [_rect(0, xa, (ya, z0), (yb, z1), -1), _rect(0, xb, (ya, z0), (yb, z1), +1)]
        if b.gap_below > 0:
            quads.append(_rect(1, ya, (xa, z0), (xb, z1), -1))
        if b.gap_above > 0:
            quads.append(_rect(1, yb, (xa, z0), (xb, z1), +1))
        out[f"baffle {k}"] = quads
    return out


def stl(quads, name: str = "walls") -> str:
    """ASCII STL of ``quads`` (two triangles each) [m]."""
    out = [f"solid {name}"]
    for q in quads:
        for tri in ((q[0], q[1], q[2]), (q[0], q[2], q[3])):
            a, b, c = tri
            n = np.cross(b - a, c - a)
            n /= np.linalg.norm(n)
            out.append(f"facet normal {n[0]:.6e} {n[1]:.6e} {n[2]:.6e}\n outer loop")
            out += [f"  vertex {p[0]:.9e} {p[1]:.9e} {p[2]:.9e}" for p in (a, b, c)]
            out.append(" endloop\nendfacet")
    out.append(f"endsolid {name}")
    return "\n".join(out) + "\n"


# --- materials and contact pairs -------------------------------------------------------------------

def _cor(contact, a, b) -> float:
    """The constant COR of materials a, b by pdamper's rule (a [[contact.pair]] law, else a
    coating's own restitution, the lower of two, else the contact model's law)."""
    pair = (a.name, b.name) in contact.pair_restitution or (b.name, a.name) in contact.pair_restitution
    own = [m.restitution for m in (a, b) if m.restitution is not None]
    if not pair and own:
        return float(min(own))
    law = contact.restitution_for(a.name, b.name)
    value = getattr(law, "value", None)
    if value is None or type(law).__name__ != "ConstantRestitution":
        raise ValueError(f"the LIGGGHTS deck writes a constant COR only; {a.name}-{b.name} has {law!r}")
    return float(value)


def meshes(case, per_wall: bool = False):
    """(materials, meshes): the materials of the atom types (type 1: the spheres, then one type
    per distinct wall material), and [(mesh id, [wall names], atom type), ...] -- one mesh per wall
    material, or per wall with ``per_wall``."""
    c = case.container
    names = c.walls()[2]
    mats = c.wall_material_list()
    types = [case.particles[0].material]
    kinds: dict[str, int] = {}
    groups: dict[str, list] = {}
    for name, m in zip(names, mats):
        if m.name not in kinds:
            kinds[m.name] = len(types) + 1
            types.append(m)
        key = name if per_wall else m.name
        groups.setdefault(key, []).append((name, kinds[m.name]))
    out = []
    for k, (key, walls) in enumerate(groups.items()):
        out.append((f"w{k}", [w for w, _ in walls], walls[0][1]))
    return types, out


def _matrix(values) -> str:
    return " ".join(f"{v:.12g}" for row in values for v in row)


# --- the deck ---------------------------------------------------------------------------------------

def write_deck(case, workdir: Path, *, dt: float, per_wall: bool = False, dump_fps: float = 0.0,
               model_options: str = "") -> dict:
    """Write ``in.damper`` and one ``<mesh>.stl`` per mesh for the cuboid ``case`` into ``workdir``;
    return what :func:`run` needs to read the record back. ``model_options``: LIGGGHTS keywords
    appended to the contact model (e.g. ``"tangential_damping off"``; none by default)."""
    opts = f" {model_options}" if model_options else ""
    from pdamper.geometry.tilt import container_vectors
    from pdamper.initial import initial_positions

    g = case.container.geometry
    if g.shape != "cuboid":
        raise ValueError("the LIGGGHTS deck models the cuboid only")
    if len(case.particles) != 1:
        raise ValueError("the LIGGGHTS deck models one particle set")
    if case.drive.stroke is None or not case.drive.frequency:
        raise ValueError("the LIGGGHTS deck models a harmonic drive (stroke and frequency)")
    p = case.particles[0]
    pos = initial_positions(case, np.random.default_rng(case.initial.seed))
    gvec, dvec = container_vectors(case.container.tilt, case.gravity, case.drive.lab_direction())
    gn = float(np.linalg.norm(gvec))
    types, mesh_list = meshes(case, per_wall)
    nt = len(types)
    cor = [[_cor(case.contact, a, b) if 1 in (i, j) else 0.5 for j, b in enumerate(types, 1)]
           for i, a in enumerate(types, 1)]
    mu = [[case.contact.friction_for(a.name, b.name) if 1 in (i, j) else 0.0 for j, b in enumerate(types, 1)]
          for i, a in enumerate(types, 1)]
    fs = case.recording.sample_rate
    sub = int(round(1.0 / (fs * dt)))
    if abs(sub * dt * fs - 1.0) > 1e-9:
        raise ValueError(f"dt = {dt} s does not divide the sample interval 1/{fs:g} s")
    settle = int(math.ceil(case.initial.settle_time * fs)) * sub
    drive = int(round(case.duration * fs)) * sub
    X, period = case.drive.stroke, 1.0 / case.drive.frequency
    m = 2 * X + 4 * p.radius  # domain margin beyond the box's travel
    workdir.mkdir(parents=True, exist_ok=True)
    quads = wall_quads(case)
    for mid, walls, _ in mesh_list:
        (workdir / f"{mid}.stl").write_text(stl([q for w in walls for q in quads[w]], mid))
    atoms = "\n".join(f"create_atoms 1 single {x:.12e} {y:.12e} {z:.12e} units box" for x, y, z in pos)
    mesh_fixes = "\n".join(f"fix {mid} all mesh/surface/stress file {mid}.stl type {t}  # {', '.join(walls)}"
                           for mid, walls, t in mesh_list)
    ids = " ".join(mid for mid, _, _ in mesh_list)
    moves = "\n".join(f"fix move_{mid} all move/mesh mesh {mid} wiggle amplitude {X * dvec[0]:.15e} "
                      f"{X * dvec[1]:.15e} {X * dvec[2]:.15e} period {period:.15e}" for mid, _, _ in mesh_list)
    forces = " ".join(f"f_{mid}[{k}]" for mid, _, _ in mesh_list for k in (1, 2, 3))
    dump_every = int(round(1.0 / (dump_fps * dt))) if dump_fps > 0 else 0
    dump = (f"dump traj all custom {dump_every} traj.dump id x y z vx vy vz omegax omegay omegaz\n"
            "dump_modify traj sort id\n") if dump_every else ""
    deck = f"""# pdamper cross-check: {case.n_particles} spheres, {case.container.describe()}, X = {X * 1e3:g} mm, f = {1 / period:g} Hz, seed {case.initial.seed}
# drive direction (container frame) {dvec[0]:.6e} {dvec[1]:.6e} {dvec[2]:.6e}; gravity {gvec[0]:.6e} {gvec[1]:.6e} {gvec[2]:.6e} m/s^2
# atom types: {', '.join(f'{k} {t.name}' for k, t in enumerate(types, 1))}
atom_style granular
atom_modify map array
boundary f f f
newton off
communicate single vel yes
units si
region domain block {-g.length / 2 - m} {g.length / 2 + m} {-m} {g.height + m} {-g.width / 2 - m} {g.width / 2 + m} units box
create_box {nt} domain
neighbor {0.2 * p.radius} bin
neigh_modify delay 0
fix m1 all property/global youngsModulus peratomtype {' '.join(f'{t.youngs_modulus:.12g}' for t in types)}
fix m2 all property/global poissonsRatio peratomtype {' '.join(f'{t.poisson_ratio:.12g}' for t in types)}
fix m3 all property/global coefficientRestitution peratomtypepair {nt} {_matrix(cor)}
fix m4 all property/global coefficientFriction peratomtypepair {nt} {_matrix(mu)}
hard_particles yes
pair_style gran {MODEL}{opts}
pair_coeff * *
timestep {dt}
fix gravi all gravity {gn} vector {gvec[0] / gn:.15e} {gvec[1] / gn:.15e} {gvec[2] / gn:.15e}
{mesh_fixes}
fix walls all wall/gran {MODEL} mesh n_meshes {len(mesh_list)} meshes {ids}{opts}
{atoms}
set group all diameter {2 * p.radius} density {p.material.density}
fix integr all nve/sphere
thermo_style custom step atoms ke
thermo {settle}
run {settle}
{moves}
fix fav all ave/time 1 {sub} {sub} {forces} file force.txt
{dump}thermo {drive}
run {drive}
"""
    (workdir / "in.damper").write_text(deck)
    return {"settle_steps": settle, "drive_steps": drive, "sub": sub, "dvec": dvec, "gvec": gvec,
            "meshes": [(mid, walls) for mid, walls, _ in mesh_list], "dump_every": dump_every}


def read_force(workdir: Path, info: dict) -> dict:
    """{mesh id: (n, 3) mean force of the spheres on that mesh in every sample interval [N]}."""
    rows = np.loadtxt(Path(workdir) / "force.txt", comments="#", ndmin=2)
    return {mid: rows[:, 1 + 3 * k: 4 + 3 * k] for k, (mid, _) in enumerate(info["meshes"])}


def read_dump(workdir: Path, case, info: dict, dt: float) -> dict:
    """The dumped frames as pdamper's trajectory arrays, in the container frame: ``time`` [s] from
    the start of the drive, ``position``, ``velocity`` (frames, N, 3) [m, m/s], ``spin`` [rad/s]."""
    text = (Path(workdir) / "traj.dump").read_text().split("ITEM: TIMESTEP\n")[1:]
    steps, frames = [], []
    for block in text:
        lines = block.splitlines()
        steps.append(int(lines[0]))
        n = int(lines[2])
        frames.append(np.array([ln.split() for ln in lines[8:8 + n]], dtype=float))
    steps = np.array(steps)
    keep = steps >= info["settle_steps"]
    arr = np.array(frames)[keep]
    t = (steps[keep] - info["settle_steps"]) * dt
    x, v, _ = case.drive.motion(t)
    d = info["dvec"]
    return {"time": t, "position": arr[:, :, 1:4] - x[:, None, None] * d, "velocity": arr[:, :, 4:7] - v[:, None, None] * d,
            "spin": arr[:, :, 7:10]}


def run(case, workdir: Path, *, dt: float = 1e-6, timeout: float | None = None, per_wall: bool = False,
        dump_fps: float = 0.0, model_options: str = "") -> dict:
    """Run ``case`` in LIGGGHTS at the fixed step ``dt`` [s]; return its step cost and eta*.

    ``us_per_step`` is LIGGGHTS' own loop time of the driven phase over its steps (the bed in
    motion, forces averaged every step); ``wall_time_s`` and ``cpu_time_s`` the whole process's
    (the CPU time is the one to compare on a shared machine); ``eta_star`` and ``energy_per_cycle_J`` come from
    pdamper's complex-power analysis of the LIGGGHTS force record; ``wall_power_W`` is the mean
    power the container puts into the spheres through each mesh over the analysed cycles
    (<-f_mesh . d v_c>; their sum is the mean power of the drive).
    """
    exe = available()
    if exe is None:
        raise FileNotFoundError(f"`{LIGGGHTS}` is not on PATH; {INSTALL_HINT}")
    workdir = Path(workdir)
    info = write_deck(case, workdir, dt=dt, per_wall=per_wall, dump_fps=dump_fps, model_options=model_options)
    t0, c0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    proc = subprocess.run([exe, "-in", "in.damper", "-log", "log.liggghts", "-nocite"],
                          cwd=workdir, capture_output=True, text=True, timeout=timeout)
    wall = time.perf_counter() - t0
    c1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    log = (workdir / "log.liggghts").read_text() if (workdir / "log.liggghts").exists() else ""
    if proc.returncode != 0:
        tail = "\n".join((log or proc.stdout + proc.stderr).splitlines()[-15:])
        raise RuntimeError(f"LIGGGHTS failed (exit {proc.returncode}) in {workdir}:\n{tail}")
    res = read_results(case, workdir, info)
    res["wall_time_s"] = wall
    res["cpu_time_s"] = (c1.ru_utime - c0.ru_utime) + (c1.ru_stime - c0.ru_stime)
    return res


def finished(workdir: Path) -> bool:
    """Whether ``workdir`` holds a LIGGGHTS run that reached its end (both runs' loop times)."""
    log = Path(workdir) / "log.liggghts"
    return log.exists() and len(re.findall(r"Loop time of", log.read_text())) >= 2


def read_results(case, workdir: Path, info: dict) -> dict:
    """eta* and the rest of :func:`run`'s answer from a finished run in ``workdir``."""
    from pdamper.recorders.signals import Signals
    from pdamper.run import analyze_signals

    log = (Path(workdir) / "log.liggghts").read_text()
    loops = [(float(a), int(b)) for a, b in re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", log)]
    drive_time, drive_steps = loops[-1]
    per_mesh = read_force(workdir, info)
    # the spheres push the box with f_mesh; the walls push the spheres with -f_mesh (along the drive)
    along = {mid: -(f @ info["dvec"]) for mid, f in per_mesh.items()}
    wall_force = sum(along.values())
    interval = 1.0 / case.recording.sample_rate
    sig = Signals.from_run(case, interval, wall_force)
    res = analyze_signals(case, sig)
    first = int(round(case.drop_cycles * case.recording.sample_rate / case.drive.frequency))
    power = {", ".join(walls): float(np.mean(along[mid][first:] * sig.velocity[first:])) for mid, walls in info["meshes"]}
    return {"us_per_step": 1e6 * drive_time / drive_steps, "steps": drive_steps, "loop_time_s": drive_time,
            "eta_star": float(res.eta_star), "energy_per_cycle_J": float(res.energy_per_cycle_J),
            "wall_power_W": power}
