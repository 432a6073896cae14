"""The kernels' state as a few typed bundles of arrays (``typing.NamedTuple``; numba passes them to
compiled functions as structs, at no cost to speed).

Each bundle holds one concern, in SI units, in the container frame (x along the length, y up
against gravity, z across). The Python side builds them from a case
(:func:`pdamper.engine.build.build`); the kernels read them and update the arrays in place.
Scalars in a bundle are fixed for a call; a count the kernels change lives in a one-element array.

**In a kernel, name a bundle's arrays once, before the loop** (``pos = bodies.position``): numba
counts a reference each time a loop reads an array out of a bundle where it cannot prove the
count away, and in the contact loops that cost a third of the step (measured: 1.06 against
0.81 us for one 36-sphere force evaluation).

=================  =========================================================================
bundle             holds
=================  =========================================================================
:class:`Bodies`    the spheres: state, forces, constants
:class:`PairList`  the Verlet list of sphere pairs with each pair's constants and history
:class:`WallList`  the walls (signed-distance primitives), the sphere-wall candidates and
                   each sphere-wall contact's constants and history
:class:`Search`    neighbour-search settings and scratch (link cells, reference positions)
:class:`ContactTable`  the contact laws per material pair (moduli, friction, damping tables)
:class:`Drive`     gravity, the drive direction and the prescribed or coupled container motion
:class:`Samples`   what is recorded at the end of each sample interval, and the running sums
:class:`FrictionRecord`  the touching friction contacts of one force evaluation (Gear)
:class:`ContactSplit`  the ledger's dissipation by contact type, when asked for
:class:`ContactConstants`, :class:`ContactGeometry`  one contact as a force loop hands it to the
                   contact law (:func:`pdamper.kernels.contact.contact`): its constants, its
                   geometry now
:class:`VerletState`, :class:`GearState`  an integrator's own state
:class:`VerletSpan`, :class:`GearSpan`  what one call of an integrator advances
=================  =========================================================================

**Markers.** Some choices are made by the *type* of an empty bundle rather than by a value:
:attr:`Search.method` (:class:`DirectSearch` or :class:`CellSearch`) and :attr:`Drive.coupling`
(:class:`PrescribedMotion` or :class:`CoupledMotion`), as :attr:`ContactTable.law` picks the damping
law, :attr:`ContactTable.tangential` the tangential law and :attr:`Samples.split` (:class:`SplitOff` or a
:class:`ContactSplit`) whether the ledger is split by contact type. numba compiles a kernel for the marker
it is given, so a run compiles the pair search, the structure code and the laws it uses and no other (the link cells and the structure's step are ~2 CPU-s of a
first run's compiling that a small bed on a prescribed drive never needs).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Bodies", "PairList", "WallList", "Search", "DirectSearch", "CellSearch", "ContactTable", "Drive",
           "PrescribedMotion", "CoupledMotion", "marker_class", "Samples", "FrictionRecord", "ContactConstants",
           "ContactGeometry",
           "VerletState", "GearState", "VerletSpan", "GearSpan", "ENERGY_COLUMNS", "STRUCTURE_COLUMNS",
           "FRAME_COLUMNS", "TANGENTIAL_COLUMNS", "SAVED_HISTORY_ROWS", "NO_LOAD", "CONTACT_TYPES", "SplitOff",
           "ContactSplit", "NO_SPLIT"]

#: Columns of :attr:`Samples.energy`: kinetic (lab frame), rotational, potential, elastic, work done
#: by the container, dissipated by normal damping, dissipated by friction [J].
ENERGY_COLUMNS = ("kinetic", "rotational", "potential", "elastic", "work", "damping", "friction")
#: Columns of :attr:`Samples.structure`: x_s [m], v_s [m/s], external work [J], damping loss [J],
#: the structure's mechanical energy [J], the response point's displacement [m].
STRUCTURE_COLUMNS = ("displacement", "velocity", "external_work", "damping_loss", "energy", "response_displacement")
#: Columns of a frame in :attr:`Samples.frames`: position [m], velocity [m/s], spin [rad/s].
FRAME_COLUMNS = 9
#: Columns of a contact's tangential history (:attr:`PairList.tangential`, :attr:`WallList.tangential`),
#: kept by a tangential law with history (the spring, :mod:`pdamper.contact.tangential_spring`): the
#: stored spring force on body i (x, y, z) [N], the stiffness it was stored with [N/m] (0: no
#: spring), the tangential damping ratio fixed when the contact started [-]. All 0 for a contact
#: that is not touching, and for every contact under a law without history.
TANGENTIAL_COLUMNS = ("force_x", "force_y", "force_z", "stiffness", "damping_ratio")
#: Rows of :attr:`GearState.saved_pair_history` (and of ``saved_wall_history``): the approach
#: speed, the damping parameter, then the tangential history's columns.
SAVED_HISTORY_ROWS = 2 + len(TANGENTIAL_COLUMNS)


class Bodies(NamedTuple):
    """The spheres, one row each (container frame)."""

    position: np.ndarray      #: (N, 3) centre [m]
    velocity: np.ndarray      #: (N, 3) velocity relative to the container [m/s]
    spin: np.ndarray          #: (N, 3) angular velocity [rad/s]
    force: np.ndarray         #: (N, 3) contact force [N], filled by the force loops
    torque: np.ndarray        #: (N, 3) contact torque [N m]
    radius: np.ndarray        #: (N,) [m]
    mass: np.ndarray          #: (N,) [kg]
    inv_mass: np.ndarray      #: (N,) [1/kg]
    inv_inertia: np.ndarray   #: (N,) 1 / (2/5 m r^2) [1/(kg m^2)]
    material: np.ndarray      #: (N,) int: row of the sphere's material in the contact table


class PairList(NamedTuple):
    """Verlet list of sphere pairs within ``r_i + r_j + skin``: CSR rows, ``row[i]:row[i+1]`` index
    the partners ``j > i`` of sphere ``i`` (ascending), with each listed pair's constants and
    contact history. The ``next_*`` arrays receive a rebuilt list first, so an overflow leaves the
    list intact."""

    row: np.ndarray              #: (N + 1,) int
    first: np.ndarray            #: (capacity,) int: sphere i of each listed pair
    second: np.ndarray           #: (capacity,) int: sphere j > i
    approach_speed: np.ndarray   #: (capacity,) history: approach speed v_in at (re)touch [m/s]; 0 = not touching
    damping: np.ndarray          #: (capacity,) history: the damping law's parameter of the contact
    stiffness: np.ndarray        #: (capacity,) Hertz k = 4/3 E* sqrt(R*) [N/m^1.5]
    material_pair: np.ndarray    #: (capacity,) int: row of the pair in the contact table
    friction_cap: np.ndarray     #: (capacity,) FRICTION_CAP x reduced mass m* [kg] (Verlet's friction guard)
    tangential: np.ndarray       #: (capacity, 5) history: the tangential law's, columns TANGENTIAL_COLUMNS
    next_row: np.ndarray         #: (N + 1,) int, scratch of the rebuild
    next_second: np.ndarray      #: (capacity,) int, scratch
    next_approach_speed: np.ndarray  #: (capacity,) scratch
    next_damping: np.ndarray     #: (capacity,) scratch
    next_tangential: np.ndarray  #: (capacity, 5) scratch


class WallList(NamedTuple):
    """The container's walls (:mod:`pdamper.geometry.walls`) and the sphere-wall contacts.

    The floor (plane y = 0, normal +y), which every resting sphere touches, is looped over
    directly (``floor`` is its wall index, -1: none); the candidate list holds the other
    (sphere, wall) pairs within ``r + skin``."""

    kind: np.ndarray             #: (W,) int: PLANE or CYLINDER_INSIDE
    data: np.ndarray             #: (W, 7) the primitives' parameters
    floor: int                   #: index of the floor wall, -1 if none
    candidate_body: np.ndarray   #: (capacity,) int: sphere of each candidate
    candidate_wall: np.ndarray   #: (capacity,) int: wall of each candidate
    n_candidates: np.ndarray     #: (1,) int: candidates listed
    stiffness: np.ndarray        #: (N, W) Hertz k [N/m^1.5]
    material_pair: np.ndarray    #: (N, W) int: row in the contact table
    approach_speed: np.ndarray   #: (N, W) history: v_in [m/s]; 0 = not touching
    damping: np.ndarray          #: (N, W) history: the damping law's parameter
    effective_radius: np.ndarray  #: (N, W) R* [m] (flat wall r; concave wall 1/(1/r - 1/R))
    tangential: np.ndarray       #: (N, W, 5) history: the tangential law's, columns TANGENTIAL_COLUMNS


class DirectSearch(NamedTuple):
    """:attr:`Search.method` marker: every pair is tested (small beds)."""


class CellSearch(NamedTuple):
    """:attr:`Search.method` marker: link cells (large beds)."""


class Search(NamedTuple):
    """Neighbour-search settings and scratch (:mod:`pdamper.kernels.neighbours`)."""

    skin: float                  #: list skin [m]
    method: tuple                #: DirectSearch() or CellSearch(): a marker whose *type* picks the pair
                                 #: search when a kernel is compiled, so a run compiles only its own
    origin: np.ndarray           #: (3,) corner of the link-cell grid [m]
    cell_size: float             #: edge of a cell [m]
    cells: np.ndarray            #: (3,) int: cells per axis
    head: np.ndarray             #: (cells,) int scratch
    next: np.ndarray             #: (N,) int scratch
    counts: np.ndarray           #: (N,) int scratch
    reference: np.ndarray        #: (N, 3) positions at the last rebuild [m]


class ContactTable(NamedTuple):
    """The contact laws per material pair; row ``a * n_materials + b`` (the wall material last)."""

    law: tuple                   #: the damping law's marker (:mod:`pdamper.contact.damping`)
    tangential: tuple            #: the tangential law's marker (:mod:`pdamper.contact.tangential`)
    n_materials: int
    modulus: np.ndarray          #: (M*M,) effective modulus E* [Pa]
    shear_modulus: np.ndarray    #: (M*M,) Mindlin's effective shear modulus G* [Pa] (the spring's stiffness)
    friction: np.ndarray         #: (M*M,) mu [-]
    coefficient: np.ndarray      #: (M*M, G) the damping law's coefficient over log-spaced impact speeds
    tangential_damping: np.ndarray  #: (M*M, G) the spring's tangential damping ratio over the same speeds (0: off)
    yield_pressure: np.ndarray   #: (M*M,) Thornton's p_y [Pa] (table over v / v_y), 0: table over v
    log_speed0: float            #: log of the first speed of the table [log(m/s)]
    dlog_speed: float            #: log spacing of the table
    tau: float                   #: friction smoothing [s/m]
    v_floor: float               #: floor on the first-touch approach speed [m/s]
    overlap_limit: float         #: a run stops when an overlap exceeds this fraction of the radius


class PrescribedMotion(NamedTuple):
    """:attr:`Drive.coupling` marker: the container's motion is given (the bed does not move it)."""


class CoupledMotion(NamedTuple):
    """:attr:`Drive.coupling` marker: the container rides on a structure the bed's force moves."""


def marker_class(bundle_type, field):
    """The class of the marker in field ``field`` of a bundle's numba type (``Drive.coupling``,
    ``Search.method``): what an overload resolves on when a kernel is compiled. (The markers are
    empty tuples, so they compare equal as values: ask for their class, never ``==``.)"""
    return bundle_type.types[bundle_type.fields.index(field)].instance_class


#: :attr:`Drive.load` of a drive without a load table (one row, never read or written; writeable, so
#: that a bundle holding it has the numba type of one holding a load).
NO_LOAD = np.zeros((1, 4))


class Drive(NamedTuple):
    """Gravity, the drive direction and the container's motion along it
    (:mod:`pdamper.kernels.drive`)."""

    kind: int                    #: DRIVE_STILL, DRIVE_HARMONIC, DRIVE_SAMPLED, DRIVE_STRUCTURE, DRIVE_MODAL,
                                 #: DRIVE_MODAL_LOAD (drive.py)
    coupling: tuple              #: PrescribedMotion() or CoupledMotion(): a marker whose *type* decides, when a
                                 #: kernel is compiled, whether the structure's step is compiled into it
    par: np.ndarray              #: parameters of the kind (harmonic: X, Omega, phase; structure: M, K, c, F0, Omega)
    table: np.ndarray            #: (K, 5) sampled motion: rows (t_k, c0, c1, c2, c3)
    state: np.ndarray            #: (2, 5) the coupled structure's state, (2 + N, 5) with N modes (kernels/structure.py)
    gravity: np.ndarray          #: (3,) gravity vector in the container frame [m/s^2]
    direction: np.ndarray        #: (3,) unit drive direction in the container frame
    load: np.ndarray = NO_LOAD   #: (K, 4) a structure's load in time (DRIVE_MODAL_LOAD, kernels/structure.py)


#: The contact types of the ledger's split by contact type (the rows of :class:`ContactSplit`'s arrays;
#: the ``"energy_by_contact"`` channel): sphere-sphere pairs, the floor, the container's other walls,
#: the baffles.
CONTACT_TYPES = ("sphere", "floor", "wall", "baffle")


class SplitOff(NamedTuple):
    """:attr:`Samples.split` of a run whose ledger is not split by contact type: an empty marker, so
    the kernels compiled for it hold none of the split (:func:`pdamper.kernels.forces.split_add` and
    its kin resolve to nothing)."""


class ContactSplit(NamedTuple):
    """The energy ledger's dissipation split by contact type (:data:`CONTACT_TYPES`), when a recorder
    asks for the ``"energy_by_contact"`` channel (:attr:`Samples.split`; its *type* puts the split into
    the kernels compiled for it)."""

    wall_type: np.ndarray        #: (W,) int: the row of :data:`CONTACT_TYPES` of each wall
    power: np.ndarray            #: (4, 3) of the last force evaluation, per type: normal damping power [W],
                                 #: tanh friction power [W], a tangential spring's loss [J]
    sums: np.ndarray             #: (4, 2) running, per type: dissipated by normal damping, by friction [J]
    last: np.ndarray             #: (4, 2) Gear's damping and friction powers at the last accepted step [W]
    record: np.ndarray           #: (n, 4, 2) ``sums`` at the end of each sample (the channel)


#: :attr:`Samples.split` of a run without the split.
NO_SPLIT = SplitOff()


class Samples(NamedTuple):
    """What the integrators write at the end of each sample interval (the recorders' kernel
    channels, :mod:`pdamper.recorders.base`); a channel with no rows is not recorded."""

    interval: float              #: sample interval [s]
    wall_force: np.ndarray       #: (n,) mean force of the walls on the spheres along the drive [N]
    energy: np.ndarray           #: (n, 7) energies [J], columns ENERGY_COLUMNS
    frames: np.ndarray           #: (F, N, 9) position, velocity, spin every ``frame_every`` samples
    frame_every: int             #: samples per frame (0: no frames)
    structure: np.ndarray        #: (n, 6 + N) the coupled structure, columns STRUCTURE_COLUMNS, then the N modal
                                 #: coordinates q_k (one mode: x_s) where the array has the columns
    sums: np.ndarray             #: (4,) running: work by the container, damping loss, friction loss [J],
                                 #: impulse along the drive since the last sample [N s]
    split: tuple = NO_SPLIT      #: a ContactSplit: the ledger's dissipation by contact type (NO_SPLIT: not
                                 #: recorded, none of it compiled)


class FrictionRecord(NamedTuple):
    """The touching friction contacts of one force evaluation, for Gear's implicit pass: pairs
    first, then the floor, then the other walls (``ends`` their end rows)."""

    bodies: np.ndarray           #: (capacity, 2) int: (i, j), j < 0 at a wall (-1 - w at wall w with the
                                 #: ledger split by contact type, else -1)
    rows: np.ndarray             #: (capacity, 8): normal (3), slip (3), secant coefficient c, mu F_N
    ends: np.ndarray             #: (3,) int


class ContactConstants(NamedTuple):
    """What the contact law needs to know of one contact besides its geometry: the constants a force
    loop reads from its list (a pair's row of :class:`PairList`, a sphere-wall entry of
    :class:`WallList`). Built in the loop for each touching contact and handed to
    :func:`pdamper.kernels.contact.contact`; scalars only, so the CPU loops and a GPU device
    function build and pass it alike (numba and numba-cuda lower it to registers)."""

    material_pair: int           #: row of the contact in the contact table
    friction: float              #: mu [-]
    stiffness: float             #: Hertz k [N/m^1.5]
    radius: float                #: effective radius R* [m]
    mass: float                  #: effective mass m* [kg]
    friction_cap: float          #: Verlet's friction guard, FRICTION_CAP x m* [kg]


class ContactGeometry(NamedTuple):
    """What the geometry gives of one touching contact now, in the container frame: the overlap and
    its rate, the unit normal ``n`` (from sphere i to j; at a wall into the container), the
    tangential slip ``t`` of i's contact point relative to j's and its length, and the displacement
    ``d`` of i's contact point relative to j's since a tangential law with history last advanced its
    spring (zeros under a law without history, which does not read it). Scalars only, as
    :class:`ContactConstants`."""

    overlap: float               #: delta [m], > 0 touching
    rate: float                  #: d delta / dt [m/s], > 0 approaching
    nx: float                    #: unit normal (x, y, z)
    ny: float
    nz: float
    tx: float                    #: slip (x, y, z) [m/s]
    ty: float
    tz: float
    slip: float                  #: |t| [m/s] (the caller's: the floor's slip has no y part)
    dx: float                    #: contact-point displacement (x, y, z) [m]
    dy: float
    dz: float


class VerletState(NamedTuple):
    """Velocity Verlet's accelerations, now and one step back (for the velocity prediction), and
    what the last drift moved each sphere by."""

    acceleration: np.ndarray
    angular_acceleration: np.ndarray
    previous_acceleration: np.ndarray
    previous_angular_acceleration: np.ndarray
    moved: np.ndarray            #: (N, 6) the last drift's displacement [m] and rotation [rad] (a
                                 #: tangential law with history advances its springs by it; else unused)


class GearState(NamedTuple):
    """Gear's Nordsieck vectors and what a rejected step restores."""

    nordsieck: np.ndarray        #: (6, N, 6) scaled derivatives r_k = h^k/k! x^(k) of position and angle
    predicted: np.ndarray        #: (6, N, 6) the prediction of the current step
    increments: np.ndarray       #: (N, 6) the corrector's increments Delta of the current step (position, angle)
    step: np.ndarray             #: (1,) the step [s] the Nordsieck vector is scaled to
    integrands: np.ndarray       #: (4,) the ledger's integrands at the last accepted step (trapezoid)
    saved_pair_history: np.ndarray   #: (SAVED_HISTORY_ROWS, capacity) pair history before the step
    saved_wall_history: np.ndarray   #: (SAVED_HISTORY_ROWS, N, W) wall history before the step
    saved_structure: np.ndarray  #: the coupled structure's state before the step (the shape of Drive.state)
    friction: FrictionRecord
    anchor: np.ndarray           #: (N, 6) the predicted position and angle the springs were last advanced at
    moved: np.ndarray            #: (N, 6) the prediction of the step less ``anchor``: what the springs advance by
                                 #: (both used by a tangential law with history only)


class VerletSpan(NamedTuple):
    """One call of :func:`pdamper.kernels.verlet.run_verlet`."""

    steps: int                   #: steps to take
    dt: float                    #: the step [s]
    t0: float                    #: time at the start [s]
    step0: int                   #: global step count at the start (samples end every ``sub`` steps)
    sub: int                     #: steps per sample interval
    record: bool                 #: write samples
    skip_samples: int            #: samples of the settling phase (not recorded) before sample 0
    prime: bool                  #: compute the initial accelerations first (first call of a run)


class GearSpan(NamedTuple):
    """One call of :func:`pdamper.kernels.gear.run_gear`."""

    t0: float                    #: time at the start [s]
    t_end: float                 #: time to reach [s]
    h_try: float                 #: the next step to try [s]
    interval: float              #: sample interval [s]; steps end on sample boundaries
    record: bool                 #: write samples
    prime: bool                  #: initialise the Nordsieck vector first (first call of a run)
    tolerance: float             #: local position error per step [m]
    h_min: float                 #: shortest step [s]
    h_max: float                 #: longest step [s]
    max_steps: int               #: accepted steps at most
