"""A case turned into the kernels' bundles (:mod:`pdamper.kernels.bundles`).

:func:`build` computes everything the kernels need from a :class:`~pdamper.params.Case`: the
spheres' initial state and constants, the material table of the chosen contact laws, the
walls and their per-sphere constants, the neighbour-search grid, the drive. The bundles'
arrays are then owned by the :class:`~pdamper.simulation.Simulation` that advances them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..contact import DAMPING_LAWS, SPEED_GRID, TANGENTIAL_LAWS, kernel_law
from ..contact.cor_constant import ConstantRestitution
from ..contact.hertz import hertz_stiffness
from ..contact.hertz_gonthier import contact_time, effective_radius
from ..contact.tangential_spring import damping_ratio as tangential_damping_ratio
from ..errors import InputError
from ..geometry.tilt import container_vectors
from ..geometry.walls import CYLINDER_INSIDE, PLANE
from ..initial import initial_positions
from ..kernels.bundles import (CONTACT_TYPES, TANGENTIAL_COLUMNS, Bodies, CellSearch, ContactTable, CoupledMotion,
                               DirectSearch, Drive, PairList, PrescribedMotion, Search, WallList)
from ..kernels.drive import DRIVE_KINDS
from ..materials import effective_modulus, effective_shear_modulus
from ..params import Case

__all__ = ["Engine", "build", "drive_bundle", "auto_time_step", "grow_pairs", "grow_walls", "CELLS_THRESHOLD"]

#: Above this many spheres the Verlet list is built with link cells ("auto" search).
CELLS_THRESHOLD = 200


@dataclass
class Engine:
    """The kernel bundles of one case (replaced, not resized, when a list outgrows its arrays)."""

    case: Case
    bodies: Bodies
    pairs: PairList
    walls: WallList
    search: Search
    table: ContactTable
    drive: Drive
    #: "direct" (all pairs) or "cells" (link cells)
    search_name: str
    #: names of the walls, in the order of ``walls.kind``
    wall_names: tuple
    #: the fixed step [s] for Verlet (:func:`auto_time_step`)
    dt: float
    #: (W,) int: each wall's row of :data:`~pdamper.kernels.bundles.CONTACT_TYPES` (the floor, the
    #: container's other walls, the baffles), for the ledger's split by contact type
    wall_types: np.ndarray = None

    @property
    def n(self) -> int:
        """Number of spheres."""
        return self.bodies.radius.shape[0]


def auto_time_step(case: Case) -> float:
    """Time step [s] for the fixed-step integrator: the shortest Hertz contact time among the
    case's contact types at the expected largest impact speed, over ``steps_per_contact``,
    capped by ``max_time_step``. The expected impact speed is ``numerics.max_impact_speed`` or
    2.5 x the larger of the drive's largest speed (:meth:`~pdamper.excitation.DriveBase.speed_bound`)
    and the largest initial sphere speed, plus 0.1 m/s."""
    num = case.numerics
    if num.time_step is not None:
        return num.time_step
    if num.max_impact_speed is not None:
        v = num.max_impact_speed
    else:
        v0 = np.asarray(case.initial.velocities if case.initial.velocities is not None else [[0.0, 0.0, 0.0]])
        v = 2.5 * max(case.drive.speed_bound(), float(np.max(np.linalg.norm(v0, axis=-1)))) + 0.1
    walls = list(dict.fromkeys(case.container.wall_material_list()))
    best = math.inf
    for a in case.particles:
        for b in case.particles:
            es = effective_modulus(a.material, b.material)
            rs = effective_radius(a.radius, b.radius)
            ms = a.mass * b.mass / (a.mass + b.mass)
            best = min(best, contact_time(ms, rs, es, v))
        for wall in walls:
            best = min(best, contact_time(a.mass, a.radius, effective_modulus(a.material, wall), v))
    return min(best / num.steps_per_contact, num.max_time_step)


def build(case: Case) -> Engine:
    """The kernel bundles of ``case`` at its initial state (spheres placed, at rest unless the
    case gives velocities and spins)."""
    rng = np.random.default_rng(case.initial.seed)
    rad = np.concatenate([np.full(p.count, p.radius) for p in case.particles])
    mass = np.concatenate([np.full(p.count, p.mass) for p in case.particles])
    n = rad.size
    # materials: the spheres' first, then the walls' (the container's material first)
    names = list(dict.fromkeys(p.material.name for p in case.particles))
    mats = [next(p.material for p in case.particles if p.material.name == nm) for nm in names]
    material = np.concatenate([np.full(p.count, names.index(p.material.name)) for p in case.particles]).astype(np.int64)
    per_wall = case.container.wall_material_list()
    wall_mats = list(dict.fromkeys([case.container.material] + per_wall))
    table = _contact_table(case, mats + wall_mats)
    wall_material = np.array([len(mats) + wall_mats.index(m) for m in per_wall], dtype=np.int64)
    bodies = Bodies(position=initial_positions(case, rng), velocity=_initial_vectors(case.initial.velocities, n, "velocities"),
                    spin=_initial_vectors(case.initial.spins, n, "spins"), force=np.zeros((n, 3)), torque=np.zeros((n, 3)),
                    radius=rad, mass=mass, inv_mass=1.0 / mass, inv_inertia=1.0 / (0.4 * mass * rad * rad),
                    material=material)
    walls, wall_names = _walls(case, bodies, table, wall_material)
    search, search_name = _search(case, rad, n)
    gvec, dvec = container_vectors(case.container.tilt, case.gravity, case.drive.lab_direction())
    drive = drive_bundle(case.running_drive, gvec, dvec)
    return Engine(case=case, bodies=bodies, pairs=grow_pairs(None, max(16, n * 8), n), walls=walls, search=search,
                  table=table, drive=drive, search_name=search_name, wall_names=wall_names, dt=auto_time_step(case),
                  wall_types=_wall_types(case, walls))


def drive_bundle(drive, gravity=None, direction=None) -> Drive:
    """The kernels' :class:`~pdamper.kernels.bundles.Drive` of a drive (:mod:`pdamper.excitation`),
    with the gravity vector and drive direction in the container frame (default: none, along x)."""
    name, par, tab, state = drive.kernel_drive()
    if name not in DRIVE_KINDS:
        raise InputError(f"{type(drive).__name__}.kernel_drive() names the compiled motion {name!r}; the kernels have "
                         f"{', '.join(repr(k) for k in DRIVE_KINDS)} (pdamper.kernels.drive.DRIVE_KINDS)")
    gravity = np.zeros(3) if gravity is None else np.asarray(gravity, dtype=float)
    direction = np.array([1.0, 0.0, 0.0]) if direction is None else np.asarray(direction, dtype=float)
    # the marker follows what the drive is: one the bed's force moves is read from the state
    coupling = CoupledMotion() if drive.coupled else PrescribedMotion()
    return Drive(kind=DRIVE_KINDS[name], coupling=coupling, par=par, table=tab, state=state, gravity=gravity,
                 direction=direction, load=np.ascontiguousarray(drive.kernel_load(), dtype=float))


def _initial_vectors(given, n, name):
    if given is None:
        return np.zeros((n, 3))
    arr = np.array(given, dtype=float)
    if arr.shape != (n, 3) or not np.all(np.isfinite(arr)):
        raise InputError(f"initial.{name}: expected {n} finite rows of (x, y, z), got shape {arr.shape}")
    return arr


def _contact_table(case, mats) -> ContactTable:
    """Per material pair (row a * M + b): E*, G*, mu, the damping law's coefficient and the
    tangential spring's damping ratio over impact speed (zeros with ``tangential_damping`` off)."""
    law = DAMPING_LAWS[case.contact.damping]
    nmat = len(mats)
    npair = nmat * nmat
    modulus = np.empty(npair)
    shear_modulus = np.empty(npair)
    friction = np.empty(npair)
    coefficient = np.empty((npair, SPEED_GRID.size))
    tangential_damping = np.zeros((npair, SPEED_GRID.size))
    yield_pressure = np.zeros(npair)
    for a in range(nmat):
        for b in range(nmat):
            mp = a * nmat + b
            modulus[mp] = effective_modulus(mats[a], mats[b])
            shear_modulus[mp] = effective_shear_modulus(mats[a], mats[b])
            friction[mp] = case.contact.friction_for(mats[a].name, mats[b].name)
            # epsilon over impact speed, or over v / v_y (p_y > 0: the kernel computes v_y per contact)
            eps, yield_pressure[mp] = kernel_law(_restitution(case.contact, mats[a], mats[b])).kernel_table()
            coefficient[mp] = law.coefficient(eps)
            if case.contact.tangential_damping:
                tangential_damping[mp] = tangential_damping_ratio(eps)
    return ContactTable(law=law.marker(), tangential=TANGENTIAL_LAWS[case.contact.tangential].marker(),
                        n_materials=nmat, modulus=modulus, shear_modulus=shear_modulus, friction=friction,
                        coefficient=coefficient, tangential_damping=tangential_damping, yield_pressure=yield_pressure,
                        log_speed0=math.log(SPEED_GRID[0]),
                        dlog_speed=math.log(SPEED_GRID[1]) - math.log(SPEED_GRID[0]),
                        tau=float(case.contact.tau), v_floor=float(case.contact.v_in_floor),
                        overlap_limit=float(case.numerics.overlap_limit))


def _restitution(contact, a, b):
    """The COR law of materials a, b: a [[contact.pair]] law, else a coating's own restitution
    (the lower of the two where both have one), else the contact model's law."""
    if (a.name, b.name) in contact.pair_restitution or (b.name, a.name) in contact.pair_restitution:
        return contact.restitution_for(a.name, b.name)
    own = [m.restitution for m in (a, b) if m.restitution is not None]
    return ConstantRestitution(value=min(own)) if own else contact.restitution


def _walls(case, bodies, table, wall_material):
    kinds, data, names = case.container.walls()
    data = np.ascontiguousarray(data)
    nw = len(kinds)
    n = bodies.radius.size
    # the floor (plane y = 0, normal +y) gets the force loop's direct path
    floor = -1
    for w in range(nw):
        if kinds[w] == PLANE and np.allclose(data[w, :4], [0.0, 1.0, 0.0, 0.0]):
            floor = w
    stiffness = np.empty((n, nw))
    r_star = np.empty((n, nw))
    material_pair = np.empty((n, nw), dtype=np.int64)
    nmat = table.n_materials
    for w in range(nw):
        for i in range(n):
            rs = effective_radius(bodies.radius[i], concave_radius=data[w, 6]) if kinds[w] == CYLINDER_INSIDE \
                else bodies.radius[i]
            mp = bodies.material[i] * nmat + wall_material[w]
            r_star[i, w] = rs
            material_pair[i, w] = mp
            stiffness[i, w] = hertz_stiffness(table.modulus[mp], rs)
    cap = max(8, n * nw)
    walls = WallList(kind=np.asarray(kinds), data=data, floor=int(floor), candidate_body=np.empty(cap, dtype=np.int64),
                     candidate_wall=np.empty(cap, dtype=np.int64), n_candidates=np.zeros(1, dtype=np.int64),
                     stiffness=stiffness, material_pair=material_pair, approach_speed=np.zeros((n, nw)),
                     damping=np.zeros((n, nw)), effective_radius=r_star,
                     tangential=np.zeros((n, nw, len(TANGENTIAL_COLUMNS))))
    return walls, tuple(names)


def _wall_types(case, walls) -> np.ndarray:
    """Each wall's row of :data:`~pdamper.kernels.bundles.CONTACT_TYPES`: the floor, the shape's other
    walls, then the baffles (:meth:`pdamper.params.Container.walls` lists the shape's first)."""
    own = len(case.container.geometry.walls()[0])
    types = np.array([CONTACT_TYPES.index("wall" if w < own else "baffle") for w in range(walls.kind.shape[0])],
                     dtype=np.int64)
    if walls.floor >= 0:
        types[walls.floor] = CONTACT_TYPES.index("floor")
    return types


def _search(case, rad, n):
    num = case.numerics
    skin = num.skin if num.skin is not None else 0.2 * float(rad.max())
    name = num.neighbour_search
    if name == "auto":
        name = "cells" if n > CELLS_THRESHOLD else "direct"
    cut = 2 * float(rad.max()) + skin
    vmin, vmax = case.container.geometry.bounding_box()
    span = vmax - vmin + 2 * cut
    cells = np.maximum(1, np.floor(span / cut)).astype(np.int64)
    # keep cells at least `cut` wide in every direction
    cell_size = max(float(np.max(span / cells)), cut)
    method = CellSearch() if name == "cells" else DirectSearch()
    search = Search(skin=float(skin), method=method, origin=vmin - cut, cell_size=cell_size, cells=cells,
                    head=np.empty(int(np.prod(cells)), dtype=np.int64), next=np.empty(n, dtype=np.int64),
                    counts=np.zeros(n, dtype=np.int64), reference=np.full((n, 3), np.inf))
    return search, name


def grow_pairs(pairs: PairList | None, capacity: int, n: int | None = None) -> PairList:
    """A pair list of ``capacity`` listed pairs, keeping the rows of ``pairs`` (None: a new, empty
    list for ``n`` spheres)."""
    if pairs is not None:
        n = pairs.row.shape[0] - 1
    new = PairList(row=np.zeros(n + 1, dtype=np.int64), first=np.zeros(capacity, dtype=np.int64),
                   second=np.zeros(capacity, dtype=np.int64), approach_speed=np.zeros(capacity),
                   damping=np.zeros(capacity), stiffness=np.zeros(capacity),
                   material_pair=np.zeros(capacity, dtype=np.int64), friction_cap=np.zeros(capacity),
                   tangential=np.zeros((capacity, len(TANGENTIAL_COLUMNS))),
                   next_row=np.zeros(n + 1, dtype=np.int64), next_second=np.zeros(capacity, dtype=np.int64),
                   next_approach_speed=np.zeros(capacity), next_damping=np.zeros(capacity),
                   next_tangential=np.zeros((capacity, len(TANGENTIAL_COLUMNS))))
    if pairs is not None:
        for old, arr in zip(pairs, new):
            arr[: old.shape[0]] = old
    return new


def grow_walls(walls: WallList, capacity: int) -> WallList:
    """``walls`` with room for ``capacity`` sphere-wall candidates (the candidates are rebuilt)."""
    return walls._replace(candidate_body=np.empty(capacity, dtype=np.int64),
                          candidate_wall=np.empty(capacity, dtype=np.int64))
