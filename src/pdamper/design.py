"""Design assistant: the filling that puts a given operating stroke at the damper's optimum.

The paper's result -- the optimal stroke depends on the filling only, ``X_opt = 0.4075 h``
(eq. 17) with the clearance ``h = L (1 - N_p/N_p,max)`` (eq. 6) -- turned round: for a
structure vibrating with stroke X at frequency f, the clearance ``h = X / 0.4075`` gives
``N_p = N_p,max (1 - h/L)``. A whole number of spheres is needed; pdamper takes the
**smallest N_p whose X_opt does not exceed X** (round the exact filling up). That is also the
filling with the largest η* of the paper's laws at X: one sphere fewer puts X below its
X_opt, in the scattered state (η* = X/h < 0.41), while N_p keeps X at or just above X_opt on
the rolling law (η* close to 20/(7π) ≈ 0.91). Close above X_opt the rolling orbit is marginal
in a real bed (docs/motion.md): a warning says so when X < 1.03 X_opt.

Pure theory (:mod:`pdamper.theory`) and the floor packing of :mod:`pdamper.geometry`; the
CLI's ``pdamper design --verify`` adds a short DEM sweep.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from . import theory as th
from .errors import InputError
from .geometry.cuboid import Cuboid
from .geometry.cylinder import Cylinder
from .theory.bounds import TILT_MARGIN  # the margin `pdamper theory` uses
from .units import quantities

__all__ = ["Design", "design_filling", "TILT_MARGIN", "MIN_ROWS", "MARGINAL"]

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

    def to_dict(self) -> dict:
        return asdict(self)

    def describe_container(self) -> str:
        """The container as the design sizes it (its floor; the height is not the design's)."""
        mm = lambda x: f"{1e3 * x:.4g} mm"  # noqa: E731
        if self.shape == "cuboid":
            return f"cuboid {mm(self.length_m)} x {mm(self.width_m)}"
        return f"cylinder R = {mm(self.length_m / 2)} (L = 2R)"

    def container_geometry(self):
        """The container shape of this design (default height)."""
        if self.shape == "cuboid":
            return Cuboid(length=self.length_m, width=self.width_m)
        return Cylinder(radius=self.length_m / 2)


@quantities(frequency="frequency", stroke="length", sphere_radius="length", length="length", width="length",
            container_radius="length", tilt="angle", density="density", gravity="acceleration")
def design_filling(*, frequency: float, stroke: float, sphere_radius: float, shape: str = "cuboid",
                   length: float | None = None, width: float | None = None,
                   container_radius: float | None = None, max_particles: int | None = None,
                   tilt: float | None = None, density: float = 7900.0, gravity: float = th.GRAVITY) -> Design:
    """The filling N_p that puts ``stroke`` [m] at (just above) X_opt, and its expected η*.

    Parameters: ``frequency`` [Hz]; ``stroke`` X [m]; ``sphere_radius`` r [m]; ``shape``
    "cuboid" (``length`` along the drive and ``width`` [m]) or "cylinder" (``container_radius``
    [m], L = 2R); ``max_particles`` overrides the floor count; ``tilt`` α [rad]; sphere
    ``density`` [kg/m^3]; ``gravity`` [m/s^2].

    >>> d = design_filling(frequency=2.0, stroke=0.01223, sphere_radius=0.005, length=0.12, width=0.0404)
    >>> d.particles, d.max_particles, round(d.eta_star, 3)
    (36, 48, 0.909)
    """
    from .theory._common import positive

    f = positive("frequency", frequency, "Hz", "2")
    x = positive("stroke", stroke, "m", "0.01 (10 mm)")
    r = positive("radius", sphere_radius, "m", "0.005 (5 mm), the sphere radius")
    rho = positive("density", density, "kg/m^3", "7900 (steel)")
    if shape == "cuboid":
        if container_radius is not None:
            raise InputError("--container-radius applies to the cylinder only; the cuboid takes --length and --width")
        if length is None or width is None:
            raise InputError("the cuboid needs --length (inner length along the drive, e.g. 120mm) and --width "
                             "(e.g. 40.4mm)")
        geo = Cuboid(length=positive("length", length, "m", "0.12 (120 mm)"),
                     width=positive("width", width, "m", "0.0404 (40.4 mm)"))
        per_row = int(math.floor(geo.width / (2 * r) + 1e-9))
    elif shape == "cylinder":
        if length is not None or width is not None:
            raise InputError("the cylinder takes --container-radius (inner radius R, e.g. 39mm), not --length/--width")
        if container_radius is None:
            raise InputError("the cylinder needs --container-radius (inner radius R, e.g. 39mm); L = 2R")
        geo = Cylinder(radius=positive("container_radius", container_radius, "m", "0.039 (39 mm)"))
        per_row = None
    else:
        raise InputError(f"shape = {shape!r} is unknown; use one of {', '.join(th.SHAPES)}")
    big_l = geo.drive_length
    for name, span in (("length" if shape == "cuboid" else "container_radius (2R)", big_l),
                       ("width", getattr(geo, "width", big_l))):
        if 2 * r > span:
            raise InputError(f"radius = {r * 1e3:g} mm is not allowed: a sphere ({2 * r * 1e3:g} mm across) does not "
                             f"fit the {name} of {span * 1e3:g} mm; use smaller spheres or a larger container")
    n_max = max_particles if max_particles is not None else geo.clearance_capacity(r)
    if isinstance(n_max, bool) or not isinstance(n_max, int) or n_max < 2:
        raise InputError(f"max_particles = {n_max!r} is not allowed: it must be a whole number >= 2 of spheres "
                         "covering the floor in one layer")
    if per_row is None:
        per_row = max(1, round(n_max / max(1, math.floor(big_l / (2 * r) + 1e-9))))
    warnings = []
    h_wanted = x / th.X_OPT_OVER_H
    exact = n_max * (1.0 - h_wanted / big_l)
    n = math.ceil(exact - 1e-6)
    if n < 1:
        n = 1
        warnings.append(f"the stroke {x * 1e3:.4g} mm is too large for this container: even one sphere has "
                        f"X_opt = {th.optimal_stroke(th.clearance(big_l, 1, n_max)) * 1e3:.4g} mm; a container at "
                        f"least {h_wanted * 1e3:.4g} mm long along the drive (plus the bed) is needed")
    if n >= n_max:
        n = n_max - 1
        warnings.append(f"the stroke {x * 1e3:.4g} mm is too small for this container: {n} of {n_max} spheres "
                        f"leave X_opt = {th.optimal_stroke(th.clearance(big_l, n, n_max)) * 1e3:.4g} mm; use a "
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
    return Design(shape=shape, length_m=big_l, width_m=getattr(geo, "width", None), sphere_radius_m=r,
                  density_kg_m3=rho, frequency_hz=f, stroke_m=x, tilt_rad=tilt, particles=n, max_particles=n_max,
                  exact_particles=exact, rows=rows, clearance_m=h, x_opt_m=x_opt, stroke_over_x_opt=x / x_opt,
                  regime=regime, eta_star=eta, energy_per_cycle_J=energy, bed_mass_kg=m_bed, sphere_mass_kg=m_sphere,
                  velocity_amplitude_m_s=v, acceleration_amplitude_m_s2=acc, max_stroke_no_liftoff_m=x_lift,
                  warnings=warnings)
