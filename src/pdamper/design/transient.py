"""The design against a load in time: the lightest filling whose coupled DEM transient meets a
target peak ratio and RMS ratio (with / without the damper) under the structure's ``[load]``.

The designer's question: "my frame, this record (or this suite of records): which
damper cuts the top floor's peak by 30 % and its RMS by 40 %?" Three steps, each a function:

1. **The candidates** (:func:`pdamper.design.search._candidates`): every container length of the
   range and every filling that fits (:func:`~pdamper.design.filling.most_spheres`) within the
   bed-mass bounds, as the design for a harmonic force has them.
2. **The screen** (:func:`screen_candidates`, cheap): each candidate's response under the load from
   the paper's closed-form fields (:func:`pdamper.theory.fields.closed_form_fields`) put into the
   structure's modal equations in time -- the damper as an amplitude-dependent dashpot ``c_d =
   eta*(A / X_opt) m_bed Omega_1`` and mass ``m_eff(A / X_opt)`` at the damper point, ``A`` the
   damper point's instantaneous amplitude ``sqrt(x^2 + (x' / Omega_1)^2)`` at the first mode's
   frequency (a quasi-steady describing function; the energy per cycle of eqs. 4, 5) -- integrated
   by fourth-order Runge-Kutta, all candidates at once, with the bare structure integrated the same
   way for the ratios. It knows nothing of how long a bed takes to start its collect-and-collide
   motion; the DEM does.
3. **The DEM checks** (:func:`check_candidate`): the coupled transient
   (:func:`pdamper.studies.transient.run_transient`, or one a record of a suite,
   :func:`pdamper.studies.suite.run_suite`) of the candidates in turn, lightest first among those
   the screen, corrected by what the checks so far measured (the DEM's ratio over the screen's),
   expects to meet the targets; at most ``checks`` runs. The lightest candidate whose DEM ratios
   meet the targets is the design (:class:`TransientDesign`, ``met``); else the best one checked is
   the best achievable, with the reasons measured on its run (:func:`measured_reasons`: the stroke
   below X_opt during the large swing, the peak before the bed engages, the added mass detuning,
   a strong motion too short for damping to bound the peak).

The ratios are the damper point's (default) or those of the dofs asked for, each target at
every one of them; under a suite the mean with the damper over the mean without (the codes'
design value). The design's case (:func:`load_design_case`) is the structure file's with the
design's bed and the load kept: its own ``pdamper transient`` is the DEM check that passed.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import InputError, shown
from ..theory.fields import closed_form_fields
from ..theory.rolling import ETA_MAX
from .case import _bed, design_container
from .filling import design_filling
from .names import name
from .search import _Candidate, _candidates, _lengths, _mass_caps, _particle_bounds, structure_mode

__all__ = ["TransientDesign", "TransientCheck", "CheckedBed", "LoadDesign", "Screen", "design_for_load", "screen_candidates", "check_candidate",
           "measured_reasons", "load_design_case", "load_design_text", "ENGAGED", "STRONG"]

#: The bed "works" from the time it has dissipated this share of the energy it takes over the run
#: (a peak before it came before the bed engaged).
ENGAGED = 0.1
#: The large swing: where the bare response's envelope is at least this share of its peak.
STRONG = 0.5
#: The screen's steps per period of the highest mode (fourth-order Runge-Kutta).
_STEPS_PER_PERIOD = 40


@dataclass(frozen=True, kw_only=True)
class Screen:
    """The screen's estimate for every candidate (:func:`screen_candidates`): ``peak_ratio`` and
    ``rms_ratio`` [candidates, dofs] (with / without the damper, at the dofs judged), the damper
    point's largest amplitude over X_opt ``stroke_over_x_opt`` [candidates]."""

    peak_ratio: np.ndarray
    rms_ratio: np.ndarray
    stroke_over_x_opt: np.ndarray


@dataclass(frozen=True, kw_only=True)
class CheckedBed:
    """The bed of a candidate the DEM checked, SI units: ``particles`` of ``max_particles``,
    ``bed_mass_kg``, the container ``length_m`` along the drive, ``x_opt_m``, the ``container`` in
    words; the check's ``summary`` and the candidate's filling (a
    :class:`~pdamper.design.filling.Design`) beside them."""

    particles: int
    max_particles: int
    bed_mass_kg: float
    length_m: float
    x_opt_m: float
    container: str
    summary: dict = field(default_factory=dict, repr=False)
    filling: object = field(default=None, repr=False, compare=False)

    @staticmethod
    def of(cand) -> dict:
        """The bed's fields of the candidate ``cand``."""
        return dict(particles=cand.particles, max_particles=cand.max_particles, bed_mass_kg=cand.bed_mass,
                    length_m=float(cand.geometry.drive_length), x_opt_m=float(cand.x_opt),
                    container=cand.geometry.describe())

    def to_dict(self) -> dict:
        """Every field but the filling object (its numbers are in ``particles`` ...) and the check's summary."""
        out = asdict(self)
        out.pop("filling")
        out.pop("summary")
        return out


@dataclass(frozen=True, kw_only=True)
class TransientCheck(CheckedBed):
    """The DEM check of one candidate under the load (:func:`check_candidate`), SI units: its bed
    (:class:`CheckedBed`), the ratios at the dofs judged (``dofs``; ``peak_ratio``, ``rms_ratio``
    per dof; under a suite the mean over the records with the damper over the mean without),
    whether it meets the targets (``met``), the screen's estimate for it, the numbers its reasons
    were measured from (``measured``, :func:`measured_reasons`) and the run's summary."""

    dofs: list
    peak_ratio: list
    rms_ratio: list
    met: bool
    screen_peak_ratio: list
    screen_rms_ratio: list
    measured: dict
    reasons: list
    records: int


@dataclass(frozen=True, kw_only=True)
class LoadDesign:
    """What every design against a load in time reports: ``met``, the targets (``target_peak_ratio``,
    ``target_rms_ratio``) at the ``dofs`` judged, ``design`` (None when unmet) and ``best`` (the
    design, or unmet the best achievable), every check in the order run (``checks``), the
    ``candidates`` screened and ``screen_met`` of them expected to meet the targets, the
    ``reasons`` when unmet, the ``load`` in words, the structure's first mode
    (``natural_frequency_hz``, ``mass_at_damper_kg``), the ``search`` bounds and ``warnings``."""

    met: bool
    target_peak_ratio: float | None
    target_rms_ratio: float | None
    dofs: list
    design: object
    best: object
    checks: list
    candidates: int
    screen_met: int
    reasons: list
    load: str
    natural_frequency_hz: float
    mass_at_damper_kg: float
    search: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)


@dataclass(frozen=True, kw_only=True)
class TransientDesign(LoadDesign):
    """The design against a load in time (:func:`design_for_load`; the fields of
    :class:`LoadDesign`): ``met`` (some candidate's DEM check meets every target), ``design`` the
    lightest such check (a :class:`TransientCheck`, None when unmet), ``best`` the best checked
    (the design, or for an unmet target the best achievable: the smallest worst ratio over its
    target), every DEM check in the order run (``checks``), the ``reasons`` an unmet target was not
    met (measured on the best's run), the ``records`` of a suite."""

    records: int

    def to_dict(self) -> dict:
        """Every field, the checks as dicts (for JSON): ``peak_ratio`` / ``rms_ratio`` of the design
        (or, unmet, of the best achievable) per dof at the top level."""
        out = {k: getattr(self, k) for k in ("met", "target_peak_ratio", "target_rms_ratio", "dofs", "candidates",
                                             "screen_met", "reasons", "records", "load", "natural_frequency_hz",
                                             "mass_at_damper_kg", "search", "warnings")}
        out["design"] = self.design.to_dict() if self.design is not None else None
        out["best_achievable"] = self.best.to_dict() if self.best is not None and not self.met else None
        chosen = self.design if self.met else self.best
        out["peak_ratio"] = chosen.peak_ratio if chosen is not None else None
        out["rms_ratio"] = chosen.rms_ratio if chosen is not None else None
        out["checks"] = [c.to_dict() for c in self.checks]
        return out


# --------------------------------------------------------------------------- the screen

def _judged(structure, dofs):
    """(labels, shapes [judged, modes]) of the dofs the targets hold at: ``dofs`` (labels of
    :meth:`~pdamper.structure.StructureBase.dof_shapes`), or None: the damper point."""
    from ..studies.structure_base import select_dofs

    if dofs is None:
        return ["damper"], np.asarray(structure.modal_arrays()[3], dtype=float)[None, :]
    labels, idx = select_dofs(structure, dofs)
    return labels, np.asarray(structure.dof_shapes()[1], dtype=float)[idx]


def screen_candidates(structure, cands: list, *, dofs=None, kappa: float = 1.0) -> Screen:
    """The screen (module docstring) of the candidates ``cands`` on ``structure`` (as it runs,
    with its load in time; a suite: every record, the ratio of the means): peak and RMS ratios at
    the dofs judged (``dofs``; None: the damper point)."""
    loads = structure.load.records()
    labels, shapes = _judged(structure, dofs)
    peaks, rms, strokes = [], [], []
    for load in loads:
        s = dataclasses.replace(structure, load=load)
        p, r, a = _integrate(s, cands, shapes, kappa)
        peaks.append(p)
        rms.append(r)
        strokes.append(a)
    peaks, rms = np.mean(peaks, axis=0), np.sqrt(np.mean(np.square(rms), axis=0))
    with np.errstate(divide="ignore", invalid="ignore"):
        peak_ratio = peaks[1:] / peaks[:1]
        rms_ratio = rms[1:] / rms[:1]
    return Screen(peak_ratio=peak_ratio, rms_ratio=rms_ratio, stroke_over_x_opt=np.max(strokes, axis=0)[1:])


def _integrate(s, cands, shapes, kappa):
    """(peak [1 + C, judged], RMS [1 + C, judged], damper amplitude / X_opt [1 + C]) of the bare
    structure (row 0) and each candidate under the load of ``s``, by fourth-order Runge-Kutta."""
    mass, k, c, pd, _, _ = (np.asarray(a, dtype=float) for a in s.modal_arrays())
    load = s.load
    b = np.asarray(load.modal_coefficients(s), dtype=float)
    ground = 1.0 if load.ground else 0.0
    w1 = 2.0 * math.pi * float(np.min(s.mode_frequencies))
    top = float(max(np.max(s.mode_frequencies), load.highest_frequency))
    duration = float(load.duration)
    h = min(1.0 / (_STEPS_PER_PERIOD * top), duration / 200.0)
    steps = int(math.ceil(duration / h))
    h = duration / steps
    m_bed = np.array([0.0] + [cd.bed_mass for cd in cands])[:, None]
    x_opt = np.array([1.0] + [cd.x_opt for cd in cands])[:, None]
    n = m_bed.shape[0]
    q = np.zeros((n, mass.size)) + np.asarray(s.initial_modal_state()[0], dtype=float)
    v = np.zeros((n, mass.size)) + np.asarray(s.initial_modal_state()[1], dtype=float)
    inv = 1.0 / mass
    pd_inv = pd * inv                                  # M^-1 phi_d
    phi_m_phi = float(pd @ pd_inv)                     # phi_d^T M^-1 phi_d

    forces = load.values(0.5 * h * np.arange(2 * steps + 1))  # f(t) at every step and half step

    def accel(f, q, v):
        xd, vd = q @ pd, v @ pd
        amp = np.sqrt(xd * xd + (vd / w1) ** 2)[:, None]
        eta, mu = closed_form_fields(amp / x_opt, kappa)
        c_d, m_eff = eta * m_bed * w1, mu * m_bed
        # (M + m_eff phi phi^T) q'' = b f - C q' - K q - phi (c_d x_d' + m_eff g a_g)   (Sherman-Morrison)
        r = b * f - c * v - k * q - pd * (c_d * vd[:, None] + m_eff * ground * f)
        minv_r = r * inv
        return minv_r - pd_inv * (m_eff * (minv_r @ pd)[:, None]) / (1.0 + m_eff * phi_m_phi), amp

    peak = np.zeros((n, shapes.shape[0]))
    sq = np.zeros((n, shapes.shape[0]))
    amp_top = np.zeros(n)
    for i in range(steps):
        f0, fh, f1 = forces[2 * i], forces[2 * i + 1], forces[2 * i + 2]
        a1, amp = accel(f0, q, v)
        a2, _ = accel(fh, q + h / 2 * v, v + h / 2 * a1)
        a3, _ = accel(fh, q + h / 2 * (v + h / 2 * a1), v + h / 2 * a2)
        a4, _ = accel(f1, q + h * (v + h / 2 * a2), v + h * a3)
        q = q + h * (v + h / 6 * (a1 + a2 + a3))
        v = v + h / 6 * (a1 + 2 * a2 + 2 * a3 + a4)
        x = q @ shapes.T
        peak = np.maximum(peak, np.abs(x))
        sq += x * x
        amp_top = np.maximum(amp_top, amp[:, 0] / x_opt[:, 0])
    return peak, np.sqrt(sq / steps), amp_top


# --------------------------------------------------------------------------- the DEM check

def _candidate_case(case, cand: _Candidate, *, radius: float, density: float, frequency: float, stroke: float):
    """The case of candidate ``cand``: the structure file's ``case`` with the candidate's bed, and
    its filling (:func:`~pdamper.design.filling.design_filling` of it at ``stroke`` and ``frequency``)."""
    fill = design_filling(frequency=frequency, stroke=max(stroke, 1e-6), sphere_radius=radius, container=cand.geometry,
                          max_particles=cand.max_particles, density=density, particles=cand.particles)
    return dataclasses.replace(case, **_bed(case, fill)), fill


def check_candidate(case, cand: _Candidate, *, dofs=None, targets=(None, None), screen=(None, None), radius: float,
                    density: float, progress=None) -> TransientCheck:
    """The DEM check of candidate ``cand`` on the structure file's ``case`` under its load (one
    transient; a suite: one a record), judged at ``dofs`` (None: the damper point) against
    ``targets`` (peak, RMS ratio; None: not judged); ``screen`` the screen's (peak, RMS) ratios for it."""
    from ..studies.suite import run_suite
    from ..studies.transient import run_transient

    f1 = float(np.min(case.running_drive.mode_frequencies))
    one, fill = _candidate_case(case, cand, radius=radius, density=density, frequency=f1, stroke=cand.x_opt)
    suite = len(case.drive.load.records()) > 1
    if suite:
        res = run_suite(one, dofs=[d for d in dofs] if dofs is not None else None, progress=progress)
        s = res.summary
        runs = res.runs
        if dofs is None:
            peak, rms = [s["damper_peak_ratio"]], [s["damper_rms_ratio"]]
        else:
            peak, rms = list(s["peak_ratio"]), list(s["rms_ratio"])
        worst = max(range(len(runs)), key=lambda j: runs[j].summary["damper_peak_reduction"])
        run = runs[worst]
    else:
        run = run_transient(one, dofs=dofs, progress=progress)
        s = run.summary
        if dofs is None:
            peak, rms = [s["damper_peak_reduction"]], [s["damper_rms_reduction"]]
        else:
            peak, rms = list(s["peak_reduction"]), list(s["rms_reduction"])
    met = _meets(peak, rms, targets)
    measured, reasons = measured_reasons(run, x_opt=cand.x_opt, bed_mass=cand.bed_mass, targets=targets,
                                         peak=peak, rms=rms)
    return TransientCheck(**CheckedBed.of(cand), dofs=list(_labels(case, dofs)),
                          peak_ratio=[float(x) for x in peak], rms_ratio=[float(x) for x in rms], met=met,
                          screen_peak_ratio=_floats(screen[0]), screen_rms_ratio=_floats(screen[1]),
                          measured=measured, reasons=reasons if not met else [],
                          records=len(case.drive.load.records()), summary=s, filling=fill)


def _floats(x):
    return None if x is None else [float(v) for v in np.atleast_1d(x)]


def _labels(case, dofs):
    return ["damper"] if dofs is None else _judged(case.running_drive, dofs)[0]


def _meets(peak, rms, targets) -> bool:
    tp, tr = targets
    ok = True
    if tp is not None:
        ok &= all(math.isfinite(x) and x <= tp for x in peak)
    if tr is not None:
        ok &= all(math.isfinite(x) and x <= tr for x in rms)
    return bool(ok)


def _excess(peak, rms, targets) -> float:
    """The worst ratio over its target (<= 1: met)."""
    tp, tr = targets
    out = []
    if tp is not None:
        out += [x / tp for x in np.atleast_1d(peak)]
    if tr is not None:
        out += [x / tr for x in np.atleast_1d(rms)]
    vals = [v if math.isfinite(v) else math.inf for v in out]
    return max(vals) if vals else math.inf


def measured_reasons(run, *, x_opt: float, bed_mass: float, targets=(None, None), peak=None, rms=None):
    """(numbers, reasons in words) of why a damper's transient ``run``
    (:class:`~pdamper.studies.transient.TransientResult`) fell short, measured on it:

    - **the peak before the bed engages**: the damper point's bare peak came at ``peak_time_s``,
      before ``engaged_time_s``, when the bed had dissipated :data:`ENGAGED` of the energy it took
      over the run (``dissipated_share_at_peak``: its share by the peak);
    - **the stroke below X_opt during the large swing** (where the bare envelope is at least
      :data:`STRONG` of its peak, ``large_swing_s``): the share of that time the damper point's
      amplitude (its running peak over a period of the first mode) stayed below X_opt, and its largest;
    - **the added mass detuning**: the bare structure carrying the bed as a rigid mass (exact):
      its peak over the bare peak (above 1: the bed's mass alone moves the structure to where the
      load has more, which its damping must first undo);
    - **the strong motion too short** for damping to bound the peak (:func:`_duration_bound`): the
      peak ratio of a resonant burst of the load's significant duration with this bed at its best,
      above the peak target.
    """
    from ..structure.linear import damper_motion

    t = np.asarray(run.time, dtype=float)
    x, xb = np.asarray(run.damper, dtype=float), np.asarray(run.damper_bare, dtype=float)
    st = run.case.running_drive
    f1 = float(np.min(st.mode_frequencies))
    bare_peak = float(np.max(np.abs(xb)))
    k_peak = int(np.argmax(np.abs(xb)))
    lost = np.asarray(run.dissipated, dtype=float) if run.dissipated is not None else None
    if lost is not None and lost[-1] > 0:
        engaged = float(t[np.argmax(lost >= ENGAGED * lost[-1])])   # the bed's first tenth of its work
        share_at_peak = float(max(lost[k_peak], 0.0) / lost[-1])
    else:
        apart = np.nonzero(np.abs(x - xb) > ENGAGED * bare_peak)[0]
        engaged = float(t[apart[0]]) if apart.size else math.inf
        share_at_peak = math.nan
    # running peak over one period of the first mode: the damper point's amplitude
    dt = float(t[1] - t[0]) if t.size > 1 else 1.0
    width = max(1, int(round(1.0 / (f1 * dt))))
    env_b = _running_max(np.abs(xb), width)
    env = _running_max(np.abs(x), width)
    strong = env_b >= STRONG * bare_peak
    below = float(np.mean(env[strong] < x_opt)) if strong.any() else 0.0
    t_strong = (float(t[strong][0]), float(t[strong][-1])) if strong.any() else (math.nan, math.nan)
    largest = float(np.max(env[strong])) if strong.any() else float(np.max(env))
    solid, _, _ = damper_motion(st.carrying(bed_mass), t)
    solid_ratio = float(np.max(np.abs(solid)) / bare_peak) if bare_peak > 0 else math.nan
    duration, periods, bound, zeta_b, zeta_d = _duration_bound(run, st, bed_mass, f1)
    numbers = {"peak_time_s": float(t[k_peak]), "engaged_time_s": engaged, "dissipated_share_at_peak": share_at_peak, "large_swing_s": list(t_strong),
               "stroke_below_x_opt_share": below, "largest_stroke_m": largest, "x_opt_m": float(x_opt),
               "solid_mass_peak_ratio": solid_ratio, "bare_peak_m": bare_peak, "significant_duration_s": duration,
               "strong_motion_periods": periods, "peak_ratio_bound": bound}
    reasons = []
    if engaged > numbers["peak_time_s"]:
        when = f"{engaged:.3g} s" if math.isfinite(engaged) else "never within the run"
        done = (f"it had dissipated {100 * share_at_peak:.2g} % of the energy it took over the run by then, "
                f"{100 * ENGAGED:g} % by {when}" if math.isfinite(share_at_peak) else
                f"the response with the damper departed from the bare one by {100 * ENGAGED:g} % of the bare peak at "
                f"{when}")
        reasons.append(f"the peak came at {numbers['peak_time_s']:.3g} s, before the bed started to work ({done})")
    if below > 0.25:
        reasons.append(f"while the structure swung at more than half its bare peak ({t_strong[0]:.3g}-{t_strong[1]:.3g} "
                       f"s) the damper's stroke stayed below X_opt = {1e3 * x_opt:.3g} mm for {100 * below:.0f} % of the time (largest "
                       f"{1e3 * largest:.3g} mm): there the bed scatters, below its collect-and-collide motion")
    if solid_ratio > 1.0:
        reasons.append(f"the added mass detunes: the bed as a rigid mass alone raises the peak by "
                       f"{100 * (solid_ratio - 1):.2g} % (the load has more at the lowered frequency)")
    if targets[0] is not None and bound > targets[0]:
        reasons.append(f"the load's strong motion is short: {duration:.3g} s (D5-95, its Arias intensity from 5 to 95 %), "
                       f"{periods:.3g} periods of the {f1:.3g} Hz mode; a resonant burst that long, with the structure's "
                       f"zeta = {100 * zeta_b:.2g} % and this bed at its best from the first cycle (eta* = {ETA_MAX:.3g}: "
                       f"{100 * zeta_d:.2g} % more), still leaves a peak ratio of {bound:.3g}: the peak is set by how "
                       "long the load builds up, which damping changes little; more bed mass or another target")
    if not reasons and peak is not None:
        reasons.append("the bed engaged and worked above X_opt, but did not take enough energy: more bed mass (a "
                       "longer or wider container, more spheres) or a larger mass bound")
    return numbers, reasons


def _duration_bound(run, st, bed_mass: float, f1: float):
    """(D5-95 [s], periods of the first mode in it, the peak ratio bound, zeta of the structure, the
    bed's largest zeta): the significant duration of the load (Trifunac & Brady 1975: the time
    between 5 % and 95 % of the integral of f^2) and the peak ratio of a resonant harmonic burst of
    N = f1 D5-95 periods with and without the damping of the bed at the rolling law's largest eta*,

        X(zeta) ~ (1 - exp(-2 pi zeta N)) / zeta,   bound = X(zeta_b + zeta_d) / X(zeta_b),

    zeta_d = eta*_max m_bed phi_d^2 / (2 m) (the bed's dashpot eta* m_bed Omega, eqs. 4-5)."""
    f = np.asarray(run.load, dtype=float)
    t = np.asarray(run.time, dtype=float)
    ia = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] ** 2 + f[:-1] ** 2) * np.diff(t))])
    if not ia[-1] > 0:
        return 0.0, 0.0, 1.0, math.nan, math.nan
    t5, t95 = float(t[np.argmax(ia >= 0.05 * ia[-1])]), float(t[np.argmax(ia >= 0.95 * ia[-1])])
    duration = t95 - t5
    periods = f1 * duration
    mass, _, _, pd, _, _ = (np.asarray(a, dtype=float) for a in st.modal_arrays())
    j = int(np.argmin(st.mode_frequencies))
    zeta_b = float(st.mode_damping_ratios[j])
    zeta_d = ETA_MAX * bed_mass * pd[j] ** 2 / (2.0 * mass[j])

    def build(z):
        return (1.0 - math.exp(-2 * math.pi * z * periods)) / z if z > 0 else 2 * math.pi * periods

    bound = build(zeta_b + zeta_d) / build(zeta_b) if periods > 0 else 1.0
    return duration, periods, float(bound), zeta_b, float(zeta_d)


def _running_max(x: np.ndarray, width: int) -> np.ndarray:
    """The largest of ``x`` over a centred window of ``width`` samples."""
    from scipy.ndimage import maximum_filter1d

    return maximum_filter1d(x, size=width, mode="nearest")


# --------------------------------------------------------------------------- the design

@dataclass(frozen=True, kw_only=True)
class _Setup:
    """What a design against a load in time starts from (:func:`_setup`)."""

    structure: object
    targets: tuple
    labels: list
    cands: list
    radius: float
    density: float
    lengths: object
    bounds: tuple
    caps: dict
    mass_at_damper: float

    def search(self, checks: int) -> dict:
        """The search's bounds, for the report (JSON)."""
        lengths, bounds = self.lengths, self.bounds
        return {"lengths_m": [float(lengths[0]), float(lengths[-1])], "length_steps": int(len(lengths)),
                "particles": [int(bounds[0]), None if math.isinf(bounds[1]) else int(bounds[1])],
                "max_bed_mass_kg": {k.replace("_", "-"): float(v) for k, v in self.caps.items()}, "checks": checks}


def _setup(case, *, target_peak_ratio, target_rms_ratio, dofs, shape, sizes, sphere_radius, density, length,
           length_range, particles, max_bed_mass, max_mass_ratio, checks) -> _Setup:
    """The checks of a design against a load in time's arguments (:func:`design_for_load`) and its
    candidates."""
    s = case.running_drive
    if not getattr(s, "coupled", False) or s.load is None:
        raise InputError("the design against a load in time needs a [structure] and a [load] (a force history, a "
                         "ground acceleration or a suite of records); give the [load], or design for a harmonic force "
                         f"with {name('force')}")
    for key, value in (("target_peak_ratio", target_peak_ratio), ("target_rms_ratio", target_rms_ratio)):
        if value is not None and not (isinstance(value, (int, float)) and not isinstance(value, bool)
                                      and 0 < value < 1):
            raise InputError(f"{name(key)} = {shown(value)}: give the ratio with / without the damper to reach, between 0 "
                             "and 1 (e.g. 0.7: 30 % less)")
    if target_peak_ratio is None and target_rms_ratio is None:
        raise InputError(f"give {name('target_peak_ratio')} and/or {name('target_rms_ratio')} (e.g. 0.7 and 0.6)")
    if isinstance(checks, bool) or not isinstance(checks, int) or checks < 1:
        raise InputError(f"{name('checks')} = {shown(checks)}: give the number of DEM checks, >= 1 (e.g. 3)")
    targets = (target_peak_ratio, target_rms_ratio)
    labels = _labels(case, dofs)
    sphere = case.particles[0]
    r = float(sphere_radius if sphere_radius is not None else sphere.radius)
    rho = float(density if density is not None else sphere.material.density)
    if not (r > 0 and rho > 0):
        raise InputError(f"{name('sphere_radius')} and {name('density')} must be > 0")
    container = design_container(case, shape=shape, sizes=sizes)
    if length_range is None:
        length = container.drive_length if length is None else length
    lengths = _lengths(length_range, length)
    bounds = _particle_bounds(particles)
    md = structure_mode(s, 1)
    m_sphere = rho * 4.0 / 3.0 * math.pi * r**3
    m_at_damper = md.mass / md.phi_damper**2
    caps = _mass_caps(max_bed_mass, max_mass_ratio, m_at_damper)
    cap = min(caps.values(), default=math.inf)
    cands = _candidates(container, lengths, r, m_sphere, cap, bounds)
    if not cands:
        raise InputError(f"no filling fits the bounds (lengths {lengths[0] * 1e3:.4g}-{lengths[-1] * 1e3:.4g} mm, "
                         f"bed mass <= {cap * 1e3:.4g} g): widen {name('length_range')} or the mass bounds")
    return _Setup(structure=s, targets=targets, labels=list(labels), cands=cands, radius=r, density=rho,
                  lengths=lengths, bounds=bounds, caps=caps, mass_at_damper=m_at_damper)


def design_for_load(case, *, target_peak_ratio: float | None = None, target_rms_ratio: float | None = None,
                    dofs=None, shape: str | None = None, sizes: dict | None = None, sphere_radius: float | None = None,
                    density: float | None = None, length: float | None = None, length_range=None, particles=None,
                    max_bed_mass: float | None = None, max_mass_ratio: float | None = None, checks: int = 3,
                    kappa: float = 1.0, progress=None) -> TransientDesign:
    """The lightest filling whose coupled DEM transient under the structure's load in time meets
    the targets (module docstring): ``case`` a structure file with a ``[load]``
    (:func:`~pdamper.design.case.load_structure`), ``target_peak_ratio`` / ``target_rms_ratio``
    (0 < R < 1, at least one) at every dof of ``dofs`` (labels; None: the damper point); the
    container and spheres as :func:`~pdamper.design.case.design_for_case` takes them (``shape``,
    ``sizes``, ``sphere_radius``, ``density``; ``length`` or ``length_range``, ``particles``,
    ``max_bed_mass`` [kg], ``max_mass_ratio`` of the first mode's mass at the damper); at most
    ``checks`` DEM runs (a suite: each one transient a record). ``progress(fraction)`` of each run.

    A DEM run starts no worker process; a script may call it as it is.
    """
    setup = _setup(case, target_peak_ratio=target_peak_ratio, target_rms_ratio=target_rms_ratio, dofs=dofs,
                   shape=shape, sizes=sizes, sphere_radius=sphere_radius, density=density, length=length,
                   length_range=length_range, particles=particles, max_bed_mass=max_bed_mass,
                   max_mass_ratio=max_mass_ratio, checks=checks)
    s, targets, labels, cands = setup.structure, setup.targets, setup.labels, setup.cands
    r, rho, m_at_damper = setup.radius, setup.density, setup.mass_at_damper
    screen = screen_candidates(s, cands, dofs=dofs, kappa=kappa)
    ex = np.array([_excess(p, q, targets) for p, q in zip(screen.peak_ratio, screen.rms_ratio)])
    mass = np.array([c.bed_mass for c in cands])
    screen_met = int(np.sum(ex <= 1.0))
    bias = [1.0, 1.0]   # the DEM's ratio over the screen's, worst measured so far (peak, RMS)

    def corrected(j):
        p = np.asarray(screen.peak_ratio[j]) * bias[0]
        q = np.asarray(screen.rms_ratio[j]) * bias[1]
        return _excess(p, q, targets)

    def run(j):
        chk = check_candidate(case, cands[j], dofs=dofs, targets=targets,
                              screen=(screen.peak_ratio[j], screen.rms_ratio[j]), radius=r, density=rho,
                              progress=progress)
        for i, (dem, scr) in enumerate(((chk.peak_ratio, screen.peak_ratio[j]), (chk.rms_ratio, screen.rms_ratio[j]))):
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.asarray(dem, dtype=float) / np.asarray(scr, dtype=float)
            if np.all(np.isfinite(ratio)):
                bias[i] = max(bias[i], float(np.max(ratio))) if not chk.met else bias[i]
        return chk

    # the lightest expected to meet it met it: done; none expected (any more), the screen's best candidate
    design, checked = _lightest_first(mass, lambda j: corrected(j) <= 1.0, lambda: np.argsort(ex, kind="stable"), run,
                                     checks)
    best = design if design is not None else min(checked, key=lambda c: _excess(c.peak_ratio, c.rms_ratio, targets))
    reasons = [] if design is not None else list(best.reasons)
    if design is None:
        reasons.insert(0, f"no filling within the bounds met it in the DEM checks ({len(checked)} run; the screen "
                          f"expected {screen_met} of {len(cands)} candidates to meet it); the best achievable: "
                          f"{best.particles} spheres, {best.bed_mass_kg * 1e3:.4g} g, in {best.length_m * 1e3:.4g} mm: "
                          f"peak ratio {_words(best.peak_ratio)}, RMS ratio {_words(best.rms_ratio)}")
    warnings = []
    if len(s.mode_frequencies) > 1:
        warnings.append("the screen's damper acts at the first mode's frequency; the DEM checks hold every mode")
    return TransientDesign(met=design is not None, target_peak_ratio=target_peak_ratio,
                           target_rms_ratio=target_rms_ratio, dofs=list(labels), design=design, best=best,
                           checks=checked, candidates=len(cands), screen_met=screen_met, reasons=reasons,
                           records=len(s.load.records()), load=s.load.describe(),
                           natural_frequency_hz=float(np.min(s.mode_frequencies)), mass_at_damper_kg=m_at_damper,
                           search=setup.search(checks), warnings=warnings)


def _lightest_first(mass, hopeful, fallback, run, checks: int, *, lighter_after_met: bool = False):
    """The search of a design against a load in time over candidates of bed ``mass``: the lightest
    not yet checked that ``hopeful(j)`` expects to meet the targets is checked (``run(j)``, a check
    with ``met``), at most ``checks``; after one met, only lighter ones, and only while
    ``lighter_after_met`` (else the search ends at the first met); none met, the first candidate of
    the order ``fallback()`` not checked (the best achievable). Returns (the lightest check that met
    or None, every check in the order run)."""
    done: dict = {}
    design = None
    while len(done) < checks:
        expected = [j for j in np.argsort(mass, kind="stable") if j not in done and hopeful(j)]
        if design is not None:
            expected = [j for j in expected if mass[j] < design.bed_mass_kg - 1e-12]
        if not expected:
            break
        j = int(expected[0])
        done[j] = run(j)
        if done[j].met:
            design = done[j]
            if not lighter_after_met:
                break
    if design is None and len(done) < checks:
        rest = [j for j in fallback() if j not in done]
        if rest:
            j = int(rest[0])
            done[j] = run(j)
            if done[j].met:
                design = done[j]
    return design, list(done.values())


def _words(ratios) -> str:
    return ", ".join(f"{x:.3g}" for x in ratios)


# --------------------------------------------------------------------------- the case

def load_design_case(td: TransientDesign, case):
    """The case of the design ``td`` (its design, or unmet its best achievable): the structure
    file's ``case`` with the design's bed and container, the load kept (the DEM check is this
    case's own ``pdamper transient``), and the damper's rig drive beside it (its largest stroke
    in the check at the first mode's frequency: ``pdamper sweep`` characterises it there)."""
    from ..excitation import HarmonicDrive

    chk = td.design if td.design is not None else td.best
    s = case.drive
    stroke = float(chk.measured.get("largest_stroke_m") or chk.x_opt_m)
    rig = HarmonicDrive(stroke=round(max(stroke, 1e-4), 7), frequency=round(td.natural_frequency_hz, 4),
                        angle=s.angle, direction=s.direction)
    return dataclasses.replace(case, **_bed(case, chk.filling), rig=rig)


def load_design_text(td: TransientDesign, case, *, command: str, name: str = "design.toml") -> str:
    """The TOML text of :func:`load_design_case` with a header that says how it was designed and what
    its DEM check measured."""
    from .._version import __version__
    from ..config import dumps_case

    chk = td.design if td.design is not None else td.best
    aims = [f"peak ratio <= {td.target_peak_ratio:g}" if td.target_peak_ratio is not None else "",
            f"RMS ratio <= {td.target_rms_ratio:g}" if td.target_rms_ratio is not None else ""]
    lines = [f"pdamper design (pdamper {__version__}): a particle damper against a load in time and the structure it "
             "was designed for, in one case.", "",
             f"Designed by:  {command}",
             f"Aim:          the lightest filling whose coupled DEM transient meets {' and '.join(a for a in aims if a)} "
             f"(with / without the damper) at {', '.join(map(str, td.dofs))}",
             f"Load:         {td.load}",
             f"The damper:   {chk.particles} of {chk.max_particles} spheres ({chk.bed_mass_kg * 1e3:.4g} g) in a "
             f"{chk.container} (X_opt = {chk.x_opt_m * 1e3:.4g} mm)",
             f"DEM check:    peak ratio {_words(chk.peak_ratio)}, RMS ratio {_words(chk.rms_ratio)}: "
             + ("meets the targets" if chk.met else "does NOT meet the targets (the best achievable within the bounds)")]
    for reason in ([] if chk.met else td.reasons[1:]):
        lines.append(f"Why not:      {reason}")
    stem = name[:-5] if name.endswith(".toml") else name
    lines += ["", "[structure] and [load] are the structure file's: `pdamper transient` runs this case and gives the "
              "DEM check's numbers:", "", f"  pdamper transient {name} --plot {stem}_transient.png", ""]
    return "".join(f"# {line}".rstrip() + "\n" for line in lines) + "\n" + dumps_case(load_design_case(td, case),
                                                                                      name=name)
