"""The robust design against a load in time: the lightest filling whose targets hold in a given
share of what may happen (an ensemble over the unknowns: :mod:`pdamper.studies.ensemble`).

The designer's question: "the frame may be 5 % softer than its model, the friction anywhere from
0.05 to 0.2, the record 30 % larger: which damper still cuts the peak by 30 % in 90 % of that?"
Four steps, each reusing what the nominal design (:mod:`.transient`) and the ensembles have:

1. **The candidates** and their screen, as :func:`~pdamper.design.transient.design_for_load` has
   them, but **screened at every sample** (:func:`robust_screen`): the same N Latin hypercube
   samples of the unknowns (:func:`pdamper.studies.unknowns.sample`) set into the structure file's
   case, each sample's structure and load screened by the closed-form fields in time; a
   candidate's *screened share* is the share of samples where it is expected to meet every target.
   The screen sees what changes the structure and the load (stiffness, mass, damping, the record
   and its scale); it does not see friction, restitution, the tilt or the seed, which only the DEM
   does.
2. **The DEM ensembles** (:func:`~pdamper.studies.ensemble.run_ensemble`, a transient study): the
   lightest candidate whose screened share, corrected by what the ensembles so far measured,
   reaches ``robust`` runs at **the same samples** (common random numbers: every candidate meets
   the same frames, frictions and records, so their shares differ by the damper, not by the
   draw); at most ``checks`` ensembles. The correction is per sample: the last ensemble's DEM
   ratio over the screen's at that sample (a miss raises the bar for the next candidate; a
   candidate that did better in the DEM than the screen expected lowers it, and a lighter one is
   tried while ``checks`` allow).
3. **The share** of an ensemble (:func:`~pdamper.studies.ensemble.summarize`): the samples whose
   ratios meet every target (at every dof judged; the damper point's without ``dofs``:
   :func:`~pdamper.studies.ensemble.damper_point`), with its Wilson interval; the design is the
   lightest checked whose share is at least ``robust`` (:class:`RobustDesign`, ``met``). A share
   is decidable from ``1 / (1 - robust)`` samples on (:func:`decidable_samples`: one sample may
   miss; fewer are refused), and is a point estimate, not a bound, until every sample meeting
   would put the interval's low end above ``robust`` (said in ``warnings``).
4. **Unmet**: the best share reached, with the unknowns that move the missed ratio most
   (Spearman's rho over the samples, :func:`pdamper.analysis.ensemble.rank_importance`): which
   unknown drives the failures.

Every candidate's ensemble is a store of its own under one folder (``store``,
``<particles>of<max>-<length>mm``): a rerun resumes each from the samples it finished.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..errors import InputError, shown
from .names import name
from .transient import CheckedBed, LoadDesign, _candidate_case, _lightest_first, _setup, screen_candidates

__all__ = ["RobustCheck", "RobustDesign", "design_robust", "robust_screen", "decidable_samples", "robust_design_text",
           "DESIGN_KEYS"]

#: The keys the design chooses (the bed and its container's size): not unknowns of a robust design.
DESIGN_KEYS = ("particles.count", "particles.radius", "particles.density", "container.length", "container.width",
               "container.height", "container.radius", "container.shape")


@dataclass(frozen=True, kw_only=True)
class RobustCheck(CheckedBed):
    """One candidate's DEM ensemble (:func:`design_robust`), SI units: its bed
    (:class:`~pdamper.design.transient.CheckedBed`; ``summary`` the ensemble's,
    :func:`~pdamper.studies.ensemble.summarize`); ``met_samples`` of ``samples`` meet every target
    (``failed`` of them failed numerically and count as not meeting), the ``share`` with its Wilson
    interval ``low`` .. ``high`` at ``confidence``; ``met``: the share is at least the design's
    ``robust``; ``screen_share`` what the screen over the samples (corrected) expected;
    ``peak_ratio`` / ``rms_ratio`` the percentiles 5, 50, 95 over the samples (``{"p05", "p50",
    "p95"}``, lists per dof judged); ``shares`` each target's own share; ``drivers`` the unknowns
    that move the ratio that missed most (``{"key", "rho", "ratio"}``, largest ``|rho|`` first);
    ``store`` its ensemble's folder, ``at_damper`` judged at the damper point."""

    samples: int
    met_samples: int
    failed: int
    share: float
    low: float
    high: float
    confidence: float
    met: bool
    screen_share: float
    peak_ratio: dict | None
    rms_ratio: dict | None
    shares: dict
    drivers: list
    store: str
    at_damper: bool = False

    def dataset(self):
        """The candidate's ensemble (its store's dataset, nothing run), judged where the design
        judged it (``at_damper``: the damper point's ratios,
        :func:`~pdamper.studies.ensemble.damper_point`): for the figures of
        :mod:`pdamper.plotting.ensemble`."""
        from ..studies.ensemble import damper_point, open_ensemble

        ds = open_ensemble(self.store)
        return damper_point(ds) if self.at_damper else ds


@dataclass(frozen=True, kw_only=True)
class RobustDesign(LoadDesign):
    """The robust design (:func:`design_robust`; the fields of
    :class:`~pdamper.design.transient.LoadDesign`): ``met`` (a candidate's ensemble meets the
    targets in at least ``robust`` of its samples), ``design`` the lightest such (a
    :class:`RobustCheck`, None when unmet), ``best`` the design or, unmet, the candidate with the
    largest share (the best achievable), every ensemble in the order run (``checks``), what the
    screen over the samples found (``screen_met`` of the ``candidates`` expected to reach the
    share), the ensemble (``samples``, ``sample_seed``, ``unknowns``, ``store``)."""

    robust: float
    samples: int
    sample_seed: int
    unknowns: list
    store: str

    @property
    def chosen(self) -> RobustCheck | None:
        """The design, or unmet the best achievable."""
        return self.design if self.met else self.best

    def to_dict(self) -> dict:
        """Every field, the ensembles as dicts (JSON); at the top level the chosen candidate's (the
        design's, unmet the best achievable's) ``share``, ``interval`` [low, high] and per-dof
        ``peak_ratio`` / ``rms_ratio`` percentiles."""
        out = {k: getattr(self, k) for k in ("met", "robust", "target_peak_ratio", "target_rms_ratio", "dofs",
                                             "candidates", "screen_met", "reasons", "samples", "sample_seed",
                                             "unknowns", "store", "load", "natural_frequency_hz",
                                             "mass_at_damper_kg", "search", "warnings")}
        c = self.chosen
        out["design"] = self.design.to_dict() if self.design is not None else None
        out["best_achievable"] = self.best.to_dict() if self.best is not None and not self.met else None
        out["share"] = c.share if c is not None else None
        out["interval"] = [c.low, c.high] if c is not None else None
        out["confidence"] = c.confidence if c is not None else None
        out["peak_ratio"] = c.peak_ratio if c is not None else None
        out["rms_ratio"] = c.rms_ratio if c is not None else None
        out["checks"] = [k.to_dict() for k in self.checks]
        return out


# --------------------------------------------------------------------------- the ensemble's size

def decidable_samples(robust: float) -> int:
    """The fewest samples at which a share of ``robust`` (0 < robust <= 1) is told from "every
    sample": at least one sample may miss (N (1 - robust) >= 1); 1 for ``robust`` = 1."""
    if robust >= 1.0:
        return 1
    return int(math.ceil(1.0 / (1.0 - robust) - 1e-6))


def _check_ensemble(robust, samples: int, confidence: float) -> list:
    """Refuse a ``robust`` outside (0, 1] or ``samples`` too few to decide it; the warnings of a
    share whose interval stays wide even when every sample meets the targets."""
    from scipy.stats import norm

    from ..analysis.ensemble import share_meeting

    if isinstance(robust, bool) or not isinstance(robust, (int, float)) or not 0 < robust <= 1:
        raise InputError(f"{name('robust')} = {shown(robust)}: give the share of the samples in which the targets must "
                         "hold, above 0 and at most 1 (e.g. 0.9: in 90 % of them)")
    if isinstance(samples, bool) or not isinstance(samples, int) or samples < 1:
        raise InputError(f"{name('samples')} = {shown(samples)}: give the number of samples of the ensemble, >= 1 "
                         "(e.g. 32)")
    need = decidable_samples(robust)
    k = int(math.ceil(robust * samples - 1e-9))
    at = share_meeting(np.r_[np.zeros(k), np.ones(samples - k)], 0.5, confidence=confidence)
    if samples < need:
        raise InputError(f"{name('samples')} = {samples} cannot decide a share of {100 * robust:.3g} %: the share "
                         f"moves in steps of {100 / samples:.3g} %, so only every sample meeting the targets would "
                         f"do, and the {100 * confidence:.0f} % interval of {k} of {samples} is {100 * at['low']:.3g}-"
                         f"{100 * at['high']:.3g} %; give at least {need} samples (or {name('robust')} 1: every "
                         "sample)")
    every = share_meeting(np.zeros(samples), 0.5, confidence=confidence)
    if every["low"] < robust:
        # every sample meeting: Wilson's interval starts at n / (n + z^2), above robust from n >= z^2 r / (1 - r)
        z2 = float(norm.ppf(0.5 + confidence / 2)) ** 2
        bound = (f"{int(math.ceil(z2 * robust / (1.0 - robust) - 1e-9))} samples all meeting would bound it"
                 if robust < 1 else "no finite ensemble bounds a share of 100 %")
        return [f"with {samples} samples even every one meeting the targets gives a share whose "
                f"{100 * confidence:.0f} % interval starts at {100 * every['low']:.3g} %: a share of "
                f"{100 * robust:.3g} % is a point estimate here, not a bound ({bound})"]
    return []


def _unknowns(unknowns):
    """The :class:`~pdamper.studies.unknowns.Unknowns` of ``unknowns`` (or its file), none of them
    a key the design chooses."""
    from ..studies.unknowns import Unknowns

    u = Unknowns.read(unknowns) if isinstance(unknowns, (str, Path)) else (
        unknowns if isinstance(unknowns, Unknowns) else Unknowns(tuple(unknowns)))
    chosen = [k for k in u.keys if k in DESIGN_KEYS]
    if chosen:
        raise InputError(f"{name('unknowns')}: {', '.join(chosen)} is what the design chooses (the bed and its "
                         "container), not an unknown of the world; leave it out of the unknowns")
    return u


# --------------------------------------------------------------------------- the screen over the samples

def robust_screen(case, cands: list, unknowns, samples: int, *, seed: int = 0, dofs=None, kappa: float = 1.0,
                  progress: bool | None = None):
    """The screen (:func:`~pdamper.design.transient.screen_candidates`) of the candidates ``cands``
    at each of the ``samples`` Latin hypercube samples of ``unknowns`` (seeded by ``seed``: the
    ensembles' own), each sample's values set into the structure file's ``case``
    (:func:`~pdamper.studies.unknowns.sample_case`): ``(peak_ratio, rms_ratio)`` arrays
    [samples, candidates, dofs judged]."""
    from ..studies._progress import progress_bar, show_progress
    from ..studies.unknowns import sample, sample_case

    points = sample(unknowns, samples, seed).points()
    peaks, rms = [], []
    bar = progress_bar(total=len(points), unit="sample", desc="screen", disable=not show_progress(progress),
                       dynamic_ncols=True)
    try:
        for i, values in enumerate(points):
            with warnings.catch_warnings():  # each sample's case read again: its ensemble says what they warn of
                warnings.simplefilter("ignore")
                one = sample_case(case, values, label=f"sample {i}")
            sc = screen_candidates(one.running_drive, cands, dofs=dofs, kappa=kappa)
            peaks.append(sc.peak_ratio)
            rms.append(sc.rms_ratio)
            bar.update(1)
    finally:
        bar.close()
    return np.asarray(peaks, dtype=float), np.asarray(rms, dtype=float)


def _excess(peak, rms, targets) -> np.ndarray:
    """The worst ratio over its target over the last axis (the dofs; <= 1: met), NaN as not met."""
    tp, tr = targets
    parts = []
    if tp is not None:
        parts.append(np.max(peak / tp, axis=-1))
    if tr is not None:
        parts.append(np.max(rms / tr, axis=-1))
    ex = np.max(parts, axis=0)
    return np.where(np.isfinite(ex), ex, np.inf)


# --------------------------------------------------------------------------- a candidate's ensemble

def _store_name(cand) -> str:
    return f"{cand.particles}of{cand.max_particles}-{cand.geometry.drive_length * 1e3:.4g}mm"


def _share(s: dict, targets) -> dict:
    """The share of an ensemble's summary ``s`` that meets every target given."""
    t = s["targets"]
    if targets[0] is not None and targets[1] is not None:
        return t["both"]
    return t["peak_ratio"] if targets[0] is not None else t["rms_ratio"]


def _drivers(s: dict, targets, top: int = 3) -> list:
    """The unknowns that move the ratio whose target the most samples miss."""
    given = [q for q, t in zip(("peak_ratio", "rms_ratio"), targets) if t is not None]
    worst = min(given, key=lambda q: s["targets"][q]["share"])
    return [{"key": r["key"], "rho": r["rho"], "ratio": worst} for r in s["ranking"].get(worst, [])[:top]
            if math.isfinite(r["rho"])]


def _run_candidate(case, cand, unknowns, samples, folder, *, seed, dofs, targets, robust, radius, density, screen_share,
                   confidence, workers, scheduler, progress, history):
    from ..studies.ensemble import run_ensemble, summarize

    f1 = float(np.min(case.running_drive.mode_frequencies))
    one, fill = _candidate_case(case, cand, radius=radius, density=density, frequency=f1, stroke=cand.x_opt)
    path = Path(folder) / _store_name(cand)
    ds = run_ensemble(one, unknowns, samples, path, seed=seed, study="transient", dofs=dofs, workers=workers,
                      scheduler=scheduler, progress=progress, history=history)
    if dofs is None:  # judged at the damper point, as the nominal design judges it
        from ..studies.ensemble import damper_point

        ds = damper_point(ds)
    s = summarize(ds, target_peak_ratio=targets[0], target_rms_ratio=targets[1], confidence=confidence)
    sh = _share(s, targets)
    check = RobustCheck(**CheckedBed.of(cand), samples=sh["samples"], met_samples=sh["met"],
                        failed=s["failed"], share=sh["share"], low=sh["low"], high=sh["high"],
                        confidence=sh["confidence"], met=bool(sh["share"] >= robust - 1e-12),
                        screen_share=float(screen_share), peak_ratio=s["peak_ratio"], rms_ratio=s["rms_ratio"],
                        shares={q: s["targets"][q]["share"] for q in ("peak_ratio", "rms_ratio") if q in s["targets"]},
                        drivers=_drivers(s, targets), store=str(path), at_damper=dofs is None, summary=s,
                        filling=fill)
    dem = tuple(ds[q].transpose("sample", "dof").values for q in ("peak_ratio", "rms_ratio"))
    return check, dem, ds


# --------------------------------------------------------------------------- the design

def design_robust(case, unknowns, *, robust: float = 0.9, samples: int = 32, sample_seed: int = 0, store,
                  target_peak_ratio: float | None = None, target_rms_ratio: float | None = None, dofs=None,
                  shape: str | None = None, sizes: dict | None = None, sphere_radius: float | None = None,
                  density: float | None = None, length: float | None = None, length_range=None, particles=None,
                  max_bed_mass: float | None = None, max_mass_ratio: float | None = None, checks: int = 3,
                  kappa: float = 1.0, confidence: float | None = None, workers: int | None = None,
                  scheduler: str | None = None, progress: bool | None = None,
                  history: str | None = None) -> RobustDesign:
    """The lightest filling whose targets hold in at least ``robust`` of an ensemble over
    ``unknowns`` (module docstring): ``case`` a structure file with a ``[load]``
    (:func:`~pdamper.design.case.load_structure`), ``unknowns`` an
    :class:`~pdamper.studies.unknowns.Unknowns` or the path of its file (no key the design chooses:
    :data:`DESIGN_KEYS`), ``samples`` Latin hypercube samples seeded by ``sample_seed``, every
    candidate at the same ones; the targets, dofs, container and bounds as
    :func:`~pdamper.design.transient.design_for_load` takes them; at most ``checks`` DEM ensembles,
    each a store under the folder ``store`` (a rerun resumes them). The share's interval is Wilson's
    at ``confidence`` (default :data:`pdamper.analysis.ensemble.CONFIDENCE`). ``workers`` local
    processes (default all cores) or a Dask ``scheduler``; ``progress`` the bars (None: on a
    terminal).

    The ensembles run in worker processes: in a script, call it under ``if __name__ ==
    "__main__":``.
    """
    from ..analysis.ensemble import CONFIDENCE

    confidence = CONFIDENCE if confidence is None else float(confidence)
    said = _check_ensemble(robust, samples, confidence)
    if target_peak_ratio is None and target_rms_ratio is None:
        raise InputError(f"{name('robust')} is the share of the samples in which the targets hold: give "
                         f"{name('target_peak_ratio')} and/or {name('target_rms_ratio')} with it (e.g. 0.7 and 0.6)")
    u = _unknowns(unknowns)
    setup = _setup(case, target_peak_ratio=target_peak_ratio, target_rms_ratio=target_rms_ratio, dofs=dofs,
                   shape=shape, sizes=sizes, sphere_radius=sphere_radius, density=density, length=length,
                   length_range=length_range, particles=particles, max_bed_mass=max_bed_mass,
                   max_mass_ratio=max_mass_ratio, checks=checks)
    s, targets, cands = setup.structure, setup.targets, setup.cands
    from ..studies.suite import is_suite

    if is_suite(case):
        raise InputError("a robust design over a suite of records: make the record an unknown instead, [[unknown]] "
                         "key = \"load.file\", distribution = \"choice\", values = [the suite's files], and give "
                         "[load] one file")
    sp, sr = robust_screen(case, cands, u, samples, seed=sample_seed, dofs=dofs, kappa=kappa, progress=progress)
    mass = np.array([c.bed_mass for c in cands])
    bias = np.ones((samples, 2))   # per sample: the last ensemble's DEM ratio over the screen's (peak, RMS)

    def excess():
        """The worst ratio over its target [samples, candidates] the screen expects (corrected)."""
        return _excess(sp * bias[:, 0][:, None, None], sr * bias[:, 1][:, None, None], targets)

    def screened():
        """The share of the samples each candidate is expected to meet the targets in (corrected)."""
        return np.mean(excess() <= 1.0, axis=0)

    expected = {"share": screened()}    # the screened shares, again after each ensemble's correction
    screen_met = int(np.sum(expected["share"] >= robust - 1e-12))

    def run(j):
        chk, dem, _ = _run_candidate(case, cands[j], u, samples, store, seed=sample_seed, dofs=dofs, targets=targets,
                                     robust=robust, radius=setup.radius, density=setup.density,
                                     screen_share=expected["share"][j], confidence=confidence, workers=workers,
                                     scheduler=scheduler, progress=progress, history=history)
        for i, (d, scr) in enumerate(((dem[0], sp[:, j]), (dem[1], sr[:, j]))):
            with np.errstate(divide="ignore", invalid="ignore"):
                ratio = np.max(d / scr, axis=1)
            ok = np.isfinite(ratio)
            bias[ok, i] = ratio[ok]
        expected["share"] = screened()
        return chk

    def nearest():
        """The candidates by their screened share, ties by their mean excess over the samples."""
        ex = excess()
        closest = np.mean(np.where(np.isfinite(ex), ex, 1e9), axis=0)
        return np.lexsort((mass, closest, -np.mean(ex <= 1.0, axis=0)))

    # after a met, on to a lighter one while the ensembles' correction expects one to reach the share too
    design, checked = _lightest_first(mass, lambda j: expected["share"][j] >= robust - 1e-12, nearest, run, checks,
                                     lighter_after_met=True)
    best = design if design is not None else max(checked, key=lambda c: (c.share, -c.bed_mass_kg))
    reasons = []
    if design is None:
        reasons.append(f"no filling within the bounds met the targets in {100 * robust:.3g} % of the {samples} samples "
                       f"({len(checked)} ensemble{'s' if len(checked) != 1 else ''} run; the screen over the samples "
                       f"expected {screen_met} of {len(cands)} candidates to); the best share: {_pct(best.share)} "
                       f"({best.met_samples} of {best.samples}, {100 * best.confidence:.0f} % interval "
                       f"{_pct(best.low)}-{_pct(best.high)}, Wilson) with {best.particles} "
                       f"sphere{'s' if best.particles != 1 else ''}, "
                       f"{best.bed_mass_kg * 1e3:.4g} g, in {best.length_m * 1e3:.4g} mm")
        if best.drivers:
            reasons.append(f"what drives the failures ({best.drivers[0]['ratio'].replace('_', ' ')}, Spearman rho over "
                           "the samples): " + ", ".join(f"{d['key']} {d['rho']:+.2f}" for d in best.drivers))
        if best.failed:
            reasons.append(f"{best.failed} sample(s) failed numerically and count as missing the targets "
                           f"(failed_message in {best.store}/results.nc)")
    if len(s.mode_frequencies) > 1:
        said.append("the screen's damper acts at the first mode's frequency; the DEM ensembles hold every mode")
    return RobustDesign(met=design is not None, robust=float(robust), target_peak_ratio=target_peak_ratio,
                        target_rms_ratio=target_rms_ratio, dofs=setup.labels, design=design, best=best,
                        checks=checked, candidates=len(cands), screen_met=screen_met, reasons=reasons,
                        samples=int(samples), sample_seed=int(sample_seed), unknowns=u.to_list(), store=str(store),
                        load=s.load.describe(), natural_frequency_hz=float(np.min(s.mode_frequencies)),
                        mass_at_damper_kg=setup.mass_at_damper, search=setup.search(checks), warnings=said)


def _pct(x: float) -> str:
    return f"{100 * x:.3g} %"


# --------------------------------------------------------------------------- the case

def robust_design_text(rd: RobustDesign, case, *, command: str, name: str = "design.toml",
                       uncertain: str = "U.toml") -> str:
    """The TOML text of the robust design ``rd`` (its design, or unmet its best achievable): the
    structure file's ``case`` with its bed and container, the ``[structure]`` and ``[load]`` kept,
    with a header that says how it was designed and what share of the samples it met the targets in.
    It is the base case of the design's ensemble: ``pdamper transient NAME --uncertain U.toml
    --samples N --store ITS_STORE`` (``uncertain`` the unknowns' file as the header names it) reads
    that ensemble back, nothing computed again."""
    import dataclasses

    from .._version import __version__
    from ..config import dumps_case
    from .case import _bed

    c = rd.chosen
    aims = [f"peak ratio <= {rd.target_peak_ratio:g}" if rd.target_peak_ratio is not None else "",
            f"RMS ratio <= {rd.target_rms_ratio:g}" if rd.target_rms_ratio is not None else ""]
    keys = ", ".join(u["key"] for u in rd.unknowns)
    lines = [f"pdamper design (pdamper {__version__}): a robust particle damper against a load in time and the "
             "structure it was designed for, in one case.", "",
             f"Designed by:  {command}",
             "Aim:          the lightest filling whose coupled DEM transient meets "
             f"{' and '.join(a for a in aims if a)} (with / without the damper) at {', '.join(map(str, rd.dofs))} "
             f"in at least {100 * rd.robust:.3g} % of {rd.samples} Latin hypercube samples (seed {rd.sample_seed}) "
             f"of the unknowns {keys}",
             f"Load:         {rd.load}",
             f"The damper:   {c.particles} of {c.max_particles} spheres ({c.bed_mass_kg * 1e3:.4g} g) in a "
             f"{c.container} (X_opt = {c.x_opt_m * 1e3:.4g} mm)",
             f"Ensemble:     meets the targets in {c.met_samples} of {c.samples} samples: {_pct(c.share)} "
             f"({100 * c.confidence:.0f} % interval {_pct(c.low)}-{_pct(c.high)}, Wilson): "
             + ("robust" if c.met else f"does NOT reach {100 * rd.robust:.3g} % (the best share within the bounds)"),
             f"Its samples:  {c.store}"]
    for reason in ([] if c.met else rd.reasons[1:]):
        lines.append(f"Why not:      {reason}")
    seed = f" --sample-seed {rd.sample_seed}" if rd.sample_seed else ""
    lines += ["", "[structure] and [load] are the structure file's, at their nominal values: `pdamper transient` runs "
              "this case; it is the base of the design's ensemble, which this reads back (the same case at the same "
              "samples: nothing computed again):", "",
              f"  pdamper transient {name} --uncertain {uncertain} --samples {rd.samples}{seed} --store {c.store}", ""]
    written = dataclasses.replace(case, **_bed(case, c.filling))
    return "".join(f"# {line}".rstrip() + "\n" for line in lines) + "\n" + dumps_case(written, name=name)
