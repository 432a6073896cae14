"""Paper-level validation: run the studies behind each check and judge them.

The checks, each against the paper's DEM (Fig. 4, 6, 7 and Sect. 6.1):

- Fig. 4, N_p = 36: peak eta* in [0.75, 1.05] at X in [10, 16] mm.
- Fig. 4, N_p = 44: peak eta* in [0.65, 1.05] at X in [3.5, 6] mm.
- Scattered branch: eta* < 0.5 for X < 0.5 X_opt (36 and 44).
- Rolling branch: |eta* - rolling law| <= 0.2 for X >= 2 X_opt (36 and 44).
- Friction: peak eta* orders mu = 0.01 > 0.1 > 1 and the peak stroke does not fall as mu grows.
- Tilt 3 deg about z, N_p = 44: eta* < 0.15 for X <= 3 mm.
- Tilt 3 deg, N_p = 36 (the paper's Sect. 6.2): about z, eta* < 0.1 for X <= 4 mm (the paper: ~0)
  and a rise to at least 0.25 by X = 8 mm (the paper: a sharp rise to ~0.5); about x, the largest
  eta* for 1 <= X <= 4 mm in [0.1, 0.5] (the paper: 0.1-0.5 instead of ~0); about y, the peak
  within 0.1 of the baseline's (the paper: negligible).
- E, rho, eps in 0.8 ... 0.95: peak eta* within 0.1 of the baseline (36 spheres).

Beyond the paper, :func:`run_vertical` compares a vertically driven two-layer bed with the bouncing
law (a separate section of the report, written by ``pdamper validate --part vertical``).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import theory
from ..errors import InputError
from .named import run_study
from .sweep import STROKE, stroke_grid

__all__ = ["Check", "run_validation", "evaluate_checks", "write_report", "run_vertical", "vertical_rows",
           "vertical_section", "write_section", "settled_clearance"]


@dataclass(frozen=True)
class Check:
    """One validation check: what, the expected band, the measured value, pass or fail."""

    name: str
    expected: str
    measured: str
    passed: bool


def _mean(ds, label):
    return ds.eta_star.sel(setting=label).mean("seed", skipna=True).values


def _peak(ds, label):
    m = _mean(ds, label)
    i = int(np.nanargmax(m))
    return float(m[i]), float(ds.stroke.values[i])


def run_validation(out, *, quick=False, seeds=1, fig4_seeds=None, workers=None, scheduler=None, progress=None,
                   overrides=None):
    """Run the studies (fig4 on the paper's 40 strokes, the others on 20; ``quick``: 12 strokes
    and 8 cycles everywhere) into ``out`` and return ``(checks, datasets, seconds)``.

    ``seeds`` initial states per stroke for every study; ``fig4_seeds`` (default: ``seeds``) for
    Fig. 4 alone, whose per-stroke checks judge the seed mean: near and above X_opt one seeded
    start can take another motion, so one seed is no fair test there. ``overrides``: config keys
    set in every study's settings (``pdamper validate --set``; :func:`~pdamper.studies.named.run_study`)."""
    if STROKE in (overrides or {}):
        raise InputError(f"override {STROKE} = {overrides[STROKE]}: the validation runs every study on the paper's "
                         "strokes (0.5 mm to 50 mm, 40 for Fig. 4 and 20 for the others; 12 when quick), which its "
                         "checks judge; leave the stroke out of the overrides (a study of your own strokes: "
                         "pdamper study NAME --strokes ...)")
    out = Path(out)
    t0 = time.perf_counter()
    kw = dict(seeds=tuple(range(seeds)), workers=workers, scheduler=scheduler, progress=progress,
              overrides=overrides)
    kw4 = {**kw, "seeds": tuple(range(fig4_seeds or seeds))}
    if quick:
        fine = coarse = tuple(stroke_grid(0.5e-3, 50e-3, 12))
        kw.update(cycles=8, drop_cycles=2)
        kw4.update(cycles=8, drop_cycles=2)
    else:
        fine, coarse = tuple(stroke_grid(0.5e-3, 50e-3, 40)), tuple(stroke_grid(0.5e-3, 50e-3, 20))
    ds = {
        "fig4": run_study("fig4", out / "fig4", strokes=fine, **kw4),
        "friction": run_study("friction", out / "friction", strokes=coarse, **kw),
        "tilt": run_study("tilt", out / "tilt", strokes=coarse, **kw),  # x, y, z; 36 and 44 spheres
        "modulus": run_study("modulus", out / "modulus", strokes=coarse, **kw),
        "density": run_study("density", out / "density", strokes=coarse, **kw),
        "restitution": run_study("restitution", out / "restitution", strokes=coarse,
                                 only=["eps = 0.8", "eps = 0.9", "eps = 0.95"], **kw),
    }
    return evaluate_checks(ds), ds, time.perf_counter() - t0


def evaluate_checks(ds: dict) -> list:
    """The checks of the module docstring on the study datasets ``ds`` (keys fig4, friction,
    tilt, modulus, density, restitution; each with a ``setting`` dimension as
    :func:`~pdamper.studies.named.run_study` returns)."""
    checks = []
    f4 = ds["fig4"]
    for label, n, (lo, hi), (xlo, xhi) in [("N_p = 36", 36, (0.75, 1.05), (10e-3, 16e-3)),
                                           ("N_p = 44", 44, (0.65, 1.05), (3.5e-3, 6e-3))]:
        eta, x = _peak(f4, label)
        checks.append(Check(f"Fig. 4, {n} spheres: peak", f"eta* in [{lo}, {hi}] at X in [{xlo * 1e3:g}, {xhi * 1e3:g}] mm",
                            f"eta* = {eta:.3f} at X = {x * 1e3:.3g} mm", lo <= eta <= hi and xlo <= x <= xhi))
        h = float(f4.clearance.sel(setting=label))
        xo = float(theory.optimal_stroke(h))
        m = _mean(f4, label)
        xs = f4.stroke.values
        below = m[xs < 0.5 * xo]
        checks.append(Check(f"Fig. 4, {n} spheres: scattered branch", f"eta* < 0.5 for X < {0.5 * xo * 1e3:.3g} mm",
                            f"max eta* = {np.nanmax(below):.3f} ({below.size} strokes)", bool(np.nanmax(below) < 0.5)))
        above = xs >= 2 * xo
        dev = np.abs(m[above] - theory.eta_rolling(xs[above], h))
        checks.append(Check(f"Fig. 4, {n} spheres: rolling branch", f"abs(eta* - eq. (14)) <= 0.2 for X >= {2 * xo * 1e3:.3g} mm",
                            f"max deviation {np.nanmax(dev):.3f} ({dev.size} strokes)", bool(np.nanmax(dev) <= 0.2)))
    fr = ds["friction"]
    for n in (36, 44):
        peaks = [_peak(fr, f"{n}, mu = {mu:g}") for mu in (0.01, 0.1, 1.0)]
        etas = [p[0] for p in peaks]
        xs_ = [p[1] for p in peaks]
        ok = etas[0] > etas[1] > etas[2] and xs_[0] <= xs_[1] <= xs_[2]
        checks.append(Check(f"Friction, {n} spheres", "peak eta* mu=0.01 > 0.1 > 1; peak stroke rises with mu",
                            "peaks " + ", ".join(f"{e:.3f}@{x * 1e3:.3g}mm" for e, x in peaks), ok))
    tl = ds["tilt"]
    xs = tl.stroke.values
    m = _mean(tl, "44, 3 deg about z")[xs <= 3e-3]
    checks.append(Check("Tilt 3 deg about z, 44 spheres", "eta* < 0.15 for X <= 3 mm",
                        f"max eta* = {np.nanmax(m):.3f} ({m.size} strokes)", bool(np.nanmax(m) < 0.15)))
    checks += _tilt_36(tl)
    for study, base, others in [("modulus", "E = 208 GPa", ["E = 3 GPa", "E = 405 GPa"]),
                                ("density", "rho = 7900 kg/m3", ["rho = 1400 kg/m3", "rho = 19250 kg/m3"]),
                                ("restitution", "eps = 0.9", ["eps = 0.8", "eps = 0.95"])]:
        d = ds[study]
        b = _peak(d, base)[0]
        diffs = [abs(_peak(d, o)[0] - b) for o in others]
        checks.append(Check(f"Sensitivity: {study}", f"peak eta* within 0.1 of the baseline ({base})",
                            ", ".join(f"{o}: {_peak(d, o)[0]:.3f}" for o in others) + f"; baseline {b:.3f}",
                            max(diffs) <= 0.1))
    return checks


def _tilt_36(tl) -> list:
    """The paper's Sect. 6.2 in numbers for 36 spheres tilted 3 deg (see the module docstring)."""
    xs = tl.stroke.values

    def band(label, lo, hi):
        m = _mean(tl, label)[(xs >= lo - 1e-12) & (xs <= hi + 1e-12)]
        return float(np.nanmax(m)) if m.size else math.nan, m.size

    z_low, nz = band("36, 3 deg about z", 0.0, 4e-3)
    z_rise, nr = band("36, 3 deg about z", 4e-3, 8e-3)
    x_low, nx = band("36, 3 deg about x", 1e-3, 4e-3)
    y_peak, base_peak = _peak(tl, "36, 3 deg about y")[0], _peak(tl, "36, baseline 0.1 deg")[0]
    return [
        Check("Tilt 3 deg about z, 36 spheres: held", "eta* < 0.1 for X <= 4 mm (paper: ~0)",
              f"max eta* = {z_low:.3f} ({nz} strokes)", bool(z_low < 0.1)),
        Check("Tilt 3 deg about z, 36 spheres: rise", "max eta* >= 0.25 for 4 < X <= 8 mm (paper: a sharp rise to ~0.5)",
              f"max eta* = {z_rise:.3f} ({nr} strokes)", bool(z_rise >= 0.25)),
        Check("Tilt 3 deg about x, 36 spheres", "max eta* in [0.1, 0.5] for 1 <= X <= 4 mm (paper: 0.1-0.5, not ~0)",
              f"max eta* = {x_low:.3f} ({nx} strokes)", bool(0.1 <= x_low <= 0.5)),
        Check("Tilt 3 deg about y, 36 spheres", "peak eta* within 0.1 of the baseline (paper: negligible)",
              f"peak {y_peak:.3f}; baseline {base_peak:.3f}", bool(abs(y_peak - base_peak) <= 0.1)),
    ]


def write_report(path, checks, figures, command, seconds):
    """Write the Markdown report (docs/validation.md): the table, the figures, the command."""
    from .._version import __version__

    lines = ["# Validation against the paper", "",
             f"Produced by `{command}` (pdamper {__version__}, {time.strftime('%Y-%m-%d')}, "
             f"{seconds / 60:.1f} min on this machine). The unit-level physics checks run in "
             "the test suite; these are the paper-level ones.", "",
             f"**{sum(c.passed for c in checks)} of {len(checks)} checks pass.**", "",
             "| check | expected | measured | result |", "|---|---|---|---|"]
    lines += [f"| {c.name} | {c.expected} | {c.measured} | {'pass' if c.passed else '**FAIL**'} |" for c in checks]
    lines += ["", "## Figures", ""]
    for title, rel in figures:
        lines += [f"### {title}", "", f"![{title}]({rel})", ""]
    old = Path(path).read_text() if Path(path).exists() else ""
    Path(path).write_text("\n".join(lines) + "\n")
    if VERTICAL_BEGIN in old:  # the part beyond the paper (the vertical drive's section and its notes) stays
        with open(path, "a") as f:
            f.write("\n" + old[old.index(VERTICAL_BEGIN):])


# ------------------------------------------------------------------ the vertical drive

#: Markers of the vertical-drive section of the report (kept when the paper's part is rewritten).
VERTICAL_BEGIN, VERTICAL_END = "<!-- vertical drive: begin -->", "<!-- vertical drive: end -->"


def settled_clearance(case) -> float:
    """h [m]: the gap between the top of the settled bed and the lid, measured by letting the
    case's bed settle in the still container (its ``initial.settle_time``)."""
    from ..simulation import Simulation

    sim = Simulation(case, recorders=[])
    sim.settle()
    top = float(np.max(sim.bodies.position[:, 1] + sim.bodies.radius))
    lo, hi = case.container.geometry.bounding_box()
    return float(hi[1] - lo[1]) - top


def vertical_rows(ds, h: float, frequency: float, gravity: float) -> list:
    """Per stroke: X [m], the intensity Gamma = X Omega^2 / g, the DEM's eta* (seed mean, min, max)
    and the bouncing law's eta* (NaN below X_opt = h / pi)."""
    from ..theory.bouncing import eta_bouncing

    eta = ds.eta_star.isel(setting=0)
    rows = []
    for k, x in enumerate(ds.stroke.values):
        e = eta.isel(stroke=k).values
        rows.append({"stroke_m": float(x), "intensity": float(x * (2 * math.pi * frequency) ** 2 / gravity),
                     "eta_dem": float(np.nanmean(e)), "eta_min": float(np.nanmin(e)), "eta_max": float(np.nanmax(e)),
                     "eta_law": float(eta_bouncing(float(x), h)), "seeds": int(np.count_nonzero(np.isfinite(e)))})
    return rows


def run_vertical(out, *, seeds=2, quick=False, workers=None, scheduler=None, progress=None, overrides=None):
    """Run the study ``vertical`` into ``out`` and compare it with the bouncing law; returns
    ``(rows, h, case, dataset, seconds)`` (see :func:`vertical_rows`). ``overrides``: config keys
    set in the study's case (``pdamper validate --set``)."""
    from ..schema import replace
    from .named import load_study

    t0 = time.perf_counter()
    kw = dict(cycles=8, drop_cycles=3) if quick else {}
    strokes = tuple(stroke_grid(4e-3, 30e-3, 5)) if quick else None
    ds = run_study("vertical", Path(out) / "vertical", strokes=strokes, seeds=tuple(range(seeds)), workers=workers,
                   scheduler=scheduler, progress=progress, overrides=overrides, **kw)
    case = replace(load_study("vertical").settings[0][1], overrides or {})
    h = settled_clearance(case)
    rows = vertical_rows(ds, h, case.drive.frequency, case.gravity)
    # the cases' own simulation time (a resumed study has computed them before)
    return rows, h, case, ds, max(float(np.nansum(ds.wall_time.values)), time.perf_counter() - t0)


def vertical_section(rows, h: float, case, figure: str, command: str, seconds: float) -> str:
    """The report's section on the vertical drive (Markdown between :data:`VERTICAL_BEGIN` and
    :data:`VERTICAL_END`): the set-up, the table of DEM against the bouncing law, the figure."""
    from ..theory.bouncing import optimal_stroke_bouncing

    xo = float(optimal_stroke_bouncing(h))
    lines = [VERTICAL_BEGIN, "## Vertical drive: DEM against the bouncing law", "",
             f"Produced by `{command}` ({seconds / 60:.1f} min of simulation over the cases). Beyond the paper: "
             f"{case.n_particles} spheres of r = {case.particles[0].radius * 1e3:g} mm in two layers in a "
             f"{case.container.describe()}, driven vertically at f = {case.drive.frequency:g} Hz. The bouncing "
             "collect-and-collide law (`pdamper.theory.eta_bouncing`; Bannerman et al., Sack et al.) takes the "
             "bed as one block that leaves the floor at the container's largest velocity and hits the lid "
             "perfectly inelastically, without gravity; the seed paper's ref. [23] finds it valid under gravity "
             f"at high intensities. Its clearance h = {h * 1e3:.2f} mm is measured: the gap between the settled "
             f"bed's top and the lid. X_opt = h / pi = {xo * 1e3:.2f} mm.", "",
             "| X [mm] | Gamma = X Omega^2 / g | eta* DEM (seed mean) | seed range | eta* bouncing law | DEM - law |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        law = r["eta_law"]
        lines.append(f"| {r['stroke_m'] * 1e3:.3g} | {r['intensity']:.3g} | {r['eta_dem']:.3f} | "
                     f"{r['eta_min']:.3f} - {r['eta_max']:.3f} | "
                     + (f"{law:.3f} | {r['eta_dem'] - law:+.3f} |" if math.isfinite(law) else "- (X < X_opt) | |"))
    lines += ["", f"![vertical drive]({figure})", "", VERTICAL_END]
    return "\n".join(lines) + "\n"


def write_section(path, section: str) -> None:
    """Put ``section`` (delimited by its markers) into the report ``path``: in place of an
    earlier one, else at the end."""
    path = Path(path)
    text = path.read_text() if path.exists() else "# Validation against the paper\n"
    if VERTICAL_BEGIN in text and VERTICAL_END in text:
        a = text.index(VERTICAL_BEGIN)
        b = text.index(VERTICAL_END) + len(VERTICAL_END)
        text = text[:a] + section.rstrip("\n") + text[b:]
    else:
        text = text.rstrip("\n") + "\n\n" + section
    path.write_text(text)
