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
           "TILT_MARGIN", "MIN_ROWS", "MARGINAL", "MARGIN_TABLE", "auto_margin", "Mode",
           "structure_mode", "rolling_mass_ratio", "closed_form_fields", "required_force", "OperatingPoint",
           "operating_points", "StructureDesign", "design_for_structure", "load_structure", "verify_factors",
           "judge_verification", "ROLLING_MODE", "VERIFY_REACH", "design_case",
           "design_case_text"]

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
    """One line on the margin the design kept (``given``: by ``--margin``, else the default for the
    bed's filling ``fraction``), in the margin's own numbers."""
    rule = ("it rises with the filling fraction N_p/N_p,max from 1.2 up to 75 % to 1.75 at 91 %, above the strokes "
            "at which the DEM checks saw such beds sway; docs/structure.md, \"The margin\"")
    if not given:
        return (f"margin: the filling keeps X >= {margin:.3g} X_opt (the default for a bed {100 * fraction:.3g} % "
                f"filled; {rule})")
    return (f"margin: the filling keeps X >= {margin:g} X_opt (--margin {margin:g}"
            + (f"; the default for this bed, {100 * fraction:.3g} % filled, is {auto_margin(fraction):.3g}: {rule}"
               if fraction is not None else "") + ")")


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
    """The filling for a structure mode (the one that minimises its resonant amplitude, or the
    lightest that meets a target ratio), with what the laws expect (SI
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
    #: the margin the chosen filling keeps, X >= margin X_opt: ``--margin``, or the default for
    #: its filling fraction (:func:`auto_margin`); ``margin_given``: which
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
    #: the ratio of the resonant amplitudes with and without the damper (at every point of the
    #: mode alike): what ``--target-ratio`` bounds
    reduction: float
    mass_ratio: float
    operating_points: list
    #: the target ratio of a design to a target (None: the design minimised the amplitude)
    target_ratio: float | None = None
    #: with a target: the best ratio of the next lighter filling in the bounds (None: none lighter
    #: keeps the margin), which is why the design is the lightest
    lighter_ratio: float | None = None
    #: what the search covered: ``lengths_m`` [LOW, HIGH] in ``length_steps``, ``particles`` [LOW,
    #: HIGH or None], ``max_bed_mass_kg`` (each bed-mass bound given, in kg), ``margin``
    search: dict = field(default_factory=dict)
    margin_given: bool = False

    def to_dict(self) -> dict:
        """Every field, the filling and the operating points as nested dicts (for JSON)."""
        return asdict(self)


def _lengths(length_range, length):
    import numpy as np

    if length_range is not None:
        lo, hi = (float(v) for v in length_range)
        if not 0 < lo <= hi:
            raise InputError(f"--length {lo * 1e3:g}mm:{hi * 1e3:g}mm: need 0 < LOW <= HIGH, e.g. 80mm:200mm")
        if length is not None:
            raise InputError("give either --length (one container length) or --length LOW:HIGH (a range), not both")
        n = max(2, min(121, int(round((hi - lo) / 0.001)) + 1))
        return np.round(np.linspace(lo, hi, n), 9) if hi > lo else np.array([lo])  # whole nanometres
    return np.array([length])


def _particle_bounds(particles) -> tuple:
    """(LOW, HIGH) of the fillings to try: ``particles`` None (every filling), N or (LOW, HIGH)."""
    if particles is None:
        return 1, math.inf
    lo, hi = particles if isinstance(particles, (tuple, list)) else (particles, particles)
    for v in (lo, hi):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise InputError(f"--particles {particles!r}: give a whole number of spheres >= 1, or LOW:HIGH, e.g. 20:60")
    if lo > hi:
        raise InputError(f"--particles {lo}:{hi}: need LOW <= HIGH, e.g. 20:60")
    return lo, hi


@dataclass(frozen=True, kw_only=True)
class _Candidate:
    """A filling the design may choose: ``particles`` of ``max_particles`` in ``geometry``."""

    geometry: object
    particles: int
    max_particles: int
    bed_mass: float
    x_opt: float


def _margin(margin, c: _Candidate) -> float:
    """The margin candidate ``c`` keeps: ``margin``, or by default (None) :func:`auto_margin` of its filling."""
    return auto_margin(c.particles / c.max_particles) if margin is None else margin


def _candidates(container, lengths, radius: float, m_sphere: float, cap: float, bounds: tuple) -> list:
    """Every filling within the bounds: each length of ``lengths`` (where a sphere fits), each
    filling from ``bounds`` (LOW, HIGH) up to N_p,max - 1 whose bed mass is within ``cap`` [kg];
    the lengths in their order, the fillings of a length from the lightest."""
    out = []
    for big_l in lengths:
        if 2 * radius > big_l:
            continue
        geo = container.with_drive_length(float(big_l))
        if 2 * radius > geo.length_along((0.0, 0.0, 1.0)):
            continue
        n_max = geo.clearance_capacity(radius)
        for n in range(bounds[0], int(min(n_max - 1, bounds[1])) + 1):
            m_bed = n * m_sphere
            if m_bed > cap * (1 + 1e-12):
                break
            out.append(_Candidate(geometry=geo, particles=n, max_particles=n_max, bed_mass=m_bed,
                                  x_opt=th.X_OPT_OVER_H * big_l * (1.0 - n / n_max)))
    return out


#: The screening's slack: a design to a target screens a candidate on the solver's grid
#: (refine=False) with its margin and the lift-off bound loosened by this fraction, then decides it
#: (margin, lift-off, target) on the refined solution.
_SCREEN = 1e-3


def _operating(md: Mode, force: float, c: _Candidate, *, kappa: float, margin, gravity: float,
               refine: bool = True, slack: float = 0.0):
    """The operating point of candidate ``c`` (its largest stable solution of the balance), or
    None when ``c`` is not admissible: a stable solution off the rolling branch or below its
    margin (``margin``, None: :func:`auto_margin`) times X_opt, or lift-off (X Omega^2 >=
    ``gravity``). ``slack``: the bounds loosened by this fraction (a screen on the unrefined grid)."""
    pts = [p for p in operating_points(md, force, x_opt=c.x_opt, bed_mass=c.bed_mass, kappa=kappa, refine=refine)
           if p.stable]
    m = _margin(margin, c)
    if not pts or any(p.state != "rolling" or p.stroke_over_x_opt < m * (1 - slack) for p in pts):
        return None
    op = max(pts, key=lambda p: p.stroke_m)
    if op.stroke_m * (2 * math.pi * op.frequency_hz) ** 2 >= gravity * (1 + slack):
        return None  # lift-off: the bed leaves the floor, the laws do not hold
    return op


def _smallest(md: Mode, force: float, cands: list, *, kappa: float, margin, gravity: float):
    """(X, candidate) of the admissible candidate with the smallest amplitude (on the solver's grid;
    the first of equals), or None."""
    best = None
    for c in cands:
        op = _operating(md, force, c, kappa=kappa, margin=margin, gravity=gravity, refine=False)
        if op is not None and (best is None or op.stroke_m < best[0] * (1 - 1e-9)):
            best = (op.stroke_m, c)
    return best


def _lightest(md: Mode, force: float, cands: list, *, target: float, x_bare: float, kappa: float, margin,
              gravity: float) -> dict:
    """The lightest candidate whose ratio X / X_bare (the damper's resonant amplitude with and
    without the damper) is at most ``target``; among the lightest fillings that meet it, the
    smallest ratio. Returns ``chosen`` ((ratio, candidate, point) or None), ``lighter`` (the best
    ratio of the next lighter filling, None if no lighter one is admissible) and ``tried``
    (candidates evaluated; fillings whose next heavier one cannot meet the target even at the
    law's eta* at the margin are skipped). A candidate is screened on the
    solver's grid with the bounds loosened by :data:`_SCREEN`, and what passes is decided on the
    refined solution."""
    groups: dict[int, list] = {}
    for c in cands:
        groups.setdefault(c.particles, []).append(c)
    # no filling beats its bed dissipating at the law's eta* at the margin at the bare resonance:
    # the ratio is at least c w_n / (c w_n + eta*(margin) m_bed phi_d^2 w_n^2) (added mass lowers Omega)
    eta_top = float(closed_form_fields(margin if margin is not None else MARGIN_TABLE[0][1], kappa)[0])
    w_n = 2 * math.pi * md.frequency

    def floor(m_bed):
        return md.damping * w_n / (md.damping * w_n + eta_top * m_bed * md.phi_damper**2 * w_n**2)

    order = sorted(groups)
    lighter, tried = None, 0
    for i, n in enumerate(order):
        met, seen = [], None
        if i + 1 < len(order) and floor(groups[order[i + 1]][0].bed_mass) > target:
            continue  # neither this filling nor the next heavier one can meet the target
        for c in groups[n]:
            tried += 1
            if _operating(md, force, c, kappa=kappa, margin=margin, gravity=gravity, refine=False,
                          slack=_SCREEN) is None:
                continue
            op = _operating(md, force, c, kappa=kappa, margin=margin, gravity=gravity)
            if op is None:
                continue
            ratio = op.stroke_m / x_bare
            if seen is None or ratio < seen[0]:
                seen = (ratio, c)
            if ratio <= target:
                met.append((ratio, c, op))
        if met:
            return {"chosen": min(met, key=lambda m: m[0]), "lighter": lighter, "tried": tried}
        lighter = seen[0] if seen is not None else None
    return {"chosen": None, "lighter": lighter, "tried": tried}


def _describe(c: _Candidate, ratio: float | None = None) -> str:
    """A candidate in words: spheres, bed mass, container length (and its ratio)."""
    return (f"{c.particles} of {c.max_particles} spheres, {c.bed_mass * 1e3:.4g} g, in "
            f"{c.geometry.drive_length * 1e3:.4g} mm" + (f": ratio {ratio:.3g}" if ratio is not None else ""))


@quantities(force="force", sphere_radius="length", length="length", width="length", density="density",
            max_bed_mass="mass", gravity="acceleration", container_mass="mass")
def design_for_structure(structure, *, force: float, mode: int = 1, sphere_radius: float = 0.005,
                         length: float | None = None, width: float | None = None, length_range=None,
                         particles=None, max_bed_mass: float | None = None, max_mass_ratio: float | None = None,
                         target_ratio: float | None = None, density: float = 7900.0, margin: float | None = None,
                         kappa: float = 1.0, gravity: float = th.GRAVITY, container=None,
                         container_mass: float = 0.0) -> StructureDesign:
    """The filling (N_p of N_p,max, and the container's length along the drive within
    ``length_range``) for ``mode`` of ``structure`` under ``force`` [N] at its resonance, from the
    closed-form fields (:func:`closed_form_fields`) and the energy balance (:func:`required_force`),
    with the operating stroke at least a margin times X_opt (``margin``; by default, None, the
    measured :func:`auto_margin` of each filling's fraction N_p / N_p,max): the one that minimises
    the resonant amplitude, or with ``target_ratio`` the **lightest** one whose ratio (the resonant amplitude
    with the damper over the bare structure's, :attr:`StructureDesign.reduction`) is at most the
    target (among the lightest that do, the smallest ratio).

    The container: ``container`` (any shape of :mod:`pdamper.geometry`, its length along the drive
    set per candidate by :meth:`~pdamper.geometry.ShapeBase.with_drive_length`), else the paper's
    cuboid of ``width`` [m] (default 40.4 mm). Its empty mass ``container_mass`` [kg] moves with
    the structure: it is put at the damper (:meth:`~pdamper.excitation.DriveBase.carrying`) before
    the mode is taken, so the mode's mass and frequency include it.

    Candidates: every length of the range (1 mm steps, at most 121), every filling 1 .. N_p,max - 1
    (``particles``: N or (LOW, HIGH)) whose bed mass is within ``max_bed_mass`` [kg] and
    ``max_mass_ratio`` (of the mode's mass at the damper, m / phi_d^2). A candidate is admissible
    when every stable solution of its balance is on the rolling branch at X >= its margin X_opt (none
    scattered, none held at X_opt) and its acceleration X Omega^2 stays below ``gravity`` (no
    lift-off: the laws assume the bed on the floor); the design's operating point is its largest
    stable solution. A target no admissible candidate meets is an :class:`InputError` naming the
    best ratio found and the bound to widen (tried: longer and shorter containers, no bed-mass bound).

    >>> from pdamper.structure import CoupledStructure
    >>> s = CoupledStructure(mass=25.0, stiffness=25.0 * (6 * math.pi) ** 2, damping_ratio=0.003,
    ...                      displacement=0.001)
    >>> d = design_for_structure(s, force=1.5)
    >>> d.stroke_over_x_opt >= d.margin, d.amplitude_damper_m < d.amplitude_damper_bare_m
    (True, True)
    >>> t = design_for_structure(s, force=1.5, target_ratio=0.6, length_range=(0.08, 0.16))
    >>> t.reduction <= 0.6, t.filling.particles < d.filling.particles
    (True, True)
    """
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
    if target_ratio is not None and not (isinstance(target_ratio, (int, float)) and not isinstance(target_ratio, bool)
                                         and 0 < target_ratio < 1):
        raise InputError(f"--target-ratio = {target_ratio!r}: give the resonant amplitude with the damper over the "
                         "bare structure's, between 0 and 1 (e.g. 0.5: half the bare amplitude)")
    r = positive("sphere_radius", sphere_radius, "m", "0.005 (5 mm)")
    rho = positive("density", density, "kg/m^3", "7900 (steel)")
    if container is None:
        container = Cuboid(width=positive("width", width if width is not None else 0.0404, "m", "0.0404 (40.4 mm)"))
    elif width is not None:
        raise InputError("give the container's width in the container itself (--width sets the cuboid's), not both")
    if margin is not None and not (isinstance(margin, (int, float)) and margin >= 1.0):
        raise InputError(f"--margin = {margin!r}: the operating stroke over X_opt must be >= 1 (default: by the "
                         "filling fraction, 1.2 to 1.75)")
    if length_range is None:
        length = container.drive_length if length is None else positive("length", length, "m", "0.12 (120 mm)")
    bounds = _particle_bounds(particles)
    m_sphere = rho * 4.0 / 3.0 * math.pi * r**3
    m_at_damper = md.mass / md.phi_damper**2
    caps = {}
    for name, bound in (("--max-bed-mass", max_bed_mass), ("--max-mass-ratio", max_mass_ratio)):
        if bound is not None and not (bound > 0 and math.isfinite(bound)):
            raise InputError(f"{name} = {bound!r}: must be > 0 (a mass ratio of 0.01 is 1 % of the mode's mass)")
    if max_bed_mass is not None:
        caps["--max-bed-mass"] = max_bed_mass
    if max_mass_ratio is not None:
        caps["--max-mass-ratio"] = max_mass_ratio * m_at_damper
    cap = min(caps.values(), default=math.inf)
    if cap < m_sphere:
        raise InputError(f"the bed-mass bound {cap * 1e3:.4g} g is below one sphere's mass ({m_sphere * 1e3:.4g} g); "
                         "raise --max-bed-mass / --max-mass-ratio or use smaller spheres (--sphere-radius)")
    across = container.length_along((0.0, 0.0, 1.0))
    if 2 * r > across:
        raise InputError(f"--sphere-radius = {r * 1e3:g} mm: a sphere does not fit the width across the drive of "
                         f"{across * 1e3:g} mm ({container.describe()})")
    lengths = _lengths(length_range, length)
    cands = _candidates(container, lengths, r, m_sphere, cap, bounds)
    pd, pf, pr = abs(md.phi_damper), abs(md.phi_force), abs(md.phi_response)
    q_bare = pf * f0 / (md.damping * 2 * math.pi * md.frequency)
    lighter = None
    if target_ratio is None:
        best = _smallest(md, f0, cands, kappa=kappa, margin=margin, gravity=gravity)
        count = len(cands)
        if best is None:
            raise InputError(
                f"no filling within the bounds keeps the operating stroke at or above {_margin_words(margin)} on the "
                f"rolling branch without lift-off (A = X Omega^2 < g; {count} fillings tried): the force {f0:g} N "
                "puts the damper below the margin for the clearances of these containers (a shorter container or more "
                "spheres lower X_opt; a larger --max-bed-mass allows more spheres) or, with a large force, lifts the "
                "bed off (a longer container); see docs/structure.md, \"Design for a structure\"")
        chosen = best[1]
    else:
        found = _lightest(md, f0, cands, target=target_ratio, x_bare=pd * q_bare, kappa=kappa, margin=margin,
                          gravity=gravity)
        count = found["tried"]
        if found["chosen"] is None:
            raise InputError(_unmet(md, f0, found, container, lengths, r, m_sphere, caps, bounds, target=target_ratio,
                                    x_bare=pd * q_bare, kappa=kappa, margin=margin, gravity=gravity))
        _, chosen, _ = found["chosen"]
        lighter = found["lighter"]
    geo, n, n_max, m_bed, x_opt = chosen.geometry, chosen.particles, chosen.max_particles, chosen.bed_mass, chosen.x_opt
    pts = operating_points(md, f0, x_opt=x_opt, bed_mass=m_bed, kappa=kappa, refine=True)
    op = max((p for p in pts if p.stable), key=lambda p: p.stroke_m)
    x = op.stroke_m
    om = 2 * math.pi * op.frequency_hz
    fill = design_filling(frequency=op.frequency_hz, stroke=x, sphere_radius=r, container=geo, max_particles=n_max,
                          density=rho, gravity=gravity, particles=n)  # its warnings for the design's n, X
    warnings = list(fill.warnings)
    q = x / pd
    c_d = op.eta_star * m_bed * om
    m_add = pd**2 * op.effective_mass_kg
    zeta_b = md.damping_ratio
    zeta_s = md.damping / (2 * (md.mass + m_add) * om)
    zeta_d = pd**2 * c_d / (2 * (md.mass + m_add) * om)
    zeta_t = (md.damping + pd**2 * c_d) / (2 * (md.mass + m_add) * om)
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
    if margin is None:
        warnings += _margin_warnings(geo, r, rho, op.frequency_hz)
    return StructureDesign(
        mode=md.number, modes=md.modes, modal_mass_kg=md.mass, mass_at_damper_kg=m_at_damper,
        container_mass_kg=float(container_mass), natural_frequency_hz=md.frequency,
        damping_ratio=md.damping_ratio, phi_damper=md.phi_damper, phi_force=md.phi_force,
        phi_response=md.phi_response, force_N=f0, filling=fill, margin=_margin(margin, chosen),
        margin_given=margin is not None, kappa=kappa, candidates=count,
        frequency_hz=op.frequency_hz, damper_stroke_m=x, stroke_over_x_opt=op.stroke_over_x_opt,
        eta_star=op.eta_star, energy_per_cycle_J=math.pi * op.eta_star * m_bed * (x * om) ** 2,
        effective_mass_kg=op.effective_mass_kg, added_modal_mass_kg=m_add, equivalent_damping_N_s_per_m=c_d,
        zeta_bare=zeta_b, zeta_structure=zeta_s, zeta_damper=zeta_d, zeta_total=zeta_t, amplitude_damper_m=x,
        amplitude_damper_bare_m=pd * q_bare, amplitude_damper_solid_m=pd * q_solid, amplitude_response_m=pr * q,
        amplitude_response_bare_m=pr * q_bare, reduction=x / (pd * q_bare), mass_ratio=m_bed / m_at_damper,
        operating_points=[asdict(p) for p in pts], warnings=warnings, target_ratio=target_ratio,
        lighter_ratio=lighter, search=_search_bounds(lengths, bounds, caps, margin))


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
    return ["default margin outside what it was measured on: " + "; ".join(off) + "; check the design with --verify "
            "(or give --margin)"]


def _margin_words(margin) -> str:
    """The margin in words: ``1.4 X_opt``, or the default's rule."""
    return f"{margin:g} X_opt" if margin is not None else "its margin (by the filling fraction, 1.2-1.75) X_opt"


def _search_bounds(lengths, bounds: tuple, caps: dict, margin) -> dict:
    """What the design searched: the container lengths [m], the fillings, the bed-mass bounds [kg], the
    margin (``"auto"``: by the filling fraction)."""
    return {"lengths_m": [float(lengths[0]), float(lengths[-1])], "length_steps": int(len(lengths)),
            "particles": [int(bounds[0]), None if math.isinf(bounds[1]) else int(bounds[1])],
            "max_bed_mass_kg": {k.lstrip("-"): float(v) for k, v in caps.items()},
            "margin": "auto" if margin is None else margin}


def _unmet(md, f0, found, container, lengths, radius, m_sphere, caps, bounds, *, target, x_bare, kappa, margin,
           gravity) -> str:
    """The one line of a target that no filling within the bounds meets: the best ratio found, and
    which bound to widen (each tried: the container lengths, from half the shortest to twice the
    longest; the bed-mass bounds lifted; both)."""
    cands = _candidates(container, lengths, radius, m_sphere, min(caps.values(), default=math.inf), bounds)
    best = _smallest(md, f0, cands, kappa=kappa, margin=margin, gravity=gravity)
    head = (f"--target-ratio {target:g}: no filling within the bounds meets it with X >= {_margin_words(margin)} on "
            f"the rolling branch without lift-off ({len(cands)} in the bounds; "
            + (f"the best: {_describe(best[1], best[0] / x_bare)})" if best else "none keeps that margin)"))
    lo, hi = float(lengths[0]), float(lengths[-1])
    wide = _lengths((max(4 * radius, 0.5 * lo), 2.0 * hi), None)
    mass_names = [k for k, v in caps.items() if v == min(caps.values())]
    if bounds[1] < math.inf and bounds[1] * m_sphere <= min(caps.values(), default=math.inf):
        mass_names = ["--particles"]
    free = (bounds[0], math.inf)
    tries = [("length", wide, min(caps.values(), default=math.inf), bounds)]
    if mass_names:
        tries += [("mass", lengths, math.inf, free), ("both", wide, math.inf, free)]
    length_words = f"--length {wide[0] * 1e3:.4g}mm:{wide[-1] * 1e3:.4g}mm"
    for what, ls, cap, bnd in tries:
        got = _lightest(md, f0, _candidates(container, ls, radius, m_sphere, cap, bnd), target=target, x_bare=x_bare,
                        kappa=kappa, margin=margin, gravity=gravity)["chosen"]
        if got is None:
            continue
        ratio, c, _ = got
        widen = {"length": f"widen the container's length ({length_words} meets it",
                 "mass": f"raise {' / '.join(mass_names)} (without it the design meets it",
                 "both": f"widen both the container's length ({length_words}) and {' / '.join(mass_names)} "
                         "(together they meet it"}[what]
        return f"{head}; {widen}: {_describe(c, ratio)})"
    return (f"{head}; neither containers of {wide[0] * 1e3:.4g}-{wide[-1] * 1e3:.4g} mm"
            + (f" nor lifting {' / '.join(mass_names)}" if mass_names else "")
            + " meet it: a wider container (more spheres per row) or smaller spheres (--sphere-radius) give more "
            "bed per length; see docs/structure.md, \"Design to a target\"")


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
#: A design that minimises the amplitude passes its DEM check when the DEM's amplitude is at most
#: this factor times the laws' (a design to a target: at most the target).
VERIFY_REACH = 1.1


def judge_verification(sd: StructureDesign, strokes, eta_star, modes) -> dict:
    """The verdict of a DEM check of design ``sd``: ``eta_star`` (mean over seeds) and ``modes``
    (the majority motion mode) measured at the damper ``strokes`` [m] at the design's frequency.

    The DEM's eta* replaces the law's in the energy balance (:func:`required_force` with the DEM
    value): the force each checked stroke needs to be held. From rest the resonant amplitude grows
    while the bed takes less than the force's work and stops at the first stroke where it takes as
    much, so the first checked stroke whose force reaches the design's **bounds** the DEM's
    amplitude from above, and the crossing before it (linear between the strokes; below the
    strokes extrapolated with the first stroke's eta* held) **estimates** it. The amplitude judged
    is the estimate where the bed rolls (collect-and-collide) on both sides of the crossing, else
    the bound (a crossing at the jump between a swaying and a rolling bed may lie anywhere between).

    Verdict ``"pass"`` when the amplitude judged is at most the design's promise: its target ratio
    times the bare amplitude (a design to a target), else :data:`VERIFY_REACH` times the laws'
    amplitude; otherwise ``"fails the target"`` (to a target) or ``"move the filling"``, with the
    reason and what to try; when no checked stroke takes the force, the amplitude grows beyond
    them (estimated with the last stroke's eta* held). ``"no verdict"`` when no stroke gave an eta*
    (every case failed). The effective mass (so the frequency) stays the laws'.
    """
    import numpy as np

    fill = sd.filling
    xs = np.asarray(strokes, dtype=float)
    order = np.argsort(xs)
    xs, eta = xs[order], np.asarray(eta_star, dtype=float)[order]
    modes = [str(modes[i]) for i in order]
    om = 2 * math.pi * sd.frequency_hz
    damping = 2 * sd.damping_ratio * sd.modal_mass_kg * 2 * math.pi * sd.natural_frequency_hz
    need = xs / abs(sd.phi_damper) * (damping * om + eta * fill.bed_mass_kg * sd.phi_damper**2 * om**2) / abs(
        sd.phi_force)
    bare = sd.amplitude_damper_bare_m
    target = sd.target_ratio
    promise = target * bare if target is not None else VERIFY_REACH * sd.amplitude_damper_m
    out = {"strokes_m": xs.tolist(), "eta_star_dem": eta.tolist(),
           "eta_star_law": [float(v) for v in closed_form_fields(xs / fill.x_opt_m, sd.kappa)[0]],
           "stroke_over_x_opt": (xs / fill.x_opt_m).tolist(), "modes": modes, "force_required_N": need.tolist(),
           "target_ratio": target, "promise_m": promise, "amplitude_damper_dem_m": None,
           "amplitude_damper_bound_m": None, "ratio_dem": None, "ratio_bound": None, "operating_stroke": "no DEM value"}
    n, n_max = fill.particles, fill.max_particles

    def other(k):
        if not 1 <= k < n_max:
            return ""
        x_opt = th.optimal_stroke(th.clearance(fill.length_m, k, n_max))
        return f"{k} spheres (X_opt = {x_opt * 1e3:.4g} mm, X/X_opt = {sd.damper_stroke_m / x_opt:.3g})"

    fails = "fails the target" if target is not None else "move the filling"
    ok = np.isfinite(need)
    if not ok.any():
        return {**out, "verdict": "no verdict", "reason": "no stroke of the DEM check gave an eta* (every case failed)",
                "move": "run the check with more --verify-cycles"}
    xv, nv = xs[ok], need[ok]
    mv = [m for m, good in zip(modes, ok) if good]
    more = "add spheres (a smaller clearance puts the stroke further above X_opt, more bed dissipates more): try " + (
        other(n + 1) or "a shorter container")
    rolls_from = next((j for j in range(len(xv)) if all(m == ROLLING_MODE for m in mv[j:])), None)
    if rolls_from is not None and rolls_from > 0:
        margin = math.ceil(10 * xv[rolls_from] / fill.x_opt_m - 1e-9) / 10
        more += (f"; or design again with --margin {margin:g} (the bed rolled from {xv[rolls_from] / fill.x_opt_m:.3g} "
                 "X_opt on in this check)")
    reach = np.nonzero(nv >= sd.force_N)[0]
    if reach.size == 0:  # the amplitude grows beyond the checked strokes
        x_dem = float(xv[-1] * sd.force_N / nv[-1])
        out.update(amplitude_damper_dem_m=x_dem, ratio_dem=x_dem / bare,
                   operating_stroke="above the checked strokes (extrapolated with eta* held)")
        return {**out, "verdict": fails, "move": more,
                "reason": (f"no checked stroke takes the force's work: the DEM bed dissipates less than the laws and "
                           f"the damper swings beyond {xv[-1] * 1e3:.4g} mm, about {x_dem * 1e3:.4g} mm (ratio "
                           f"{x_dem / bare:.3g}; {mv[-1] or 'mode n/a'} at the largest stroke)")}
    k = int(reach[0])
    bound = float(xv[k])
    if k == 0:
        x_dem = float(xv[0] * sd.force_N / nv[0])
        rolls, where = False, "below the checked strokes (extrapolated with eta* held)"
    else:
        g0, g1 = nv[k - 1] - sd.force_N, nv[k] - sd.force_N
        x_dem = float(xv[k - 1] - g0 * (xv[k] - xv[k - 1]) / (g1 - g0))
        rolls, where = mv[k - 1] == ROLLING_MODE and mv[k] == ROLLING_MODE, "within the checked strokes"
    judged = x_dem if rolls else bound
    out.update(amplitude_damper_dem_m=x_dem, amplitude_damper_bound_m=bound, ratio_dem=x_dem / bare,
               ratio_bound=bound / bare, operating_stroke=where)
    words = (f"the DEM's eta* puts the damper at about {x_dem * 1e3:.4g} mm, at most {bound * 1e3:.4g} mm (the first "
             f"checked stroke that takes the force, {bound / fill.x_opt_m:.3g} X_opt, {mv[k] or 'mode n/a'}): ratio "
             f"{x_dem / bare:.3g}, at most {bound / bare:.3g}")
    off = [j for j in ((k - 1, k) if k > 0 else (0,)) if mv[j] != ROLLING_MODE]
    if off:
        words += ("; judged at the bound, as the bed's mode is " + " and ".join(
            f"{mv[j] or 'not classified'} at {xv[j] * 1e3:.4g} mm" for j in off)
                  + (" (a jump between modes: the amplitude may lie anywhere up to the bound)" if k > 0 else ""))
    elif k == 0:
        words += "; judged at the bound (below the checked strokes the bed was not checked)"
    aim = (f"the target {target:g}" if target is not None else
           f"{VERIFY_REACH:g} times the laws' {sd.amplitude_damper_m * 1e3:.4g} mm (ratio {sd.reduction:.3g})")
    if judged <= promise:
        return {**out, "verdict": "pass", "move": "", "reason": f"{words}; within {aim}"}
    return {**out, "verdict": fails, "move": more, "reason": f"{words}; beyond {aim}"}


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


def design_case(sd: StructureDesign, case, *, cycles: float | None = None):
    """The design ``sd`` as one runnable :class:`~pdamper.params.Case`: ``case`` (the structure
    file's: materials, contact, numerics) with the design's container (its length along the drive),
    filling and sphere density; its drive the structure forced by the design's force at the
    design's resonance, from rest; and the damper's rig drive beside it
    (:attr:`~pdamper.params.Case.rig`): the operating stroke at that frequency, along the
    structure's direction, which a sweep (and the fields made of it) runs.

    ``cycles`` (``[run] cycles``): forcing periods of a run; default five decay times of the
    damped mode, 5 / (2 pi zeta_total) rounded up to tens, so a response from rest is steady;
    ``drop_cycles`` the paper's 2 (what a sweep's analysis drops; a response measures its last cycles).
    """
    import dataclasses

    from .excitation import HarmonicDrive

    d = sd.filling
    sphere = case.particles[0]
    mat = sphere.material
    if mat.density != d.density_kg_m3:
        mat = dataclasses.replace(mat, density=d.density_kg_m3)
    f = round(sd.frequency_hz, 4)
    s = case.drive
    structure = dataclasses.replace(s, force_amplitude=sd.force_N, force_frequency=f, displacement=0.0, velocity=0.0)
    rig = HarmonicDrive(stroke=round(sd.damper_stroke_m, 7), frequency=f, angle=s.angle, direction=s.direction)
    if cycles is None:
        cycles = 10 * math.ceil(5.0 / (2 * math.pi * sd.zeta_total) / 10)
    return dataclasses.replace(
        case, particles=(dataclasses.replace(sphere, count=d.particles, radius=d.sphere_radius_m, material=mat),),
        container=dataclasses.replace(case.container, geometry=d.container_geometry()), drive=structure, rig=rig,
        cycles=cycles, drop_cycles=2)


def design_case_text(sd: StructureDesign, case, *, command: str, name: str = "design.toml",
                     verify: dict | None = None) -> str:
    """The TOML text of :func:`design_case` (``case``: that case) with a header that says how it
    was designed (``command``), the target, the predicted ratio, the margin, the DEM check's
    verdict (``verify``, if run) and the commands it is meant for."""
    from ._version import __version__
    from .config import dumps_case

    d = sd.filling
    mm = lambda x: f"{x * 1e3:.4g} mm"  # noqa: E731
    aim = (f"the lightest filling whose resonant amplitude is at most {sd.target_ratio:g} times the bare "
           "structure's" if sd.target_ratio is not None else "the filling with the smallest resonant amplitude")
    lines = [
        f"pdamper design (pdamper {__version__}): a particle damper and the structure it was designed for, in one "
        "case.",
        "",
        f"Designed by:  {command}",
        f"Aim:          {aim} (mode {sd.mode} of {sd.modes}, F = {sd.force_N:.4g} N at resonance)",
        f"Predicted:    ratio {sd.reduction:.3g}: the damper point swings {mm(sd.amplitude_damper_m)} at "
        f"{sd.frequency_hz:.5g} Hz, the bare structure {mm(sd.amplitude_damper_bare_m)} at "
        f"{sd.natural_frequency_hz:.5g} Hz (energy balance at resonance with the paper's closed forms)",
        f"The damper:   {d.particles} of {d.max_particles} spheres r = {mm(d.sphere_radius_m)} "
        f"({d.bed_mass_kg * 1e3:.4g} g, {100 * sd.mass_ratio:.3g} % of the mode's {sd.mass_at_damper_kg:.4g} kg at "
        f"the damper) in a {d.describe_container()}"
        + (f"; one sphere fewer gives at best ratio {sd.lighter_ratio:.3g}" if sd.lighter_ratio is not None else ""),
        f"Margin:       the operating stroke {mm(sd.damper_stroke_m)} is {sd.stroke_over_x_opt:.3g} X_opt "
        f"(X_opt = {mm(d.x_opt_m)}), kept >= {sd.margin:.3g} X_opt ("
        + ("--margin" if sd.margin_given else f"the default for a bed {100 * d.particles / d.max_particles:.3g} % "
           "filled, above the strokes at which the DEM checks saw such beds sway")
        + "; docs/structure.md, \"The margin\")",
    ]
    if verify is not None:
        lines.append(f"DEM check:    {verify['verdict']}: {verify['reason']}")
    else:
        lines.append("DEM check:    not run (pdamper design ... --verify)")
    lo, hi = 0.4 * sd.damper_stroke_m, 1.6 * sd.damper_stroke_m
    f = case.drive.force_frequency
    stem = name[:-5] if name.endswith(".toml") else name
    lines += [
        "",
        "[drive] is the damper alone on its rig, at the operating stroke and the resonance: `pdamper sweep` runs",
        "it (the damper's eta* and fields). [structure] is the structure forced by F at the design's resonance,",
        "from rest: `pdamper response` runs it (and `pdamper decay` with --set structure.displacement=...). [run]",
        "cycles are forcing periods, about five decay times of the damped mode (a sweep takes --cycles of its own):",
        "",
        f"  pdamper response {name} --frequencies {f:.5g}Hz",
        f"  pdamper sweep {name} --vary drive.stroke={lo * 1e3:.3g}mm:{hi * 1e3:.3g}mm:6 "
        f"--vary drive.frequency={0.97 * f:.4g}Hz,{f:.4g}Hz,{1.03 * f:.4g}Hz --seeds 2 --cycles 12 --out {stem}_sweep",
        f"  pdamper fields {stem}_sweep --out {stem}_fields.nc",
        f"  pdamper response {name} --fields {stem}_fields.nc --frequencies {0.99 * f:.4g}Hz:{1.01 * f:.4g}Hz:9",
        "",
    ]
    return "".join(f"# {line}".rstrip() + "\n" for line in lines) + "\n" + dumps_case(case, name=name)
