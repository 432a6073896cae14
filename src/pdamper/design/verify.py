"""The verification: the design's damper in a short DEM sweep, and the verdict on the design.

The laws the design rests on are the paper's; a real bed may dissipate less (it sways instead of
rolling close above X_opt). The check runs the design's damper alone on its rig (its bed and
container, driven harmonically: :func:`rig_case`) at strokes around the operating stroke, a few
seeds each (:func:`rig_sweep`, the sweep executor of :mod:`pdamper.studies`), and puts the DEM's
eta* into the design's energy balance in place of the law's (:func:`judge_verification`).

- :func:`verify_design` -- a design for a structure: the strokes 0.85-1.15 times its operating
  stroke at its resonance, the verdict as a :class:`Verification`;
- :func:`verify_filling` -- a filling for a stroke: 0.9, 1, 1.1 and 1.25 times the stroke, the DEM's
  eta* beside the laws' (a :class:`FillingCheck`).

Another load (a load in time) or several dampers add a judge of their own over the same
measurement (:func:`rig_sweep`'s :class:`RigSweep`).
"""

from __future__ import annotations

import dataclasses
import math
import tempfile
from dataclasses import asdict, dataclass

from .. import theory as th
from ..errors import InputError
from ..theory.fields import closed_form_fields
from .case import _bed
from .filling import Design
from .names import name
from .search import StructureDesign

__all__ = ["verify_design", "verify_filling", "Verification", "FillingCheck", "RigSweep", "rig_case", "rig_sweep",
           "verify_factors", "judge_verification", "ROLLING_MODE", "VERIFY_REACH"]


def rig_case(case, d: Design, *, stroke: float, frequency: float, cycles: float, drop_cycles: int):
    """The damper of design ``d`` alone on its rig: ``case`` (its materials, contact, numerics)
    with the design's bed and container (:func:`pdamper.design.case.design_case`'s), driven
    harmonically with ``stroke`` [m] at ``frequency`` [Hz] for ``cycles``, ``drop_cycles`` dropped."""
    from ..excitation import HarmonicDrive

    return dataclasses.replace(case, **_bed(case, d), drive=HarmonicDrive(stroke=stroke, frequency=frequency),
                               cycles=cycles, drop_cycles=drop_cycles)


@dataclass(frozen=True, kw_only=True)
class RigSweep:
    """What a DEM sweep of a damper on its rig measured: per stroke [m] (ascending), eta* (mean over
    the seeds, a failed case left out) and the majority motion mode ("" where none was classified);
    ``eta_star_seeds`` per stroke and seed."""

    strokes_m: list
    eta_star_mean: list
    modes: list
    eta_star_seeds: list
    seeds: list


def rig_sweep(base, strokes, *, seeds, workers: int | None = None, progress: bool | None = None) -> RigSweep:
    """The DEM sweep of the rig case ``base`` (:func:`rig_case`) over ``strokes`` [m] and ``seeds``
    (:func:`pdamper.studies.run_sweep` into a store that is deleted after it): ``workers`` local
    processes (None: all cores), ``progress`` its bar (None: on a terminal)."""
    import numpy as np

    from ..analysis.modes import majority_mode
    from ..studies import SweepSpec, run_sweep

    spec = SweepSpec(base=base, strokes=tuple(strokes), seeds=tuple(seeds))
    with tempfile.TemporaryDirectory(prefix="pdamper-design-") as tmp:
        ds = run_sweep(spec, f"{tmp}/store", workers=workers, progress=progress)
        eta = ds.eta_star.mean("seed", skipna=True).values
        xs = ds.stroke.values
        modes = ([majority_mode(ds["mode"].sel(stroke=x).values.ravel())[0] for x in xs] if "mode" in ds
                 else [""] * len(xs))
        seeded = np.asarray(ds.eta_star.values).tolist()
    return RigSweep(strokes_m=xs.tolist(), eta_star_mean=eta.tolist(), modes=modes, eta_star_seeds=seeded,
                    seeds=list(spec.seeds))


@dataclass(frozen=True, kw_only=True)
class FillingCheck:
    """The DEM check of a filling for a stroke (:func:`verify_filling`): per stroke [m], eta* of the
    DEM (mean over ``seeds``) and of the paper's laws, ``cycles`` a case."""

    strokes_m: list
    eta_star_mean: list
    seeds: list
    cycles: float
    eta_theory: list

    def to_dict(self) -> dict:
        """Every field (for JSON)."""
        return asdict(self)


def verify_filling(d: Design, *, cycles: int = 8, workers: int | None = None,
                   progress: bool | None = None) -> FillingCheck:
    """A short DEM sweep of the filling ``d`` (:func:`~pdamper.design.filling.design_filling`) at
    0.9, 1, 1.1 and 1.25 times its stroke, 2 seeds, ``cycles`` a case (the first 2 dropped): the
    paper's 5 mm steel spheres' material at the design's density, the container at the paper's
    0.1 deg tilt (the design's tilt as its pitch).

    ``workers``: local processes (None: all cores); ``progress``: the sweep's bar (None: on a terminal)."""
    import numpy as np

    from ..excitation import HarmonicDrive
    from ..materials import STEEL_S235
    from ..params import Case, Container, ParticleSet

    paper = np.radians(0.1)
    tilt = (paper, paper, d.tilt_rad if d.tilt_rad is not None else paper)  # the given tilt as a pitch
    paper_case = Case(particles=(ParticleSet(count=d.particles, radius=d.sphere_radius_m, material=STEEL_S235),),
                      container=Container(geometry=d.container_geometry(), tilt=tilt),
                      drive=HarmonicDrive(stroke=d.stroke_m, frequency=d.frequency_hz))
    base = rig_case(paper_case, d, stroke=d.stroke_m, frequency=d.frequency_hz, cycles=cycles, drop_cycles=2)
    got = rig_sweep(base, d.stroke_m * np.array([0.9, 1.0, 1.1, 1.25]), seeds=(0, 1), workers=workers,
                    progress=progress)
    return FillingCheck(strokes_m=got.strokes_m, eta_star_mean=got.eta_star_mean, seeds=got.seeds, cycles=cycles,
                        eta_theory=[float(th.eta_theory(x, d.clearance_m)) for x in got.strokes_m])


@dataclass(frozen=True, kw_only=True)
class Verification:
    """The verdict of a DEM check of a design for a structure (:func:`verify_design`,
    :func:`judge_verification`), with its numbers (SI): per checked stroke (ascending) the DEM's
    and the law's eta*, s = X/X_opt, the majority motion mode and the force that holds the damper
    there; the design's promise [m] and the DEM's amplitude at the damper (``amplitude_damper_dem_m``
    the estimate, ``amplitude_damper_bound_m`` the bound; None where not found) and their ratios to
    the bare amplitude; ``verdict`` (``"pass"``, ``"fails the target"``, ``"move the filling"``,
    ``"no verdict"``), ``move`` (what to try) and ``reason`` in words; the seeds, the cycles a case
    and eta* per stroke and seed."""

    strokes_m: list
    eta_star_dem: list
    eta_star_law: list
    stroke_over_x_opt: list
    modes: list
    force_required_N: list
    target_ratio: float | None
    promise_m: float
    amplitude_damper_dem_m: float | None
    amplitude_damper_bound_m: float | None
    ratio_dem: float | None
    ratio_bound: float | None
    operating_stroke: str
    verdict: str
    move: str
    reason: str
    seeds: list
    cycles: float
    eta_star_seeds: list

    @property
    def passed(self) -> bool:
        """Whether the design passed its check."""
        return self.verdict == "pass"

    def to_dict(self) -> dict:
        """Every field (for JSON)."""
        return asdict(self)


def verify_design(sd: StructureDesign, case, *, cycles: int = 8, strokes: int = 3, seeds: int = 2,
                  workers: int | None = None, progress: bool | None = None) -> Verification:
    """The DEM check of the design ``sd`` for the structure of ``case`` (the structure file's, whose
    materials, contact and numerics the damper keeps: :func:`~pdamper.design.case.load_structure`):
    the design's damper on its rig (:func:`rig_case`) at its resonance, ``strokes`` strokes around
    the operating stroke (:func:`verify_factors`), ``seeds`` seeds each, ``cycles`` a case (2
    dropped, 1 below 5 cycles), and the verdict (:func:`judge_verification`).

    ``workers``: local processes (None: all cores); ``progress``: the sweep's bar (None: on a terminal).
    A sweep starts worker processes: call it under ``if __name__ == "__main__":`` in a script::

        from pdamper.design import design_for_case, load_structure, verify_design

        if __name__ == "__main__":
            case = load_structure("examples/frame_3hz.toml")
            v = verify_design(design_for_case(case, force=1.5), case, cycles=8, strokes=3, seeds=2)
            print(v.verdict, v.reason)
    """
    # fewer than 5 cycles drop 1: the record's whole cycles are one fewer than asked at an odd frequency
    base = rig_case(case, sd.filling, stroke=sd.damper_stroke_m, frequency=sd.frequency_hz, cycles=cycles,
                    drop_cycles=2 if cycles >= 5 else 1)
    got = rig_sweep(base, [sd.damper_stroke_m * f for f in verify_factors(strokes)], seeds=range(seeds),
                    workers=workers, progress=progress)
    verdict = judge_verification(sd, got.strokes_m, got.eta_star_mean, got.modes)
    return Verification(**verdict, seeds=got.seeds, cycles=cycles, eta_star_seeds=got.eta_star_seeds)


def verify_factors(n: int):
    """Strokes of the DEM check as factors of the operating stroke: 1 alone, 0.85 and 1 for two,
    else ``n`` from 0.85 to 1.15 (the operating stroke among them for odd ``n``).

    >>> verify_factors(2), verify_factors(3)
    ([0.85, 1.0], [0.85, 1.0, 1.15])
    """
    import numpy as np

    if n < 1:
        raise InputError(f"{name('strokes')} = {n}: give at least 1 (e.g. 3)")
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
                "move": f"run the check with more {name('cycles')}"}
    xv, nv = xs[ok], need[ok]
    mv = [m for m, good in zip(modes, ok) if good]
    more = "add spheres (a smaller clearance puts the stroke further above X_opt, more bed dissipates more): try " + (
        other(n + 1) or "a shorter container")
    rolls_from = next((j for j in range(len(xv)) if all(m == ROLLING_MODE for m in mv[j:])), None)
    if rolls_from is not None and rolls_from > 0:
        margin = math.ceil(10 * xv[rolls_from] / fill.x_opt_m - 1e-9) / 10
        more += (f"; or design again with {name('margin')} {margin:g} (the bed rolled from {xv[rolls_from] / fill.x_opt_m:.3g} "
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
