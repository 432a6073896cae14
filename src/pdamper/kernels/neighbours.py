"""Verlet neighbour lists (pairs within r_i + r_j + skin), built by direct all-pairs search or
by link cells, stored as CSR rows (``row[i]:row[i+1]`` hold the partners j > i of particle i).

Contact history (approach speed at first touch, damping parameter, the tangential law's history)
lives in arrays aligned with the list; :func:`transfer_history` carries it over when the list is
rebuilt.

The link-cell grid is fixed in the container frame (the walls do not move there), so it is
set up once per run (:class:`~pdamper.kernels.bundles.Search`: ``origin`` the grid corner,
``cells`` cells per axis, ``cell_size`` the edge). Spheres outside the grid box are clamped into
the border cells.

The building blocks take plain arrays; :func:`rebuild_lists` runs them on the bundles.
"""

from __future__ import annotations

from numba.extending import overload

from ..contact.hertz import hertz_stiffness
from ..geometry.walls import wall_distance
from ..jit import JIT, njit
from .bundles import CellSearch
from .contact import FRICTION_CAP

__all__ = ["build_direct", "build_cells", "build_pairs", "transfer_history", "build_wall_list", "max_displacement_sq",
           "rebuild_lists"]


@njit
def build_direct(pos, rad, skin, row, pj):
    """All-pairs O(N^2) build. Returns the number of pairs, or -1 if ``pj`` is too small."""
    n = pos.shape[0]
    cap = pj.shape[0]
    m = 0
    for i in range(n):
        row[i] = m
        xi = pos[i, 0]
        yi = pos[i, 1]
        zi = pos[i, 2]
        ri = rad[i] + skin
        for j in range(i + 1, n):
            dx = pos[j, 0] - xi
            dy = pos[j, 1] - yi
            dz = pos[j, 2] - zi
            cut = ri + rad[j]
            if dx * dx + dy * dy + dz * dz < cut * cut:
                if m >= cap:
                    return -1
                pj[m] = j
                m += 1
    row[n] = m
    return m


@njit
def _cell_index(x, lo, cell, nc):
    c = int((x - lo) / cell)
    if c < 0:
        return 0
    if c >= nc:
        return nc - 1
    return c


@njit
def build_cells(pos, rad, search, row, pj):
    """Link-cell build, O(N), on the grid and scratch of ``search``
    (:class:`~pdamper.kernels.bundles.Search`).

    Returns the number of pairs, or -1 if ``pj`` is too small.
    """
    skin = search.skin
    lo = search.origin
    cell = search.cell_size
    ncell = search.cells
    head = search.head
    nxt = search.next
    counts = search.counts
    n = pos.shape[0]
    ncx = ncell[0]
    ncy = ncell[1]
    ncz = ncell[2]
    for c in range(head.shape[0]):
        head[c] = -1
    for i in range(n):
        cx = _cell_index(pos[i, 0], lo[0], cell, ncx)
        cy = _cell_index(pos[i, 1], lo[1], cell, ncy)
        cz = _cell_index(pos[i, 2], lo[2], cell, ncz)
        c = (cx * ncy + cy) * ncz + cz
        nxt[i] = head[c]
        head[c] = i
    # pass 1: count partners j > i; pass 2: fill rows
    for sweep in range(2):
        if sweep == 1:
            m = 0
            for i in range(n):
                row[i] = m
                m += counts[i]
            row[n] = m
            if m > pj.shape[0]:
                return -1
            for i in range(n):
                counts[i] = 0
        else:
            for i in range(n):
                counts[i] = 0
        for i in range(n):
            cx = _cell_index(pos[i, 0], lo[0], cell, ncx)
            cy = _cell_index(pos[i, 1], lo[1], cell, ncy)
            cz = _cell_index(pos[i, 2], lo[2], cell, ncz)
            ri = rad[i] + skin
            for ax in range(max(cx - 1, 0), min(cx + 2, ncx)):
                for ay in range(max(cy - 1, 0), min(cy + 2, ncy)):
                    for az in range(max(cz - 1, 0), min(cz + 2, ncz)):
                        j = head[(ax * ncy + ay) * ncz + az]
                        while j >= 0:
                            if j > i:
                                dx = pos[j, 0] - pos[i, 0]
                                dy = pos[j, 1] - pos[i, 1]
                                dz = pos[j, 2] - pos[i, 2]
                                cut = ri + rad[j]
                                if dx * dx + dy * dy + dz * dz < cut * cut:
                                    if sweep == 1:
                                        pj[row[i] + counts[i]] = j
                                    counts[i] += 1
                            j = nxt[j]
    # partners in ascending order, as the direct build gives them: the force sums then run in
    # the same order whichever search built the list, so results do not depend on it
    for i in range(n):
        for a in range(row[i] + 1, row[i + 1]):
            v = pj[a]
            b = a - 1
            while b >= row[i] and pj[b] > v:
                pj[b + 1] = pj[b]
                b -= 1
            pj[b + 1] = v
    return row[n]


@njit
def transfer_history(old_row, old_pj, old_vin, old_d, old_t, row, pj, vin, d, t):
    """Copy contact history -- approach speed, damping parameter, the rows of the tangential
    history ``t`` (capacity, columns) -- of pairs present in both the old and the new list; new
    pairs start clean."""
    n = row.shape[0] - 1
    nt = t.shape[1]
    for i in range(n):
        for a in range(row[i], row[i + 1]):
            j = pj[a]
            v = 0.0
            dd = 0.0
            b_old = -1
            for b in range(old_row[i], old_row[i + 1]):
                if old_pj[b] == j:
                    v = old_vin[b]
                    dd = old_d[b]
                    b_old = b
                    break
            vin[a] = v
            d[a] = dd
            for c in range(nt):
                t[a, c] = old_t[b_old, c] if b_old >= 0 else 0.0


@njit
def build_wall_list(pos, rad, skin, wall_kind, wall_data, wl_i, wl_w, skip=-1):
    """(particle, wall) candidates with signed distance < r + skin, leaving out wall ``skip``
    (the floor, which the force loop handles directly). Returns count or -1 on overflow."""
    m = 0
    cap = wl_i.shape[0]
    for i in range(pos.shape[0]):
        for w in range(wall_kind.shape[0]):
            if w == skip:
                continue
            s, nx, ny, nz = wall_distance(wall_kind[w], wall_data, w, pos[i, 0], pos[i, 1], pos[i, 2])
            if s < rad[i] + skin:
                if m >= cap:
                    return -1
                wl_i[m] = i
                wl_w[m] = w
                m += 1
    return m


@njit
def max_displacement_sq(pos, ref):
    """Largest squared displacement [m^2] of any particle since ``ref`` was taken."""
    best = 0.0
    for i in range(pos.shape[0]):
        dx = pos[i, 0] - ref[i, 0]
        dy = pos[i, 1] - ref[i, 1]
        dz = pos[i, 2] - ref[i, 2]
        s = dx * dx + dy * dy + dz * dz
        if s > best:
            best = s
    return best


def build_pairs(method, pos, rad, search, row, pj):
    """The pair list by the search that ``method`` (``search.method``) marks: :func:`build_cells`
    for :class:`~pdamper.kernels.bundles.CellSearch`, else :func:`build_direct` -- chosen when the
    calling kernel is compiled (compiled kernels only)."""
    raise NotImplementedError("build_pairs is compiled into the kernels")


@overload(build_pairs, inline="always", jit_options=JIT)
def _build_pairs(method, pos, rad, search, row, pj):
    if method.instance_class is CellSearch:
        def impl(method, pos, rad, search, row, pj):
            return build_cells(pos, rad, search, row, pj)
    else:
        def impl(method, pos, rad, search, row, pj):
            return build_direct(pos, rad, search.skin, row, pj)
    return impl


@njit
def rebuild_lists(bodies, pairs, walls, search, table):
    """Rebuild the pair and wall lists at ``bodies.position``, carrying contact history over.

    The new pair list is built into the ``next_*`` arrays of ``pairs`` first, so on overflow
    (return -1 for pairs, -2 for walls) the current lists are left untouched and the caller can
    grow the arrays and call again. On success returns the number of wall candidates (also in
    ``walls.n_candidates``) and records the reference positions for the displacement check.
    """
    pos = bodies.position
    rad = bodies.radius
    m = build_pairs(search.method, pos, rad, search, pairs.next_row, pairs.next_second)
    if m < 0:
        return -1
    nw = build_wall_list(pos, rad, search.skin, walls.kind, walls.data, walls.candidate_body, walls.candidate_wall,
                         walls.floor)
    if nw < 0:
        return -2
    transfer_history(pairs.row, pairs.second, pairs.approach_speed, pairs.damping, pairs.tangential,
                     pairs.next_row, pairs.next_second, pairs.next_approach_speed, pairs.next_damping,
                     pairs.next_tangential)
    n = pos.shape[0]
    row = pairs.row
    pj = pairs.second
    next_row = pairs.next_row
    next_pj = pairs.next_second
    pvin = pairs.approach_speed
    next_pvin = pairs.next_approach_speed
    pd = pairs.damping
    next_pd = pairs.next_damping
    pt = pairs.tangential
    next_pt = pairs.next_tangential
    for i in range(n + 1):
        row[i] = next_row[i]
    for a in range(m):
        pj[a] = next_pj[a]
        pvin[a] = next_pvin[a]
        pd[a] = next_pd[a]
        for c in range(pt.shape[1]):
            pt[a, c] = next_pt[a, c]
    mass = bodies.mass
    mat = bodies.material
    nmat = table.n_materials
    modulus = table.modulus
    ref = search.reference
    pi_ = pairs.first
    pmp = pairs.material_pair
    pk = pairs.stiffness
    pcap = pairs.friction_cap
    for i in range(n):
        mi = mat[i]
        for a in range(row[i], row[i + 1]):
            j = pj[a]
            pi_[a] = i
            mp = mi * nmat + mat[j]
            pmp[a] = mp
            rs = rad[i] * rad[j] / (rad[i] + rad[j])
            pk[a] = hertz_stiffness(modulus[mp], rs)
            pcap[a] = FRICTION_CAP * mass[i] * mass[j] / (mass[i] + mass[j])
        ref[i, 0] = pos[i, 0]
        ref[i, 1] = pos[i, 1]
        ref[i, 2] = pos[i, 2]
    walls.n_candidates[0] = nw
    return nw
