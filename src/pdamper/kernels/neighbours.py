"""Verlet neighbour lists (pairs within r_i + r_j + skin), built by direct all-pairs search or
by link cells, stored as CSR rows (``row[i]:row[i+1]`` hold the partners j > i of particle i).

Contact history (approach speed at first touch, damping parameter) lives in arrays aligned with
the list; :func:`transfer_history` carries it over when the list is rebuilt.

The link-cell grid is fixed in the container frame (the walls do not move there), so it is
set up once per run: ``lo`` the grid origin, ``ncell`` cells per axis, ``cell`` the edge.
Particles outside the grid box are clamped into the border cells.
"""

from __future__ import annotations

import math

from ..geometry.walls import wall_distance
from .forces import FRICTION_CAP
from .jit import njit

__all__ = ["build_direct", "build_cells", "transfer_history", "build_wall_list", "max_displacement_sq"]


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
def build_cells(pos, rad, skin, lo, cell, ncell, row, pj, head, nxt, counts):
    """Link-cell build, O(N). ``head`` (ncell product), ``nxt`` and ``counts`` (N) are scratch.

    Returns the number of pairs, or -1 if ``pj`` is too small.
    """
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
def transfer_history(old_row, old_pj, old_vin, old_d, row, pj, vin, d):
    """Copy contact history of pairs present in both the old and the new list; new pairs start clean."""
    n = row.shape[0] - 1
    for i in range(n):
        for a in range(row[i], row[i + 1]):
            j = pj[a]
            v = 0.0
            dd = 0.0
            for b in range(old_row[i], old_row[i + 1]):
                if old_pj[b] == j:
                    v = old_vin[b]
                    dd = old_d[b]
                    break
            vin[a] = v
            d[a] = dd


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


@njit
def rebuild_lists(pos, rad, mass, mat, nmat, estar, skin, use_cells, lo, cell, ncell, head, nxt, counts,
                  row, pi_, pj, pvin, pd, pk, pmp, pms, row2, pj2, pvin2, pd2,
                  wall_kind, wall_data, wl_i, wl_w, floor, ref):
    """Rebuild the pair and wall lists, carrying contact history over.

    The new pair list is built into the scratch arrays (``*2``) first, so on overflow (return
    -1 for pairs, -2 for walls) the current lists are left untouched and the caller can grow
    the arrays and call again. On success returns the number of wall candidates and records
    the reference positions for the displacement check.
    """
    if use_cells:
        m = build_cells(pos, rad, skin, lo, cell, ncell, row2, pj2, head, nxt, counts)
    else:
        m = build_direct(pos, rad, skin, row2, pj2)
    if m < 0:
        return -1
    nw = build_wall_list(pos, rad, skin, wall_kind, wall_data, wl_i, wl_w, floor)
    if nw < 0:
        return -2
    transfer_history(row, pj, pvin, pd, row2, pj2, pvin2, pd2)
    n = pos.shape[0]
    for i in range(n + 1):
        row[i] = row2[i]
    for a in range(m):
        pj[a] = pj2[a]
        pvin[a] = pvin2[a]
        pd[a] = pd2[a]
    for i in range(n):
        mi = mat[i]
        for a in range(row[i], row[i + 1]):
            j = pj[a]
            pi_[a] = i
            mp = mi * nmat + mat[j]
            pmp[a] = mp
            rs = rad[i] * rad[j] / (rad[i] + rad[j])
            pk[a] = 4.0 / 3.0 * estar[mp] * math.sqrt(rs)
            pms[a] = FRICTION_CAP * mass[i] * mass[j] / (mass[i] + mass[j])
        ref[i, 0] = pos[i, 0]
        ref[i, 1] = pos[i, 1]
        ref[i, 2] = pos[i, 2]
    return nw
