"""The structure search: the filling (and container length) for a structure's mode under a harmonic force.

The designer's question: a structure's mode, a harmonic force at its resonance; which filling
(and container length, within bounds) makes the resonant amplitude smallest, or which is the
lightest that meets a target ratio? The damper is described by fields built from the paper's
closed forms (eta* of eqs. 8/14, the energy per cycle E(X) = pi eta*(X) m_bed (X Omega)^2 of eqs.
4/5, and the effective mass of the rolling bed from the kinematics of eqs. 10-12:
:mod:`pdamper.theory.fields`); the mode's amplitude follows from the energy balance at phase
resonance (:mod:`pdamper.theory.balance`; docs/structure.md, "Design for a structure").

The pieces, so another load or several dampers can reuse them: :func:`structure_mode` (the mode
as the balance sees it), the candidates (:func:`_candidates`: every container length and filling
within the bounds), their operating points (:func:`_operating`: admissible or not) and the two
choices (:func:`_smallest`, :func:`_lightest`); :func:`design_for_structure` puts them together.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

from .. import theory as th
from ..errors import InputError, shown
from ..geometry import Cuboid
from ..theory.balance import Mode, operating_points
from ..theory.fields import closed_form_fields
from ..units import quantities
from .filling import (MARGIN_TABLE, Design, _margin_warnings, _margin_words, auto_margin, design_filling,
                      most_spheres)
from .names import name

__all__ = ["StructureDesign", "design_for_structure", "structure_mode"]


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
        raise InputError(f"{name('mode')} {shown(number)}: give the mode's number, 1 for the lowest")
    if not getattr(structure, "coupled", False):
        raise InputError("the structure must be a [structure] section (mass with stiffness or natural_frequency, "
                         "or modes = [...], or matrices = ...)")
    mass, k, c, pd, pf, pr = structure.modal_arrays()
    n = int(mass.size)
    j = number - 1
    if not 0 <= j < n:
        raise InputError(f"{name('mode')} {number}: the structure has {n} mode{'s' if n > 1 else ''} (give "
                         + (f"1 to {n}, 1 the lowest)" if n > 1 else f"{name('mode')} 1)"))
    if pd[j] == 0.0:
        raise InputError(f"{name('mode')} {number}: the mode shape is zero at the damper (damper = 0); the damper cannot "
                         "act on this mode")
    return Mode(number=number, mass=float(mass[j]), stiffness=float(k[j]), damping=float(c[j]),
                frequency=math.sqrt(k[j] / mass[j]) / (2 * math.pi),
                damping_ratio=float(c[j] / (2 * math.sqrt(k[j] * mass[j]))), phi_damper=float(pd[j]),
                phi_force=float(pf[j]), phi_response=float(pr[j]), modes=n)



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
    #: the margin the chosen filling keeps, X >= margin X_opt: ``margin``, or the default for
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
    #: mode alike): what ``target_ratio`` bounds
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
            raise InputError(f"{name('length_range')} {lo * 1e3:g}mm:{hi * 1e3:g}mm: need 0 < LOW <= HIGH, e.g. 80mm:200mm")
        if length is not None:
            raise InputError(f"give either {name('length')} (one container length) or {name('length_range')} LOW:HIGH (a "
                             "range), not both")
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
            raise InputError(f"{name('particles')} {shown(particles)}: give a whole number of spheres >= 1, or LOW:HIGH, e.g. 20:60")
    if lo > hi:
        raise InputError(f"{name('particles')} {lo}:{hi}: need LOW <= HIGH, e.g. 20:60")
    return lo, hi


def _mass_caps(max_bed_mass, max_mass_ratio, m_at_damper: float) -> dict:
    """The bed-mass bounds [kg] given, by the parameter that gives them: ``max_bed_mass`` [kg] and
    ``max_mass_ratio`` of the mode's mass at the damper ``m_at_damper`` [kg]."""
    caps = {}
    for key, bound in (("max_bed_mass", max_bed_mass), ("max_mass_ratio", max_mass_ratio)):
        if bound is not None and not (bound > 0 and math.isfinite(bound)):
            raise InputError(f"{name(key)} = {shown(bound)}: must be > 0 (a mass ratio of 0.01 is 1 % of the mode's mass)")
    if max_bed_mass is not None:
        caps["max_bed_mass"] = max_bed_mass
    if max_mass_ratio is not None:
        caps["max_mass_ratio"] = max_mass_ratio * m_at_damper
    return caps


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
        for n in range(bounds[0], int(min(most_spheres(geo, radius, n_max), bounds[1])) + 1):
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
    from ..theory._common import positive

    if not (isinstance(container_mass, (int, float)) and container_mass >= 0 and math.isfinite(container_mass)):
        raise InputError(f"container mass = {shown(container_mass)} kg is not allowed: give the empty container's mass, "
                         ">= 0 ([container] mass, e.g. '80g')")
    if getattr(structure, "coupled", False):
        structure = structure.carrying(container_mass)
    md = structure_mode(structure, mode)
    f0 = force
    if isinstance(f0, bool) or not isinstance(f0, (int, float)) or not (f0 > 0 and math.isfinite(f0)):
        raise InputError(f"{name('force')} = {shown(force)} N is not allowed: give the force amplitude on the structure, > 0, "
                         f"e.g. {name('force')} 1.5N")
    if target_ratio is not None and not (isinstance(target_ratio, (int, float)) and not isinstance(target_ratio, bool)
                                         and 0 < target_ratio < 1):
        raise InputError(f"{name('target_ratio')} = {shown(target_ratio)}: give the resonant amplitude with the damper over the "
                         "bare structure's, between 0 and 1 (e.g. 0.5: half the bare amplitude)")
    r = positive("sphere_radius", sphere_radius, "m", "0.005 (5 mm)")
    rho = positive("density", density, "kg/m^3", "7900 (steel)")
    if container is None:
        container = Cuboid(width=positive("width", width if width is not None else 0.0404, "m", "0.0404 (40.4 mm)"))
    elif width is not None:
        raise InputError(f"give the container's width in the container itself ({name('width')} sets the cuboid's), not "
                         "both")
    if margin is not None and not (isinstance(margin, (int, float)) and margin >= 1.0):
        raise InputError(f"{name('margin')} = {shown(margin)}: the operating stroke over X_opt must be >= 1 (default: by the "
                         "filling fraction, 1.2 to 1.75)")
    if length_range is None:
        length = container.drive_length if length is None else positive("length", length, "m", "0.12 (120 mm)")
    bounds = _particle_bounds(particles)
    m_sphere = rho * 4.0 / 3.0 * math.pi * r**3
    m_at_damper = md.mass / md.phi_damper**2
    caps = _mass_caps(max_bed_mass, max_mass_ratio, m_at_damper)
    cap = min(caps.values(), default=math.inf)
    if cap < m_sphere:
        raise InputError(f"the bed-mass bound {cap * 1e3:.4g} g is below one sphere's mass ({m_sphere * 1e3:.4g} g); "
                         f"raise {name('max_bed_mass')} / {name('max_mass_ratio')} or use smaller spheres ({name('sphere_radius')})")
    across = container.length_along((0.0, 0.0, 1.0))
    if 2 * r > across:
        raise InputError(f"{name('sphere_radius')} = {r * 1e3:g} mm: a sphere does not fit the width across the drive of "
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
                f"spheres lower X_opt; a larger {name('max_bed_mass')} allows more spheres) or, with a large force, lifts the "
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



def _search_bounds(lengths, bounds: tuple, caps: dict, margin) -> dict:
    """What the design searched: the container lengths [m], the fillings, the bed-mass bounds [kg], the
    margin (``"auto"``: by the filling fraction)."""
    return {"lengths_m": [float(lengths[0]), float(lengths[-1])], "length_steps": int(len(lengths)),
            "particles": [int(bounds[0]), None if math.isinf(bounds[1]) else int(bounds[1])],
            "max_bed_mass_kg": {k.replace("_", "-"): float(v) for k, v in caps.items()},
            "margin": "auto" if margin is None else margin}


def _unmet(md, f0, found, container, lengths, radius, m_sphere, caps, bounds, *, target, x_bare, kappa, margin,
           gravity) -> str:
    """The one line of a target that no filling within the bounds meets: the best ratio found, and
    which bound to widen (each tried: the container lengths, from half the shortest to twice the
    longest; the bed-mass bounds lifted; both)."""
    cands = _candidates(container, lengths, radius, m_sphere, min(caps.values(), default=math.inf), bounds)
    best = _smallest(md, f0, cands, kappa=kappa, margin=margin, gravity=gravity)
    head = (f"{name('target_ratio')} {target:g}: no filling within the bounds meets it with X >= {_margin_words(margin)} on "
            f"the rolling branch without lift-off ({len(cands)} in the bounds; "
            + (f"the best: {_describe(best[1], best[0] / x_bare)})" if best else "none keeps that margin)"))
    lo, hi = float(lengths[0]), float(lengths[-1])
    wide = _lengths((max(4 * radius, 0.5 * lo), 2.0 * hi), None)
    mass_names = [name(k) for k, v in caps.items() if v == min(caps.values())]
    if bounds[1] < math.inf and bounds[1] * m_sphere <= min(caps.values(), default=math.inf):
        mass_names = [name("particles")]
    free = (bounds[0], math.inf)
    tries = [("length", wide, min(caps.values(), default=math.inf), bounds)]
    if mass_names:
        tries += [("mass", lengths, math.inf, free), ("both", wide, math.inf, free)]
    length_words = f"{name('length_range')} {wide[0] * 1e3:.4g}mm:{wide[-1] * 1e3:.4g}mm"
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
            + f" meet it: a wider container (more spheres per row) or smaller spheres ({name('sphere_radius')}) give more "
            "bed per length; see docs/structure.md, \"Design to a target\"")
