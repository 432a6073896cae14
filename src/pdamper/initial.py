"""Initial particle positions: a compact block against the -x wall, a random scatter, or given.

Both generated arrangements apply a seeded random jitter in the floor plane, so a run repeats
bit for bit with the same seed and varies on purpose with another. Spheres start a hair
(1 um) above the floor and settle under gravity before the drive starts
(:attr:`pdamper.params.InitialState.settle_time`).
"""

from __future__ import annotations

import numpy as np

from .errors import InputError
from .geometry.walls import wall_distances

__all__ = ["initial_positions"]

_GAP = 1e-6  # clearance between neighbours and to the floor at the start [m]
#: Largest initial overlap accepted, as a fraction of the radius.
OVERLAP_TOLERANCE = 1e-3


def _radii(case) -> np.ndarray:
    return np.concatenate([np.full(p.count, p.radius) for p in case.particles])


def initial_positions(case, rng: np.random.Generator) -> np.ndarray:
    """Centres (N, 3) [m] in the container frame for ``case.initial``; validated against the walls."""
    init = case.initial
    rad = _radii(case)
    if init.positions is not None:
        pos = np.asarray(init.positions, dtype=float)
        if pos.shape != (rad.size, 3):
            raise InputError(f"initial.positions: expected {rad.size} rows of (x, y, z) [m], got shape {pos.shape}")
    elif init.arrangement == "block":
        pos = _block(case, rad, rng)
    else:
        pos = _scatter(case, rad, rng)
    check_positions(case, pos, rad)
    return pos


def _capacity_error(case, n_fit, rad):
    g = case.container.geometry
    if case.initial.arrangement == "scatter":
        more = "or arrangement = 'block' with initial.layers = 'auto' to stack layers (a scatter has one layer)"
    else:
        more = "or set initial.layers = 'auto' to stack layers"
    raise InputError(
        f"particles.count = {rad.size}: {rad.size} spheres of r = {rad.max() * 1e3:g} mm do not fit on the floor of the {g.shape} "
        f"in one layer (at most {n_fit}); use fewer particles, a larger container, {more}")


def _layer_sites(case, r, jitter, n_needed=None):
    """One layer of lattice sites (x, z), ordered from -x, with the jitter they allow.

    The jitter shrinks where ``n_needed`` spheres would otherwise not fit (the paper's 48
    spheres of r = 5 mm fill 120 mm x 40.4 mm with no room to spare)."""
    g = case.container.geometry
    if g.shape == "cuboid":
        # rows across the width, each with its start clearance: a width of exactly k diameters
        # holds k - 1 rows (k rows would leave the outer spheres 1 um inside the walls)
        nz = int(np.floor((g.width - _GAP) / (2 * r + _GAP) + 1e-9))
        if nz < 1:
            return np.zeros((0, 2)), 0.0, 0.0
        # rows across the width: room for jitter only where the width leaves some
        jz = max(0.0, min(jitter, (g.width - 2 * r * nz - _GAP * (nz + 1)) / (2 * nz)))
        sz = 2 * r + _GAP + 2 * jz
        # columns along the length: as many as needed (all that fit without overlap when not
        # told), with 1 um gaps and jitter room only where the length leaves some
        nx_full = int(np.floor(g.length / (2 * r) + 1e-9))
        if nx_full < 1:
            return np.zeros((0, 2)), 0.0, 0.0
        nx_need = min(nx_full, int(np.ceil(n_needed / nz))) if n_needed else nx_full
        spare = g.length - 2 * r * nx_need
        gx = max(0.0, min(_GAP, spare / (nx_need + 1)))
        jx = max(0.0, min(jitter, (spare - gx * (nx_need + 1)) / (2 * nx_need)))
        sx = 2 * r + 2 * jx + gx
        nx = min(nx_full, int(np.floor((g.length - 2 * r - 2 * jx - 2 * gx) / sx + 1e-9)) + 1)
        xs = -g.length / 2 + r + jx + gx + sx * np.arange(nx)
        zs = (np.arange(nz) - (nz - 1) / 2) * sz
        X, Z = np.meshgrid(xs, zs, indexing="ij")
        return np.column_stack([X.ravel(), Z.ravel()]), jx, jz
    j = jitter
    while True:
        spacing = 2 * r + 2 * j + _GAP
        sites = g.floor_sites(r + j + _GAP, spacing)
        if not n_needed or len(sites) >= n_needed or j == 0.0:
            return sites, j, j
        j = 0.0 if j < 1e-6 else j / 2


def _block(case, rad, rng):
    r = float(rad.max())  # mixed radii: the lattice of the largest sphere
    n = rad.size
    g = case.container.geometry
    sites, jx, jz = _layer_sites(case, r, case.initial.jitter, n)
    per_layer = len(sites)
    if per_layer == 0:
        raise InputError(f"particles: a sphere of r = {r * 1e3:g} mm does not fit in the {g.shape}")
    n_layers = int(np.ceil(n / per_layer))
    if n_layers > 1 and case.initial.layers != "auto":
        # report the paper's one-layer capacity (without jitter room) in the message
        full, _, _ = _layer_sites(case, r, 0.0)
        if n > len(full):
            _capacity_error(case, len(full), rad)
        sites, jx, jz = _layer_sites(case, r, 0.0)
        per_layer, n_layers = len(sites), 1
    layer_h = 2 * r + _GAP
    if r + (n_layers - 1) * layer_h + r > g.height:
        raise InputError(f"particles: {n} spheres need {n_layers} layers ({(n_layers * layer_h) * 1e3:.1f} mm) but the "
                         f"container is {g.height * 1e3:g} mm high; use fewer particles or a taller container")
    pos = np.empty((n, 3))
    k = 0
    for layer in range(n_layers):
        m = min(per_layer, n - k)
        pos[k:k + m, [0, 2]] = sites[:m] + _jitter(g, rng, m, jx, jz)
        pos[k:k + m, 1] = r + _GAP + layer * layer_h
        k += m
    # smaller spheres sit lower: keep each centre one radius above its layer's floor
    if np.ptp(rad) > 0:
        layer_index = np.arange(n) // per_layer
        pos[:, 1] = rad + _GAP + layer_index * layer_h
    return pos


def _jitter(g, rng, m, jx, jz):
    """(m, 2) random displacements in the floor plane: uniform in the rectangle [-jx, jx] x
    [-jz, jz] (cuboid) or in the disc of radius jx (cylinder: the ring sites keep jx from the
    curved wall in every direction)."""
    if g.shape == "cuboid":
        return np.column_stack([rng.uniform(-jx, jx, m), rng.uniform(-jz, jz, m)])
    rr = jx * np.sqrt(rng.uniform(size=m))
    th = rng.uniform(0.0, 2.0 * np.pi, m)
    return np.column_stack([rr * np.cos(th), rr * np.sin(th)])


def _scatter(case, rad, rng):
    """Spheres on randomly chosen sites of the floor lattice (all sites that leave room for the
    jitter), jittered: a random scatter over the whole floor that never jams, unlike random
    sequential placement, which stalls near half coverage."""
    r = float(rad.max())
    n = rad.size
    g = case.container.geometry
    sites, jx, jz = _layer_sites(case, r, case.initial.jitter)
    if len(sites) < n:
        sites, jx, jz = _layer_sites(case, r, case.initial.jitter, n)
    if len(sites) < n:
        full, _, _ = _layer_sites(case, r, 0.0)
        _capacity_error(case, len(full), rad)
    pick = np.sort(rng.choice(len(sites), size=n, replace=False))
    pos = np.empty((n, 3))
    pos[:, [0, 2]] = sites[pick] + _jitter(g, rng, n, jx, jz)
    pos[:, 1] = rad + _GAP
    return pos


def check_positions(case, pos, rad) -> None:
    """Raise InputError if a sphere overlaps another or sticks out of the container by more than
    :data:`OVERLAP_TOLERANCE` of its radius (resting Hertz overlaps, ~1e-5 r, are fine, so a
    settled state can be restarted)."""
    if not np.all(np.isfinite(pos)):
        raise InputError("initial positions contain NaN or inf")
    kinds, data, names = case.container.geometry.walls()
    s, _ = wall_distances(kinds, np.ascontiguousarray(data), np.ascontiguousarray(pos))
    out = s < rad[:, None] * (1 - OVERLAP_TOLERANCE)
    if out.any():
        i, w = np.argwhere(out)[0]
        raise InputError(f"initial positions: sphere {i} at {np.round(pos[i] * 1e3, 3).tolist()} mm is outside the "
                         f"container or cuts the {names[w]} wall (distance {s[i, w] * 1e3:.3f} mm < r = {rad[i] * 1e3:g} mm)")
    if len(pos) > 1:
        from scipy.spatial import cKDTree

        pairs = cKDTree(pos).query_pairs(2 * rad.max(), output_type="ndarray")
        if len(pairs):
            d = np.linalg.norm(pos[pairs[:, 0]] - pos[pairs[:, 1]], axis=1)
            bad = d < (rad[pairs[:, 0]] + rad[pairs[:, 1]]) * (1 - OVERLAP_TOLERANCE)
            if bad.any():
                i, j = pairs[np.argmax(bad)]
                raise InputError(f"initial positions: spheres {i} and {j} overlap (centres {np.linalg.norm(pos[i] - pos[j]) * 1e3:.3f} mm "
                                 f"apart, radii sum {(rad[i] + rad[j]) * 1e3:g} mm); move them apart")
