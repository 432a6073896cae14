"""Initial particle positions: a compact block against the -x wall, a random scatter, or given.

Both generated arrangements apply a seeded random jitter in the floor plane, so a run repeats
bit for bit with the same seed and varies on purpose with another. Spheres start a hair
(1 um) above the floor and settle under gravity before the drive starts
(:attr:`pdamper.params.InitialState.settle_time`).
"""

from __future__ import annotations

import numpy as np

from .errors import InputError
from .geometry.walls import PLANE, wall_distances

__all__ = ["initial_positions", "floor_capacity"]

from .geometry.shape import GAP as _GAP  # clearance between neighbours and to the floor at the start [m]
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


def floor_capacity(container, radius: float) -> int:
    """Spheres of ``radius`` [m] that the initial block places on the floor of ``container`` (a
    :class:`~pdamper.params.Container`, its baffles counted) in one layer: the lattice sites
    without jitter (:func:`_layer_sites`). The one rule of what fits: a run refuses more spheres in
    one layer than this, and the design (:mod:`pdamper.design`) offers no filling above it.

    >>> from pdamper.params import Container
    >>> floor_capacity(Container(), 0.005)  # the paper's cuboid, 12 x 4
    48
    """
    return int(len(_layer_sites(container, radius, 0.0)[0]))


def _capacity_error(case, n_fit, rad):
    g = case.container.geometry
    if case.initial.arrangement == "scatter":
        more = "or arrangement = 'block' with initial.layers = 'auto' to stack layers (a scatter has one layer)"
    else:
        more = "or set initial.layers = 'auto' to stack layers"
    raise InputError(
        f"particles.count = {rad.size}: {rad.size} spheres of r = {rad.max() * 1e3:g} mm do not fit on the floor of the {g.shape} "
        f"in one layer (at most {n_fit}); use fewer particles, a larger container, {more}")


def _layer_sites(container, r, jitter, n_needed=None):
    """One layer of lattice sites (x, z), ordered from -x, with the jitter they allow (the shape's
    :meth:`~pdamper.geometry.shape.Shape.layer_sites`).

    Inner baffles that reach down into the layer split the floor into compartments: the shape's
    columns (sites of equal x) are laid from the -x wall on, and a column that would cut a baffle
    moves, with all after it, to just past the baffle; the sites that then no longer fit in the
    container are left out. Each compartment is so filled from its -x side."""
    c = container
    blocking = [b for b in c.baffles if b.gap_below < 2 * r + _GAP]
    if not blocking:
        return c.geometry.layer_sites(r, jitter, n_needed)
    sites, jx, jz = c.geometry.layer_sites(r, jitter, None)
    reach = r + jx + _GAP
    plates = sorted((b.position - b.thickness / 2, b.position + b.thickness / 2) for b in blocking)
    xs = sites[:, 0].copy()
    columns = np.unique(np.round(sites[:, 0], 12))
    shift = 0.0
    for x in columns:
        moved = x + shift
        for lo, hi in plates:
            if moved + reach > lo and moved - reach < hi:
                shift += hi + reach - moved
                moved = hi + reach
        xs[np.round(sites[:, 0], 12) == x] = moved
    placed = np.column_stack([xs, sites[:, 1]])
    kinds, data, _ = c.walls()
    pts = np.column_stack([placed[:, 0], np.full(len(placed), r + _GAP), placed[:, 1]])
    s, _ = wall_distances(np.ascontiguousarray(kinds), np.ascontiguousarray(data), np.ascontiguousarray(pts))
    # the floor and the lid (planes with a vertical normal): the layer's height is set apart
    floor_like = (kinds == PLANE) & (np.abs(data[:, 1]) > 0.99)
    moved = xs != sites[:, 0]                # the shape's own sites keep the room it gave them
    room = np.where(moved, r + max(jx, jz), r)[:, None] - 1e-12
    keep = np.all((s >= room) | floor_like[None, :], axis=1)
    return placed[keep], jx, jz


def _block(case, rad, rng):
    r = float(rad.max())  # mixed radii: the lattice of the largest sphere
    n = rad.size
    g = case.container.geometry
    sites, jx, jz = _layer_sites(case.container, r, case.initial.jitter, n)
    per_layer = len(sites)
    if per_layer == 0:
        raise InputError(f"particles: a sphere of r = {r * 1e3:g} mm does not fit in the {g.shape}")
    n_layers = int(np.ceil(n / per_layer))
    if n_layers > 1 and case.initial.layers != "auto":
        # report the paper's one-layer capacity (without jitter room) in the message
        full = floor_capacity(case.container, r)
        if n > full:
            _capacity_error(case, full, rad)
        sites, jx, jz = _layer_sites(case.container, r, 0.0)
        per_layer, n_layers = len(sites), 1
    layer_h = 2 * r + _GAP
    lo, hi = g.bounding_box()
    height = hi[1] - lo[1]
    if r + (n_layers - 1) * layer_h + r > height:
        raise InputError(f"particles: {n} spheres need {n_layers} layers ({(n_layers * layer_h) * 1e3:.1f} mm) but the "
                         f"container is {height * 1e3:g} mm high; use fewer particles or a taller container")
    pos = np.empty((n, 3))
    k = 0
    for layer in range(n_layers):
        m = min(per_layer, n - k)
        pos[k:k + m, [0, 2]] = sites[:m] + g.jitter(rng, m, jx, jz)
        pos[k:k + m, 1] = r + _GAP + layer * layer_h
        k += m
    # smaller spheres sit lower: keep each centre one radius above its layer's floor
    if np.ptp(rad) > 0:
        layer_index = np.arange(n) // per_layer
        pos[:, 1] = rad + _GAP + layer_index * layer_h
    return pos


def _scatter(case, rad, rng):
    """Spheres on randomly chosen sites of the floor lattice (all sites that leave room for the
    jitter), jittered: a random scatter over the whole floor that never jams, unlike random
    sequential placement, which stalls near half coverage."""
    r = float(rad.max())
    n = rad.size
    g = case.container.geometry
    sites, jx, jz = _layer_sites(case.container, r, case.initial.jitter)
    if len(sites) < n:
        sites, jx, jz = _layer_sites(case.container, r, case.initial.jitter, n)
    if len(sites) < n:
        _capacity_error(case, floor_capacity(case.container, r), rad)
    pick = np.sort(rng.choice(len(sites), size=n, replace=False))
    pos = np.empty((n, 3))
    pos[:, [0, 2]] = sites[pick] + g.jitter(rng, n, jx, jz)
    pos[:, 1] = rad + _GAP
    return pos


def check_positions(case, pos, rad) -> None:
    """Raise InputError if a sphere overlaps another or sticks out of the container by more than
    :data:`OVERLAP_TOLERANCE` of its radius (resting Hertz overlaps, ~1e-5 r, are fine, so a
    settled state can be restarted)."""
    if not np.all(np.isfinite(pos)):
        raise InputError("initial positions contain NaN or inf")
    kinds, data, names = case.container.walls()
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
