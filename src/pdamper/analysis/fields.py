"""The damper's effective fields: eta*, energy per cycle, m_eff and c_eq over amplitude x frequency.

A particle damper characterised once, over the container's displacement amplitude X (the stroke)
and the drive frequency f (Meyer & Seifried, Granular Matter 2021), can be coupled to any model
of a structure: at each (X, f) it acts as a mass m_eff and a dashpot c_eq (docs/analysis.md,
"effective mass"). :class:`DamperFields` holds those fields as a labelled dataset (mean over
seeds or repeats, and their spread) and interpolates them; :meth:`DamperFields.from_results`
builds it from a sweep's results (dimensions ``stroke`` [, ``frequency``], ``seed``) or from a
measured campaign's dataset. Files are read and written by :mod:`pdamper.studies.fields`.

Interpolation (:meth:`DamperFields.at`), per frequency node ("column"):

- along the amplitude with :class:`scipy.interpolate.PchipInterpolator` in log X: it passes
  through every node and is monotone between monotone nodes (no overshoot);
- only **within a segment** of points of one mode family (:func:`mode_family`: the efficient
  collect-and-collide modes, or the rest). Between two segments the fields jump: the interval
  between the last node of one and the first of the next is a **jump interval**, in which both
  branches exist: ``branch="below"`` continues the lower-amplitude segment, ``branch="above"``
  the higher one, each at the eta* and m_eff of its end node (so c_eq = eta* m_bed Omega stays
  and the energy per cycle grows as X^2). Without a branch the value jumps at the interval's
  geometric midpoint. :meth:`DamperFields.branches` returns every branch at a point (one or two):
  what a harmonic-balance solver needs to find every solution;
- then along the frequency, through the columns' values at X, by PCHIP in f. When every
  column has the same families in the same order (e.g. "other" then "collide"), the jump is
  tracked between the columns too: the ends of each jump interval are interpolated (log X,
  linear in f) to the asked f, X is placed on a segment (or in an interval, with its branches) by
  them, and every column is evaluated on that segment (continued beyond its own nodes as in a jump
  interval) before PCHIP in f: no value between two branches. Columns whose families differ are
  interpolated at X as they are (each on its own segment there).

Outside the measured box (the amplitudes of the columns on either side of f, the frequency
range) :meth:`DamperFields.at` raises an :class:`~pdamper.errors.InputError` naming the box and
the point; with ``extrapolate=True`` the end values are continued the same way as in a jump
interval (eta* and m_eff held; E per cycle ~ X^2 f^2, c_eq ~ f).

Points without a mode (a campaign, an older store: mode ``""`` or ``"unknown"``), and points
whose seeds split evenly between two families, join the segment next to them: a campaign has one
segment per frequency unless its dataset carries modes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..errors import InputError, shown
from .modes import COLLIDE_MODES, majority_mode

__all__ = ["DamperFields", "FieldValues", "FIELDS", "FORMAT", "BRANCHES", "mode_family"]

#: Format tag of a fields dataset (attribute ``format``).
FORMAT = "pdamper-damper-fields/1"

#: The fields: dataset variable -> (attribute of :class:`FieldValues`, units, long name).
FIELDS = {
    "eta_star": ("eta_star", "1", "reduced loss factor eta*"),
    "energy_per_cycle": ("energy_per_cycle_J", "J", "energy dissipated per cycle (complex power)"),
    "effective_mass": ("effective_mass_kg", "kg", "effective mass of the bed, Im(P) / (1/2 Omega |V*|^2)"),
    "equivalent_damping": ("equivalent_damping_N_s_per_m", "N s m-1", "equivalent viscous damping, 2 Re(P) / |V*|^2"),
}

#: What ``branch=`` takes: the segment below or above a jump interval in amplitude (None: the
#: value jumps at the interval's geometric midpoint).
BRANCHES = (None, "below", "above")

#: Mode -> family; a mode not listed is in the family "other". Interpolation never crosses a
#: change of family along the amplitude. "collide": the efficient modes, the bed (or each
#: compartment's bed) collected at one wall and striking the other in step with the drive.
_FAMILIES = {m: "collide" for m in COLLIDE_MODES}
_NO_MODE = ("", "unknown", "failed")
_SAME_F = 1e-6  # a frequency this close (relative) to a single column's is that column's


def mode_family(mode: str) -> str:
    """The family of a motion mode: ``"collide"`` (the efficient collect-and-collide modes:
    rolling, bouncing, per compartment; :data:`pdamper.analysis.modes.COLLIDE_MODES`), ``"other"``
    (every other mode), ``""`` (no mode known).

    >>> mode_family("rolling-collect-and-collide"), mode_family("swaying"), mode_family("unknown")
    ('collide', 'other', '')
    """
    mode = str(mode)
    if mode in _NO_MODE:
        return ""
    return _FAMILIES.get(mode, "other")


def _majority_family(modes) -> str:
    """The family most of ``modes`` are in; ``""`` when none is known or two tie (such a point
    joins the segment next to it instead of starting one).

    >>> _majority_family(["lift-off", "rolling-collect-and-collide"])
    ''
    """
    from collections import Counter

    counts = Counter(f for f in map(mode_family, modes) if f).most_common()
    if not counts or (len(counts) > 1 and counts[0][1] == counts[1][1]):
        return ""
    return counts[0][0]


@dataclass(frozen=True)
class FieldValues:
    """The fields at one point (SI). ``branch``: ``"below"`` or ``"above"`` where the point lies in
    a jump interval of a column it was interpolated from (``""`` elsewhere); ``family``: the mode
    family of the segment used at the nearest frequency node; ``extrapolated``: outside the box."""

    amplitude_m: float
    frequency_hz: float
    eta_star: float
    energy_per_cycle_J: float
    effective_mass_kg: float
    equivalent_damping_N_s_per_m: float
    branch: str = ""
    family: str = ""
    extrapolated: bool = False

    def to_dict(self) -> dict:
        return dict(self.__dict__)


class _Column:
    """The amplitude interpolants of one frequency node."""

    def __init__(self, frequency, amplitude, values: dict, families):
        self.frequency = float(frequency)
        self.x = np.asarray(amplitude, dtype=float)
        self.lx = np.log(self.x)
        fam = list(families)
        for i in range(len(fam)):  # a point without a mode joins the segment before it (else after)
            if not fam[i]:
                fam[i] = next((fam[j] for j in range(i - 1, -1, -1) if fam[j]), "") or \
                    next((fam[j] for j in range(i + 1, len(fam)) if fam[j]), "")
        fam = [str(v) for v in fam]
        self.segments = []  # (first index, last index, family)
        start = 0
        for i in range(1, len(fam) + 1):
            if i == len(fam) or fam[i] != fam[start]:
                self.segments.append((start, i - 1, fam[start]))
                start = i
        self.values = np.column_stack([np.asarray(values[n], dtype=float) for n in FIELDS])
        self.interp = [_pchip(self.lx[a:b + 1], self.values[a:b + 1]) for a, b, _ in self.segments]

    @property
    def box(self) -> tuple[float, float]:
        return float(self.x[0]), float(self.x[-1])

    def jumps(self) -> list[tuple[float, float, str, str]]:
        return [(float(self.x[b0]), float(self.x[a1]), f0, f1)
                for (_, b0, f0), (a1, _, f1) in zip(self.segments, self.segments[1:])]

    def _end(self, k: int, at_end: bool, X: float) -> np.ndarray:
        """Segment ``k`` continued from its last (``at_end``) or first node to X: eta*, m_eff and
        c_eq held, E ~ X^2."""
        i = self.segments[k][1] if at_end else self.segments[k][0]
        out = self.values[i].copy()
        out[_E] *= (X / self.x[i]) ** 2
        return out

    @property
    def sequence(self) -> tuple[str, ...]:
        """The families of its segments, in order of amplitude."""
        return tuple(fam for _, _, fam in self.segments)

    def on_segment(self, k: int, X: float) -> np.ndarray:
        """Segment ``k`` at X: interpolated within its nodes, continued (:meth:`_end`) outside."""
        a, b, _ = self.segments[k]
        if X < self.x[a]:
            return self._end(k, False, X)
        if X > self.x[b]:
            return self._end(k, True, X)
        return self.interp[k](math.log(X))

    def evaluate(self, X: float, branch) -> tuple[np.ndarray, str, str]:
        """(the fields in :data:`FIELDS` order, branch used, family) at X."""
        lo, hi = self.box
        if X < lo:
            return self._end(0, False, X), "", self.segments[0][2]
        if X > hi:
            return self._end(len(self.segments) - 1, True, X), "", self.segments[-1][2]
        lx = math.log(X)
        for k, (a, b, fam) in enumerate(self.segments):
            if self.x[a] <= X <= self.x[b]:
                return self.interp[k](lx), "", fam
            if k + 1 < len(self.segments) and self.x[b] < X < self.x[self.segments[k + 1][0]]:
                mid = math.sqrt(self.x[b] * self.x[self.segments[k + 1][0]])
                below = branch == "below" or (branch is None and X < mid)
                if below:
                    return self._end(k, True, X), "below", fam
                return self._end(k + 1, False, X), "above", self.segments[k + 1][2]
        raise AssertionError("unreachable: X inside the box but in no segment or gap")


_E = list(FIELDS).index("energy_per_cycle")


def _pchip(t, y):
    """A callable through the nodes (t, y[:, k]) of every field k, returning an array: PCHIP through
    the finite nodes of a field (two or more), its value (one), NaN (none)."""
    from scipy.interpolate import PchipInterpolator

    ok = np.isfinite(y)
    if ok.all() and len(t) >= 2:
        p = PchipInterpolator(t, y, axis=0, extrapolate=True)
        return lambda v: np.asarray(p(v), dtype=float)
    if ok.all():
        row = y[0].astype(float)
        return lambda v: row.copy()
    parts = [_pchip(t[ok[:, k]], y[ok[:, k], k:k + 1]) if ok[:, k].any() else (lambda v: np.array([math.nan]))
             for k in range(y.shape[1])]
    return lambda v: np.concatenate([p(v) for p in parts])


def _pchip_at(t, y, v: float) -> np.ndarray:
    """PCHIP through the nodes (t, y[:, k]) evaluated at one point v (continued beyond the ends by
    the end cubics): the same numbers as :func:`_pchip` (scipy's PchipInterpolator: Fritsch-Butland
    derivatives, scipy's one-sided three-point ends) without building an interpolator, for the
    many single-point calls of a solver. Columns with a non-finite node go through :func:`_pchip`."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    n = t.size
    if n < 3 or not np.isfinite(y).all():
        return _pchip(t, y)(v)
    h = np.diff(t)
    m = np.diff(y, axis=0) / h[:, None]
    j = int(min(max(np.searchsorted(t, v, side="right") - 1, 0), n - 2))
    d = [_pchip_slope(h, m, i) for i in (j, j + 1)]
    s = (v - t[j]) / h[j]
    h00, h10, h01, h11 = (2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2)
    return h00 * y[j] + h10 * h[j] * d[0] + h01 * y[j + 1] + h11 * h[j] * d[1]


def _pchip_slope(h, m, i: int) -> np.ndarray:
    """The PCHIP derivative at node i of every column (scipy's ``_find_derivatives``)."""
    n = h.size + 1
    if i == 0 or i == n - 1:
        h0, h1, m0, m1 = (h[0], h[1], m[0], m[1]) if i == 0 else (h[-1], h[-2], m[-1], m[-2])
        d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
        d = np.where(np.sign(d) != np.sign(m0), 0.0, d)
        return np.where((np.sign(m0) != np.sign(m1)) & (np.abs(d) > 3.0 * np.abs(m0)), 3.0 * m0, d)
    mk, mk1 = m[i - 1], m[i]
    w1, w2 = 2 * h[i] + h[i - 1], h[i] + 2 * h[i - 1]
    flat = (np.sign(mk) != np.sign(mk1)) | (mk == 0) | (mk1 == 0)
    with np.errstate(divide="ignore", invalid="ignore"):
        whmean = (w1 / mk + w2 / mk1) / (w1 + w2)
        return np.where(flat, 0.0, 1.0 / whmean)


def _spread(values, dim="seed") -> dict:
    """Mean, standard deviation (ddof 1; 0 for a single value), min and max over ``dim``."""
    import warnings

    n = np.isfinite(values).sum(dim)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN points stay NaN
        std = values.std(dim, ddof=1, skipna=True).where(n >= 2, 0.0).where(n >= 1)
        return {"": values.mean(dim, skipna=True), "_std": std, "_min": values.min(dim, skipna=True),
                "_max": values.max(dim, skipna=True)}


class DamperFields:
    """The damper's fields over amplitude x frequency (module docstring), a wrapper of
    :attr:`dataset`: dimensions ``amplitude`` [m] and ``frequency`` [Hz]; for each field of
    :data:`FIELDS` its mean over seeds and ``<name>_std``, ``<name>_min``, ``<name>_max``;
    ``seeds`` (finite seeds per point), ``mode`` (the seeds' majority), ``mode_mixed`` (1 where the
    seeds disagree), ``mode_family`` (:func:`mode_family`); provenance in the attributes."""

    def __init__(self, dataset):
        missing = [n for n in ("eta_star", "mode_family") if n not in dataset]
        if missing or tuple(dataset["eta_star"].dims) != ("amplitude", "frequency"):
            raise InputError("not a pdamper damper-fields dataset (it needs eta_star and mode_family over "
                             f"amplitude x frequency; missing {', '.join(missing) or 'those dimensions'}); "
                             "make one with 'pdamper fields STORE --out F.nc'")
        self.dataset = dataset

    # ---------------------------------------------------------------- building
    @classmethod
    def from_results(cls, results, *, attrs: dict | None = None) -> "DamperFields":
        """The fields of a sweep's results or a campaign's dataset (dimensions ``stroke``,
        optionally ``frequency``, and ``seed``): mean and spread over seeds, the seeds' majority
        mode per point. Without a ``frequency`` dimension the frequency is the ``frequency_hz``
        attribute. Points where no seed has a finite eta* are left out, and so are amplitudes
        and frequencies left without any point. ``attrs``: provenance added to the dataset's."""
        import xarray as xr

        from .._version import __version__

        ds = results
        if "stroke" not in ds.dims or "eta_star" not in ds:
            raise InputError("these results have no eta* over the stroke (dimension 'stroke'); give the store of "
                             "a sweep over drive.stroke (and drive.frequency) or a 'pdamper campaign' dataset")
        extra = [d for d in ds.dims if d not in ("stroke", "frequency", "seed")]
        if extra:
            raise InputError(f"these results vary {', '.join(extra)} besides the stroke and the frequency; "
                             "fix each at one value first (e.g. --sel " + f"{extra[0]}=VALUE)")
        if "seed" not in ds.dims:
            ds = ds.expand_dims("seed")
        if "frequency" not in ds.dims:
            f = float(ds.attrs.get("frequency_hz", math.nan))
            if not (math.isfinite(f) and f > 0):
                raise InputError("these results have no frequency: no 'frequency' dimension and no frequency_hz "
                                 "attribute; sweep over drive.frequency or give a store of a single-frequency case")
            ds = ds.expand_dims(frequency=[f])
        ds = ds.transpose("stroke", "frequency", "seed")
        eta = ds["eta_star"]
        good = np.isfinite(eta.values)
        if not good.any():
            raise InputError("these results hold no finished point (every eta* is NaN or missing); "
                             "run the sweep (or the campaign's records) first")
        keep_x = good.any(axis=(1, 2))
        keep_f = good.any(axis=(0, 2))
        ds = ds.isel(stroke=np.flatnonzero(keep_x), frequency=np.flatnonzero(keep_f))
        good = np.isfinite(ds["eta_star"].values)
        out = xr.Dataset(coords={
            "amplitude": ("amplitude", np.asarray(ds["stroke"].values, dtype=float),
                          {"units": "m", "long_name": "container displacement amplitude X (the stroke)",
                           "config_key": "drive.stroke"}),
            "frequency": ("frequency", np.asarray(ds["frequency"].values, dtype=float),
                          {"units": "Hz", "long_name": "drive frequency f", "config_key": "drive.frequency"})})
        for name, (_, units, long_name) in FIELDS.items():
            v = ds[name] if name in ds else xr.full_like(ds["eta_star"], np.nan)
            v = v.where(good)  # a seed counts for all fields or none
            for suffix, arr in _spread(v).items():
                what = {"": "mean over seeds of the", "_std": "standard deviation over seeds of the",
                        "_min": "minimum over seeds of the", "_max": "maximum over seeds of the"}[suffix]
                out[name + suffix] = (("amplitude", "frequency"), arr.transpose("stroke", "frequency").values,
                                      {"units": units, "long_name": f"{what} {long_name}"})
        out["seeds"] = (("amplitude", "frequency"), good.sum(axis=2).astype(np.int64),
                        {"units": "1", "long_name": "seeds (repeats) with a finite eta* at the point"})
        modes = ds["mode"].values if "mode" in ds else np.full(good.shape, "", dtype=object)
        mode = np.full(good.shape[:2], "", dtype=object)
        mixed = np.zeros(good.shape[:2], dtype=np.int8)
        family = np.full(good.shape[:2], "", dtype=object)
        for i in range(good.shape[0]):
            for j in range(good.shape[1]):
                seen = [modes[i, j, s] for s in range(good.shape[2]) if good[i, j, s]]
                mode[i, j], disagree = majority_mode(seen)
                mixed[i, j] = int(disagree)
                family[i, j] = _majority_family(seen)
        out["mode"] = (("amplitude", "frequency"), mode.astype(str),
                       {"long_name": "motion mode most seeds are in ('' or 'unknown': not classified)"})
        out["mode_mixed"] = (("amplitude", "frequency"), mixed,
                             {"units": "1", "long_name": "1 where the seeds are in different motion modes"})
        out["mode_family"] = (("amplitude", "frequency"), family.astype(str),
                              {"long_name": "mode family most seeds are in: interpolation never crosses a change "
                                            "of it ('collide', 'other'; '' unknown or a tie)"})
        src = results.attrs
        out.attrs.update({
            "Conventions": "CF-1.10", "format": FORMAT,
            "title": "pdamper damper fields: " + str(src.get("title", "results")),
            "pdamper_version": __version__,
            "bed_mass_kg": float(src.get("bed_mass_kg", math.nan)),
            "container_mass_kg": float(src.get("container_mass_kg", math.nan)),
            "source_kind": "campaign" if src.get("kind") == "campaign" else "sweep",
            "source_pdamper_version": str(src.get("pdamper_version", "")),
            "source_history": str(src.get("history", "")),
            "source_config": str(src.get("config", "")),
        })
        if "x_opt_m" in src:
            out.attrs["x_opt_m"] = float(src["x_opt_m"])
        out.attrs.update(attrs or {})
        return cls(out)

    # ---------------------------------------------------------------- reading
    @property
    def amplitudes(self) -> np.ndarray:
        return np.asarray(self.dataset["amplitude"].values, dtype=float)

    @property
    def frequencies(self) -> np.ndarray:
        return np.asarray(self.dataset["frequency"].values, dtype=float)

    @property
    def bed_mass(self) -> float:
        return float(self.dataset.attrs.get("bed_mass_kg", math.nan))

    @cached_property
    def _columns(self) -> list[_Column]:
        ds = self.dataset
        cols = []
        for j, f in enumerate(self.frequencies):
            eta = ds["eta_star"].values[:, j]
            ok = np.isfinite(eta)
            if not ok.any():
                continue
            cols.append(_Column(f, self.amplitudes[ok], {n: ds[n].values[ok, j].astype(float) for n in FIELDS},
                                ds["mode_family"].values[ok, j]))
        if not cols:
            raise InputError("these fields hold no finite eta*; nothing to interpolate")
        return cols

    def jumps(self, frequency: float | None = None) -> list[dict]:
        """The jump intervals (mode-family changes along the amplitude): ``[{"frequency_hz",
        "below_m", "above_m", "family_below", "family_above"}, ...]`` at every frequency node, or
        at the node ``frequency`` (nearest)."""
        cols = self._columns
        if frequency is not None:
            cols = [min(cols, key=lambda c: abs(c.frequency - frequency))]
        return [{"frequency_hz": c.frequency, "below_m": lo, "above_m": hi, "family_below": f0, "family_above": f1}
                for c in cols for lo, hi, f0, f1 in c.jumps()]

    def box(self) -> str:
        """The measured box in words: the amplitude range at each frequency node."""
        cols = self._columns
        boxes = {c.box for c in cols}
        if len(boxes) == 1:
            lo, hi = boxes.pop()
            return f"X {lo * 1e3:.4g}-{hi * 1e3:.4g} mm x f {cols[0].frequency:g}-{cols[-1].frequency:g} Hz"
        per = "; ".join(f"at {c.frequency:g} Hz: X {c.box[0] * 1e3:.4g}-{c.box[1] * 1e3:.4g} mm" for c in cols)
        return f"f {cols[0].frequency:g}-{cols[-1].frequency:g} Hz ({per})"

    def amplitude_box(self, frequency: float) -> tuple[float, float]:
        """(lowest, highest) amplitude [m] at which :meth:`at` answers at ``frequency`` [Hz] without
        extrapolating: the overlap of the boxes of the frequency nodes on either side of it
        (NaN, NaN outside the frequency range)."""
        cols = self._columns
        fs = np.array([c.frequency for c in cols])
        f = float(frequency)
        if len(cols) == 1 and abs(f - fs[0]) <= _SAME_F * fs[0]:
            return cols[0].box
        if f < fs[0] or f > fs[-1]:
            return math.nan, math.nan
        j = int(np.searchsorted(fs, f))
        near = [cols[j]] if fs[j] == f else [cols[j - 1], cols[j]]
        return max(c.box[0] for c in near), min(c.box[1] for c in near)

    def at(self, amplitude: float, frequency: float | None = None, *, branch: str | None = None,
           extrapolate: bool = False) -> FieldValues:
        """The fields at amplitude X [m] and frequency f [Hz] (module docstring).

        ``frequency``: may be left out when the fields have a single frequency. ``branch``:
        ``"below"`` / ``"above"`` picks the segment below or above a jump interval X lies in
        (elsewhere it changes nothing); None: the jump at the interval's geometric midpoint.
        ``extrapolate``: outside the measured box, continue the end values (eta* and m_eff held)
        instead of raising :class:`~pdamper.errors.InputError`.
        """
        if branch not in BRANCHES:
            raise InputError(f"branch = {shown(branch)}; choose one of {', '.join(map(repr, BRANCHES))}")
        X = float(amplitude)
        if not (math.isfinite(X) and X > 0):
            raise InputError(f"amplitude = {shown(amplitude)} m; give a finite amplitude > 0")
        cols = self._columns
        if frequency is None:
            if len(cols) > 1:
                raise InputError(f"these fields span {len(cols)} frequencies ({self.box()}); give the frequency")
            frequency = cols[0].frequency
        f = float(frequency)
        if not (math.isfinite(f) and f > 0):
            raise InputError(f"frequency = {shown(frequency)} Hz; give a finite frequency > 0")
        fs = np.array([c.frequency for c in cols])
        if len(cols) == 1 and abs(f - fs[0]) <= _SAME_F * fs[0]:
            f = float(fs[0])
        outside_f = f < fs[0] or f > fs[-1]
        if outside_f:
            near = [cols[0] if f < fs[0] else cols[-1]]
        else:
            j = int(np.searchsorted(fs, f))
            near = [cols[j]] if fs[j] == f else [cols[j - 1], cols[j]]
        outside_x = any(not (c.box[0] <= X <= c.box[1]) for c in near)
        if (outside_f or outside_x) and not extrapolate:
            raise InputError(f"X = {X * 1e3:.4g} mm, f = {f:g} Hz is outside the measured box of these fields: "
                             f"{self.box()}; widen the sweep or pass extrapolate=True (end values continued: "
                             "eta* and m_eff held)")
        if len(near) == 2 and len({c.sequence for c in cols}) == 1:
            return self._tracked(X, f, near, branch, outside_x)
        if not outside_f and len(cols) > 1:  # along f: the columns that hold X (and the two around f)
            cols = [c for c in cols if c in near or c.box[0] <= X <= c.box[1]]
            fs = np.array([c.frequency for c in cols])
        results = [c.evaluate(X, branch) for c in cols]
        if outside_f:  # the end column at X, continued in f: eta*, m_eff held, c_eq ~ f, E ~ f^2
            vals, br, fam = results[0 if f < fs[0] else -1]
            r = f / near[0].frequency
            out = vals * np.array([1.0, r * r, 1.0, r])
        elif len(near) == 1:  # on a frequency node
            vals, br, fam = results[cols.index(near[0])]
            out = vals
        else:
            out = _pchip_at(fs, np.array([r[0] for r in results]), f)
            nearest = min(range(len(cols)), key=lambda i: abs(fs[i] - f))
            fam = results[nearest][2]
            br = next((results[cols.index(c)][1] for c in near if results[cols.index(c)][1]), "")
        return FieldValues(amplitude_m=X, frequency_hz=f, **{a: float(v) for (a, _, _), v in zip(FIELDS.values(), out)},
                           branch=br, family=str(fam), extrapolated=outside_f or outside_x)

    def _tracked(self, X, f, near, branch, extrapolated) -> FieldValues:
        """Between two frequency nodes when every node has the same families in the same order:
        the jump intervals' ends interpolated (log X, linear in f) to f, X placed on a segment or in
        an interval by them, every node evaluated on that segment, PCHIP along f."""
        c0, c1 = near
        t = (f - c0.frequency) / (c1.frequency - c0.frequency)
        k, br = 0, ""
        for (lo0, hi0, _, _), (lo1, hi1, _, _) in zip(c0.jumps(), c1.jumps()):
            lo = math.exp((1 - t) * math.log(lo0) + t * math.log(lo1))
            hi = math.exp((1 - t) * math.log(hi0) + t * math.log(hi1))
            if X <= lo:
                break
            if X < hi:
                below = branch == "below" or (branch is None and X < math.sqrt(lo * hi))
                br = "below" if below else "above"
                k += 0 if below else 1
                break
            k += 1
        cols = self._columns
        out = _pchip_at(np.array([c.frequency for c in cols]), np.array([c.on_segment(k, X) for c in cols]), f)
        return FieldValues(amplitude_m=X, frequency_hz=f, **{a: float(v) for (a, _, _), v in zip(FIELDS.values(), out)},
                           branch=br, family=c0.sequence[k], extrapolated=extrapolated)

    def branches(self, amplitude: float, frequency: float | None = None, *,
                 extrapolate: bool = False) -> list[FieldValues]:
        """Every branch of the fields at (X, f): one :class:`FieldValues` outside jump intervals,
        two (``"below"``, ``"above"``) inside one, for a solver that follows each branch."""
        lower = self.at(amplitude, frequency, branch="below", extrapolate=extrapolate)
        if not lower.branch:
            return [lower]
        upper = self.at(amplitude, frequency, branch="above", extrapolate=extrapolate)
        return [lower, upper]

    def __repr__(self) -> str:
        return (f"DamperFields({len(self.amplitudes)} amplitudes x {len(self.frequencies)} frequencies; "
                f"{self.box()}; {len(self.jumps())} jump interval(s))")
