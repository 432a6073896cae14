"""Parameters of a simulated case: frozen, keyword-only dataclasses in SI units.

A case is a :class:`Case`; a sweep is ``dataclasses.replace`` over a base case, by config keys
(:func:`pdamper.schema.replace`: ``replace(case, {"drive.stroke": "13mm"})``). Validation happens in ``__post_init__`` and raises
:class:`pdamper.errors.InputError` naming the field, the value and what is allowed.
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import warnings
from dataclasses import dataclass

from .contact.cor_constant import ConstantRestitution
from .contact.friction_tanh import DEFAULT_TAU
from .contact import DAMPING_CHOICES, TANGENTIAL_CHOICES, kernel_law, read_restitution
from .contact.hertz_gonthier import V_IN_FLOOR
from .errors import InputError, shown
from .excitation import DriveBase, HarmonicDrive
from .geometry import Baffle, Cuboid, Shape
from .geometry.baffles import baffle_outlines, baffle_walls, floor_sections
import numpy as np

from .materials import PVC, STEEL_S235, Material, read_material
from .units import is_quantity, to_si
from .schema import check_choice, check_keys, config_keys, convert_fields, param, read_fields, read_list, read_quantity, replace

__all__ = ["ParticleSet", "Container", "ContactModel", "Numerics", "Recording", "InitialState", "Case", "Damper",
           "PAPER_TILT", "with_stroke"]

#: Largest gravity a case may have [m/s^2]: ten times Earth's.
MAX_GRAVITY = 100.0
#: Largest impact speed a case may expect [m/s]: beyond it the contact time, and the time step, vanish.
MAX_IMPACT_SPEED = 1000.0
#: Most spheres a set may hold: a whole number beyond it (10**400 in a config) is no bed, and no float.
MAX_COUNT = 2**31 - 1

#: The paper's default tilt: 0.1 deg about the container's x, y and z axes [rad].
PAPER_TILT = (math.radians(0.1),) * 3


#: The config section of each parameter class, for messages that name a key as a config file has it.
_SECTION = {"ParticleSet": "particles", "Container": "container", "ContactModel": "contact", "Numerics": "numerics",
            "Recording": "recording", "InitialState": "initial", "Case": "run"}


def _positive(obj, name, allowed="> 0"):
    v = getattr(obj, name)
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not (v > 0) or not math.isfinite(v):
        section = _SECTION.get(type(obj).__name__, type(obj).__name__.lower())
        raise InputError(f"{section}.{name} = {shown(v)}; must be {allowed}")


@dataclass(frozen=True, kw_only=True)
class ParticleSet:
    """``count`` identical spheres.

    Parameters
    ----------
    count : int, >= 1.
    radius : float, r [m] > 0 (paper: 5 mm).
    material : Material (paper: steel S235).
    """

    count: int = param(kind="whole")
    radius: float = param(0.005, dimension="length", paper="5 mm")
    material: Material = param(STEEL_S235, kind="custom", read=read_material)

    def __post_init__(self):
        convert_fields(self, "particles")
        if isinstance(self.count, bool) or not isinstance(self.count, int) or not 1 <= self.count <= MAX_COUNT:
            raise InputError(f"particles.count = {shown(self.count)}; must be a whole number from 1 to {MAX_COUNT:,} "
                             "(the spheres of one set)")
        _positive(self, "radius", "> 0 m (paper: 5 mm)")

    @property
    def mass(self) -> float:
        """Mass of one sphere [kg]."""
        return self.material.density * 4.0 / 3.0 * math.pi * self.radius**3


@dataclass(frozen=True, kw_only=True)
class Container:
    """The container: its inner shape, wall materials, inner baffles, tilt and mass.

    Parameters
    ----------
    geometry : a registered container shape (:mod:`pdamper.geometry.shape`: Cuboid, Cylinder, ...).
    material : Material of the walls (paper: PVC).
    tilt : (a_x, a_y, a_z) [rad] about the container's x, y, z axes, applied in that order
        (see :mod:`pdamper.geometry.tilt`). Paper default 0.1 deg each.
    mass : float, m_c [kg] >= 0, the empty container's (a key of the damper): with a prescribed
        drive it enters the driving force as m_c x_c'' (no effect on Re P); on a structure it
        moves with the structure, at the damper (:attr:`Case.running_drive`).
    baffles : inner plates across the x axis (:class:`pdamper.geometry.baffles.Baffle`).
    wall_materials : {wall name: Material} for walls of another material than ``material`` (a
        coating), by the names of :meth:`walls` (a cuboid: x_min, x_max, floor, lid, z_min, z_max).
    """

    geometry: Shape = param(default_factory=Cuboid, kind="custom", inline=True)
    material: Material = param(PVC, kind="custom", read=read_material)
    tilt: tuple = param(PAPER_TILT, kind="custom", read=lambda value, section: read_tilt(value, section))
    mass: float = param(0.0, dimension="mass")
    baffles: tuple = param((), kind="custom", read=lambda value, section: read_baffles(value, section))
    wall_materials: dict = param(default_factory=dict, kind="custom",
                                 read=lambda value, section: read_wall_materials(value, section))

    def __post_init__(self):
        convert_fields(self, "container")
        tilt = self.tilt
        if isinstance(tilt, str) or is_quantity(tilt) and tilt.ndim == 0:
            raise InputError(f"container.tilt = {shown(tilt)}; give three angles about x, y, z, e.g. "
                             "('0.1deg', '0.1deg', '0.1deg')")
        tilt = to_si(list(tilt), "angle", name="container.tilt")
        t = tuple(float(a) for a in tilt)
        if len(t) != 3 or any(not math.isfinite(a) or abs(a) >= math.pi / 4 for a in t):
            raise InputError(f"container.tilt = {shown(self.tilt)}; give three angles about x, y, z, each below 45 deg")
        object.__setattr__(self, "tilt", t)
        if not (self.mass >= 0 and math.isfinite(self.mass)):
            raise InputError(f"container.mass = {shown(self.mass)} kg; must be >= 0")
        if not isinstance(self.geometry, Shape):
            raise InputError(f"container.geometry = {shown(self.geometry)}; give a container shape such as Cuboid(...)")
        baffles = tuple(self.baffles)
        for k, b in enumerate(baffles, 1):
            if not isinstance(b, Baffle):
                raise InputError(f"container.baffles #{k} = {shown(b)}; give a Baffle(position=...)")
            b.check_fits(self.geometry, k)
            if b.material is not None and not isinstance(b.material, Material):
                raise InputError(f"container.baffles #{k}: material = {shown(b.material)}; give a Material")
        object.__setattr__(self, "baffles", baffles)
        names = self.walls()[2]
        for name, m in self.wall_materials.items():
            if name not in names:
                near = difflib.get_close_matches(str(name), names, n=1)
                hint = f"did you mean {near[0]!r}? " if near else ""
                raise InputError(f"container.wall_materials: no wall {shown(name)} in this container; {hint}its walls are "
                                 f"{', '.join(names)}")
            if not isinstance(m, Material):
                raise InputError(f"container.wall_materials.{name} = {shown(m)}; give a Material")

    def walls(self):
        """(kinds, data, names) of all walls: the shape's, then the baffles' (see
        :mod:`pdamper.geometry.walls`)."""
        kinds, data, names = self.geometry.walls()
        if not self.baffles:
            return kinds, data, names
        lo, hi = self.geometry.bounding_box()
        bk, bd, bn = baffle_walls(self.baffles, hi[1] - lo[1])
        return np.concatenate([kinds, bk]), np.vstack([data, bd]), list(names) + bn

    def compartments(self, radius: float) -> list[tuple[float, float]]:
        """The floor's sections along x [m], ``[(a, b), ...]``, that a sphere of ``radius`` cannot
        leave along the floor: split by the baffles whose gap below is under its diameter
        (:func:`pdamper.geometry.baffles.floor_sections`); one section without such baffles."""
        lo, hi = self.geometry.bounding_box()
        return floor_sections(self.baffles, float(lo[0]), float(hi[0]), radius)

    def wall_material_list(self) -> list:
        """The material of each wall, in the order of :meth:`walls`."""
        names = self.walls()[2]
        own = {f"baffle {k + 1}": b.material for k, b in enumerate(self.baffles) if b.material is not None}
        return [self.wall_materials.get(n, own.get(n, self.material)) for n in names]

    def outline(self, view: str) -> list:
        """Closed polygons, (k, 2) arrays in metres, of the container seen from ``"top"`` (x, z) or the
        ``"side"`` (x, y): the shape's, then the baffles'."""
        polys = list(self.geometry.outline(view))
        if self.baffles:
            lo, hi = self.geometry.bounding_box()
            polys += baffle_outlines(self.baffles, view, hi[1] - lo[1], (lo[2], hi[2]))
        return polys

    def describe(self) -> str:
        """One line: the shape, its baffles and coated walls."""
        out = self.geometry.describe()
        if self.baffles:
            out += f", {len(self.baffles)} baffle{'s' if len(self.baffles) > 1 else ''}"
        if self.wall_materials:
            out += ", " + ", ".join(f"{n} {m.name}" for n, m in self.wall_materials.items())
        return out


@dataclass(frozen=True, kw_only=True)
class ContactModel:
    """Contact laws for all contacts, with optional per-material-pair overrides.

    Parameters
    ----------
    friction : float, mu [-] >= 0 (paper: 0.1 for all contacts).
    restitution : a COR law (ConstantRestitution, TabulatedRestitution, ThorntonRestitution);
        default constant 0.9.
    tau : float, friction smoothing [s/m] > 0 (default 1000; see :mod:`pdamper.contact.friction_tanh`).
    v_in_floor : float, floor on the first-touch approach speed [m/s] > 0 (default 1 mm/s).
    damping : the normal damping law, a name of :data:`pdamper.contact.DAMPING_LAWS`:
        "calibrated" (default: eq. (1), an impact rebounds with exactly the COR asked for),
        "gonthier" (the paper's ``d = (1 - eps^2)/(eps v_in)`` as written, which rebounds up to
        4 % lower; see :mod:`pdamper.contact.hertz_gonthier`) or "tsuji" (Hertz with Tsuji's
        viscoelastic damping, as LIGGGHTS' ``model hertz``; :mod:`pdamper.contact.hertz_tsuji`).
    tangential : the tangential law, a name of :data:`pdamper.contact.TANGENTIAL_LAWS`: "tanh"
        (default: the paper's regularised Coulomb friction, eq. (2),
        :mod:`pdamper.contact.friction_tanh`) or "spring" (an incremental tangential spring with
        Mindlin's stiffness 8 G* sqrt(R* delta) and a Coulomb cap, as LIGGGHTS' ``tangential
        history``; :mod:`pdamper.contact.tangential_spring`).
    tangential_damping : bool, with the spring: LIGGGHTS' tangential damping on the slip
        (default True, as in LIGGGHTS); no effect on "tanh".
    pair_friction, pair_restitution : dict mapping ``(material_a, material_b)`` names (e.g.
        ``("steel", "pvc")``) to a friction coefficient / a COR law; order does not matter.
    """

    friction: float = param(0.1, paper="0.1")
    restitution: object = param(default_factory=ConstantRestitution, kind="custom", read=read_restitution)
    tau: float = param(DEFAULT_TAU, unit="s/m")
    v_in_floor: float = param(V_IN_FLOOR, dimension="velocity")
    damping: str = param("calibrated", choices=DAMPING_CHOICES)
    tangential: str = param("tanh", choices=TANGENTIAL_CHOICES, write_default=False)
    tangential_damping: bool = param(True, write_default=False)
    pair_friction: dict = param(default_factory=dict, kind="custom")
    pair_restitution: dict = param(default_factory=dict, kind="custom")

    def __post_init__(self):
        convert_fields(self, "contact")
        for mu in [self.friction, *self.pair_friction.values()]:
            if not (isinstance(mu, (int, float)) and mu >= 0 and math.isfinite(mu)):
                raise InputError(f"contact.friction = {shown(mu)}; a friction coefficient must be >= 0 (paper: 0.1)")
        _positive(self, "tau", "> 0 s/m (default 1000)")
        _positive(self, "v_in_floor", "> 0 m/s (default 1e-3)")
        check_choice(self, "damping", "contact")
        check_choice(self, "tangential", "contact")
        if not isinstance(self.tangential_damping, bool):
            raise InputError(f"contact.tangential_damping = {shown(self.tangential_damping)}; must be true or false "
                             "(default true)")

    def friction_for(self, a: str, b: str) -> float:
        """mu [-] for the material pair (a, b)."""
        return float(self.pair_friction.get((a, b), self.pair_friction.get((b, a), self.friction)))

    def restitution_for(self, a: str, b: str):
        """COR law for the material pair (a, b)."""
        return self.pair_restitution.get((a, b), self.pair_restitution.get((b, a), self.restitution))

    def written_laws(self) -> "ContactModel":
        """This model with every COR law as a config file holds it: a law of your own (any object with
        ``restitution(speed)``) as the table law of its values at the kernels' speeds
        (:func:`pdamper.contact.kernel_law`: the kernels run the same bits), refused in one line where it
        cannot be tabulated once for every contact; this model itself when every law is pdamper's."""
        law = kernel_law(self.restitution)
        pairs = {k: kernel_law(v) for k, v in self.pair_restitution.items()}
        if law is self.restitution and all(pairs[k] is v for k, v in self.pair_restitution.items()):
            return self
        return dataclasses.replace(self, restitution=law, pair_restitution=pairs)


@dataclass(frozen=True, kw_only=True)
class Numerics:
    """How the equations are integrated.

    Parameters
    ----------
    integrator : "gear" (variable-step 5th-order predictor-corrector, the paper's; default) or
        "verlet" (fixed step). Gear is the default because it is faster at equal accuracy on the
        paper's runs (measured: docs/integrators.md).
    time_step : fixed step [s] for Verlet; None picks it from the Hertz contact time at
        ``max_impact_speed`` divided by ``steps_per_contact``.
    steps_per_contact : int, steps per shortest Hertz contact (default 15).
    max_impact_speed : expected largest impact speed [m/s]; None: 2.5 X Omega + 0.1 m/s.
    max_time_step : upper bound on any step [s] (default 1e-5).
    gear_tolerance : Gear's local position error bound [m] per step (default 1e-9; docs/integrators.md).
    gear_max_step : Gear's longest step [s] (default 5e-5).
    neighbour_search : "auto", "direct" (all pairs) or "cells" (link cells) for building the Verlet list.
    skin : Verlet-list skin [m]; None: 0.2 r_max.
    overlap_limit : a run stops when an overlap exceeds this fraction of the radius (default 0.05).
    device : "cpu" (default) or "cuda": the GPU engine (:mod:`pdamper.engine.cuda`), which runs the
        cases of a batch together on one NVIDIA GPU, each with its integrator (docs/engine.md, "The GPU
        engine"); it needs numba-cuda (``pip install -e ".[gpu]"``).
    """

    integrator: str = param("gear", choices=("verlet", "gear"))
    time_step: float | None = param(None, dimension="time", auto=True)
    steps_per_contact: int = 15
    max_impact_speed: float | None = param(None, dimension="velocity", auto=True)
    max_time_step: float = param(1e-5, dimension="time")
    gear_tolerance: float = param(1e-9, dimension="length")
    gear_max_step: float = param(5e-5, dimension="time")
    neighbour_search: str = param("auto", choices=("auto", "direct", "cells"))
    skin: float | None = param(None, dimension="length", auto=True)
    overlap_limit: float = 0.05
    # where a case runs is not what it is: "cpu" is left out of a written config (a store's fingerprint stays)
    device: str = param("cpu", choices=("cpu", "cuda"), write_default=False)

    def __post_init__(self):
        convert_fields(self, "numerics")
        check_choice(self, "integrator", "numerics")
        check_choice(self, "device", "numerics")
        check_choice(self, "neighbour_search", "numerics")
        if self.time_step is not None:
            _positive(self, "time_step", "> 0 s (or omit it for the automatic step)")
        if not (isinstance(self.steps_per_contact, int) and self.steps_per_contact >= 4):
            raise InputError(f"numerics.steps_per_contact = {shown(self.steps_per_contact)}; must be a whole number >= 4")
        if self.max_impact_speed is not None:
            _positive(self, "max_impact_speed", "> 0 m/s")
            if self.max_impact_speed > MAX_IMPACT_SPEED:  # the contact time, and the step, would vanish
                raise InputError(f"numerics.max_impact_speed = {shown(self.max_impact_speed)} m/s; must be at most "
                                 f"{MAX_IMPACT_SPEED:g} m/s (spheres in a damper meet at a few m/s), or 'auto'")
        _positive(self, "max_time_step", "> 0 s")
        _positive(self, "gear_tolerance", "> 0 m")
        _positive(self, "gear_max_step", "> 0 s")
        if self.skin is not None:
            _positive(self, "skin", "> 0 m")
        if not (0 < self.overlap_limit < 0.5):
            raise InputError(f"numerics.overlap_limit = {shown(self.overlap_limit)}; must be in (0, 0.5)")


@dataclass(frozen=True, kw_only=True)
class Recording:
    """What is recorded and how often.

    Parameters
    ----------
    sample_rate : float [Hz] of the force/motion signals (default 1000, as the paper's rig);
        each sample is the mean over its interval (impulse / interval), never a point value.
    trajectory_fps : frames per second of decimated particle trajectories (0: none).
    """

    sample_rate: float = param(1000.0, dimension="frequency", paper="1000 Hz")
    trajectory_fps: float = param(0.0, dimension="frequency")

    def __post_init__(self):
        convert_fields(self, "recording")
        _positive(self, "sample_rate", "> 0 Hz (default 1000)")
        if not (self.trajectory_fps >= 0 and math.isfinite(self.trajectory_fps)):
            raise InputError(f"recording.trajectory_fps = {shown(self.trajectory_fps)}; must be >= 0")
        if self.trajectory_fps > self.sample_rate:
            raise InputError(f"recording.trajectory_fps = {shown(self.trajectory_fps)} exceeds sample_rate = "
                             f"{shown(self.sample_rate)}; use at most the sample rate")


@dataclass(frozen=True, kw_only=True)
class InitialState:
    """How the particles start.

    Parameters
    ----------
    arrangement : "block" (compact block at rest against the -x wall, default) or "scatter"
        (randomly chosen sites of the floor lattice, each jittered, over the whole floor).
    jitter : random displacement [m] of each sphere in the floor plane, uniform in
        [-jitter, jitter] (default 0.1 mm); set 0 for a perfect lattice.
    seed : int, seed of the random generator (same seed, same run, bit for bit).
    settle_time : time [s] the particles settle under gravity in the still container before the
        drive starts (default 0.1 s).
    layers : "one" (error when the spheres do not fit in one layer on the floor) or "auto"
        (stack further layers, for large beds).
    positions : optional explicit initial centres [(x, y, z), ...] [m] in the container frame.
    velocities, spins : optional initial velocities [m/s] and spins [rad/s], (N, 3) each, in the
        lab frame at the start of the run (before settling; use ``settle_time = 0`` to keep them).
    """

    arrangement: str = param("block", choices=("block", "scatter"))
    jitter: float = param(1e-4, dimension="length")
    seed: int = 0
    settle_time: float = param(0.1, dimension="time")
    layers: str = param("one", choices=("one", "auto"))
    positions: tuple | None = param(None, kind="rows", dimension="length", example="'5mm'")
    velocities: tuple | None = param(None, kind="rows", dimension="velocity", example="'0.1m/s'")
    spins: tuple | None = param(None, kind="rows", dimension="frequency", example="'10rad/s'")

    def __post_init__(self):
        convert_fields(self, "initial")
        check_choice(self, "arrangement", "initial")
        if not (self.jitter >= 0 and math.isfinite(self.jitter)):
            raise InputError(f"initial.jitter = {shown(self.jitter)} m; must be >= 0")
        if isinstance(self.seed, bool) or not isinstance(self.seed, int) or self.seed < 0:
            raise InputError(f"initial.seed = {shown(self.seed)}; must be a whole number >= 0")
        if not (self.settle_time >= 0 and math.isfinite(self.settle_time)):
            raise InputError(f"initial.settle_time = {shown(self.settle_time)} s; must be >= 0")
        check_choice(self, "layers", "initial")


@dataclass(frozen=True, kw_only=True)
class Damper:
    """One of several dampers on a structure (a ``[[damper]]`` table): its own container and
    filling, and the direction it moves in (lab frame; default the structure's ``angle`` /
    ``direction``). Where it sits is the structure's: the k-th table is at the structure's k-th
    damper point (``damper_dof = [3, 1]``, ``damper_nodes``; the table's ``dof`` or ``node`` sets it),
    or at its one point.

    Parameters
    ----------
    container : :class:`Container`.
    particles : tuple of :class:`ParticleSet`.
    angle : float, the horizontal direction [rad] (as a drive's), or
    direction : (x, y, z) in the lab frame, or None: the structure's.
    """

    container: Container = param(default_factory=Container, kind="custom")
    particles: tuple = param(kind="custom")
    angle: float | None = param(None, dimension="angle")
    direction: tuple | None = param(None, kind="list")

    def __post_init__(self):
        convert_fields(self, "damper")
        ps = (self.particles,) if isinstance(self.particles, ParticleSet) else tuple(self.particles)
        if not ps or not all(isinstance(p, ParticleSet) for p in ps):
            raise InputError("damper.particles: give one or more ParticleSet entries ([damper.particles] count = 36)")
        object.__setattr__(self, "particles", ps)
        if not isinstance(self.container, Container):
            raise InputError(f"damper.container = {shown(self.container)}; give a Container ([damper.container] keys)")
        if self.angle is not None and self.direction is not None:
            raise InputError("damper: angle and direction are both given; give one")
        if self.angle is not None and not math.isfinite(self.angle):
            raise InputError(f"damper.angle = {shown(self.angle)}; must be a finite angle")
        if self.direction is not None:
            v = np.asarray(self.direction, dtype=float)
            if v.shape != (3,) or not np.all(np.isfinite(v)) or not np.linalg.norm(v) > 0:
                raise InputError(f"damper.direction = {shown(self.direction)}; give three finite numbers, not all 0 (lab "
                                 "frame: y up)")
            object.__setattr__(self, "direction", tuple(float(x) for x in v / np.linalg.norm(v)))

    @property
    def bed_mass(self) -> float:
        """Its spheres' mass [kg]."""
        return sum(p.count * p.mass for p in self.particles)

    @property
    def n_particles(self) -> int:
        return sum(p.count for p in self.particles)


@dataclass(frozen=True, kw_only=True)
class Case:
    """One simulated case: what is simulated (particles, container, drive, contact laws), how
    (numerics), what is recorded, how it starts, and for how long (``cycles`` of the drive)."""

    particles: tuple = param(kind="custom", section="particles")
    container: Container = param(default_factory=Container, kind="custom", section="container")
    drive: DriveBase = param(
        default_factory=lambda: HarmonicDrive(stroke=0.012), kind="custom", section="drive")
    contact: ContactModel = param(default_factory=ContactModel, kind="custom", section="contact")
    numerics: Numerics = param(default_factory=Numerics, kind="custom", section="numerics")
    recording: Recording = param(default_factory=Recording, kind="custom", section="recording")
    initial: InitialState = param(default_factory=InitialState, kind="custom", section="initial")
    # the [run] section of a config file
    cycles: float = param(20, kind="number", paper="20", section="run")
    drop_cycles: int = param(2, paper="2", section="run")
    gravity: float = param(9.81, dimension="acceleration", section="run")
    #: the damper's own drive beside a structure (a ``[drive]`` in a file whose ``[structure]`` is
    #: the case's drive): how the damper alone is driven on its test rig, for what characterises the
    #: damper (a sweep, the fields made of it; :attr:`on_rig`). None: ``drive`` is the only drive
    rig: DriveBase | None = param(None, kind="custom", section="drive")
    #: several dampers on the structure (``[[damper]]`` tables), each its own container, filling and
    #: direction, in the order of the structure's damper points; empty: the case's own container and
    #: particles at every damper point of the structure (``damper_dof = [2, 1]``: the same damper at each)
    dampers: tuple = param((), kind="custom", section="damper")

    def __post_init__(self):
        convert_fields(self, "run")
        ps = self.particles
        if isinstance(ps, ParticleSet):
            ps = (ps,)
        ps = tuple(ps)
        if not ps or not all(isinstance(p, ParticleSet) for p in ps):
            raise InputError("case.particles: give one or more ParticleSet entries")
        object.__setattr__(self, "particles", ps)
        if not (self.cycles > 0 and math.isfinite(self.cycles)):
            raise InputError(f"run.cycles = {shown(self.cycles)}; must be > 0 (paper: 20)")
        if not (isinstance(self.drop_cycles, int) and 0 <= self.drop_cycles):
            raise InputError(f"run.drop_cycles = {shown(self.drop_cycles)}; must be a whole number >= 0 (paper: 2)")
        if self.drive.periodic and self.drop_cycles >= self.cycles:
            raise InputError(f"run.cycles = {shown(self.cycles)} leaves nothing after dropping {self.drop_cycles:g} cycles "
                             "(run.drop_cycles); "
                             "run more cycles or drop fewer")
        if self.rig is not None and (self.rig.coupled or not self.drive.coupled):
            raise InputError("case.rig: the damper's rig drive stands beside a structure only (a [drive] with a "
                             "[structure]); a case with a prescribed [drive] has no second drive")
        ds = tuple(self.dampers)
        object.__setattr__(self, "dampers", ds)
        if ds:
            if not all(isinstance(d, Damper) for d in ds):
                raise InputError("case.dampers: give Damper entries ([[damper]] tables)")
            if not self.drive.coupled:
                raise InputError("[[damper]] tables put dampers on a structure; this case has no [structure] (its "
                                 "drive moves one container): remove [[damper]] or give a [structure]")
            if self.drive.damper_count not in (1, len(ds)):
                raise InputError(f"[[damper]]: {len(ds)} tables, but the structure has {self.drive.damper_count} "
                                 "damper points (damper_dof / damper_nodes); give a table for each, or let each "
                                 "table name its own (dof = ..., node = ...)")
        if not (0 <= self.gravity <= MAX_GRAVITY):
            raise InputError(f"run.gravity = {shown(self.gravity)} m/s^2; must be in [0, {MAX_GRAVITY:g}] m/s^2: 0 for "
                             f"no gravity, 9.81 on Earth; above {MAX_GRAVITY:g} (ten g) no damper is tested and the "
                             "contacts would need a far shorter time step (a number without a unit is m/s^2)")

    def __repr__(self) -> str:
        """One line: what is simulated, how long (``dataclasses.asdict`` gives every field)."""
        parts = ", ".join(f"{p.count} x r = {p.radius * 1e3:g} mm {p.material.name}" for p in self.particles)
        return (f"Case({parts} in a {self.container.describe()}, {self.drive.describe()}, "
                f"mu = {self.contact.friction:g}, {self.numerics.integrator}, {self.cycles:g} cycles, "
                f"seed {self.initial.seed})")

    @property
    def n_particles(self) -> int:
        """Total number of spheres."""
        return sum(p.count for p in self.particles)

    @property
    def bed_mass(self) -> float:
        """m_bed [kg]: mass of all spheres."""
        return sum(p.count * p.mass for p in self.particles)

    @property
    def duration(self) -> float:
        """Driven time [s] (after settling)."""
        return self.drive.duration(self.cycles)

    @property
    def on_rig(self) -> "Case":
        """The damper alone on its rig: this case with ``drive`` = ``rig`` (itself when it has no
        rig). A sweep runs this case: it characterises the damper (eta*, its fields), which a
        prescribed motion does and a structure does not."""
        if self.rig is None:
            return self
        return dataclasses.replace(self, drive=self.rig, rig=None)

    @property
    def running_drive(self):
        """The drive as a run moves it: with the empty container's mass (``container.mass``) on it
        (:meth:`~pdamper.excitation.DriveBase.carrying`: a structure carries it at the damper, each
        damper's at its point; a prescribed motion is the drive itself)."""
        if self.damper_count == 1:
            return self.drive.carrying(self.container.mass)
        masses = [0.0] * self.drive.damper_count
        for k, d in enumerate(self.damper_beds()):
            masses[self.damper_point(k)] += d.container.mass
        return self.drive.carrying(masses if len(masses) > 1 else masses[0])

    @property
    def damper_count(self) -> int:
        """The dampers of the case: its ``[[damper]]`` tables, or one at each of the structure's damper
        points (one for a prescribed drive)."""
        return len(self.dampers) or self.drive.damper_count

    def damper_point(self, k: int) -> int:
        """The structure's damper point (a row of its ``damper_shapes()``) damper ``k`` sits at."""
        return k if self.drive.damper_count > 1 else 0

    def damper_beds(self) -> tuple:
        """Each damper's :class:`Damper` (container, particles, direction): its ``[[damper]]`` table,
        or the case's own container and particles."""
        if self.dampers:
            return self.dampers
        return tuple(Damper(container=self.container, particles=self.particles) for _ in range(self.damper_count))

    @property
    def in_loop(self) -> bool:
        """Whether the case runs in the coupling loop (:mod:`pdamper.cosim`): several dampers, or a
        structure another code advances; else the compiled tight coupling of one bed."""
        return bool(self.drive.coupled and (self.damper_count > 1 or self.drive.cosimulated))


def read_tilt(value, section: str = "container") -> tuple:
    """The container's tilt as a config gives it: three angles about x, y, z, or one angle for all
    three (each a number in rad, a text with a unit or a pint quantity)."""
    if isinstance(value, (list, tuple)):
        if len(value) != 3:
            raise InputError(f"[{section}] tilt = {shown(value)}: give three angles about x, y, z, "
                             "e.g. ['0.1deg', '0.1deg', '0.1deg'] (or one angle for all three)")
        return read_list(list(value), f"[{section}] tilt", "angle")
    if is_quantity(value) and getattr(value, "ndim", 0) > 0:
        return read_tilt(list(value), section)
    a = read_quantity(value, f"[{section}] tilt", "angle")
    return (a, a, a)


def read_baffles(value, section: str = "container") -> tuple:
    """``[container] baffles`` as a config gives them: a list of tables (position, thickness,
    gap_below, gap_above, material), or :class:`~pdamper.geometry.Baffle` objects as they are."""
    if isinstance(value, tuple) and all(isinstance(b, Baffle) for b in value):
        return value
    if not isinstance(value, (list, tuple)) or not all(isinstance(b, (dict, Baffle)) for b in value):
        raise InputError(f"[{section}] baffles = {shown(value)}: give a list of tables, e.g. "
                         "baffles = [{position = '-20mm'}, {position = '20mm', gap_below = '12mm'}]")
    out = []
    for k, b in enumerate(value, 1):
        if isinstance(b, Baffle):
            out.append(b)
            continue
        out.append(read_with_material(b, f"{section}.baffles #{k}", Baffle, required="position",
                                      hint=": give the x of the plate, e.g. position = '20mm'"))
    return tuple(out)


def read_with_material(t: dict, label: str, cls, *, required: str, hint: str):
    """A ``cls`` from the config table ``t`` (``[label]`` in messages): its keys checked, the
    ``required`` one present (else ``[label] <required> is missing<hint>``), its fields read by
    their specs and its ``material`` by :func:`~pdamper.materials.read_material`."""
    check_keys(t, label, config_keys(cls))
    if required not in t:
        raise InputError(f"[{label}] {required} is missing{hint}")
    kw = read_fields(t, label, cls)
    if "material" in t:
        kw["material"] = read_material(t["material"], label)
    return cls(**kw)


def read_wall_materials(value, section: str = "container") -> dict:
    """``[container] wall_materials`` as a config gives them: a table of wall name = material (a
    library name or an inline table)."""
    if not isinstance(value, dict):
        raise InputError(f"[{section}] wall_materials = {shown(value)}: give a table of wall = material, e.g. "
                         "wall_materials = {x_min = 'silicone', x_max = 'silicone'}")
    return {str(w): read_material(m, f"{section}.wall_materials.{w}") for w, m in value.items()}


def with_stroke(case: Case, stroke) -> Case:
    """Deprecated: ``pdamper.schema.replace(case, {"drive.stroke": stroke})``."""
    warnings.warn('with_stroke is deprecated; use pdamper.schema.replace(case, {"drive.stroke": stroke})',
                  DeprecationWarning, stacklevel=2)
    if not case.drive.sweepable:
        raise InputError(f"a stroke can only be set on a drive swept by its stroke, a harmonic drive; this one is "
                         f"{case.drive.describe()}")
    return replace(case, {"drive.stroke": stroke})
