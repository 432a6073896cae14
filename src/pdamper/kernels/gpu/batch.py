"""A batch of cases as a few flat buffers, one row per case: the GPU kernels' state, laid out so that
a case's block finds everything at offsets of its own row.

Eight arrays make the whole batch (:class:`Batch`), a row (or a block of rows) a case; a kernel
takes them as one bundle, the contact table and the laws' markers (its parameters: about 1 KB,
against the 7 KB of the ~90 arrays of the kernels before). Inside a case's row the values sit in *fields* of one value
per sphere (``st``: field ``f`` of sphere ``i`` at ``f * N + i``, ``N`` the batch's padded sphere
count), one per pair (``gv``, ``iv``: at ``offset + p``, ``P`` pairs at most) or one per
sphere-wall contact (``w * N + i``), so the lanes of a warp, which take consecutive spheres or
pairs, read consecutive addresses. The offsets of each region within a row are worked out once on
the host (:func:`layout`) and kept in the case's integer slots (``ci[O_*]``); every other slot has
a name here, none is a number in the kernels.

- ``st`` (float): the spheres: position, velocity, spin (kept in the block's shared memory while a
  launch runs), Verlet's accelerations, the list's reference positions, the springs' displacement
  and anchor, radius, mass, inverse mass and inertia, and Gear's Nordsieck vector (``NORD + 6 k +
  d``: row ``k`` of degree of freedom ``d``).
- ``gv`` (float): per pair, in two list buffers (the rebuild writes the other, carrying the history
  over): Hertz stiffness and Verlet's friction guard; the contact history (approach speed, the damping
  law's parameter), in two list buffers times two time buffers: a step reads one time buffer and
  writes the other, and the buffers change places when the step is accepted, so a rejected step
  leaves nothing to restore; the contact law's result (:data:`RESULT` values); each sphere-wall
  contact's constants, history (two time buffers) and friction row.
- ``th`` (float, ``(C, rows, 5)``): the tangential law's five columns of history a contact
  (:data:`~pdamper.kernels.bundles.TANGENTIAL_COLUMNS`), in the same buffers: pair ``p`` of list
  buffer ``lb`` and time buffer ``tb`` at row ``(2 lb + tb) TP + p``, sphere-wall contact ``(i, w)``
  at ``TWALL + tb TW + i W + w``; under a law without history one row of each, never read. A table,
  as the CPU's contact law takes it.
- ``iv`` (int32): the pair lists (CSR rows in the CPU's order: ``i`` ascending, then its partners
  ``j > i`` ascending) and, per sphere, the pairs it is the second of (ascending ``i``): a sphere's
  sum over its pairs in ascending partner order, the CPU pair loop's order for it, with no atomics;
  the material pairs; Gear's compact list of touching friction rows and their levels.
- ``ci`` (int64), ``cf`` (float): the case's counts, clock, status and progress (``I_*``, ``F_*``),
  its threads' running sums between launches.
- ``walls`` (float, ``(C W, 7)``): the walls' signed-distance primitives, ``W`` rows a case.
- ``out`` (float): the recorded channels (wall force, energies, frames).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Batch", "layout", "row_widths", "WARP", "MAX_WARPS", "MAX_SPHERES", "SPHERES_PER_LANE", "RESULT", "WALL_ROW",
           "PARTIALS", "SHARED_FIELDS", "STATE_SLOTS"]

#: Lanes of a warp.
WARP = 32
#: Spheres a lane takes in a step's sphere passes (a warp holds a bed of up to 64 spheres).
SPHERES_PER_LANE = 2
#: Warps of a block at most: a bed of up to ``MAX_WARPS x WARP x SPHERES_PER_LANE`` spheres (the paper's
#: 144 and 176 beds in 3 warps); a larger bed runs on the CPU engine (:func:`pdamper.engine.cuda.refusal`).
MAX_WARPS = 4
#: The largest bed a block takes: its spheres' hot state fills the block's 48 KB of shared memory.
MAX_SPHERES = MAX_WARPS * WARP * SPHERES_PER_LANE

# ---- st: one value per sphere (field f of sphere i at f * N + i)
X, V, SPIN, A, AL, AP, ALP, REF = 0, 3, 6, 9, 12, 15, 18, 21
MOVED = 24          #: (6) what the springs advance by: Verlet's drift, Gear's prediction less its anchor
ANCHOR = 30         #: (6) Gear: the predicted position and angle the springs were last advanced at
RAD, MASS, IMASS, IINERT = 36, 37, 38, 39
NORD = 40           #: (36) Gear's Nordsieck vector, NORD + 6 k + d
ST_FIELDS = 76

# ---- the block's shared memory, one value per sphere (field f of sphere i at f * N + i)
S_X, S_V, S_SPIN, S_MOVED, S_RAD = 0, 3, 6, 9, 15
SHARED_FIELDS = 16

#: Values of a pair's result: the force on i (3), the unit normal from i to j (3), the friction force
#: on i (3), the slip (3), the friction coefficient c and the Coulomb limit (Gear's friction row).
RESULT = 14
R_F, R_N, R_T, R_S, R_C, R_LIM = 0, 3, 6, 9, 12, 13
#: Values of a sphere-wall contact's friction row: the unit normal (3), the slip (3), c, the limit.
WALL_ROW = 8
#: Running sums each thread keeps between launches: work done by the container, loss by normal
#: damping, loss by friction [J], impulse along the drive since the last sample [N s].
PARTIALS = 4

# ---- ci: the case's integer slots
(I_N, I_NW, I_FLOOR, I_LIST, I_TIME, I_STATUS, I_CULPRIT, I_FAIL_STEP, I_STEP, I_STARTED, I_MOVED, I_PRIMED,
 I_SUB, I_SETTLE_STEPS, I_TOTAL_STEPS, I_SEG_STEPS, I_SEG_SAMPLES, I_WF_ROWS, I_EN_ROWS, I_FR_ROWS, I_FRAME_EVERY,
 I_SETTLE_SAMPLES, I_NMAT, I_ROW0, I_DRIVE, I_SPAN, I_SPANS, I_SAMPLES, I_REJECTED) = range(29)
# the offsets of the regions of the case's rows (layout)
(O_PK, O_PCAP, O_PV, O_PD, O_RES, O_DP, O_WK, O_WRS, O_WV, O_WD, O_WROW,
 O_ROW, O_SEC, O_FIRST, O_MP, O_INROW, O_INPAIR, O_WMP, O_MAT, O_WALK, O_LEVEL, O_WKIND,
 O_ENERGY, O_FRAMES, O_N, O_P, O_W, O_TP, O_TW, O_TWALL) = range(32, 62)
CI = 64
#: Values a thread keeps of its loop's state (:func:`pdamper.kernels.gpu.forces.get`): the step's counters,
#: clock, flags and times live in the case's rows, read where they are used, not in registers through
#: every phase; integer slot ``k`` of thread ``t`` at ``ci[CI + k bd + t]``, float slot ``k`` after the
#: threads' ledger rows in ``cf`` (:data:`F_STATE`).
STATE_SLOTS = 21

# ---- cf: the case's float slots
(F_DT, F_INTERVAL, F_SAMPLE_INTERVAL, F_SKIN, F_BED_MASS, F_T, F_H, F_HS, F_TOL, F_H_MIN, F_H_MAX) = range(11)
F_GRAVITY, F_DIRECTION, F_JUMP, F_PAR = 11, 14, 17, 20
F_PARTIALS = 24     #: (3, threads, PARTIALS) each thread's ledger rows (pdamper.kernels.gpu.forces.ledger)
CF_FIXED = F_PARTIALS
#: The threads' float state slots in ``cf`` start ``F_STATE x threads`` after :data:`F_PARTIALS`.
F_STATE = 3 * PARTIALS


class Batch(NamedTuple):
    """The batch's buffers (module docstring): one row per case."""

    st: np.ndarray      #: (C, ST_FIELDS x N) float: the spheres
    gv: np.ndarray      #: (C, .) float: pairs and sphere-wall contacts
    th: np.ndarray      #: (C, ., 5) float: the tangential history, a row a contact (pairs, then walls)
    iv: np.ndarray      #: (C, .) int32: lists, material pairs, Gear's rows
    ci: np.ndarray      #: (C, CI + STATE_SLOTS x threads) int64: counts, clock, status, offsets, the threads' slots
    cf: np.ndarray      #: (C, .) float: clock, drive, running sums
    walls: np.ndarray   #: (C x W, 7) float: the walls' primitives, W rows a case
    out: np.ndarray     #: (C, .) float: the recorded channels


def layout(n: int, p: int, w: int, spring: bool, samples: int, frames: int) -> dict:
    """The offsets of the regions of a case's rows of ``gv``, ``iv``, ``th`` and ``out`` for ``n`` spheres
    (padded), ``p`` pairs at most, ``w`` walls (padded), the tangential history's rows (``spring``: a
    law that keeps one; else one row, never read), ``samples`` and ``frames`` recorded: ``{O_*:
    offset}``, with the widths ``"gv"``, ``"iv"``, ``"th"`` (rows), ``"out"``."""
    tp = p if spring else 1
    tw = n * w if spring else 1
    o = {}
    at = 0
    for slot, size in ((O_PK, 2 * p), (O_PCAP, 2 * p), (O_PV, 4 * p), (O_PD, 4 * p), (O_RES, RESULT * p), (O_DP, p),
                       (O_WK, w * n), (O_WRS, w * n), (O_WV, 2 * w * n), (O_WD, 2 * w * n),
                       (O_WROW, WALL_ROW * w * n)):
        o[slot] = at
        at += size
    o["gv"] = at
    at = 0
    for slot, size in ((O_ROW, 2 * (n + 1)), (O_SEC, 2 * p), (O_FIRST, 2 * p), (O_MP, 2 * p), (O_INROW, 2 * (n + 1)),
                       (O_INPAIR, 2 * p), (O_WMP, w * n), (O_MAT, n), (O_WALK, p), (O_LEVEL, p), (O_WKIND, w)):
        o[slot] = at
        at += size
    o["iv"] = at
    o[O_ENERGY] = samples
    o[O_FRAMES] = 8 * samples
    o["out"] = 8 * samples + frames * n * 9
    o.update({O_N: n, O_P: p, O_W: w, O_TP: tp, O_TW: tw, O_TWALL: 4 * tp, "th": 4 * tp + 2 * tw})
    return o


def row_widths(n: int, threads: int) -> dict:
    """The widths of a case's rows of ``st``, ``ci`` and ``cf`` for ``n`` spheres (padded) and
    ``threads`` a block."""
    return {"st": ST_FIELDS * n, "ci": CI + STATE_SLOTS * threads,
            "cf": CF_FIXED + (F_STATE + STATE_SLOTS) * threads}

