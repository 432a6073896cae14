"""The container-shape protocol and its registry: what a shape module says, once, for everything else.

A container shape is one module in :mod:`pdamper.geometry` holding a frozen dataclass that is
registered with :func:`register_shape` (as LAMMPS registers a region style with one macro line).
Everything that needs to know about the container asks the shape through :class:`Shape`; nothing
outside the shape's module switches on which shape it is.

What a shape answers (all in the container frame: x along the length, y up from the floor,
z across; metres):

==========================  =====================================================================
``shape``                   its tag, the config value of ``[container] shape``
config keys                 its dataclass fields, declared with :func:`pdamper.schema.param`
``walls()``                 ``(kinds, data, names)``: its wall primitives (:mod:`.walls`) for the
                            kernels' wall list; the floor is the plane y = 0 with normal +y
``bounding_box()``          ``(lo, hi)``: corners of the box holding the inside (neighbour grid)
``layer_sites(r, j, n)``    ``(sites (k, 2) of (x, z), jx, jz)``: one layer of the initial block or
                            scatter for spheres of radius r with jitter room (jx, jz) (at most j)
``jitter(rng, m, jx, jz)``  ``(m, 2)`` random offsets of the sites in the floor plane
``outline(view)``           closed polygons ``[(k, 2), ...]`` of the walls seen from ``"top"``
                            (x, z) or from the ``"side"`` (x, y), for figures and animations
``length_along(d)``         the inner length [m] along the horizontal unit vector d through the
                            floor's centre
``drive_length``            L [m] of the clearance law, eq. (6): the inner length along the
                            container's x axis (the drive's); from ``length_along`` by default
``length_keys``             the config keys that set ``drive_length`` (what ``pdamper theory`` and
                            ``design`` must be given): the cuboid's ``length``, the cylinder's
                            ``radius``; by default every key but ``height``
``with_drive_length(L)``    the shape scaled so that ``drive_length`` is L (its ``length_keys``
                            in proportion; the design's container lengths)
``row_capacity(r)``         spheres side by side across the drive in one row (the design's rows)
``end_contacts(...)``       which frames have a sphere at the wall ahead / behind along the drive
``max_particles(r)``        spheres that fit on the floor in one layer
``clearance_capacity(r)``   N_p,max of the clearance law, eq. (6), as the paper counts it
``mesh()``                  ``(vertices, quads)`` of the inner surface (VTK export)
``describe()``              one line for people ("cuboid 120 x 40.4 x 40 mm")
==========================  =====================================================================

:class:`ShapeBase` gives every shape the answers that follow from the others (the jitter in a
disc, layer sites from ``floor_sites``, the side outline from the bounding box, planar end walls),
so a new shape writes only what is its own. ``tests/geometry/test_shape_protocol.py`` adds a toy
shape inside the test and runs a case in it.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Protocol, runtime_checkable

import numpy as np

from ..schema import register_tagged

__all__ = ["Shape", "ShapeBase", "SHAPES", "register_shape", "shape_from_keys", "sizing_keys", "GAP"]

#: Clearance [m] between neighbours and to the floor at the start (the initial block's gap).
GAP = 1e-6

#: Registered shapes by tag (``[container] shape``).
SHAPES: dict[str, type] = {}


@runtime_checkable
class Shape(Protocol):
    """What a container shape answers (see the module docstring)."""

    shape: str

    def walls(self): ...

    def bounding_box(self): ...

    def layer_sites(self, radius: float, jitter: float, n_needed: int | None = None): ...

    def jitter(self, rng, m: int, jx: float, jz: float): ...

    def outline(self, view: str): ...

    def length_along(self, direction) -> float: ...

    @property
    def drive_length(self) -> float: ...

    def with_drive_length(self, length: float): ...

    def row_capacity(self, radius: float) -> int: ...

    def end_contacts(self, position, radius, along, length: float, gap): ...

    def max_particles(self, radius: float) -> int: ...

    def clearance_capacity(self, radius: float) -> int: ...

    def mesh(self): ...

    def describe(self) -> str: ...


def register_shape(cls):
    """Class decorator: register a shape dataclass under its ``shape`` tag (the default of its
    ``shape`` field). Returns the class."""
    return register_tagged(SHAPES, cls, "shape", "shape",
                           needs=("walls", "bounding_box", "layer_sites", "outline", "max_particles", "describe",
                                  "length_along", "clearance_capacity", "with_drive_length", "row_capacity"),
                           has=("drive_length",))


def sizing_keys(cls) -> tuple:
    """The config keys that set the shape ``cls``'s ``drive_length``: its ``length_keys``, or every
    config key but ``height`` where it names none."""
    from ..schema import config_keys

    return tuple(getattr(cls, "length_keys", ())) or tuple(k for k in config_keys(cls) if k != "height")


def shape_from_keys(shape: str, keys: dict, *, option=lambda key: f"--{key.replace('_', '-')}",
                    require: bool = True):
    """The registered shape ``shape`` built from its config keys ``keys`` (None values left out),
    for a command that sizes a container from options: each key must be the shape's, and (with
    ``require``) its :func:`sizing_keys` (which set the clearance's L) must be given.
    ``option(key)`` names the command's option of a key in messages."""
    from ..errors import InputError, shown
    from ..schema import config_keys

    if shape not in SHAPES:
        raise InputError(f"shape = {shown(shape)} is unknown; use one of {', '.join(SHAPES)}")
    cls = SHAPES[shape]
    given = {k: v for k, v in keys.items() if v is not None}
    own = config_keys(cls)
    for k in given:
        if k not in own:
            owners = [s for s, c in SHAPES.items() if k in config_keys(c)]
            where = f"to shape {owners[0]!r}" if owners else "to no shape"
            raise InputError(f"{option(k)} applies {where}, not to the {shape}; the {shape} takes "
                             + ", ".join(option(x) for x in own))
    missing = [k for k in sizing_keys(cls) if k not in given]
    if missing and require:
        raise InputError(f"the {shape} needs {' and '.join(option(k) for k in missing)} (its size along the drive, "
                         f"which sets the clearance's L)")
    return cls(**given)



class ShapeBase:
    """Answers of the shape protocol that follow from a shape's own ``walls``, ``bounding_box``
    and ``floor_sites``; a shape overrides any of them where it knows better."""

    #: the config keys that set ``drive_length`` (empty: every key but ``height``, :func:`sizing_keys`)
    length_keys: tuple = ()

    @property
    def drive_length(self) -> float:
        """L [m] of the clearance, eq. (6): the inner length along the container's x axis through
        the floor's centre (:meth:`length_along`)."""
        return self.length_along((1.0, 0.0, 0.0))

    def with_drive_length(self, length: float):
        """This shape scaled so that :attr:`drive_length` is ``length`` [m]: its
        :func:`sizing_keys` in proportion, the other keys (the height, a width) kept."""
        scale = float(length) / self.drive_length
        return dataclasses.replace(self, **{k: getattr(self, k) * scale for k in sizing_keys(type(self))})

    def row_capacity(self, radius: float) -> int:
        """Spheres of ``radius`` side by side across the drive in one row: the one-layer count
        over the rows that fit along the drive."""
        along = max(1, math.floor(self.drive_length / (2 * radius) + 1e-9))
        return max(1, round(self.clearance_capacity(radius) / along))

    def layer_sites(self, radius: float, jitter: float, n_needed: int | None = None):
        """One layer of sites from :meth:`floor_sites` with room ``jitter`` around each, the
        jitter halved until ``n_needed`` sites fit (then 0)."""
        j = jitter
        while True:
            spacing = 2 * radius + 2 * j + GAP
            sites = self.floor_sites(radius + j + GAP, spacing)
            if not n_needed or len(sites) >= n_needed or j == 0.0:
                return sites, j, j
            j = 0.0 if j < 1e-6 else j / 2

    def jitter(self, rng, m: int, jx: float, jz: float):
        """(m, 2) random offsets uniform in the disc of radius ``jx`` (the sites keep ``jx`` from
        every wall in every direction)."""
        rr = jx * np.sqrt(rng.uniform(size=m))
        th = rng.uniform(0.0, 2.0 * np.pi, m)
        return np.column_stack([rr * np.cos(th), rr * np.sin(th)])

    def outline(self, view: str):
        """The side view is the bounding box's x-y rectangle; a shape draws its own top view."""
        lo, hi = self.bounding_box()
        if view == "side":
            return [_rectangle(lo[0], hi[0], lo[1], hi[1])]
        if view == "top":
            return [_rectangle(lo[0], hi[0], lo[2], hi[2])]
        raise ValueError(f"outline view {view!r}; choose 'top' or 'side'")

    def length_along(self, direction) -> float:
        """The chord [m] through the floor's centre along the horizontal part of ``direction``,
        found from the walls' signed distances (bisection on each side)."""
        d = np.array([direction[0], 0.0, direction[2]], dtype=float)
        n = np.linalg.norm(d)
        if n == 0:
            return 0.0
        d /= n
        lo, hi = self.bounding_box()
        centre = np.array([0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])])
        reach = float(np.linalg.norm(hi - lo))
        return _exit_distance(self, centre, d, reach) + _exit_distance(self, centre, -d, reach)

    def end_contacts(self, position, radius, along, length: float, gap):
        """(on_lo, on_hi): per frame, whether a sphere is within ``gap`` of the wall behind / ahead
        along the drive; ``along`` (F, N) the centres' coordinate along the drive from the floor's
        centre, ``length`` the inner length along it (planar end walls across the drive)."""
        on_lo = np.any(along - radius <= -length / 2 + gap, axis=1)
        on_hi = np.any(along + radius >= length / 2 - gap, axis=1)
        return on_lo, on_hi

    def volume(self) -> float:
        """The inside's volume [m^3]: the top outline's area times the height."""
        ring = self.outline("top")[0]
        x, z = ring[:, 0], ring[:, 1]
        lo, hi = self.bounding_box()
        return 0.5 * abs(float(np.dot(x, np.roll(z, 1)) - np.dot(z, np.roll(x, 1)))) * float(hi[1] - lo[1])

    def max_particles(self, radius: float) -> int:
        """Spheres of ``radius`` on the floor in one layer (the layer sites without jitter)."""
        return int(len(self.layer_sites(radius, 0.0)[0]))

    def clearance_capacity(self, radius: float) -> int:
        """N_p,max [-] of the clearance law, eq. (6): the one-layer count."""
        return self.max_particles(radius)

    def mesh(self):
        """(vertices, quads) of the side walls: the top outline extruded from the floor to the lid."""
        ring = self.outline("top")[0]
        k = len(ring)
        lo, hi = self.bounding_box()
        v = np.vstack([np.column_stack([ring[:, 0], np.full(k, lo[1]), ring[:, 1]]),
                       np.column_stack([ring[:, 0], np.full(k, hi[1]), ring[:, 1]])])
        quads = np.array([[i, (i + 1) % k, k + (i + 1) % k, k + i] for i in range(k)])
        return v, quads

    def describe(self) -> str:
        keys = [f.name for f in dataclasses.fields(self) if f.name != "shape"]
        return f"{self.shape} " + ", ".join(f"{k} = {getattr(self, k) * 1e3:g} mm" for k in keys)


def _rectangle(x0, x1, y0, y1) -> np.ndarray:
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]], dtype=float)


def _exit_distance(shape, start, d, reach) -> float:
    from .walls import wall_distances

    kinds, data, _ = shape.walls()
    data = np.ascontiguousarray(data, dtype=float)

    def inside(t):
        s, _ = wall_distances(np.asarray(kinds), data, np.ascontiguousarray((start + t * d)[None, :]))
        return bool(np.all(s[0] > 0))

    a, b = 0.0, reach
    for _ in range(60):
        m = 0.5 * (a + b)
        a, b = (m, b) if inside(m) else (a, m)
    return 0.5 * (a + b)


def polygon_circle(cx: float, cy: float, radius: float, segments: int = 96) -> np.ndarray:
    """A closed polygon (segments, 2) approximating a circle (for outlines)."""
    th = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
    return np.column_stack([cx + radius * np.cos(th), cy + radius * np.sin(th)])
