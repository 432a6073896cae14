"""A batch of cases as bundles of arrays with a leading case axis (``C`` cases, at most ``N``
spheres, ``K`` list entries per sphere, ``W`` walls): the GPU kernels' state.

The bundles are ``typing.NamedTuple`` s of arrays, as the CPU kernels' (:mod:`pdamper.kernels.bundles`);
numba-cuda passes them to a kernel field by field. :func:`pdamper.engine.cuda` packs them from the
CPU engine's own bundles of each case (:func:`pdamper.engine.build.build`), so a case starts on the
GPU from exactly the state it starts from on the CPU.

**The neighbour list** is per sphere: row ``i`` lists every partner ``j != i`` within
``r_i + r_j + skin``, ascending, in one of two buffers (the rebuild writes the other, then swaps, so
the history can be carried over). The pair ``(i, j)`` with ``i < j`` is *owned* by ``i``: its
constants, its contact history and the result of its contact law (the force on ``i``, the normal and
the friction force: what :func:`~pdamper.kernels.contact.scatter` takes) live in ``i``'s row; ``j``'s
row points to it (``slot``). Every sphere sums its pairs in ascending partner order, then the floor,
then the other walls: the CPU pair loop's order for that sphere (its list is sorted by ``(i, j)``).

**The tangential history** of a law that keeps one (the spring,
:data:`~pdamper.kernels.bundles.TANGENTIAL_COLUMNS`) lives beside ``approach_speed`` and ``damping``:
``(C, 2, N, K, 5)`` for the owned pairs (per buffer, carried over by the rebuild the same way) and
``(C, N, W, 5)`` for the sphere-wall contacts. Under a law without history the kernels never touch it,
and it is packed with one entry per row (``(C, 2, N, 1, 5)``, ``(C, N, 1, 5)``): the same types, so the
same kernel signature, and no memory for nothing.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Spheres", "Lists", "Walls", "Motion", "Control", "Record", "PAIR_RESULT", "CONTROL_FLAGS",
           "FLAG_STARTED", "FLAG_MOVED", "FLAG_PRIMED", "PARTIALS", "WALL_ROW", "PAIR_ROW", "GearState", "GearClock",
           "pair_row_capacity"]

#: Values stored per owned pair after its contact law: the force on the owner (3), the unit normal
#: from the owner to its partner (3), the friction force on the owner (3); then its friction row
#: (Gear's implicit pass): the slip (3), the friction coefficient c and the Coulomb limit.
PAIR_RESULT = 14
#: Values stored per sphere-wall contact: its friction row, the unit normal (3), the slip (3), c and
#: the Coulomb limit.
WALL_ROW = 8
#: Values of a touching pair's row in Gear's compact list for the implicit friction pass: what does not
#: depend on the increments, gathered by every thread before one thread walks the rows: the radii
#: r_i, r_j, the unit normal (3), the slip (3), c, the Coulomb limit, the inverse tangential mass kk,
#: the slip's magnitude, and the factors that turn a force into increments (h^2/2 of 1/m_i, 1/m_j,
#: r_i/I_i, r_j/I_j); last, the row's change of the friction power once walked.
PAIR_ROW = 17
#: Running sums each thread keeps (and saves between launches): work done by the container, loss
#: by normal damping, loss by friction [J], impulse along the drive since the last sample [N s].
PARTIALS = 4
#: :attr:`Control.flags` columns: the drive has started (the velocities jumped), a rebuild is due,
#: the initial accelerations are computed.
FLAG_STARTED = 0
FLAG_MOVED = 1
FLAG_PRIMED = 2
CONTROL_FLAGS = 3


class Spheres(NamedTuple):
    """The spheres of every case (container frame), padded to ``N`` rows."""

    position: np.ndarray          #: (C, N, 3) [m]
    velocity: np.ndarray          #: (C, N, 3) relative to the container [m/s]
    spin: np.ndarray              #: (C, N, 3) [rad/s]
    acceleration: np.ndarray      #: (C, N, 3) Verlet's accelerations now and one step back
    angular_acceleration: np.ndarray
    previous_acceleration: np.ndarray
    previous_angular_acceleration: np.ndarray
    reference: np.ndarray         #: (C, N, 3) positions at the last list build [m]
    moved: np.ndarray             #: (C, N, 6) what the springs advance by: Verlet's drift, Gear's prediction
                                  #: less the one they were last advanced at (displacement [m], rotation [rad])
    radius: np.ndarray            #: (C, N) [m]
    mass: np.ndarray              #: (C, N) [kg]
    inv_mass: np.ndarray          #: (C, N)
    inv_inertia: np.ndarray       #: (C, N)
    material: np.ndarray          #: (C, N) int: the sphere's material in its case's table
    count: np.ndarray             #: (C,) int: spheres of each case


class Lists(NamedTuple):
    """The per-sphere neighbour lists (module docstring), their constants and contact history."""

    partner: np.ndarray           #: (C, 2, N, K) int32: partners in ascending order, per buffer
    length: np.ndarray            #: (C, 2, N) int32: entries of each row, per buffer
    slot: np.ndarray              #: (C, N, K) int32: for j's entry of a pair (i, j), i < j, the entry in i's row
    approach_speed: np.ndarray    #: (C, 2, N, K) history of the owned pairs (0: not touching), per buffer
    damping: np.ndarray           #: (C, 2, N, K) history: the damping law's parameter, per buffer
    tangential: np.ndarray        #: (C, 2, N, K, 5) history: the tangential law's, per buffer ((C, 2, N, 1, 5): none)
    stiffness: np.ndarray         #: (C, N, K) Hertz k of the owned pairs [N/m^1.5]
    material_pair: np.ndarray     #: (C, N, K) int: row in the batch's contact table
    friction_cap: np.ndarray      #: (C, N, K) FRICTION_CAP x m* [kg]
    result: np.ndarray            #: (C, N, K, PAIR_RESULT) the owned pairs' contact results
    buffer: np.ndarray            #: (C,) int32: the buffer in use
    skin: np.ndarray              #: (C,) list skin [m]


class Walls(NamedTuple):
    """The walls of every case (:mod:`pdamper.geometry.walls`) and each sphere-wall contact."""

    kind: np.ndarray              #: (C, W) int
    data: np.ndarray              #: (C, W, 7)
    count: np.ndarray             #: (C,) int: walls of each case
    floor: np.ndarray             #: (C,) int: the floor's index, -1 if none
    stiffness: np.ndarray         #: (C, N, W) [N/m^1.5]
    material_pair: np.ndarray     #: (C, N, W) int: row in the batch's contact table
    effective_radius: np.ndarray  #: (C, N, W) [m]
    approach_speed: np.ndarray    #: (C, N, W) history
    damping: np.ndarray           #: (C, N, W) history
    tangential: np.ndarray        #: (C, N, W, 5) history: the tangential law's ((C, N, 1, 5): none)
    row: np.ndarray               #: (C, N, W, WALL_ROW) each contact's friction row (Gear's implicit pass)


class Motion(NamedTuple):
    """Each case's drive: a motion of its parameters alone along ``direction``
    (:func:`pdamper.kernels.drive.parametric_motion`)."""

    kind: np.ndarray              #: (C,) int: the compiled motion's kind number (Drive.kind)
    par: np.ndarray               #: (C, 3) its parameters (harmonic: X [m], Omega [rad/s], phase [rad])
    gravity: np.ndarray           #: (C, 3) [m/s^2], container frame
    direction: np.ndarray         #: (C, 3) unit drive direction, container frame
    jump: np.ndarray              #: (C, 3) the velocity jump -v_c(0+) d at the drive's start [m/s]


class Control(NamedTuple):
    """Each case's clock, progress and status (kept between launches)."""

    dt: np.ndarray                #: (C,) Verlet's step [s]
    sub: np.ndarray               #: (C,) int: steps per sample
    settle_steps: np.ndarray      #: (C,) int: steps of the settling, before the drive
    total_steps: np.ndarray       #: (C,) int: settling and drive
    segment_steps: np.ndarray     #: (C,) int: steps of one of the CPU engine's segments (its clock restarts there)
    segment_samples: np.ndarray   #: (C,) int: samples of one segment
    interval: np.ndarray          #: (C,) 1 / sample rate [s]
    sample_interval: np.ndarray   #: (C,) sub x dt [s]: what a sample's impulse is divided by
    step: np.ndarray              #: (C,) int: steps done
    status: np.ndarray            #: (C,) int: STATUS_* of pdamper.kernels.forces
    culprit: np.ndarray           #: (C,) int: the sphere concerned
    fail_step: np.ndarray         #: (C,) int: the step that failed
    flags: np.ndarray             #: (C, CONTROL_FLAGS) int
    partials: np.ndarray          #: (C, threads, PARTIALS) the threads' running sums


class Record(NamedTuple):
    """What is recorded at the end of each sample of the drive (the CPU kernels' channels,
    :class:`pdamper.kernels.bundles.Samples`); a case's channel with no rows is not recorded."""

    wall_force: np.ndarray        #: (C, S) [N]
    energy: np.ndarray            #: (C, S, 7) [J]
    frames: np.ndarray            #: (C, F, N, 9)
    wall_force_rows: np.ndarray   #: (C,) int
    energy_rows: np.ndarray       #: (C,) int
    frame_rows: np.ndarray        #: (C,) int
    frame_every: np.ndarray       #: (C,) int: samples per frame (0: none)
    settle_samples: np.ndarray    #: (C,) int
    bed_mass: np.ndarray          #: (C,) [kg]


class GearState(NamedTuple):
    """Gear's Nordsieck vectors of every case and what a rejected step restores."""

    nordsieck: np.ndarray         #: (C, 6, N, 6) scaled derivatives of position and angle
    increments: np.ndarray        #: (C, N, 6) the corrector's increments (position, angle) of a bed larger
                                  #: than gear.STAGED_SPHERES (a smaller one's are in shared memory)
    saved_pair: np.ndarray        #: (C, R, N, K) the rows' history before the step: approach speed, damping,
                                  #: then the tangential history's columns (R = SAVED_HISTORY_ROWS; 2: none)
    saved_wall: np.ndarray        #: (C, R, N, W) the walls' history before the step
    anchor: np.ndarray            #: (C, N, 6) the predicted position and angle the springs were last advanced at
    integrands: np.ndarray        #: (C, threads, 4) each thread's ledger integrands at the last accepted step
    pair_rows: np.ndarray         #: (C, P, PAIR_ROW) scratch: this step's touching pairs for the implicit
                                  #: friction pass, in the CPU's order (P = pair_row_capacity)
    pair_ends: np.ndarray         #: (C, P, 3) int: the spheres (i, j) of each of those rows, and its level in the
                                  #: walk (rows of one level share no sphere)


def pair_row_capacity(n: int, k: int) -> int:
    """Rows of :attr:`GearState.pair_rows` that every owned pair of ``n`` spheres with ``k`` list
    entries each fits in: row ``i`` owns at most ``min(k, n - 1 - i)`` (its partners ``j > i``)."""
    return max(1, sum(min(k, n - 1 - i) for i in range(n)))


class GearClock(NamedTuple):
    """Each case's Gear clock over the CPU stepper's spans (the settling, then the drive's segments)."""

    interval: np.ndarray          #: (C,) 1 / sample rate [s]
    tolerance: np.ndarray         #: (C,) local position error per step [m]
    h_min: np.ndarray             #: (C,) [s]
    h_max: np.ndarray             #: (C,) [s]
    settle_samples: np.ndarray    #: (C,) int
    n_samples: np.ndarray         #: (C,) int: samples of the drive
    segment_samples: np.ndarray   #: (C,) int
    spans: np.ndarray             #: (C,) int: spans of the run
    span: np.ndarray              #: (C,) int: the span under way (spans: done)
    t: np.ndarray                 #: (C,) time [s]
    h: np.ndarray                 #: (C,) the next step to try [s]
    hs: np.ndarray                #: (C,) the step the Nordsieck vector is scaled to [s]
    rejected: np.ndarray          #: (C,) int: rejected steps
    cycles: np.ndarray            #: (C, PROBES) int: the probed kernel's cycles in each phase of a step, and its
                                  #: counts (:mod:`.probe`; zeros under the production kernel)
