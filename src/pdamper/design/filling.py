"""The filling: the N_p that puts a given operating stroke at the damper's optimum, and the margin.

The paper's result -- the optimal stroke depends on the filling only, ``X_opt = 0.4075 h``
(eq. 17) with the clearance ``h = L (1 - N_p/N_p,max)`` (eq. 6) -- turned round: for a
structure vibrating with stroke X at frequency f, the clearance ``h = X / 0.4075`` gives
``N_p = N_p,max (1 - h/L)``. A whole number of spheres is needed; pdamper takes the
**smallest N_p whose X_opt does not exceed X** (round the exact filling up). That is also the
filling with the largest η* of the paper's laws at X: one sphere fewer puts X below its
X_opt, in the scattered state (η* = X/h < 0.41), while N_p keeps X at or just above X_opt on
the rolling law (η* close to 20/(7π) ≈ 0.91). Close above X_opt the rolling orbit is marginal
in a real bed (docs/motion.md): a warning says so when X < 1.03 X_opt.

The margin (:data:`MARGIN_TABLE`, :func:`auto_margin`): how far above X_opt a design for a
structure keeps its operating stroke, by the bed's filling fraction.

Pure theory (:mod:`pdamper.theory`) and the floor packing of :mod:`pdamper.geometry`; the DEM
check of a filling is :func:`pdamper.design.verify.verify_filling`.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from .. import theory as th
from ..errors import InputError, shown
from ..geometry import shape_from_keys
from ..theory.bounds import TILT_MARGIN  # the margin `pdamper theory` uses
from ..units import quantities
from .names import name

__all__ = ["Design", "design_filling", "check_fits", "most_spheres", "size_name", "MIN_ROWS", "MARGINAL", "TILT_MARGIN",
           "MARGIN_TABLE", "MARGIN_MEASURED", "auto_margin", "margin_note"]

#: Fewer rows of spheres along the drive than this: the bed is a thin slab, little mass per wall.
MIN_ROWS = 3
#: X below this factor times X_opt: the collect-and-collide orbit is marginal (docs/motion.md).
MARGINAL = 1.03


@dataclass(frozen=True, kw_only=True)
class Design:
    """A recommended filling and what the paper's laws expect of it (SI units).

    ``particles`` of ``max_particles``; ``exact_particles`` the unrounded eq. (6) inverse;
    ``rows`` of spheres along the drive; ``eta_star`` and ``energy_per_cycle_J`` at the given
    stroke (eqs. 8/14, 4, 5); ``warnings`` in words.
    """

    shape: str
    length_m: float
    width_m: float | None
    sphere_radius_m: float
    density_kg_m3: float
    frequency_hz: float
    stroke_m: float
    tilt_rad: float | None
    particles: int
    max_particles: int
    exact_particles: float
    rows: int
    clearance_m: float
    x_opt_m: float
    stroke_over_x_opt: float
    regime: str
    eta_star: float
    energy_per_cycle_J: float
    bed_mass_kg: float
    sphere_mass_kg: float
    velocity_amplitude_m_s: float
    acceleration_amplitude_m_s2: float
    max_stroke_no_liftoff_m: float
    warnings: list = field(default_factory=list)
    #: the container (a shape of :mod:`pdamper.geometry`); ``shape``, ``length_m`` (its L along the
    #: drive) and ``width_m`` (its inner width across the drive) are its numbers
    geometry: object = field(default=None, compare=False, repr=False)

    def to_dict(self) -> dict:
        """Every field but the container object (its numbers are ``shape``, ``length_m``, ``width_m``)."""
        out = asdict(self)
        out.pop("geometry")
        return out

    def describe_container(self) -> str:
        """The container as the design sizes it (the shape's own words)."""
        return self.geometry.describe()

    def container_geometry(self):
        """The container shape of this design."""
        return self.geometry


#: The parameters of :func:`design_filling` that set a [container] key (another key: ``sizes``).
_SIZE_PARAMETERS = {"length": "length", "width": "width", "radius": "container_radius"}


def size_name(key: str) -> str:
    """How the design names the [container] key ``key`` (:func:`~pdamper.design.names.name` of the
    parameter that sets it: ``radius`` is ``container_radius``; a key without a parameter of its
    own is ``sizes.KEY``)."""
    return name(_SIZE_PARAMETERS.get(key, f"sizes.{key}"))


@quantities(frequency="frequency", stroke="length", sphere_radius="length", length="length", width="length",
            container_radius="length", tilt="angle", density="density", gravity="acceleration")
def design_filling(*, frequency: float, stroke: float, sphere_radius: float, shape: str = "cuboid",
                   length: float | None = None, width: float | None = None,
                   container_radius: float | None = None, max_particles: int | None = None,
                   tilt: float | None = None, density: float = 7900.0, gravity: float = th.GRAVITY,
                   container=None, sizes: dict | None = None, particles: int | None = None) -> Design:
    """The filling N_p that puts ``stroke`` [m] at (just above) X_opt, and its expected η*.

    Parameters: ``frequency`` [Hz]; ``stroke`` X [m]; ``sphere_radius`` r [m]; the container:
    ``container`` (a shape of :mod:`pdamper.geometry`), or a registered ``shape`` with its sizes
    as [container] keys (``length``, ``width`` [m] of the cuboid; ``container_radius`` [m], the
    cylinder's ``radius``; any other shape's keys in ``sizes``), its L along the drive from the
    shape (:attr:`~pdamper.geometry.ShapeBase.drive_length`: the cuboid's length, the
    cylinder's 2R); ``max_particles`` overrides the floor count; ``tilt`` α [rad]; sphere
    ``density`` [kg/m^3]; ``gravity`` [m/s^2]; ``particles``: evaluate this filling instead of
    choosing one (its warnings are its own: the design for a structure chooses N_p itself).

    >>> d = design_filling(frequency=2.0, stroke=0.01223, sphere_radius=0.005, length=0.12, width=0.0404)
    >>> d.particles, d.max_particles, round(d.eta_star, 3)
    (36, 48, 0.909)
    """
    from ..theory._common import positive

    f = positive("frequency", frequency, "Hz", "2")
    x = positive("stroke", stroke, "m", "0.01 (10 mm)")
    r = positive("radius", sphere_radius, "m", "0.005 (5 mm), the sphere radius")
    rho = positive("density", density, "kg/m^3", "7900 (steel)")
    geo = container if container is not None else _container(shape, length=length, width=width,
                                                              container_radius=container_radius, sizes=sizes)
    big_l = geo.drive_length
    check_fits(geo, r)
    n_max = max_particles if max_particles is not None else geo.clearance_capacity(r)
    if isinstance(n_max, bool) or not isinstance(n_max, int) or n_max < 2:
        raise InputError(f"max_particles = {shown(n_max)} is not allowed: it must be a whole number >= 2 of spheres "
                         "covering the floor in one layer")
    per_row = max(1, geo.row_capacity(r))
    warnings = []
    h_wanted = x / th.X_OPT_OVER_H
    exact = n_max * (1.0 - h_wanted / big_l)
    n = math.ceil(exact - 1e-6) if particles is None else particles
    if particles is not None and not (isinstance(particles, int) and 1 <= particles < n_max):
        raise InputError(f"particles = {shown(particles)}: give a filling from 1 to {n_max - 1} (N_p,max = {n_max})")
    if n < 1:
        n = 1
        warnings.append(f"the stroke {x * 1e3:.4g} mm is too large for this container: even one sphere has "
                        f"X_opt = {th.optimal_stroke(th.clearance(big_l, 1, n_max)) * 1e3:.4g} mm; a container at "
                        f"least {h_wanted * 1e3:.4g} mm long along the drive (plus the bed) is needed")
    top = most_spheres(geo, r, n_max)
    if particles is not None and particles > top:
        raise InputError(f"particles = {shown(particles)}: only {top} spheres fit on the floor in one layer (the initial "
                         f"packing of a run); give a filling from 1 to {top}")
    if n > top:
        n = top
        warnings.append(f"the stroke {x * 1e3:.4g} mm is too small for this container: {n} of {n_max} spheres "
                        + ("(the most that fit on its floor in one layer) " if top < n_max - 1 else "")
                        + f"leave X_opt = {th.optimal_stroke(th.clearance(big_l, n, n_max)) * 1e3:.4g} mm; use a "
                        "shorter container or smaller spheres")
    h = th.clearance(big_l, n, n_max)
    x_opt = th.optimal_stroke(h)
    eta = float(th.eta_theory(x, h))
    regime = "rolling collect-and-collide" if x >= x_opt else "scattered"
    m_sphere = rho * 4.0 / 3.0 * math.pi * r**3
    m_bed = n * m_sphere
    v = th.velocity_amplitude(x, f)
    acc = th.acceleration_amplitude(x, f)
    energy = math.pi * m_bed * v**2 * eta  # eqs. (4), (5): E~ = 2 pi eta* (1/2 m V^2)
    x_lift = th.max_stroke_no_liftoff(f, gravity=gravity)
    rows = math.ceil(n / per_row)
    if acc >= gravity:
        warnings.append(f"lift-off: A = X Omega^2 = {acc:.3g} m/s^2 >= g = {gravity:.3g} m/s^2 (the largest stroke "
                        f"without lift-off at {f:g} Hz is {x_lift * 1e3:.3g} mm); the bed leaves the floor and the "
                        "paper's laws do not hold")
    if tilt is not None and tilt > 0:
        a_min = th.min_acceleration_tilt(tilt, gravity=gravity)
        if acc * math.cos(tilt) <= gravity * math.sin(tilt):
            warnings.append(f"tilt: A cos a = {acc * math.cos(tilt):.3g} m/s^2 does not exceed g sin a = "
                            f"{gravity * math.sin(tilt):.3g} m/s^2 at a = {math.degrees(tilt):.3g} deg: the bed stays "
                            "at the low wall (paper Sect. 6.2); level the container")
        elif acc < TILT_MARGIN * a_min:
            warnings.append(f"tilt-sensitive: A = {acc:.3g} m/s^2 is only {acc / a_min:.2g} times g tan a = "
                            f"{a_min:.3g} m/s^2 at a = {math.degrees(tilt):.3g} deg (want >= {TILT_MARGIN:g}); expect "
                            "a lower eta* peak at a larger stroke (paper Sect. 6.2)")
    if rows < MIN_ROWS:
        warnings.append(f"inefficient: {n} spheres make only {rows} row(s) along the drive (fewer than {MIN_ROWS}); "
                        "a thin bed carries little mass per impact; a longer container or smaller spheres help")
    if x_opt <= x < MARGINAL * x_opt:
        warnings.append(f"marginal: X = {x * 1e3:.4g} mm is only {100 * (x / x_opt - 1):.2g} % above X_opt = "
                        f"{x_opt * 1e3:.4g} mm; a real bed may fall out of collect-and-collide there (docs/motion.md)"
                        + (f"; {n + 1} spheres give X_opt = {th.optimal_stroke(th.clearance(big_l, n + 1, n_max)) * 1e3:.4g} mm"
                           if n + 1 < n_max else ""))
    return Design(shape=geo.shape, length_m=big_l, width_m=geo.length_along((0.0, 0.0, 1.0)), sphere_radius_m=r,
                  density_kg_m3=rho, frequency_hz=f, stroke_m=x, tilt_rad=tilt, particles=n, max_particles=n_max,
                  exact_particles=exact, rows=rows, clearance_m=h, x_opt_m=x_opt, stroke_over_x_opt=x / x_opt,
                  regime=regime, eta_star=eta, energy_per_cycle_J=energy, bed_mass_kg=m_bed, sphere_mass_kg=m_sphere,
                  velocity_amplitude_m_s=v, acceleration_amplitude_m_s2=acc, max_stroke_no_liftoff_m=x_lift,
                  warnings=warnings, geometry=geo)


def most_spheres(geo, radius: float, n_max: int) -> int:
    """The largest filling a design offers in the container shape ``geo`` for spheres of ``radius``
    [m]: below the clearance law's N_p,max (``n_max``; N_p,max itself has no clearance) and no more
    than a run places on its floor in one layer (:func:`pdamper.initial.floor_capacity`, the one rule
    of what fits)."""
    from ..initial import floor_capacity
    from ..params import Container

    return min(n_max - 1, floor_capacity(Container(geometry=geo), radius))


def _container(shape: str, *, length=None, width=None, container_radius=None, sizes=None):
    """The registered ``shape`` from the design's sizes (:func:`pdamper.geometry.shape_from_keys`)."""
    keys = {"length": length, "width": width, "radius": container_radius, **(sizes or {})}
    for key, value in keys.items():
        if value is not None and not isinstance(value, str) and not (value > 0 and math.isfinite(value)):
            raise InputError(f"{size_name(key)} = {shown(value)} m is not allowed: it must be > 0, a length such as "
                             "0.12 (120 mm)")
    return shape_from_keys(shape, keys, option=size_name)


def check_fits(geo, radius: float) -> None:
    """An InputError when a sphere of ``radius`` [m] does not fit the container ``geo`` along the
    drive or across it (its inner lengths through the floor's centre)."""
    for name, span in (("length along the drive", geo.drive_length),
                       ("width across the drive", geo.length_along((0.0, 0.0, 1.0)))):
        if 2 * radius > span:
            raise InputError(f"radius = {radius * 1e3:g} mm is not allowed: a sphere ({2 * radius * 1e3:g} mm across) "
                             f"does not fit the {name} of {span * 1e3:g} mm ({geo.describe()}); use smaller spheres "
                             "or a larger container")



# --------------------------------------------------------------------------- the margin

#: The design keeps the operating stroke at least a margin above X_opt. The laws' eta* is largest
#: at X_opt, but below some stroke above it a real bed sways in step with the container (eta*
#: 0.05-0.5) instead of rolling collect-and-collide, and how far above X_opt depends on the bed:
#: the denser the filling, the further. By default (``margin=None``) the margin is this table's,
#: by the filling fraction phi = N_p / N_p,max: (phi, margin) nodes, linear between, the end
#: values held; above every stroke at which a measured bed of about that filling swayed (DEM
#: checks of 4-wide beds of 5 mm steel spheres at 3 Hz, docs/structure.md, "The margin"). A
#: constant 1.2, the value of one early try on a 9-row bed, failed the DEM check of a 15-row
#: design (87 % filled).
MARGIN_TABLE = ((0.75, 1.2), (0.82, 1.3), (0.875, 1.45), (0.91, 1.75))


def auto_margin(filling_fraction: float) -> float:
    """The default margin (over X_opt) of a bed filling ``filling_fraction`` = N_p / N_p,max of
    its floor: :data:`MARGIN_TABLE` interpolated, its end values held.

    >>> auto_margin(0.75), auto_margin(0.5), auto_margin(1.0)
    (1.2, 1.2, 1.75)
    """
    import numpy as np

    phi, m = zip(*MARGIN_TABLE)
    return round(float(np.interp(filling_fraction, phi, m)), 6)


def margin_note(margin: float, given: bool = False, fraction: float | None = None) -> str:
    """One line on the margin the design kept (``given``: by the ``margin`` parameter, else the default for the
    bed's filling ``fraction``), in the margin's own numbers."""
    rule = ("it rises with the filling fraction N_p/N_p,max from 1.2 up to 75 % to 1.75 at 91 %, above the strokes "
            "at which the DEM checks saw such beds sway; docs/structure.md, \"The margin\"")
    if not given:
        return (f"margin: the filling keeps X >= {margin:.3g} X_opt (the default for a bed {100 * fraction:.3g} % "
                f"filled; {rule})")
    return (f"margin: the filling keeps X >= {margin:g} X_opt ({name('margin')} {margin:g}"
            + (f"; the default for this bed, {100 * fraction:.3g} % filled, is {auto_margin(fraction):.3g}: {rule}"
               if fraction is not None else "") + ")")


#: What the default margin was measured on (docs/structure.md, "The margin"): beds this many
#: spheres wide, spheres of this radius [m] and density [kg/m^3], drive frequencies in this band [Hz].
MARGIN_MEASURED = {"row": 4, "radius": 0.005, "density": 7900.0, "frequency": (2.0, 3.0)}


def _margin_warnings(geo, radius: float, density: float, frequency: float) -> list:
    """A warning when the default margin is applied outside what it was measured on."""
    m = MARGIN_MEASURED
    off = []
    per_row = geo.row_capacity(radius)
    if per_row != m["row"]:
        off.append(f"this bed is {per_row} spheres wide, not {m['row']} (a 6-wide bed swayed up to 1.41 X_opt at "
                   "86 % filled, where the default is 1.41)")
    if abs(radius - m["radius"]) > 1e-9 or abs(density - m["density"]) > 1.0:
        off.append(f"its spheres are r = {radius * 1e3:.3g} mm, {density:.4g} kg/m^3, not 5 mm steel")
    lo, hi = m["frequency"]
    if not lo * 0.98 <= frequency <= hi * 1.02:
        off.append(f"it works at {frequency:.3g} Hz, outside {lo:g}-{hi:g} Hz")
    if not off:
        return []
    return ["default margin outside what it was measured on: " + "; ".join(off) + f"; check the design with "
            f"{name('verify')} (or give {name('margin')})"]


def _margin_words(margin) -> str:
    """The margin in words: ``1.4 X_opt``, or the default's rule."""
    return f"{margin:g} X_opt" if margin is not None else "its margin (by the filling fraction, 1.2-1.75) X_opt"

