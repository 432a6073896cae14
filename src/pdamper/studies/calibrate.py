"""Calibration: the model parameters that make the DEM's η*(X) match a test campaign.

The search is a **response surface on sweep grids** (scipy's least squares for the surrogate),
not a gradient optimiser: the DEM's η* is a noisy function of its parameters (a seed changes η* by a
few hundredths near X_opt), so a gradient-based ``scipy.optimize.minimize`` chases the noise, and a
Gaussian-process search would need far more sequential evaluations than two rounds of parallel
cases. Here every DEM case of a round runs at once on the local cores or a Dask cluster, and each
round is an ordinary resumable sweep store (interrupt and re-run: only the missing cases run).

1. **Round 1**: each fitted key on a grid over its range (log-spaced where the range spans a decade
   or more, e.g. friction 0.01-1; else linear), crossed with the campaign's strokes and the seeds.
2. The misfit of a parameter point is
   ``chi2 = sum_i (eta_DEM(X_i) - eta_meas(X_i))^2 / (s_meas,i^2 + s_DEM,i^2)``
   over the campaign's strokes: ``eta_DEM`` is the mean over seeds, ``s_DEM`` its standard error
   (at least :data:`DEM_FLOOR`, the seed scatter of one seed), ``s_meas`` the measurement's error
   bar (at least :data:`MEAS_FLOOR`).
3. **Round 2**: a finer grid around the best point of round 1 (1.5 grid steps either side).
4. **The surrogate**: at each stroke the DEM's mean eta* over every evaluated point is fitted by a
   low-order polynomial in the (log-)parameters (cubic for one parameter, quadratic for more;
   numpy least squares), which smooths the seed scatter; its residual scatter joins the
   measurement error. The misfit of the smooth curves is minimised over the range (a fine grid
   and ``scipy.optimize.minimize``); the uncertainty is the profile ``Delta chi2 = 1`` about the
   minimum (1-D: where the smooth misfit crosses it; more: the covariance ``2 H^-1`` of its
   Hessian), scaled by the reduced ``chi2_min / dof`` when that exceeds 1.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..analysis.surrogate import poly_basis
from ..errors import InputError, shown

__all__ = ["FitParameter", "parse_fit", "calibrate", "Calibration", "DEM_FLOOR", "MEAS_FLOOR"]

#: Smallest standard error of the DEM's eta* at a stroke (the seed scatter of a single seed).
DEM_FLOOR = 0.02
#: Smallest measurement error of eta* at a stroke.
MEAS_FLOOR = 0.01


@dataclass(frozen=True)
class FitParameter:
    """A config key to fit over ``[low, high]`` (SI); ``log``: search its logarithm."""

    key: str
    low: float
    high: float
    log: bool

    def grid(self, n: int, lo=None, hi=None) -> np.ndarray:
        lo = self.low if lo is None else lo
        hi = self.high if hi is None else hi
        return np.geomspace(lo, hi, n) if self.log else np.linspace(lo, hi, n)

    def to_u(self, v):
        return np.log10(v) if self.log else np.asarray(v, dtype=float)

    def from_u(self, u):
        return 10.0 ** u if self.log else u


def parse_fit(text: str) -> FitParameter:
    """``KEY=LOW:HIGH[:log|:linear]`` with units as in a config file, e.g. ``contact.friction=0.01:1`` or
    ``container.tilt=0deg:3deg``. Log search where ``HIGH/LOW >= 10`` unless said."""
    from ..config import key_spec
    from ..units import parse_quantity

    key, sep, rng = str(text).partition("=")
    key = key.strip()
    parts = [p.strip() for p in rng.split(":")]
    if not sep or len(parts) not in (2, 3):
        raise InputError(f"--fit {shown(text)}: write KEY=LOW:HIGH, e.g. contact.friction=0.01:1")
    spec = key_spec(key)
    if spec.kind not in ("number", "whole") and spec.dimension is None:
        raise InputError(f"--fit {key}: only a number can be fitted")
    dim = spec.dimension or "dimensionless"
    lo = parse_quantity(parts[0], dim, name=f"--fit {key} (low)")
    hi = parse_quantity(parts[1], dim, name=f"--fit {key} (high)")
    if not lo < hi:
        raise InputError(f"--fit {shown(text)}: need LOW < HIGH")
    if len(parts) == 3:
        if parts[2] not in ("log", "linear"):
            raise InputError(f"--fit {shown(text)}: the spacing {shown(parts[2])} is not 'log' or 'linear'")
        log = parts[2] == "log"
    else:
        log = lo > 0 and hi / lo >= 10
    if log and lo <= 0:
        raise InputError(f"--fit {shown(text)}: a log search needs LOW > 0")
    return FitParameter(key=key, low=float(lo), high=float(hi), log=log)


@dataclass
class Calibration:
    """The result of :func:`calibrate` (SI units)."""

    best: dict
    uncertainty: dict
    misfit: float
    reduced_misfit: float
    rms_difference: float
    points: list = field(default_factory=list)      # [{key: value, ..., "misfit": chi2}, ...] every evaluated point
    strokes_m: list = field(default_factory=list)
    measured: list = field(default_factory=list)
    measured_error: list = field(default_factory=list)
    dem_at_best: list = field(default_factory=list)  # eta* of the evaluated point nearest the best
    convex: bool = True
    surrogate: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        def clean(v):
            if isinstance(v, dict):
                return {k: clean(x) for k, x in v.items()}
            if isinstance(v, (list, tuple)):
                return [clean(x) for x in v]
            if isinstance(v, (float, np.floating)):
                return float(v) if math.isfinite(v) else None
            return v
        return clean({"best": self.best, "uncertainty": self.uncertainty, "misfit": self.misfit,
                      "reduced_misfit": self.reduced_misfit, "rms_difference": self.rms_difference,
                      "convex": self.convex, "strokes_m": self.strokes_m, "measured": self.measured,
                      "measured_error": self.measured_error, "dem_at_best": self.dem_at_best, "points": self.points})


def _measured(campaign):
    """(strokes, mean eta*, its error) of a campaign dataset."""
    eta = campaign["eta_star"]
    if [d for d in eta.dims if d not in ("stroke", "seed")]:
        raise InputError("calibration against a campaign over stroke and frequency is not supported yet; "
                         "select one frequency first")
    e = eta.transpose("stroke", "seed").values
    err = campaign["eta_star_error"].transpose("stroke", "seed").values if "eta_star_error" in campaign else \
        np.full_like(e, np.nan)
    ok = np.isfinite(e).any(axis=1)
    strokes = campaign["stroke"].values[ok]
    mean = np.nanmean(e[ok], axis=1)
    n = np.isfinite(e[ok]).sum(axis=1)
    spread = np.where(n > 1, np.nanstd(np.where(np.isfinite(e[ok]), e[ok], np.nan), axis=1, ddof=0) / np.sqrt(n), 0)
    bar = np.sqrt(np.nanmean(np.where(np.isfinite(err[ok]), err[ok] ** 2, np.nan), axis=1)) / np.sqrt(n)
    s = np.fmax(np.fmax(np.nan_to_num(bar, nan=0.0), spread), MEAS_FLOOR)
    if strokes.size < 1:
        raise InputError("the campaign has no analysed record")
    return strokes.astype(float), mean, s


def _misfit(ds, fits, strokes, meas, s_meas):
    """chi2 of every parameter point of a round's dataset: [(values tuple, chi2, eta per stroke)]."""
    eta = ds["eta_star"]
    names = [f.key.rsplit(".", 1)[-1] for f in fits]
    out = []
    grids = [ds[n].values for n in names]
    for idx in np.ndindex(*[len(g) for g in grids]):
        sel = {n: g[i] for n, g, i in zip(names, grids, idx)}
        e = eta.sel(sel).transpose("stroke", "seed").values
        if not np.isfinite(e).any(axis=1).all():
            continue  # a failed case: this point is not judged
        n = np.isfinite(e).sum(axis=1)
        m = np.nanmean(e, axis=1)
        sd = np.where(n > 1, np.nanstd(e, axis=1, ddof=1) / np.sqrt(n), DEM_FLOOR) if e.shape[1] > 1 else \
            np.full(m.shape, DEM_FLOOR)
        sd = np.fmax(sd, DEM_FLOOR / np.sqrt(n))
        chi2 = float(np.sum((m - meas) ** 2 / (s_meas ** 2 + sd ** 2)))
        out.append((tuple(float(g[i]) for g, i in zip(grids, idx)), chi2, m))
    return out


def calibrate(campaign, base, fits, *, out, seeds=(0,), cycles=None, points=None, workers=None, scheduler=None,
              progress=None) -> Calibration:
    """Fit ``fits`` (:class:`FitParameter`) of the ``base`` case to the ``campaign`` dataset (see the
    module docstring); the DEM rounds are sweep stores under ``out`` (resumable)."""
    import dataclasses

    from .sweep import Axis, SweepSpec, run_sweep

    fits = list(fits)
    if not fits:
        raise InputError("give at least one parameter to fit, e.g. --fit contact.friction=0.01:1")
    if len({f.key for f in fits}) != len(fits):
        raise InputError("a key is fitted twice")
    strokes, meas, s_meas = _measured(campaign)
    if not base.drive.sweepable:
        raise InputError("the config must have a harmonic drive ([drive]): the DEM is run at the campaign's strokes")
    f_meas = float(campaign.attrs.get("frequency_hz", base.drive.frequency))
    if abs(f_meas - base.drive.frequency) > 5e-3 * f_meas:  # the rig's frequency, not the config's
        base = dataclasses.replace(base, drive=dataclasses.replace(base.drive, frequency=f_meas))
    if cycles is not None:
        base = dataclasses.replace(base, cycles=cycles)
    n = points or (7 if len(fits) == 1 else 5)
    out = Path(out)
    evaluated = []

    def run_round(k, grids):
        axes = [Axis(key=f.key, values=tuple(g), spacing="list") for f, g in zip(fits, grids)]
        spec = SweepSpec(base=base, axes=axes + [Axis(key="drive.stroke", values=tuple(strokes), spacing="list")],
                         seeds=seeds)
        ds = run_sweep(spec, out / f"round{k}", workers=workers, scheduler=scheduler, progress=progress, keep="none")
        return _misfit(ds, fits, strokes, meas, s_meas)

    evaluated += run_round(1, [f.grid(n) for f in fits])
    if not evaluated:
        raise InputError(f"every DEM case of round 1 failed; see the stores under {out / 'round1'}")
    best = min(evaluated, key=lambda r: r[1])
    grids2 = []
    for f, v in zip(fits, best[0]):
        u = float(f.to_u(v))
        step = (float(f.to_u(f.high)) - float(f.to_u(f.low))) / (n - 1)
        lo_u = max(u - 1.5 * step, float(f.to_u(f.low)))
        hi_u = min(u + 1.5 * step, float(f.to_u(f.high)))
        grids2.append(f.from_u(np.linspace(lo_u, hi_u, n)))
    evaluated += run_round(2, grids2)
    best = min(evaluated, key=lambda r: r[1])

    # the surrogate: eta*(u) per stroke as a polynomial in the (log-)parameters through every point
    us = np.array([[float(f.to_u(v)) for f, v in zip(fits, r[0])] for r in evaluated])
    etas = np.array([r[2] for r in evaluated])                     # (points, strokes)
    lo_u = np.array([float(f.to_u(f.low)) for f in fits])
    hi_u = np.array([float(f.to_u(f.high)) for f in fits])
    scale = (hi_u - lo_u) / (n - 1)
    z = (us - lo_u) / (hi_u - lo_u)                                  # 0..1 on the range
    basis = poly_basis(z)
    coef, *_ = np.linalg.lstsq(basis, etas, rcond=None)
    resid = etas - basis @ coef
    dof_fit = max(len(us) - basis.shape[1], 1)
    s_fit = np.sqrt((resid ** 2).sum(axis=0) / dof_fit) * np.sqrt(basis.shape[1] / len(us))
    s_tot2 = s_meas ** 2 + s_fit ** 2

    def chi2(zz):
        pred = poly_basis(np.atleast_2d(zz)) @ coef
        return ((pred - meas) ** 2 / s_tot2).sum(axis=1)

    dof = max(len(strokes) - len(fits), 1)
    if len(fits) == 1:
        grid = np.linspace(0.0, 1.0, 2001)[:, None]
        c = chi2(grid)
        k = int(np.argmin(c))
        z_hat = grid[k]
        chi_min = float(c[k])
        red = chi_min / dof
        level = chi_min + max(1.0, red)
        left = grid[:k + 1, 0][c[:k + 1] > level]
        right = grid[k:, 0][c[k:] > level]
        lo_z = left[-1] if left.size else 0.0
        hi_z = right[0] if right.size else 1.0
        sig_u = np.array([0.5 * (hi_z - lo_z) * (hi_u[0] - lo_u[0])])
        convex = bool(left.size and right.size)
    else:
        from scipy.optimize import minimize

        g = np.stack(np.meshgrid(*[np.linspace(0, 1, 41)] * len(fits), indexing="ij"), axis=-1).reshape(-1, len(fits))
        start = g[int(np.argmin(chi2(g)))]
        res = minimize(lambda zz: float(chi2(zz)[0]), start, bounds=[(0.0, 1.0)] * len(fits), method="L-BFGS-B")
        z_hat = res.x
        chi_min = float(res.fun)
        red = chi_min / dof
        h = 1e-3
        H = np.zeros((len(fits), len(fits)))
        for a_ in range(len(fits)):
            for b_ in range(len(fits)):
                e_a, e_b = np.eye(len(fits))[a_] * h, np.eye(len(fits))[b_] * h
                H[a_, b_] = (chi2(z_hat + e_a + e_b)[0] - chi2(z_hat + e_a - e_b)[0]
                             - chi2(z_hat - e_a + e_b)[0] + chi2(z_hat - e_a - e_b)[0]) / (4 * h * h)
        convex = bool(np.all(np.linalg.eigvalsh(H) > 0))
        cov = 2.0 * np.linalg.inv(H) * max(red, 1.0) if convex else np.diag(np.full(len(fits), np.inf))
        sig_u = np.sqrt(np.diag(cov)) * (hi_u - lo_u)
    u_hat = lo_u + np.asarray(z_hat) * (hi_u - lo_u)
    best_vals = {f.key: float(f.from_u(u)) for f, u in zip(fits, u_hat)}
    unc = {f.key: float(best_vals[f.key] * math.log(10) * sg if f.log else sg) for f, sg in zip(fits, sig_u)}
    misfit = chi_min
    nearest = min(evaluated, key=lambda r: sum(((float(f.to_u(v)) - float(f.to_u(best_vals[f.key]))) / sc) ** 2
                                               for f, v, sc in zip(fits, r[0], scale)))
    rms = float(np.sqrt(np.mean((nearest[2] - meas) ** 2)))
    return Calibration(best=best_vals, uncertainty=unc, misfit=misfit, reduced_misfit=float(red), rms_difference=rms,
                       points=[{**{f.key: v for f, v in zip(fits, r[0])}, "misfit": r[1]} for r in evaluated],
                       strokes_m=strokes.tolist(), measured=meas.tolist(), measured_error=s_meas.tolist(),
                       dem_at_best=nearest[2].tolist(), convex=convex,
                       surrogate={"coefficients": coef.tolist(), "scatter": s_fit.tolist(), "low_u": lo_u.tolist(),
                                  "high_u": hi_u.tolist(), "log": [f.log for f in fits]})
