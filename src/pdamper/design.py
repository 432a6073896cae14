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
from .geometry import Cuboid, shape_from_keys
from .theory.bounds import TILT_MARGIN  # the margin `pdamper theory` uses
from .units import quantities

__all__ = ["Design", "design_filling", "design_container", "check_fits", "size_option", "margin_note",
           "TILT_MARGIN", "MIN_ROWS", "MARGINAL", "OPERATING_MARGIN", "Mode",
           "structure_mode", "rolling_mass_ratio", "closed_form_fields", "required_force", "OperatingPoint",
           "operating_points", "StructureDesign", "design_for_structure", "load_structure", "verify_factors",
           "judge_verification", "ROLLING_MODE", "VERIFY_REACH"]

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


#: The command-line options of ``pdamper design`` that set a [container] key.
_SIZE_OPTIONS = {"length": "--length", "width": "--width", "radius": "--container-radius"}


def size_option(key: str, named: dict = _SIZE_OPTIONS) -> str:
    """The option that sets the [container] key ``key`` (``radius``: ``--container-radius``; a key
    without an option of its own: ``--size key=VALUE``)."""
    return named.get(key, f"--size {key}=VALUE")


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
    from .theory._common import positive

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
        raise InputError(f"max_particles = {n_max!r} is not allowed: it must be a whole number >= 2 of spheres "
                         "covering the floor in one layer")
    per_row = max(1, geo.row_capacity(r))
    warnings = []
    h_wanted = x / th.X_OPT_OVER_H
    exact = n_max * (1.0 - h_wanted / big_l)
    n = math.ceil(exact - 1e-6) if particles is None else particles
    if particles is not None and not (isinstance(particles, int) and 1 <= particles < n_max):
        raise InputError(f"particles = {particles!r}: give a filling from 1 to {n_max - 1} (N_p,max = {n_max})")
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
    return Design(shape=geo.shape, length_m=big_l, width_m=geo.length_along((0.0, 0.0, 1.0)), sphere_radius_m=r,
                  density_kg_m3=rho, frequency_hz=f, stroke_m=x, tilt_rad=tilt, particles=n, max_particles=n_max,
                  exact_particles=exact, rows=rows, clearance_m=h, x_opt_m=x_opt, stroke_over_x_opt=x / x_opt,
                  regime=regime, eta_star=eta, energy_per_cycle_J=energy, bed_mass_kg=m_bed, sphere_mass_kg=m_sphere,
                  velocity_amplitude_m_s=v, acceleration_amplitude_m_s2=acc, max_stroke_no_liftoff_m=x_lift,
                  warnings=warnings, geometry=geo)


def _container(shape: str, *, length=None, width=None, container_radius=None, sizes=None):
    """The registered ``shape`` from the design's sizes (:func:`pdamper.geometry.shape_from_keys`)."""
    keys = {"length": length, "width": width, "radius": container_radius, **(sizes or {})}
    for key, value in keys.items():
        if value is not None and not isinstance(value, str) and not (value > 0 and math.isfinite(value)):
            raise InputError(f"{size_option(key)} = {value!r} m is not allowed: it must be > 0, a length such as "
                             "0.12 (120 mm)")
    return shape_from_keys(shape, keys, option=size_option)


def check_fits(geo, radius: float) -> None:
    """An InputError when a sphere of ``radius`` [m] does not fit the container ``geo`` along the
    drive or across it (its inner lengths through the floor's centre)."""
    for name, span in (("length along the drive", geo.drive_length),
                       ("width across the drive", geo.length_along((0.0, 0.0, 1.0)))):
        if 2 * radius > span:
            raise InputError(f"radius = {radius * 1e3:g} mm is not allowed: a sphere ({2 * radius * 1e3:g} mm across) "
                             f"does not fit the {name} of {span * 1e3:g} mm ({geo.describe()}); use smaller spheres "
                             "or a larger container")


# =========================================================================== design for a structure
#
# The designer's question: a structure's mode, a harmonic force at its resonance; which filling
# (and container length, within bounds) makes the resonant amplitude smallest? The damper is
# described by fields built from the paper's closed forms (eta* of eqs. 8/14, the energy per cycle
# E(X) = pi eta*(X) m_bed (X Omega)^2 of eqs. 4/5, and the effective mass of the rolling bed from
# the kinematics of eqs. 10-12); the mode's amplitude follows from the energy balance at phase
# resonance (docs/structure.md, "Design for a structure").

#: The design keeps the operating stroke at least this factor above X_opt: in a DEM try of the
#: design question (a frame at 3 Hz) the efficient rolling collect-and-collide set in only above ~1.1-1.2 X_opt (the bed
#: sways below it, with a lower eta*), so the law's jump at X_opt is not a point to aim at.
OPERATING_MARGIN = 1.2


def margin_note(margin: float) -> str:
    """One line on the margin the design kept, in the margin's own numbers."""
    seen = (f"in a DEM try (a frame at 3 Hz) the rolling collect-and-collide set in only above ~1.1-"
            f"{OPERATING_MARGIN:g} X_opt, the bed swaying below it with less eta*")
    if margin == OPERATING_MARGIN:
        return f"margin: the filling keeps X >= {margin:g} X_opt (--margin, the default: {seen})"
    return (f"margin: the filling keeps X >= {margin:g} X_opt (--margin {margin:g}; the default {OPERATING_MARGIN:g} "
            f"is where {seen[3:]})")


#: Effective mass over bed mass assumed in the scattered state (the scattered law, eq. 8, gives
#: none): the rolling law's value at X_opt, 2/7, so the mass is continuous across the jump.
SCATTERED_MASS_RATIO = 2.0 / 7.0
#: The rolling-law tables: s = X / X_opt from 1 to this (eta* ~ s^(-4/3) far above).
_S_TOP = 1.0e3


@dataclass(frozen=True, kw_only=True)
class Mode:
    """One mode of a structure as the design sees it (SI): modal ``mass`` m, ``stiffness`` k,
    ``damping`` c, ``frequency`` f [Hz], ``damping_ratio`` zeta and the mode shape's values at the
    damper, the force and the response point (``phi_damper``, ``phi_force``, ``phi_response``)."""

    number: int
    mass: float
    stiffness: float
    damping: float
    frequency: float
    damping_ratio: float
    phi_damper: float
    phi_force: float
    phi_response: float
    modes: int = 1


def structure_mode(structure, number: int = 1) -> Mode:
    """Mode ``number`` (1-based) of a structure of the config reader: a
    :class:`~pdamper.structure.CoupledStructure` (one mode, shape 1 everywhere) or a
    :class:`~pdamper.structure.ModalStructure` (modes given or from matrices).

    >>> from pdamper.structure import CoupledStructure
    >>> m = structure_mode(CoupledStructure(mass=25.0, stiffness=25.0 * (6 * math.pi) ** 2,
    ...                                     damping_ratio=0.003, displacement=0.001))
    >>> round(m.frequency, 6), m.phi_damper
    (3.0, 1.0)
    """
    if isinstance(number, bool) or not isinstance(number, int):
        raise InputError(f"--mode {number!r}: give the mode's number, 1 for the lowest")
    if not getattr(structure, "coupled", False):
        raise InputError("the structure must be a [structure] section (mass with stiffness or natural_frequency, "
                         "or modes = [...], or matrices = ...)")
    mass, k, c, pd, pf, pr = structure.modal_arrays()
    n = int(mass.size)
    j = number - 1
    if not 0 <= j < n:
        raise InputError(f"--mode {number}: the structure has {n} mode{'s' if n > 1 else ''} (give "
                         + (f"1 to {n}, 1 the lowest)" if n > 1 else "--mode 1)"))
    if pd[j] == 0.0:
        raise InputError(f"--mode {number}: the mode shape is zero at the damper (damper = 0); the damper cannot "
                         "act on this mode")
    return Mode(number=number, mass=float(mass[j]), stiffness=float(k[j]), damping=float(c[j]),
                frequency=math.sqrt(k[j] / mass[j]) / (2 * math.pi),
                damping_ratio=float(c[j] / (2 * math.sqrt(k[j] * mass[j]))), phi_damper=float(pd[j]),
                phi_force=float(pf[j]), phi_response=float(pr[j]), modes=n)


_TABLES: dict = {}


def _rolling_tables():
    """(log s, eta*(s), m_eff/m_bed (s)) of the rolling law on s = X/X_opt in [1, _S_TOP] (cached)."""
    if "rolling" not in _TABLES:
        import numpy as np

        s = np.geomspace(1.0, _S_TOP, 800)
        h = 1.0
        x = s * th.X_OPT_OVER_H * h
        eta = np.asarray(th.eta_rolling(x, h), dtype=float)
        eta[0] = th.ETA_MAX
        _TABLES["rolling"] = (np.log(s), eta, rolling_mass_ratio(s))
    return _TABLES["rolling"]


def rolling_mass_ratio(stroke_over_x_opt):
    """Effective mass over bed mass, m_eff / m_bed [-], of the paper's rolling bed (eqs. 10-12).

    The bed's centre moves with the container while a wall pushes it and with eq. (10) while it
    rolls (from theta = 0 to the impact phase theta_i of eq. 12; the other half cycle mirrored).
    The container's force on the bed is m_bed x_p''; its first harmonic in phase with the
    container's acceleration is m_eff = m_bed (1/pi) int u(theta) cos(theta) dtheta / V over a
    cycle, u the bed's velocity (item 1's definition of the effective mass). It is 2/7 at X_opt
    (the bed rolls the whole half cycle: a rolling sphere follows 2/7 of the floor's
    acceleration) and tends to 1 far above (the bed rides with the walls).

    >>> round(float(rolling_mass_ratio(1.0)), 4), round(float(rolling_mass_ratio(1000.0)), 2)
    (0.2857, 1.0)
    """
    import numpy as np

    s = np.atleast_1d(np.asarray(stroke_over_x_opt, dtype=float))
    if np.any(~(s >= 1.0)):
        raise InputError("rolling_mass_ratio: the rolling law holds for X >= X_opt (stroke_over_x_opt >= 1)")
    ti = np.asarray(th.impact_phase_rolling(s * th.X_OPT_OVER_H, 1.0), dtype=float).reshape(s.shape)
    theta = ti[:, None] * np.linspace(0.0, 1.0, 2001)[None, :]  # the rolling phase, 0 .. theta_i
    rolling = (2.0 * np.cos(theta) + np.sqrt(25.0 + 10.0 * np.sin(theta) ** 2)) / 7.0
    pushed = (math.pi - ti) / 2.0 - np.sin(2.0 * ti) / 4.0  # int cos^2 from theta_i to pi: the bed on the wall
    out = 2.0 / math.pi * (np.trapezoid(rolling * np.cos(theta), theta, axis=1) + pushed)
    return out if np.ndim(stroke_over_x_opt) else out[0]


def closed_form_fields(stroke_over_x_opt, kappa: float = 1.0):
    """The damper's fields from the paper's laws as functions of s = X / X_opt: (eta*, m_eff/m_bed).

    eta* = kappa 0.4075 s (scattered, eq. 8) below X_opt, the rolling law (eq. 14) from X_opt
    on (its tables, interpolated in log s); m_eff/m_bed from :func:`rolling_mass_ratio` above
    X_opt and :data:`SCATTERED_MASS_RATIO` (assumed) below. Beyond s = 1000 eta* falls as s^(-4/3).

    >>> e, m = closed_form_fields([0.5, 1.0, 1.2])
    >>> [round(float(v), 3) for v in e], [round(float(v), 3) for v in m]
    ([0.204, 0.909, 0.887], [0.286, 0.286, 0.543])
    """
    import numpy as np

    s = np.asarray(stroke_over_x_opt, dtype=float)
    ls, eta_r, mu_r = _rolling_tables()
    lg = np.log(np.maximum(s, 1e-300))
    eta_roll = np.interp(lg, ls, eta_r) * np.where(s > _S_TOP, (np.maximum(s, 1.0) / _S_TOP) ** (-4.0 / 3.0), 1.0)
    eta = np.where(s < 1.0, kappa * th.X_OPT_OVER_H * s, eta_roll)
    mu = np.where(s < 1.0, SCATTERED_MASS_RATIO, np.interp(lg, ls, mu_r))
    return eta, mu


def required_force(mode: Mode, stroke, *, x_opt: float, bed_mass: float, kappa: float = 1.0):
    """The force amplitude [N] that holds the damper at ``stroke`` X [m] at phase resonance, and
    that resonance's angular frequency Omega [rad/s]: the energy balance per cycle

        pi |phi_f| F Q = pi c Omega Q^2 + pi eta*(X) m_bed (X Omega)^2,   X = |phi_d| Q,
        Omega^2 = k / (m + phi_d^2 m_eff(X)),

    solved for F: ``F = Q (c Omega + eta*(X) m_bed phi_d^2 Omega^2) / |phi_f|``.
    """
    import numpy as np

    x = np.asarray(stroke, dtype=float)
    eta, mu = closed_form_fields(x / x_opt, kappa)
    pd2 = mode.phi_damper**2
    omega = np.sqrt(mode.stiffness / (mode.mass + pd2 * mu * bed_mass))
    q = x / abs(mode.phi_damper)
    return q * (mode.damping * omega + eta * bed_mass * pd2 * omega**2) / abs(mode.phi_force), omega


@dataclass(frozen=True, kw_only=True)
class OperatingPoint:
    """One solution of the energy balance: the damper's stroke X [m], s = X/X_opt, the state
    ("rolling" above X_opt, "scattered" below, "held at X_opt" when the force falls in the law's
    jump), whether it is stable (more amplitude, more loss than input), the resonance [Hz]."""

    stroke_m: float
    stroke_over_x_opt: float
    state: str
    stable: bool
    frequency_hz: float
    eta_star: float
    effective_mass_kg: float


def operating_points(mode: Mode, force: float, *, x_opt: float, bed_mass: float, kappa: float = 1.0,
                     refine: bool = True) -> list:
    """Every solution X of the energy balance :func:`required_force` (X) = ``force``, smallest first.

    The scattered branch (X < X_opt) and the rolling branch (X >= X_opt) are searched apart (the
    laws jump at X_opt); where the force lies inside the jump -- too much for the scattered bed at
    X_opt, too little for the rolling one -- the amplitude is held at X_opt (state "held at X_opt",
    the swaying the DEM shows there). Stable: the required force grows with X there.
    """
    import numpy as np
    from scipy.optimize import brentq

    # the bare structure's amplitude at the damper bounds the damped one (the damper only adds loss)
    x_bare = abs(mode.phi_damper) * abs(mode.phi_force) * force / max(mode.damping * 2 * math.pi * mode.frequency,
                                                                      1e-300)
    top = max(4.0 * x_bare, 2.0 * x_opt)
    out = []

    def point(x, state, stable):
        f_req, om = required_force(mode, x, x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)
        eta, mu = closed_form_fields(x / x_opt, kappa)
        return OperatingPoint(stroke_m=float(x), stroke_over_x_opt=float(x / x_opt), state=state, stable=bool(stable),
                              frequency_hz=float(om) / (2 * math.pi), eta_star=float(eta),
                              effective_mass_kg=float(mu) * bed_mass)

    for state, lo, hi in (("scattered", 1e-4 * x_opt, x_opt * (1 - 1e-12)), ("rolling", x_opt, top)):
        if hi <= lo:
            continue
        xs = np.geomspace(lo, hi, 600)
        g = required_force(mode, xs, x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)[0] - force
        for i in np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) < 0)[0]:
            if refine:
                fun = lambda x: float(required_force(mode, x, x_opt=x_opt, bed_mass=bed_mass,  # noqa: E731
                                                     kappa=kappa)[0]) - force
                x = brentq(fun, xs[i], xs[i + 1], xtol=1e-14, rtol=1e-12)
            else:
                x = xs[i] - g[i] * (xs[i + 1] - xs[i]) / (g[i + 1] - g[i])
            out.append(point(x, state, g[i + 1] > g[i]))
    low = required_force(mode, x_opt * (1 - 1e-9), x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)[0]
    high = required_force(mode, x_opt, x_opt=x_opt, bed_mass=bed_mass, kappa=kappa)[0]
    if low < force < high:
        out.append(point(x_opt, "held at X_opt", True))
    return sorted(out, key=lambda p: p.stroke_m)


@dataclass(frozen=True, kw_only=True)
class StructureDesign:
    """The filling that minimises a structure mode's resonant amplitude, with what the laws expect (SI
    units; masses physical, at the damper, where they are named so). ``amplitude_*``: at the damper
    point and at the response point, with the damper (at the operating point) and without (bare
    resonance F phi_f / (c omega_n)) and with the bed as a solid mass; ``zeta_*``: the modal damping
    ratios (``zeta_bare`` the structure's alone, ``zeta_structure + zeta_damper = zeta_total`` with the
    damper's added mass, at its resonance); ``operating_points``: every solution of the energy balance
    for the chosen filling (the design's is the largest stable one)."""

    mode: int
    modes: int
    modal_mass_kg: float
    #: the mode's mass seen at the damper, m / phi_d^2 [kg] (physical: the mass the damper moves
    #: with; ``modal_mass_kg`` is in the mode's normalisation, 1 kg for mass-normalised FE modes)
    mass_at_damper_kg: float
    #: the empty container's mass [kg], in the mode's mass (it moves with the structure)
    container_mass_kg: float
    natural_frequency_hz: float
    damping_ratio: float
    phi_damper: float
    phi_force: float
    phi_response: float
    force_N: float
    filling: Design
    warnings: list = field(default_factory=list)
    margin: float
    kappa: float
    candidates: int
    frequency_hz: float
    damper_stroke_m: float
    stroke_over_x_opt: float
    eta_star: float
    energy_per_cycle_J: float
    effective_mass_kg: float
    added_modal_mass_kg: float
    equivalent_damping_N_s_per_m: float
    zeta_bare: float
    zeta_structure: float
    zeta_damper: float
    zeta_total: float
    amplitude_damper_m: float
    amplitude_damper_bare_m: float
    amplitude_damper_solid_m: float
    amplitude_response_m: float
    amplitude_response_bare_m: float
    reduction: float
    mass_ratio: float
    operating_points: list

    def to_dict(self) -> dict:
        """Every field, the filling and the operating points as nested dicts (for JSON)."""
        return asdict(self)


def _lengths(length_range, length):
    import numpy as np

    if length_range is not None:
        lo, hi = (float(v) for v in length_range)
        if not 0 < lo <= hi:
            raise InputError(f"--length-range {lo * 1e3:g}mm:{hi * 1e3:g}mm: need 0 < LOW <= HIGH, e.g. 80mm:200mm")
        if length is not None:
            raise InputError("give either --length (one container length) or --length-range LOW:HIGH, not both")
        n = max(2, min(121, int(round((hi - lo) / 0.001)) + 1))
        return np.linspace(lo, hi, n) if hi > lo else np.array([lo])
    return np.array([length])


@quantities(force="force", sphere_radius="length", length="length", width="length", density="density",
            max_bed_mass="mass", gravity="acceleration", container_mass="mass")
def design_for_structure(structure, *, force: float, mode: int = 1, sphere_radius: float = 0.005,
                         length: float | None = None, width: float | None = None, length_range=None,
                         max_bed_mass: float | None = None, max_mass_ratio: float | None = None,
                         density: float = 7900.0, margin: float = OPERATING_MARGIN, kappa: float = 1.0,
                         gravity: float = th.GRAVITY, container=None, container_mass: float = 0.0) -> StructureDesign:
    """The filling (N_p of N_p,max, and the container's length along the drive within
    ``length_range``) that minimises the resonant amplitude of ``mode`` of ``structure`` under
    ``force`` [N] at its resonance, from the closed-form fields (:func:`closed_form_fields`) and
    the energy balance (:func:`required_force`), with the operating stroke at least ``margin``
    X_opt.

    The container: ``container`` (any shape of :mod:`pdamper.geometry`, its length along the drive
    set per candidate by :meth:`~pdamper.geometry.ShapeBase.with_drive_length`), else the paper's
    cuboid of ``width`` [m] (default 40.4 mm). Its empty mass ``container_mass`` [kg] moves with
    the structure: it is put at the damper (:meth:`~pdamper.excitation.DriveBase.carrying`) before
    the mode is taken, so the mode's mass and frequency include it.

    Candidates: every length of the range (1 mm steps, at most 121), every filling 1 .. N_p,max - 1
    whose bed mass is within ``max_bed_mass`` [kg] and ``max_mass_ratio`` (of the mode's mass at the
    damper, m / phi_d^2). A candidate is admissible when every stable solution of its balance is on
    the rolling branch at X >= margin X_opt (none scattered, none held at X_opt); the design is
    the admissible one with the smallest amplitude (the largest stable solution, if several) whose
    acceleration X Omega^2 stays below ``gravity`` (no lift-off: the laws assume the bed on the floor).

    >>> from pdamper.structure import CoupledStructure
    >>> s = CoupledStructure(mass=25.0, stiffness=25.0 * (6 * math.pi) ** 2, damping_ratio=0.003,
    ...                      displacement=0.001)
    >>> d = design_for_structure(s, force=1.5)
    >>> d.stroke_over_x_opt >= 1.2, d.amplitude_damper_m < d.amplitude_damper_bare_m
    (True, True)
    """
    import numpy as np

    from .theory._common import positive

    if not (isinstance(container_mass, (int, float)) and container_mass >= 0 and math.isfinite(container_mass)):
        raise InputError(f"container mass = {container_mass!r} kg is not allowed: give the empty container's mass, "
                         ">= 0 ([container] mass, e.g. '80g')")
    if getattr(structure, "coupled", False):
        structure = structure.carrying(container_mass)
    md = structure_mode(structure, mode)
    f0 = force
    if isinstance(f0, bool) or not isinstance(f0, (int, float)) or not (f0 > 0 and math.isfinite(f0)):
        raise InputError(f"--force = {force!r} N is not allowed: give the force amplitude on the structure, > 0, "
                         "e.g. --force 1.5N")
    r = positive("sphere_radius", sphere_radius, "m", "0.005 (5 mm)")
    rho = positive("density", density, "kg/m^3", "7900 (steel)")
    if container is None:
        container = Cuboid(width=positive("width", width if width is not None else 0.0404, "m", "0.0404 (40.4 mm)"))
    elif width is not None:
        raise InputError("give the container's width in the container itself (--width sets the cuboid's), not both")
    if not (isinstance(margin, (int, float)) and margin >= 1.0):
        raise InputError(f"--margin = {margin!r}: the operating stroke over X_opt must be >= 1 (default "
                         f"{OPERATING_MARGIN:g})")
    if length_range is None:
        length = container.drive_length if length is None else positive("length", length, "m", "0.12 (120 mm)")
    m_sphere = rho * 4.0 / 3.0 * math.pi * r**3
    m_at_damper = md.mass / md.phi_damper**2
    cap = math.inf
    for name, bound in (("--max-bed-mass", max_bed_mass), ("--max-mass-ratio", max_mass_ratio)):
        if bound is not None and not (bound > 0 and math.isfinite(bound)):
            raise InputError(f"{name} = {bound!r}: must be > 0 (a mass ratio of 0.01 is 1 % of the mode's mass)")
    if max_bed_mass is not None:
        cap = min(cap, max_bed_mass)
    if max_mass_ratio is not None:
        cap = min(cap, max_mass_ratio * m_at_damper)
    if cap < m_sphere:
        raise InputError(f"the bed-mass bound {cap * 1e3:.4g} g is below one sphere's mass ({m_sphere * 1e3:.4g} g); "
                         "raise --max-bed-mass / --max-mass-ratio or use smaller spheres (--sphere-radius)")
    across = container.length_along((0.0, 0.0, 1.0))
    if 2 * r > across:
        raise InputError(f"--sphere-radius = {r * 1e3:g} mm: a sphere does not fit the width across the drive of "
                         f"{across * 1e3:g} mm ({container.describe()})")
    best, count = None, 0
    for big_l in _lengths(length_range, length):
        if 2 * r > big_l:
            continue
        geo = container.with_drive_length(float(big_l))
        if 2 * r > geo.length_along((0.0, 0.0, 1.0)):
            continue
        n_max = geo.clearance_capacity(r)
        for n in range(1, n_max):
            m_bed = n * m_sphere
            if m_bed > cap * (1 + 1e-12):
                break
            count += 1
            x_opt = th.X_OPT_OVER_H * big_l * (1.0 - n / n_max)
            pts = [p for p in operating_points(md, f0, x_opt=x_opt, bed_mass=m_bed, kappa=kappa, refine=False)
                   if p.stable]
            if not pts or any(p.state != "rolling" or p.stroke_over_x_opt < margin for p in pts):
                continue
            x = max(p.stroke_m for p in pts)
            if x * (2 * math.pi * max(p.frequency_hz for p in pts)) ** 2 >= gravity:
                continue  # lift-off: the bed leaves the floor, the laws do not hold
            if best is None or x < best[0] * (1 - 1e-9):
                best = (x, geo, n, n_max, m_bed, x_opt)
    if best is None:
        raise InputError(
            f"no filling within the bounds keeps the operating stroke at or above {margin:g} X_opt on the rolling "
            f"branch without lift-off (A = X Omega^2 < g; {count} fillings tried): the force {f0:g} N puts the damper "
            "below the margin for the clearances of these containers (a shorter container or more spheres lower X_opt; "
            "a larger --max-bed-mass allows more spheres) or, with a large force, lifts the bed off (a longer "
            "container); see docs/structure.md, \"Design for a structure\"")
    _, geo, n, n_max, m_bed, x_opt = best
    pts = operating_points(md, f0, x_opt=x_opt, bed_mass=m_bed, kappa=kappa, refine=True)
    op = max((p for p in pts if p.stable), key=lambda p: p.stroke_m)
    x = op.stroke_m
    om = 2 * math.pi * op.frequency_hz
    fill = design_filling(frequency=op.frequency_hz, stroke=x, sphere_radius=r, container=geo, max_particles=n_max,
                          density=rho, gravity=gravity, particles=n)  # its warnings for the design's n, X
    warnings = list(fill.warnings)
    pd, pf, pr = abs(md.phi_damper), abs(md.phi_force), abs(md.phi_response)
    q = x / pd
    c_d = op.eta_star * m_bed * om
    m_add = pd**2 * op.effective_mass_kg
    zeta_b = md.damping_ratio
    zeta_s = md.damping / (2 * (md.mass + m_add) * om)
    zeta_d = pd**2 * c_d / (2 * (md.mass + m_add) * om)
    zeta_t = (md.damping + pd**2 * c_d) / (2 * (md.mass + m_add) * om)
    q_bare = pf * f0 / (md.damping * 2 * math.pi * md.frequency)
    om_s = math.sqrt(md.stiffness / (md.mass + pd**2 * m_bed))
    q_solid = pf * f0 / (md.damping * om_s)
    others = [p for p in pts if p is not op]
    if any(p.stable for p in others):
        warnings.append("several stable amplitudes: " + ", ".join(f"{p.stroke_m * 1e3:.3g} mm ({p.state})"
                                                                  for p in others if p.stable)
                        + "; the design's is the largest")
    if md.modes > 1:
        warnings.append(f"mode {md.number} of {md.modes}: the other modes are left out of the balance (their "
                        "response at this frequency is off resonance)")
    return StructureDesign(
        mode=md.number, modes=md.modes, modal_mass_kg=md.mass, mass_at_damper_kg=m_at_damper,
        container_mass_kg=float(container_mass), natural_frequency_hz=md.frequency,
        damping_ratio=md.damping_ratio, phi_damper=md.phi_damper, phi_force=md.phi_force,
        phi_response=md.phi_response, force_N=f0, filling=fill, margin=margin, kappa=kappa, candidates=count,
        frequency_hz=op.frequency_hz, damper_stroke_m=x, stroke_over_x_opt=op.stroke_over_x_opt,
        eta_star=op.eta_star, energy_per_cycle_J=math.pi * op.eta_star * m_bed * (x * om) ** 2,
        effective_mass_kg=op.effective_mass_kg, added_modal_mass_kg=m_add, equivalent_damping_N_s_per_m=c_d,
        zeta_bare=zeta_b, zeta_structure=zeta_s, zeta_damper=zeta_d, zeta_total=zeta_t, amplitude_damper_m=x,
        amplitude_damper_bare_m=pd * q_bare, amplitude_damper_solid_m=pd * q_solid, amplitude_response_m=pr * q,
        amplitude_response_bare_m=pr * q_bare, reduction=x / (pd * q_bare), mass_ratio=m_bed / m_at_damper,
        operating_points=[asdict(p) for p in pts], warnings=warnings)


def load_structure(path, overrides: dict | None = None):
    """The :class:`~pdamper.params.Case` of a structure file for the design: a config with a
    ``[structure]`` section (one mode: mass with stiffness or natural_frequency; or ``modes =
    [...]``; or ``matrices = ...``), read by :func:`pdamper.config.case_from_dict`. A file with
    only ``[structure]`` is enough: ``[particles]`` defaults to the paper's 5 mm steel spheres
    (their count is the design's), ``[container]`` to the paper's cuboid, and a structure given
    without motion (no displacement, velocity or force) gets a nominal 1 mm start (the design
    does not use it)."""
    import tomllib
    from pathlib import Path

    from .config import case_from_dict

    p = Path(path)
    if not p.is_file():
        raise InputError(f"--structure {path}: file not found (give a TOML file with a [structure] section)")
    try:
        data = tomllib.loads(p.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise InputError(f"--structure {path}: cannot read it as TOML: {exc}") from None
    t = data.get("structure")
    if not isinstance(t, dict):
        raise InputError(f"--structure {path}: no [structure] section; give the structure's mode, e.g. [structure] "
                         "mass = '25kg', natural_frequency = '3Hz', damping_ratio = 0.003 (or modes = [...], or "
                         "matrices = 'frame.npz'; docs/structure.md)")
    data.setdefault("particles", {"count": 1})
    if not any(k in t for k in ("displacement", "velocity", "force_amplitude")):
        t["displacement"] = "1mm"
    return case_from_dict(data, overrides, source=str(path), base_dir=p.parent)


def verify_factors(n: int):
    """Strokes of the DEM check as factors of the operating stroke: 1 alone, 0.85 and 1 for two,
    else ``n`` from 0.85 to 1.15 (the operating stroke among them for odd ``n``).

    >>> verify_factors(2), verify_factors(3)
    ([0.85, 1.0], [0.85, 1.0, 1.15])
    """
    import numpy as np

    if n < 1:
        raise InputError(f"--verify-strokes = {n}: give at least 1 (e.g. 3)")
    if n == 1:
        return [1.0]
    if n == 2:
        return [0.85, 1.0]
    return [round(float(v), 6) for v in np.linspace(0.85, 1.15, n)]


ROLLING_MODE = "rolling-collect-and-collide"
#: How far beyond the checked strokes the DEM's operating stroke may be extrapolated for a pass.
VERIFY_REACH = 1.1


def judge_verification(sd: StructureDesign, strokes, eta_star, modes) -> dict:
    """The verdict of a DEM check of design ``sd``: ``eta_star`` (mean over seeds) and ``modes``
    (the majority motion mode) measured at the damper ``strokes`` [m] at the design's frequency.

    The DEM's eta* replaces the law's in the energy balance (:func:`required_force` with the DEM
    value): the force each stroke needs; where it crosses the design's force (linear between the
    strokes) is the DEM's operating stroke. Verdict ``"pass"`` when that stroke lies within the
    checked strokes (or within :data:`VERIFY_REACH` beyond them, extrapolated with the end stroke's
    eta* held: the force needed then grows as X) and the bed rolls (collect-and-collide) at the
    checked strokes on both sides of it (at the end stroke, extrapolated); otherwise ``"move the
    filling"`` with the reason and the next filling (or margin) to try; ``"no verdict"`` when no
    stroke gave an eta* (every case failed). The effective mass (so the frequency) stays the laws'.
    """
    import numpy as np

    md = Mode(number=sd.mode, mass=sd.modal_mass_kg, stiffness=sd.modal_mass_kg * (2 * math.pi *
              sd.natural_frequency_hz) ** 2, damping=2 * sd.damping_ratio * sd.modal_mass_kg * 2 * math.pi *
              sd.natural_frequency_hz, frequency=sd.natural_frequency_hz, damping_ratio=sd.damping_ratio,
              phi_damper=sd.phi_damper, phi_force=sd.phi_force, phi_response=sd.phi_response, modes=sd.modes)
    fill = sd.filling
    xs = np.asarray(strokes, dtype=float)
    order = np.argsort(xs)
    xs, eta = xs[order], np.asarray(eta_star, dtype=float)[order]
    modes = [str(modes[i]) for i in order]
    om = 2 * math.pi * sd.frequency_hz
    pd2 = sd.phi_damper**2
    need = xs / abs(sd.phi_damper) * (md.damping * om + eta * fill.bed_mass_kg * pd2 * om**2) / abs(sd.phi_force)
    ok = np.isfinite(need)
    x_dem, where, inside = None, "no DEM value", False
    if ok.any():
        xv, nv = xs[ok], need[ok]
        g = nv - sd.force_N
        cross = np.nonzero(np.sign(g[:-1]) * np.sign(g[1:]) <= 0)[0]
        if cross.size:
            i = int(cross[0])
            x_dem = float(xv[i] - g[i] * (xv[i + 1] - xv[i]) / (g[i + 1] - g[i])) if g[i + 1] != g[i] else float(xv[i])
            where, inside = "within the checked strokes", True
        else:
            i = 0 if g[0] > 0 else -1  # at a fixed eta* the force needed grows as X: extrapolate so
            x_dem = float(xv[i] * sd.force_N / nv[i])
            where = f"{'below' if i == 0 else 'above'} the checked strokes (extrapolated with eta* held)"
            inside = xs[0] / VERIFY_REACH <= x_dem <= xs[-1] * VERIFY_REACH
    # the checked strokes around the DEM's operating stroke (both sides of it, or the end one)
    around = ([i, i + 1] if where.startswith("within") else [0 if where.startswith("below") else len(xs) - 1]
              ) if x_dem is not None else [0]
    off = [j for j in around if modes[j] != ROLLING_MODE]
    nearest = off[0] if off else around[0]
    mode_there = modes[nearest]
    n, n_max = fill.particles, fill.max_particles

    def other(k):
        if not 1 <= k < n_max:
            return ""
        x_opt = th.optimal_stroke(th.clearance(fill.length_m, k, n_max))
        return f"{k} spheres (X_opt = {x_opt * 1e3:.4g} mm, X/X_opt = {sd.damper_stroke_m / x_opt:.3g})"

    if x_dem is not None and inside and mode_there == ROLLING_MODE:
        verdict, reason, move = "pass", (f"the DEM's eta* puts the damper at {x_dem * 1e3:.4g} mm (the laws: "
                                         f"{sd.damper_stroke_m * 1e3:.4g} mm, X/X_opt = "
                                         f"{x_dem / fill.x_opt_m:.3g}), where the bed rolls"), ""
    elif x_dem is None:
        verdict, reason, move = ("no verdict", "no stroke of the DEM check gave an eta* (every case failed)",
                                 "run the check with more --verify-cycles")
    elif mode_there != ROLLING_MODE:
        verdict = "move the filling"
        reason = (f"the bed is {mode_there or 'not classified'} at {xs[nearest] * 1e3:.4g} mm, not rolling "
                  "collect-and-collide")
        move = "add spheres (a smaller clearance puts the stroke further above X_opt): try " + (other(n + 1) or
                                                                                            "a shorter container")
    elif x_dem < xs[0]:
        verdict = "move the filling"
        reason = (f"the DEM bed dissipates more than the laws: the damper settles at about {x_dem * 1e3:.4g} mm "
                  f"({x_dem / fill.x_opt_m:.3g} X_opt), {where}")
        move = "add spheres to keep the margin: try " + (other(n + 1) or "a shorter container")
    else:
        verdict = "move the filling"
        reason = (f"the DEM bed dissipates less than the laws: the damper settles at about {x_dem * 1e3:.4g} mm "
                  f"({x_dem / fill.x_opt_m:.3g} X_opt), {where}")
        move = "take spheres out (X_opt closer to the stroke, more eta*): try " + (other(n - 1) or
                                                                                 "a longer container")
    rolls_from = next((j for j in range(len(xs)) if all(m == ROLLING_MODE for m in modes[j:])), None)
    if verdict != "pass" and mode_there != ROLLING_MODE and rolls_from is not None and rolls_from > 0:
        need_margin = math.ceil(10 * xs[rolls_from] / fill.x_opt_m - 1e-9) / 10
        move += (f"; or design again with --margin {need_margin:g} (the bed rolled from "
                 f"{xs[rolls_from] / fill.x_opt_m:.3g} X_opt on in this check)")
    return {"strokes_m": xs.tolist(), "eta_star_dem": eta.tolist(),
            "eta_star_law": [float(v) for v in closed_form_fields(xs / fill.x_opt_m, sd.kappa)[0]],
            "stroke_over_x_opt": (xs / fill.x_opt_m).tolist(), "modes": modes, "force_required_N": need.tolist(),
            "amplitude_damper_dem_m": x_dem, "operating_stroke": where, "verdict": verdict, "reason": reason,
            "move": move}


def design_container(case, *, shape: str | None = None, sizes: dict | None = None):
    """The container a design for a structure starts from: the case's (``[container]`` of the
    structure file) with the given [container] ``sizes`` over it (None: not given), or, for another
    registered ``shape``, that shape with the sizes given. Its length along the drive is the
    design's to choose (``--length``, ``--length-range``)."""
    from .schema import config_keys

    geo = case.container.geometry
    if shape is None or shape == geo.shape:
        current = {k: getattr(geo, k) for k in config_keys(type(geo))}
        return shape_from_keys(geo.shape, {**current, **(sizes or {})}, option=size_option)
    return shape_from_keys(shape, sizes or {}, option=size_option, require=False)
