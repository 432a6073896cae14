"""The contact forces of a case on the GPU, written once for both integrators: the neighbour list's
rebuild, the pairs' contact law, each sphere's sum of its contacts, the energies and a sample.

This is :mod:`pdamper.kernels.forces` on a block (:mod:`.batch` has the layout): the same
geometry (:func:`~pdamper.kernels.forces.pair_geometry`, the walls' signed distance, the
contact-point kinematics) and the same contact law (:func:`~pdamper.kernels.contact.contact`), the
CPU's compiled functions, and the same order of every sphere's sum: its pairs by ascending partner,
the floor, then the other walls. What differs is who does what:

- :func:`pair_laws`: the lanes take the listed pairs (``p = tid, tid + bd, ...``), each pair's law
  once, its result kept at the pair (:data:`~.batch.RESULT`);
- :func:`sphere_force`: the lane of sphere ``i`` adds the results of its pairs from the two lists of
  its pairs (those it is the second of, ascending ``i``, then its own, ascending ``j``) and
  evaluates its floor and walls, which concern it alone;
- the history: a step reads the time buffer ``tb`` and writes ``1 - tb`` (:func:`pair_laws`,
  :func:`sphere_force`); the integrator flips ``tb`` when it keeps the step.

The spheres' positions, velocities, spins, the springs' displacements and the radii live in the
block's shared memory while a launch runs (``b.sh``, :data:`~.batch.SHARED_FIELDS` a sphere), where
the pairs read both their spheres'.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import cuda

from ...contact.hertz import hertz_energy, hertz_stiffness
from ...contact.tangential_spring import spring_energy
from ...geometry.walls import wall_distance
from ..bundles import ContactConstants, ContactGeometry, ContactTable
from ..contact import FRICTION_CAP, contact, drop_history, floor_slip, keeps_history, pair_point_velocity, \
    wall_point_velocity
from ..drive import parametric_motion
from ..forces import STATUS_LIST_OVERFLOW, STATUS_OK, STATUS_OVERLAP, pair_geometry
from . import targets  # noqa: F401  (registers the laws' dispatch for the CUDA target)
from .targets import SIMULATOR
from .batch import (CI, F_STATE, F_BED_MASS, F_DIRECTION, F_GRAVITY, F_JUMP, F_PAR, F_PARTIALS, F_SAMPLE_INTERVAL, F_SKIN,
                    IINERT, I_CULPRIT, I_DRIVE, I_EN_ROWS, I_FAIL_STEP, I_FLOOR, I_FRAME_EVERY, I_FR_ROWS, I_LIST,
                    I_N, I_NMAT, I_NW, I_PRIMED, I_ROW0, I_STARTED, I_STATUS, I_TIME, I_WF_ROWS, MASS, MOVED,
                    O_ENERGY, O_FIRST, O_FRAMES, O_INPAIR, O_INROW, O_MAT, O_MP, O_N, O_P, O_PCAP, O_PD, O_PK, O_PV,
                    O_RES, O_ROW, O_SEC, O_TP, O_TW, O_TWALL, O_W, O_WD, O_WK, O_WKIND, O_WMP, O_WROW, O_WRS, O_WV,
                    PARTIALS, RAD, REF, R_C, R_F, R_LIM, R_N, R_S, R_T, S_MOVED, S_RAD, S_SPIN,
                    S_V, S_X, X)
from .warp import block_max, block_min_int, block_or, block_scan, block_sum, opaque, out_of_time, sync

__all__ = ["Block", "block", "fresh", "get", "put", "getf", "putf", "load_spheres", "store_spheres", "rebuild", "pair_laws", "sphere_force", "elastic",
           "ledger", "table_of", "fresh", "record_sample", "motion_at", "prime", "start_drive", "vote", "keep_state", "RUNNING",
           "INTEGRANDS", "THIS_STEP", "MOVED_FAR", "TIME_UP", "FAILED"]

#: A thread's ledger rows in ``cf`` (:func:`ledger`): its running sums (work done by the container,
#: loss by normal damping, loss by friction [J], impulse along the drive since the last sample
#: [N s]); Gear's integrands at the last accepted step (the same four, as powers and a force); this
#: step's sums of its contacts (normal damping's and friction's power [W], a spring's loss [J], the
#: walls' force along the drive [N]).
RUNNING, INTEGRANDS, THIS_STEP = 0, 1, 2
#: Bits of a step's vote (:func:`vote`): a sphere moved more than half the skin (Verlet: a rebuild next
#: step), the launch's time is up (thread 0's clock), the step failed.
MOVED_FAR, TIME_UP, FAILED = 1, 2, 4

class Block(NamedTuple):
    """What every thread of a case's block knows: who it is, the case's rows, the shared memory."""

    tid: int
    bd: int             #: threads of the block
    n: int              #: the case's spheres
    N: int              #: the batch's padded spheres (a field's stride)
    st: np.ndarray      #: the case's rows of the batch (:class:`~.batch.Batch`)
    gv: np.ndarray
    th: np.ndarray      #: (rows, 5) the tangential history
    iv: np.ndarray
    ci: np.ndarray
    cf: np.ndarray
    walls: np.ndarray   #: (W, 7)
    sh: np.ndarray      #: the block's shared memory: SHARED_FIELDS values a sphere
    red: np.ndarray     #: shared: a word a warp for the block's reductions
    bt: tuple           #: the whole batch (:class:`~.batch.Batch`), the kernel's argument
    c: int              #: the case


@cuda.jit(device=True, inline="always")
def block(bt, c, sh, red):
    """Case ``c``'s :class:`Block` for the calling thread (``bt``: the :class:`~.batch.Batch`)."""
    ci = bt.ci[c]
    return Block(cuda.threadIdx.x, cuda.blockDim.x, ci[I_N], ci[O_N], bt.st[c], bt.gv[c], bt.th[c], bt.iv[c], ci,
                 bt.cf[c], bt.walls[c * ci[O_W]:(c + 1) * ci[O_W]], sh, red, bt, c)


if SIMULATOR:
    # (the simulator runs the kernels as Python: nothing to keep from hoisting, and each call of a
    # device function costs it a swap of the module's globals, so these are plain functions there)
    def fresh(b):
        return b

    def get(b, k):
        return b.ci[CI + k * b.bd + b.tid]

    def put(b, k, v):
        b.ci[CI + k * b.bd + b.tid] = v

    def getf(b, k):
        return b.cf[F_PARTIALS + (F_STATE + k) * b.bd + b.tid]

    def putf(b, k, v):
        b.cf[F_PARTIALS + (F_STATE + k) * b.bd + b.tid] = v
else:
    @cuda.jit(device=True)
    def fresh(b):
        """``b`` made afresh (:func:`~.warp.opaque`): the case's rows from the kernel's arguments and the
        case's index, the thread, block size and sphere counts read again. What a phase computes from
        them (a row's address, a field's offset, the first sphere of a lane) is its own, not hoisted
        out of the persistent loop and kept live through every other phase: the rows' addresses are
        the arguments' (which the assembler reads from the parameter bank where it needs them) and one
        multiply-add."""
        a = block(b.bt, opaque(b.c), b.sh, b.red)
        return Block(opaque(a.tid), opaque(a.bd), opaque(a.n), opaque(a.N), a.st, a.gv, a.th, a.iv, a.ci, a.cf,
                     a.walls, a.sh, a.red, a.bt, a.c)

    @cuda.jit(device=True)
    def get(b, k):
        """This thread's integer state slot ``k`` (:data:`~.batch.STATE_SLOTS`: a loop's counter, clock
        or flag kept in the case's row, read where it is used instead of held in a register through
        every phase)."""
        b = fresh(b)
        return b.ci[CI + k * b.bd + b.tid]

    @cuda.jit(device=True)
    def put(b, k, v):
        """Set this thread's integer state slot ``k`` to ``v``."""
        b = fresh(b)
        b.ci[CI + k * b.bd + b.tid] = v

    @cuda.jit(device=True)
    def getf(b, k):
        """This thread's float state slot ``k``."""
        b = fresh(b)
        return b.cf[F_PARTIALS + (F_STATE + k) * b.bd + b.tid]

    @cuda.jit(device=True)
    def putf(b, k, v):
        """Set this thread's float state slot ``k`` to ``v``."""
        b = fresh(b)
        b.cf[F_PARTIALS + (F_STATE + k) * b.bd + b.tid] = v


@cuda.jit(device=True, inline="always")
def table_of(tb, law, tlaw):
    """The batch's contact table (its arrays and constants ``tb``) with these laws' markers."""
    return ContactTable(law, tlaw, 0, tb[0], tb[1], tb[2], tb[3], tb[4], tb[5], tb[6], tb[7], tb[8], tb[9], tb[10])


@cuda.jit(device=True)
def _copy_spheres(b, into_shared):
    """The case's positions, velocities, spins and spring displacements between its rows of ``st``
    and the block's shared memory (each lane its spheres)."""
    N = b.N
    i = b.tid
    while i < b.n:
        for k in range(9):
            # (position, velocity and spin are st's fields 0-8 and the shared fields 0-8)
            if into_shared:
                b.sh[(S_X + k) * N + i] = b.st[(X + k) * N + i]
            else:
                b.st[(X + k) * N + i] = b.sh[(S_X + k) * N + i]
        for k in range(6):
            if into_shared:
                b.sh[(S_MOVED + k) * N + i] = b.st[(MOVED + k) * N + i]
            else:
                b.st[(MOVED + k) * N + i] = b.sh[(S_MOVED + k) * N + i]
        i += b.bd


@cuda.jit(device=True)
def load_spheres(b):
    """The case's positions, velocities, spins, spring displacements and radii into shared memory."""
    _copy_spheres(b, True)
    i = b.tid
    while i < b.n:
        b.sh[S_RAD * b.N + i] = b.st[RAD * b.N + i]
        i += b.bd
    sync(b.bd)


@cuda.jit(device=True)
def store_spheres(b):
    """The shared positions, velocities, spins and displacements back into the case's rows."""
    _copy_spheres(b, False)


@cuda.jit(device=True)
def start_drive(b):
    """The drive starts (after the settling): the velocities relative to the container jump by
    ``-jump``, this thread's running sums restart."""
    b = fresh(b)
    N = b.N
    i = b.tid
    while i < b.n:
        for k in range(3):
            b.sh[(S_V + k) * N + i] -= b.cf[F_JUMP + k]
        i += b.bd
    r = ledger(b, RUNNING)
    for k in range(4):
        b.cf[r + k] = 0.0


@cuda.jit(device=True)
def vote(b, bits, status, culprit, start, max_cycles):
    """The block's vote at a step's end: the or of every thread's ``bits``, with :data:`TIME_UP` when
    thread 0's clock says the launch's time is up and :data:`FAILED` when a thread's ``status`` says
    its step failed; then the block's status (the largest) and culprit (the smallest sphere). Returns
    ``(bits, status, culprit)``, the same in every thread."""
    if b.tid == 0 and out_of_time(start, max_cycles):
        bits |= TIME_UP
    if status != STATUS_OK:
        bits |= FAILED
    bits = block_or(bits, b.tid, b.bd, b.red)
    if bits & FAILED:
        status = int(block_max(float(status), b.tid, b.bd, b.red))
        culprit = block_min_int(culprit if culprit >= 0 else 1 << 30, b.tid, b.bd, b.red)
    return bits, status, culprit


@cuda.jit(device=True)
def keep_state(b, lb, tk, started, primed, status, culprit, step):
    """What the next launch starts from (thread 0): the list and history buffers, whether the drive
    has started and the run is primed, and a failure's status, culprit and step."""
    ci = b.ci
    ci[I_LIST] = lb
    ci[I_TIME] = tk
    ci[I_STARTED] = started
    ci[I_PRIMED] = primed
    if status != STATUS_OK:
        ci[I_STATUS] = status
        ci[I_CULPRIT] = culprit
        ci[I_FAIL_STEP] = step


@cuda.jit(device=True)
def ledger(b, row):
    """Where this thread's ledger row ``row`` starts in the case's ``cf`` (:data:`RUNNING`,
    :data:`INTEGRANDS`, :data:`THIS_STEP`; :data:`~.batch.PARTIALS` values each). A thread's sums
    live there, not in its registers: a few loads and stores a step against the registers they would
    hold through the whole step."""
    return F_PARTIALS + PARTIALS * (row * b.bd + b.tid)


@cuda.jit(device=True)
def _add_step(b, pn, pf, ef, fd):
    """Add a contact's powers [W], a spring's loss [J] and its wall force along the drive [N] to this
    thread's sums of the step (:data:`THIS_STEP`)."""
    k = ledger(b, THIS_STEP)
    b.cf[k] += pn
    b.cf[k + 1] += pf
    b.cf[k + 2] += ef
    b.cf[k + 3] += fd


@cuda.jit(device=True)
def _pair_row(b, lb, tb, p):
    """The row of ``b.th`` that holds pair ``p``'s tangential history in list buffer ``lb``, time
    buffer ``tb``."""
    return (lb * 2 + tb) * b.ci[O_TP] + p


@cuda.jit(device=True)
def _wall_row(b, tb, i, w):
    """The row of ``b.th`` that holds the tangential history of sphere ``i`` at wall ``w``, time
    buffer ``tb``."""
    ci = b.ci
    return ci[O_TWALL] + tb * ci[O_TW] + i * ci[O_W] + w


@cuda.jit(device=True)
def _carry(th, src, dst, spring):
    """Row ``src`` of the tangential history ``th`` into row ``dst`` (a law with history only)."""
    if spring:
        for q in range(5):
            th[dst, q] = th[src, q]


@cuda.jit(device=True)
def _pair_within(b, i, j, skin):
    """Whether spheres ``i < j`` are within the list's reach (the CPU build's test, in its order)."""
    N = b.N
    sh = b.sh
    dx = sh[S_X * N + j] - sh[S_X * N + i]
    dy = sh[(S_X + 1) * N + j] - sh[(S_X + 1) * N + i]
    dz = sh[(S_X + 2) * N + j] - sh[(S_X + 2) * N + i]
    cut = (sh[S_RAD * N + i] + skin) + sh[S_RAD * N + j]
    return dx * dx + dy * dy + dz * dz < cut * cut


@cuda.jit(device=True)
def _list_pair(b, table, i, j, k, lb, tb):
    """Spheres ``i < j`` as pair ``k`` of list buffer ``1 - lb`` (:func:`rebuild`'s): its spheres,
    material pair, Hertz stiffness and friction guard, and the history of time buffer ``tb`` it has
    in the list ``lb`` if any (transfer_history's); the offsets read here, not held by the build's
    loops."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    iv = b.iv
    gv = b.gv
    P = ci[O_P]
    nb = 1 - lb
    iv[ci[O_SEC] + nb * P + k] = j
    iv[ci[O_FIRST] + nb * P + k] = i
    mp = ci[I_ROW0] + iv[ci[O_MAT] + i] * ci[I_NMAT] + iv[ci[O_MAT] + j]
    iv[ci[O_MP] + nb * P + k] = mp
    ri = b.sh[S_RAD * N + i]
    mi = b.st[MASS * N + i]
    rj = b.sh[S_RAD * N + j]
    mj = b.st[MASS * N + j]
    gv[ci[O_PK] + nb * P + k] = hertz_stiffness(table.modulus[mp], ri * rj / (ri + rj))
    gv[ci[O_PCAP] + nb * P + k] = FRICTION_CAP * mi * mj / (mi + mj)
    # the history of the pair if the old list has it (transfer_history's)
    v = 0.0
    d = 0.0
    e_old = -1
    row_old = ci[O_ROW] + lb * (N + 1)
    sec_old = ci[O_SEC] + lb * P
    for e in range(iv[row_old + i], iv[row_old + i + 1]):
        if iv[sec_old + e] == j:
            v = gv[ci[O_PV] + (lb * 2 + tb) * P + e]
            d = gv[ci[O_PD] + (lb * 2 + tb) * P + e]
            e_old = e
            break
    gv[ci[O_PV] + (nb * 2 + tb) * P + k] = v
    gv[ci[O_PD] + (nb * 2 + tb) * P + k] = d
    if keeps_history(table.tangential):
        th = b.th
        r_new = _pair_row(b, nb, tb, k)
        r_old = _pair_row(b, lb, tb, e_old)
        for q in range(5):
            th[r_new, q] = th[r_old, q] if e_old >= 0 else 0.0


@cuda.jit(device=True)
def rebuild(b, table, lb, tb):
    """Rebuild the pair list into list buffer ``1 - lb`` at the shared positions, carrying the
    history of time buffer ``tb`` over (:func:`pdamper.kernels.neighbours.rebuild_lists`' build and
    ``transfer_history``), with each pair's constants and each sphere's list of the pairs it is the
    second of; the reference positions taken. Returns the status: ``STATUS_LIST_OVERFLOW`` when the
    pairs pass the case's capacity (then the old list stands)."""
    b = fresh(b)
    tid = b.tid
    bd = b.bd
    n = b.n
    N = b.N
    ci = b.ci
    iv = b.iv
    P = ci[O_P]
    nb = 1 - lb
    skin = b.cf[F_SKIN]
    row = ci[O_ROW] + nb * (N + 1)
    base = 0
    start = 0
    while start < n:
        i = start + tid
        m = 0
        if i < n:
            for j in range(i + 1, n):
                if _pair_within(b, i, j, skin):
                    m += 1
        before, total = block_scan(m, tid, bd, b.red)
        if i < n:
            k = base + before
            iv[row + i] = k
            for j in range(i + 1, n):
                if not _pair_within(b, i, j, skin):
                    continue
                if k < P:
                    _list_pair(b, table, i, j, k, lb, tb)
                k += 1
        base += total
        start += bd
    if base > P:
        sync(bd)
        return STATUS_LIST_OVERFLOW
    if tid == 0:
        iv[row + n] = base
    sync(bd)
    # each sphere's pairs it is the second of, ascending first sphere (the pair list's order)
    sec = ci[O_SEC] + nb * P
    inrow = ci[O_INROW] + nb * (N + 1)
    inpair = ci[O_INPAIR] + nb * P
    base = 0
    start = 0
    while start < n:
        k = start + tid
        m = 0
        if k < n:
            for p in range(iv[row + k]):
                if iv[sec + p] == k:
                    m += 1
        before, total = block_scan(m, tid, bd, b.red)
        if k < n:
            q = base + before
            iv[inrow + k] = q
            for p in range(iv[row + k]):
                if iv[sec + p] == k:
                    iv[inpair + q] = p
                    q += 1
            for a in range(3):
                b.st[(REF + a) * N + k] = b.sh[(S_X + a) * N + k]
        base += total
        start += bd
    if tid == 0:
        iv[inrow + n] = base
    sync(bd)
    return STATUS_OK


@cuda.jit(device=True)
def pair_laws(b, table, lb, tb, dt, step):
    """The contact law of every listed pair (the CPU pair loop's arithmetic), the lanes over the
    pairs: its history read from time buffer ``tb``, written to ``1 - tb``; its result kept at the
    pair. ``dt``: the tanh law's friction guard's step (Gear: none), ``step``: the step taken. The
    pairs' powers and a spring's loss go to this thread's sums of the step (:func:`ledger`). Returns
    ``(status, culprit)`` of this thread's pairs; a barrier after."""
    b = fresh(b)
    status = STATUS_OK
    culprit = -1
    p = b.tid
    while p < b.iv[b.ci[O_ROW] + lb * (b.N + 1) + b.n]:
        i = _pair_law(b, table, p, lb, tb, dt, step)
        if i >= 0:
            status = STATUS_OVERLAP
            culprit = i
        b = fresh(b)
        p += b.bd
    sync(b.bd)
    return status, culprit


@cuda.jit(device=True)
def _pair_law(b, table, p, lb, tb, dt, step):
    """Pair ``p``'s contact law (:func:`pair_laws`', one pair), what it needs read here, so that
    nothing of one pair is held through the next. Returns its first sphere when the overlap passes
    the limit, else -1."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    iv = b.iv
    gv = b.gv
    sh = b.sh
    P = ci[O_P]
    tlaw = table.tangential
    spring = keeps_history(tlaw)
    th = b.th
    i = iv[ci[O_FIRST] + lb * P + p]
    j = iv[ci[O_SEC] + lb * P + p]
    ri = sh[S_RAD * N + i]
    rj = sh[S_RAD * N + j]
    dx = sh[S_X * N + j] - sh[S_X * N + i]
    dy = sh[(S_X + 1) * N + j] - sh[(S_X + 1) * N + i]
    dz = sh[(S_X + 2) * N + j] - sh[(S_X + 2) * N + i]
    cut = ri + rj
    d2 = dx * dx + dy * dy + dz * dz
    v_in = gv[ci[O_PV] + (lb * 2 + tb) * P + p]
    hrow = _pair_row(b, lb, 1 - tb, p)  # (the history's row of this step)
    _carry(th, _pair_row(b, lb, tb, p), hrow, spring)
    if d2 >= cut * cut:
        gv[ci[O_PV] + (lb * 2 + 1 - tb) * P + p] = 0.0
        gv[ci[O_PD] + (lb * 2 + 1 - tb) * P + p] = 0.0
        if v_in != 0.0:
            _add_step(b, 0.0, 0.0, drop_history(tlaw, th, hrow), 0.0)
        return -1
    nx, ny, nz, delta, ddot, tx, ty, tz, vt = pair_geometry(
        dx, dy, dz, d2, cut, sh[S_V * N + i] - sh[S_V * N + j], sh[(S_V + 1) * N + i] - sh[(S_V + 1) * N + j],
        sh[(S_V + 2) * N + i] - sh[(S_V + 2) * N + j], ri * sh[S_SPIN * N + i] + rj * sh[S_SPIN * N + j],
        ri * sh[(S_SPIN + 1) * N + i] + rj * sh[(S_SPIN + 1) * N + j],
        ri * sh[(S_SPIN + 2) * N + i] + rj * sh[(S_SPIN + 2) * N + j])
    culprit = i if delta > table.overlap_limit * min(ri, rj) else -1
    dsx = dsy = dsz = 0.0
    if spring:
        m = S_MOVED * N
        dsx, dsy, dsz, dsn = pair_point_velocity(
            sh[m + i] - sh[m + j], sh[m + N + i] - sh[m + N + j], sh[m + 2 * N + i] - sh[m + 2 * N + j],
            ri * sh[m + 3 * N + i] + rj * sh[m + 3 * N + j], ri * sh[m + 4 * N + i] + rj * sh[m + 4 * N + j],
            ri * sh[m + 5 * N + i] + rj * sh[m + 5 * N + j], nx, ny, nz)
    # the normal and the slip kept at the pair before the law, read back after it: not held through it
    res = ci[O_RES]
    gv[res + R_N * P + p] = nx
    gv[res + (R_N + 1) * P + p] = ny
    gv[res + (R_N + 2) * P + p] = nz
    gv[res + R_S * P + p] = tx
    gv[res + (R_S + 1) * P + p] = ty
    gv[res + (R_S + 2) * P + p] = tz
    cap = gv[ci[O_PCAP] + lb * P + p]
    mp = iv[ci[O_MP] + lb * P + p]
    fn, ftx, fty, ftz, ff, lim, vin, dd, pn, pf, ef = contact(
        table, th, hrow,
        ContactConstants(mp, table.friction[mp], gv[ci[O_PK] + lb * P + p], ri * rj / cut, cap / FRICTION_CAP, cap),
        ContactGeometry(delta, ddot, nx, ny, nz, tx, ty, tz, vt, dsx, dsy, dsz), v_in,
        gv[ci[O_PD] + (lb * 2 + tb) * P + p], dt, step)
    b = fresh(b)
    ci = b.ci
    gv = b.gv
    P = ci[O_P]
    gv[ci[O_PV] + (lb * 2 + 1 - tb) * P + p] = vin
    gv[ci[O_PD] + (lb * 2 + 1 - tb) * P + p] = dd
    _add_step(b, pn, pf, ef, 0.0)
    res = ci[O_RES]
    gv[res + R_F * P + p] = -fn * gv[res + R_N * P + p] + ftx
    gv[res + (R_F + 1) * P + p] = -fn * gv[res + (R_N + 1) * P + p] + fty
    gv[res + (R_F + 2) * P + p] = -fn * gv[res + (R_N + 2) * P + p] + ftz
    gv[res + R_T * P + p] = ftx
    gv[res + (R_T + 1) * P + p] = fty
    gv[res + (R_T + 2) * P + p] = ftz
    gv[res + R_C * P + p] = ff
    gv[res + R_LIM * P + p] = lim
    return culprit


@cuda.jit(device=True)
def _cross(nx, ny, nz, tx, ty, tz):
    """``n x t`` (:func:`~pdamper.kernels.contact.scatter`'s lever)."""
    return ny * tz - nz * ty, nz * tx - nx * tz, nx * ty - ny * tx


@cuda.jit(device=True)
def _add_pair(gv, res, P, p, acc, i, sign, ri):
    """Pair ``p``'s result into sphere ``i``'s force and torque (``sign``: 1 for the first sphere of
    the pair, -1 for the second; ``ri`` its radius, the lever): :func:`~pdamper.kernels.contact.scatter`'s
    arithmetic."""
    if sign > 0.0:
        acc[i, 0] += gv[res + R_F * P + p]
        acc[i, 1] += gv[res + (R_F + 1) * P + p]
        acc[i, 2] += gv[res + (R_F + 2) * P + p]
    else:
        acc[i, 0] += -gv[res + R_F * P + p]
        acc[i, 1] += -gv[res + (R_F + 1) * P + p]
        acc[i, 2] += -gv[res + (R_F + 2) * P + p]
    cx, cy, cz = _cross(gv[res + R_N * P + p], gv[res + (R_N + 1) * P + p], gv[res + (R_N + 2) * P + p],
                        gv[res + R_T * P + p], gv[res + (R_T + 1) * P + p], gv[res + (R_T + 2) * P + p])
    acc[i, 3] += ri * cx
    acc[i, 4] += ri * cy
    acc[i, 5] += ri * cz


@cuda.jit(device=True)
def _pair_sums(b, acc, i, lb, tb):
    """Force and torque on sphere ``i`` from its pairs, in ascending partner order (the pairs it is
    the second of, then its own), into ``acc[i]`` (force, torque)."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    iv = b.iv
    gv = b.gv
    P = ci[O_P]
    v_new = ci[O_PV] + (lb * 2 + 1 - tb) * P
    res = ci[O_RES]
    ri = b.sh[S_RAD * N + i]
    for k in range(6):
        acc[i, k] = 0.0
    inrow = ci[O_INROW] + lb * (N + 1)
    inpair = ci[O_INPAIR] + lb * P
    for q in range(iv[inrow + i], iv[inrow + i + 1]):
        p = iv[inpair + q]
        if gv[v_new + p] != 0.0:
            _add_pair(gv, res, P, p, acc, i, -1.0, ri)
    row = ci[O_ROW] + lb * (N + 1)
    for p in range(iv[row + i], iv[row + i + 1]):
        if gv[v_new + p] != 0.0:
            _add_pair(gv, res, P, p, acc, i, 1.0, ri)


@cuda.jit(device=True)
def _wall_row_at(b, i, w):
    """Where sphere ``i``'s friction row at wall ``w`` starts in ``gv``, and its values' stride:
    the unit normal (3), the slip (3), the friction coefficient, the limit (Gear's implicit pass)."""
    N = b.N
    return b.ci[O_WROW] + w * N + i, b.ci[O_W] * N


@cuda.jit(device=True)
def sphere_force(b, table, acc, i, lb, tb, dt, step):
    """Force and torque on sphere ``i`` into ``acc[i]`` (force [N], torque [N m]): its pairs' results
    in ascending partner order, then its floor and other walls, whose law is evaluated here (each
    concerns this sphere alone: the CPU floor and wall loops' arithmetic; the history from time
    buffer ``tb`` into ``1 - tb``, the friction rows noted), summed one after another as the CPU sums
    them. The walls' powers, a spring's loss and their force along the drive go to this thread's
    sums of the step (:func:`ledger`). Returns the status."""
    _pair_sums(b, acc, i, lb, tb)
    b = fresh(b)
    floor = b.ci[I_FLOOR]
    status = STATUS_OK
    for w in range(b.ci[I_NW]):
        # the floor first, then the other walls (the CPU's loops' order for a sphere)
        if floor >= 0:
            wall = floor if w == 0 else (w - 1 if w <= floor else w)
        else:
            wall = w
        if _wall_contact(b, table, acc, i, wall, tb, dt, step) != STATUS_OK:
            status = STATUS_OVERLAP
    return status


@cuda.jit(device=True)
def _wall_contact(b, table, acc, i, wall, tb, dt, step):
    """Sphere ``i``'s contact with wall ``wall`` (:func:`sphere_force`'s, one wall): its law, its
    force and torque added to ``acc[i]``, its history and friction row; what it needs read here, so
    that nothing of one wall's contact is held through the next. Returns the status."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    gv = b.gv
    sh = b.sh
    tlaw = table.tangential
    spring = keeps_history(tlaw)
    th = b.th
    floor = ci[I_FLOOR]
    at = wall * N + i
    row = _wall_row(b, 1 - tb, i, wall)
    v_in = gv[ci[O_WV] + tb * ci[O_W] * N + at]
    _carry(th, _wall_row(b, tb, i, wall), row, spring)
    ri = sh[S_RAD * N + i]
    if wall == floor:
        delta = ri - sh[(S_X + 1) * N + i]
        nx, ny, nz = 0.0, 1.0, 0.0
    else:
        s, nx, ny, nz = wall_distance(b.iv[ci[O_WKIND] + wall], b.walls, wall, sh[S_X * N + i],
                                      sh[(S_X + 1) * N + i], sh[(S_X + 2) * N + i])
        delta = ri - s
    if delta <= 0.0:
        gv[ci[O_WV] + (1 - tb) * ci[O_W] * N + at] = 0.0
        gv[ci[O_WD] + (1 - tb) * ci[O_W] * N + at] = 0.0
        if v_in != 0.0:
            _add_step(b, 0.0, 0.0, drop_history(tlaw, th, row), 0.0)
        return STATUS_OK
    status = STATUS_OVERLAP if delta > table.overlap_limit * ri else STATUS_OK
    vx = sh[S_V * N + i]
    vy = sh[(S_V + 1) * N + i]
    vz = sh[(S_V + 2) * N + i]
    m = S_MOVED * N + i
    dsx = dsy = dsz = 0.0
    if wall == floor:
        ddot = -vy
        tx, tz = floor_slip(vx, vz, sh[S_SPIN * N + i], sh[(S_SPIN + 2) * N + i], ri)
        ty = 0.0
        vt = math.sqrt(tx * tx + tz * tz)
        if spring:
            dsx, dsz = floor_slip(sh[m], sh[m + 2 * N], sh[m + 3 * N], sh[m + 5 * N], ri)
    else:
        ddot = -(vx * nx + vy * ny + vz * nz)
        cvx, cvy, cvz, cn = wall_point_velocity(vx, vy, vz, sh[S_SPIN * N + i], sh[(S_SPIN + 1) * N + i],
                                                sh[(S_SPIN + 2) * N + i], ri, nx, ny, nz)
        tx = cvx - cn * nx
        ty = cvy - cn * ny
        tz = cvz - cn * nz
        vt = math.sqrt(tx * tx + ty * ty + tz * tz)
        if spring:
            dsx, dsy, dsz, dsn = wall_point_velocity(sh[m], sh[m + N], sh[m + 2 * N], sh[m + 3 * N],
                                                     sh[m + 4 * N], sh[m + 5 * N], ri, nx, ny, nz)
    # the friction row's normal and slip noted before the law, read back after it: not held through it
    fr, wn = _wall_row_at(b, i, wall)
    gv[fr] = nx
    gv[fr + wn] = ny
    gv[fr + 2 * wn] = nz
    gv[fr + 3 * wn] = tx
    gv[fr + 4 * wn] = ty
    gv[fr + 5 * wn] = tz
    mp = b.iv[ci[O_WMP] + at]
    mi = b.st[MASS * N + i]
    fn, ftx, fty, ftz, ff, lim, vin, dd, pn, pf, ef = contact(
        table, th, row, ContactConstants(mp, table.friction[mp], gv[ci[O_WK] + at], gv[ci[O_WRS] + at], mi,
                                         FRICTION_CAP * mi),
        ContactGeometry(delta, ddot, nx, ny, nz, tx, ty, tz, vt, dsx, dsy, dsz), v_in,
        gv[ci[O_WD] + tb * ci[O_W] * N + at], dt, step)
    b = fresh(b)
    ci = b.ci
    N = b.N
    at = wall * N + i
    b.gv[ci[O_WV] + (1 - tb) * ci[O_W] * N + at] = vin
    b.gv[ci[O_WD] + (1 - tb) * ci[O_W] * N + at] = dd
    fr, wn = _wall_row_at(b, i, wall)
    gv = b.gv
    gv[fr + 6 * wn] = ff
    gv[fr + 7 * wn] = lim
    nx = gv[fr]
    ny = gv[fr + wn]
    nz = gv[fr + 2 * wn]
    if wall == ci[I_FLOOR]:
        # (the floor's tangential force has no y part: the slip has none, and neither has a spring)
        fty = 0.0
        ex, ey, ez = ftx, fn, ftz
    else:
        ex = fn * nx + ftx
        ey = fn * ny + fty
        ez = fn * nz + ftz
    acc[i, 0] += ex
    acc[i, 1] += ey
    acc[i, 2] += ez
    cx, cy, cz = _cross(nx, ny, nz, ftx, fty, ftz)
    ri = b.sh[S_RAD * N + i]
    acc[i, 3] += -ri * cx
    acc[i, 4] += -ri * cy
    acc[i, 5] += -ri * cz
    cf = b.cf
    _add_step(b, pn, pf, ef, ex * cf[F_DIRECTION] + ey * cf[F_DIRECTION + 1] + ez * cf[F_DIRECTION + 2])
    return status


@cuda.jit(device=True)
def elastic(b, i, lb, tb, spring):
    """Energy [J] in the Hertz springs of sphere ``i``'s own pairs and its walls, and in their
    tangential springs (time buffer ``tb``) under a law with history (``spring``):
    :func:`pdamper.kernels.forces.elastic_energy`'s terms of this sphere."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    iv = b.iv
    gv = b.gv
    sh = b.sh
    P = ci[O_P]
    ri = sh[S_RAD * N + i]
    x = sh[S_X * N + i]
    y = sh[(S_X + 1) * N + i]
    z = sh[(S_X + 2) * N + i]
    row = ci[O_ROW] + lb * (N + 1)
    sec = ci[O_SEC] + lb * P
    e_el = 0.0
    for p in range(iv[row + i], iv[row + i + 1]):
        j = iv[sec + p]
        dx = sh[S_X * N + j] - x
        dy = sh[(S_X + 1) * N + j] - y
        dz = sh[(S_X + 2) * N + j] - z
        delta = ri + sh[S_RAD * N + j] - math.sqrt(dx * dx + dy * dy + dz * dz)
        if delta > 0.0:
            e_el += hertz_energy(gv[ci[O_PK] + lb * P + p], delta)
    floor = ci[I_FLOOR]
    for w in range(ci[I_NW]):
        if w == floor:
            delta = ri - y
        else:
            s, nx, ny, nz = wall_distance(iv[ci[O_WKIND] + w], b.walls, w, x, y, z)
            delta = ri - s
        if delta > 0.0:
            e_el += hertz_energy(gv[ci[O_WK] + w * N + i], delta)
    if spring:
        th = b.th
        for p in range(iv[row + i], iv[row + i + 1]):
            r = _pair_row(b, lb, tb, p)
            if th[r, 3] > 0.0:
                e_el += spring_energy(th[r, 0], th[r, 1], th[r, 2], th[r, 3])
        for w in range(ci[I_NW]):
            r = _wall_row(b, tb, i, w)
            if th[r, 3] > 0.0:
                e_el += spring_energy(th[r, 0], th[r, 1], th[r, 2], th[r, 3])
    return e_el


@cuda.jit(device=True)
def _sphere_energies(b, i, vc):
    """Sphere ``i``'s kinetic energy in the lab frame (the container at velocity ``vc`` along the
    drive), its rotational energy and ``m g . x`` (:func:`record_sample`'s terms, read here)."""
    b = fresh(b)
    N = b.N
    cf = b.cf
    sh = b.sh
    mi = b.st[MASS * N + i]
    ux = sh[S_V * N + i] + vc * cf[F_DIRECTION]
    uy = sh[(S_V + 1) * N + i] + vc * cf[F_DIRECTION + 1]
    uz = sh[(S_V + 2) * N + i] + vc * cf[F_DIRECTION + 2]
    ekin = 0.5 * mi * (ux * ux + uy * uy + uz * uz)
    erot = 0.5 / b.st[IINERT * N + i] * (sh[S_SPIN * N + i] ** 2 + sh[(S_SPIN + 1) * N + i] ** 2
                                         + sh[(S_SPIN + 2) * N + i] ** 2)
    g = mi * (cf[F_GRAVITY] * sh[S_X * N + i] + cf[F_GRAVITY + 1] * sh[(S_X + 1) * N + i]
              + cf[F_GRAVITY + 2] * sh[(S_X + 2) * N + i])
    return ekin, erot, g


@cuda.jit(device=True)
def record_sample(b, out, kk, motion, lb, tb, spring):
    """Sample ``kk`` of the case (:func:`pdamper.kernels.record.record_sample`) into its row ``out``:
    the block's sums of the threads' running sums (:func:`ledger`; the impulse restarts), the
    energies, a frame; ``motion``: the container's ``(x, v)`` [m, m/s] at the sample's end. Every
    thread of the block calls it."""
    b = fresh(b)
    N = b.N
    ci = b.ci
    cf = b.cf
    sh = b.sh
    tid = b.tid
    bd = b.bd
    xc, vc = motion
    ekin = erot = epot = eel = 0.0
    erec = kk < ci[I_EN_ROWS]
    if erec:
        i = tid
        while i < b.n:
            ek, er, eg = _sphere_energies(b, i, vc)
            ekin += ek
            erot += er
            epot -= eg
            eel += elastic(b, i, lb, tb, spring)
            i += fresh(b).bd
    b = fresh(b)
    ci = b.ci
    cf = b.cf
    tid = b.tid
    bd = b.bd
    r = ledger(b, RUNNING)
    impulse = block_sum(cf[r + 3], tid, bd, b.red)
    cf[r + 3] = 0.0
    if tid == 0 and kk < ci[I_WF_ROWS]:
        out[kk] = impulse / cf[F_SAMPLE_INTERVAL]
    if erec:
        e = ci[O_ENERGY] + 7 * kk
        work = block_sum(cf[r], tid, bd, b.red)
        damp = block_sum(cf[r + 1], tid, bd, b.red)
        fric = block_sum(cf[r + 2], tid, bd, b.red)
        ekin = block_sum(ekin, tid, bd, b.red)
        erot = block_sum(erot, tid, bd, b.red)
        epot = block_sum(epot, tid, bd, b.red)
        eel = block_sum(eel, tid, bd, b.red)
        if tid == 0:
            # the lab frame's potential energy (record_sample): the bed raised with the container
            gvx = cf[F_GRAVITY]
            gvy = cf[F_GRAVITY + 1]
            gvz = cf[F_GRAVITY + 2]
            gd = gvx * cf[F_DIRECTION] + gvy * cf[F_DIRECTION + 1] + gvz * cf[F_DIRECTION + 2]
            if abs(gd) > 1e-12 * math.sqrt(gvx ** 2 + gvy ** 2 + gvz ** 2):
                epot -= cf[F_BED_MASS] * gd * xc
            out[e] = ekin
            out[e + 1] = erot
            out[e + 2] = epot
            out[e + 3] = eel
            out[e + 4] = work
            out[e + 5] = damp
            out[e + 6] = fric
    every = ci[I_FRAME_EVERY]
    if every > 0 and (kk + 1) % every == 0:
        f = (kk + 1) // every - 1
        if f < ci[I_FR_ROWS]:
            i = tid
            while i < b.n:
                at = ci[O_FRAMES] + (f * N + i) * 9
                for k in range(3):
                    out[at + k] = sh[(S_X + k) * N + i]
                    out[at + 3 + k] = sh[(S_V + k) * N + i]
                    out[at + 6 + k] = sh[(S_SPIN + k) * N + i]
                i += bd
    sync(bd)


@cuda.jit(device=True)
def motion_at(b, t):
    """The container's (position, velocity, acceleration) along the drive at ``t`` (the kernels'
    own function of the drive's kind number and parameters)."""
    cf = b.cf
    return parametric_motion(b.ci[I_DRIVE], cf[F_PAR], cf[F_PAR + 1], cf[F_PAR + 2], t)


@cuda.jit(device=True)
def prime(b, table, lb, tb, dt):
    """The contacts at the start of a run (the CPU's priming evaluation): the list built, the pairs'
    law evaluated with the springs not advanced (nothing moved; ``dt``: the tanh law's friction
    guard's step). Returns ``(status, lb)``: the rebuild's status and the list buffer in use; the
    walls are the integrator's (:func:`sphere_force` with ``step = 0``)."""
    b = fresh(b)
    N = b.N
    i = b.tid
    while i < b.n:
        for k in range(6):
            b.sh[(S_MOVED + k) * N + i] = 0.0
        i += b.bd
    sync(b.bd)
    status = rebuild(b, table, lb, tb)
    if status == STATUS_OK:
        lb = 1 - lb
    pair_laws(b, table, lb, tb, dt, 0.0)
    return status, lb
