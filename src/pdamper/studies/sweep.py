"""A sweep: the base case at every point of a grid of config keys, for every seed.

The grid's axes are any config keys (``drive.stroke``, ``drive.frequency``, ``contact.friction``,
``particles.count``, ...; :class:`Axis`); each point is the base case with those keys set by
:func:`pdamper.schema.replace`, so a value is read and checked exactly as in a config file. The paper's sweep is one axis, the stroke (:data:`PAPER_STROKES`).

Every (point, seed) case is independent: it starts from rest with its own seeded jitter (the
paper's drive pauses between points), so the cases can run in any order, anywhere.
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, checked_file, shown, shown_path
from ..params import Case
from ..schema import replace
from ..units import is_quantity, parse_quantity, quantities, to_si

__all__ = ["Axis", "SweepSpec", "stroke_grid", "parse_strokes", "parse_axis", "case_key", "run_one", "run_sweep",
           "open_results", "PAPER_STROKES", "STROKE"]

#: The paper's sweep: 40 log-spaced strokes from 0.5 to 50 mm.
PAPER_STROKES = (0.5e-3, 50e-3, 40)
#: The config key of the stroke, the paper's sweep axis.
STROKE = "drive.stroke"
#: How a range FIRST:LAST:COUNT is spaced when the text does not say: the stroke log-spaced (the
#: paper's sweep), every other key linearly.
SPACINGS = ("log", "linear")


def _si_values(values, dimension: str, name: str):
    """A grid's values in SI: "12mm", ["5mm", "12mm"] or a pint quantity become SI floats; numbers
    and arrays stay as they are (:func:`pdamper.units.to_si`); one value becomes a list of one."""
    if isinstance(values, str) or is_quantity(values) and np.ndim(values) == 0:
        values = [values]
    elif isinstance(values, (list, tuple)):
        values = list(values)
    return to_si(values, dimension, name=name)


@quantities(lo="length", hi="length")
def stroke_grid(lo: float, hi: float, n: int) -> np.ndarray:
    """``n`` log-spaced strokes [m] from ``lo`` to ``hi`` (the paper: 0.5 mm, 50 mm, 40)."""
    if not (0 < lo <= hi) or not (isinstance(n, (int, np.integer)) and n >= 1):
        raise InputError(f"strokes: need 0 < first <= last and a count >= 1, got {shown(lo)}, {shown(hi)}, {shown(n)}")
    if n == 1:
        return np.array([lo])
    return np.geomspace(lo, hi, int(n))


def parse_strokes(text: str) -> np.ndarray:
    """Strokes from the CLI: ``"0.5mm:50mm:40"`` (log-spaced), or a list ``"5mm,12mm,13mm"``."""
    text = str(text).strip()
    if ":" in text:
        parts = text.split(":")
        if len(parts) != 3:
            raise InputError(f"--strokes {shown(text)}: write FIRST:LAST:COUNT, e.g. 0.5mm:50mm:40, or a list 5mm,12mm")
        lo = parse_quantity(parts[0], "length", name="--strokes (first)")
        hi = parse_quantity(parts[1], "length", name="--strokes (last)")
        try:
            n = int(parts[2])
        except ValueError:
            raise InputError(f"--strokes {shown(text)}: the count {shown(parts[2])} is not a whole number") from None
        return stroke_grid(lo, hi, n)
    values = [parse_quantity(p, "length", name="--strokes") for p in text.split(",") if p.strip()]
    if not values or any(v <= 0 for v in values):
        raise InputError(f"--strokes {shown(text)}: give positive lengths, e.g. 5mm,12mm or 0.5mm:50mm:40")
    return np.array(sorted(set(values)))


@dataclass(frozen=True, kw_only=True)
class Axis:
    """One dimension of a sweep: a config key and its values (SI numbers, whole numbers or text).

    ``spacing`` says how the values were made: ``"log"`` or ``"linear"`` for a range, ``"list"``
    for values given one by one.
    """

    key: str
    values: tuple
    spacing: str = "list"

    def __post_init__(self):
        from ..config import key_spec

        spec = key_spec(self.key)  # raises for an unknown key, with a suggestion
        values = self.values
        if spec.kind != "text" and (spec.dimension is not None or spec.kind == "number"):
            values = _si_values(values, spec.dimension or "dimensionless", f"axis {self.key}")
        vals = tuple(np.atleast_1d(np.asarray(values, dtype=object)).tolist())
        if not vals:
            raise InputError(f"--vary {self.key}: give at least one value")
        if spec.kind == "whole":
            vals = tuple(int(v) for v in vals)
        elif spec.kind == "number" or spec.dimension is not None:
            vals = tuple(float(v) for v in vals)
        else:
            vals = tuple(str(v) for v in vals)
        if spec.kind != "text":
            vals = tuple(sorted(set(vals)))
        else:
            vals = tuple(dict.fromkeys(vals))
        object.__setattr__(self, "values", vals)
        if self.spacing not in SPACINGS + ("list",):
            raise InputError(f"axis {self.key}: spacing {shown(self.spacing)}; choose 'log', 'linear' or 'list'")

    @property
    def name(self) -> str:
        """The dimension's name in the dataset: the key's last part (``drive.stroke`` -> ``stroke``)."""
        return self.key.rsplit(".", 1)[-1]


def parse_axis(text: str) -> Axis:
    """An axis from the CLI's ``--vary KEY=VALUES``.

    VALUES is a range ``FIRST:LAST:COUNT`` (optionally ``:log`` or ``:linear``; without it the
    stroke is log-spaced, as the paper's sweep, and every other key linearly spaced) or a list
    ``A,B,C``; each value with a unit as in a config file (``5mm``, ``2Hz``) or plain SI. A whole-
    number key (``particles.count``) takes whole numbers: ``30:44:8`` is 30, 32, ..., 44.
    """
    from ..config import key_spec

    key, sep, values = str(text).partition("=")
    key, values = key.strip(), values.strip()
    if not sep or not key or not values:
        raise InputError(f"--vary {shown(text)}: write KEY=VALUES, e.g. drive.stroke=0.5mm:50mm:40 (a range) or "
                         "contact.friction=0.01,0.1,1 (a list)")
    spec = key_spec(key)
    dimension = spec.dimension or "dimensionless"

    def one(v, what):
        v = v.strip()
        if spec.kind == "text" or spec.choices:
            return v
        if spec.kind == "whole":
            try:
                f = float(v)
            except ValueError:
                raise InputError(f"--vary {key}: {what} {shown(v)} is not a whole number") from None
            if not f.is_integer():
                raise InputError(f"--vary {key}: {what} {shown(v)} is not a whole number")
            return int(f)
        return parse_quantity(v, dimension, name=f"--vary {key} ({what})")

    if ":" in values:
        parts = values.split(":")
        spacing = "log" if key == STROKE else "linear"
        if len(parts) == 4:
            spacing = parts.pop().strip().lower()
            spacing = {"lin": "linear"}.get(spacing, spacing)
            if spacing not in SPACINGS:
                raise InputError(f"--vary {shown(text)}: the spacing {shown(spacing)} is not 'log' or 'linear'")
        if len(parts) != 3:
            raise InputError(f"--vary {shown(text)}: write FIRST:LAST:COUNT[:log|:linear], e.g. {key}=1:4:4")
        if spec.kind == "text" or spec.choices:
            raise InputError(f"--vary {key}: a text key takes a list of values, e.g. "
                             f"{key}={','.join(spec.choices or ('a', 'b'))}")
        lo, hi = one(parts[0], "first"), one(parts[1], "last")
        try:
            n = int(parts[2])
        except ValueError:
            raise InputError(f"--vary {shown(text)}: the count {shown(parts[2])} is not a whole number") from None
        if n < 1 or lo > hi:
            raise InputError(f"--vary {shown(text)}: need FIRST <= LAST and a COUNT >= 1")
        if spacing == "log":
            if lo <= 0:
                raise InputError(f"--vary {shown(text)}: log spacing needs FIRST > 0; add :linear for a linear range")
            vals = np.geomspace(lo, hi, n) if n > 1 else np.array([lo])
        else:
            vals = np.linspace(lo, hi, n) if n > 1 else np.array([lo])
        if spec.kind == "whole":
            ints = np.round(vals).astype(int)
            if len(set(ints.tolist())) != n:
                raise InputError(f"--vary {shown(text)}: {n} whole numbers do not fit between {lo} and {hi}")
            vals = ints
        return Axis(key=key, values=tuple(vals.tolist()), spacing=spacing)
    return Axis(key=key, values=tuple(one(v, "value") for v in values.split(",") if v.strip()), spacing="list")


def case_key(stroke: float, seed: int) -> str:
    """File-safe, exact key of one case of a stroke sweep: the stroke's full float repr and the seed."""
    return f"X{float(stroke)!r}_seed{int(seed)}"


def point_key(point: dict, seed: int) -> str:
    """File-safe, exact key of one case: each axis value's full repr and the seed (a stroke sweep
    keeps the key of :func:`case_key`, so its stores resume across versions)."""
    if list(point) == [STROKE]:
        return case_key(point[STROKE], seed)
    parts = [f"{k.rsplit('.', 1)[-1]}{v!r}" for k, v in point.items()]
    return re.sub(r"[^A-Za-z0-9.+=_-]", "-", "_".join(parts)) + f"_seed{int(seed)}"


def _point_id(point: dict) -> tuple:
    """A point of a grid as a key that a value read back to 15 digits finds again."""
    return tuple((k, format(v, ".15g") if isinstance(v, float) else repr(v)) for k, v in point.items())


@dataclass(frozen=True, kw_only=True)
class SweepSpec:
    """A base case, the axes of the grid and the seeds to run every point at.

    ``strokes`` is the shortcut for one axis over ``drive.stroke`` (the paper's sweep)::

        SweepSpec(base=case, strokes=[0.005, 0.012], seeds=[0, 1])
        SweepSpec(base=case, axes=[Axis(key="drive.stroke", values=[0.005, 0.012]),
                                   Axis(key="drive.frequency", values=[1.0, 2.0])], seeds=[0])

    A base case with a rig drive beside its structure (:attr:`pdamper.params.Case.rig`) is swept
    on its rig (:attr:`~pdamper.params.Case.on_rig`): a sweep characterises the damper. A restitution
    law of your own in it (any object with ``restitution(speed)``) is swept as the table law of its
    values, which the store's config holds and the kernels run to the same bits
    (:meth:`pdamper.params.ContactModel.written_laws`).
    """

    base: Case
    axes: tuple = ()
    seeds: tuple = (0,)
    strokes: tuple | None = None

    def __post_init__(self):
        base = self.base.on_rig
        contact = base.contact.written_laws()  # a COR law of the user's own: the table law its config holds
        object.__setattr__(self, "base", base if contact is base.contact else dataclasses.replace(base, contact=contact))
        axes = list(self.axes)
        if self.strokes is not None:
            strokes = tuple(float(x) for x in np.atleast_1d(_si_values(self.strokes, "length", "strokes")))
            if not strokes or any(not (x > 0 and math.isfinite(x)) for x in strokes):
                raise InputError(f"sweep strokes must be positive lengths, got {shown(self.strokes)}")
            if any(a.key == STROKE for a in axes):
                raise InputError("give the strokes either as strokes=... or as an axis over drive.stroke, not both")
            axes.insert(0, Axis(key=STROKE, values=strokes, spacing="list"))
        if not axes:
            raise InputError("a sweep needs at least one axis (e.g. strokes=... or --vary drive.stroke=...)")
        keys = [a.key for a in axes]
        if len(set(keys)) != len(keys):
            raise InputError(f"a key is varied twice: {keys}")
        names = [a.name for a in axes]
        if len(set(names)) != len(names) or "seed" in names:
            raise InputError(f"two axes would share a dimension name ({names}); vary them in separate sweeps")
        if any(k.startswith("drive.") for k in keys) and not self.base.drive.sweepable:
            raise InputError("a sweep over drive keys needs a harmonic drive ([drive] stroke and frequency)")
        seeds = tuple(int(s) for s in np.atleast_1d(self.seeds))
        if not seeds or any(s < 0 for s in seeds):
            raise InputError(f"sweep seeds must be whole numbers >= 0, got {shown(self.seeds)}")
        object.__setattr__(self, "axes", tuple(axes))
        object.__setattr__(self, "seeds", tuple(sorted(set(seeds))))
        object.__setattr__(self, "strokes", self.axis(STROKE).values if STROKE in keys else None)
        # every point must make a valid, plausible case, before anything runs: checked here once (the
        # check does not depend on the seed; its runs are not checked again); what the check warns
        # of (lift-off at some points is allowed) is said when the point runs (:meth:`cautions`)
        from ..plausible import check_case, check_memory

        import warnings

        cautions = {}
        for point in self.points():
            c = self.case(point, self.seeds[0])
            with warnings.catch_warnings(record=True) as said:
                warnings.simplefilter("always")
                check_case(c, analyze=True)
            check_memory(c)
            if said:
                cautions[_point_id(point)] = tuple((w.category, str(w.message)) for w in said)
        object.__setattr__(self, "_cautions", cautions)

    def cautions(self, points) -> list:
        """What the check of ``points`` (``{key: value}`` each) warned of when the spec was made:
        (category, message), each once, for the runs of those points to say."""
        out = []
        for point in points:
            for said in self._cautions.get(_point_id(point), ()):
                if said not in out:
                    out.append(said)
        return out

    def axis(self, key: str) -> Axis:
        """The axis over ``key``."""
        for a in self.axes:
            if a.key == key:
                return a
        raise KeyError(key)

    def case(self, point, seed: int) -> Case:
        """The base case at ``point`` (``{key: value}``; a bare number is a stroke) with seed ``seed``."""
        if not isinstance(point, dict):
            point = {STROKE: float(point)}
        return replace(self.base, {**point, "initial.seed": int(seed)})

    def points(self) -> list[dict]:
        """Every point of the grid as ``{key: value}``, the first axis slowest."""
        grids = np.meshgrid(*[np.arange(len(a.values)) for a in self.axes], indexing="ij")
        idx = np.stack([g.ravel() for g in grids], axis=1)
        return [{a.key: a.values[i] for a, i in zip(self.axes, row)} for row in idx]

    def items(self):
        """(key, point, seed) of every case."""
        return [(point_key(p, s), p, s) for p in self.points() for s in self.seeds]

    def dims(self) -> tuple[str, ...]:
        """The dataset's dimensions: one per axis, then ``seed``."""
        return tuple(a.name for a in self.axes) + ("seed",)


def run_one(case: Case, keep: str = "signals", until_steady: float | None = None, checked: bool = False) -> dict:
    """Run one case and return its summary (plain floats, the motion mode; what the store keeps)
    and, unless ``keep == "none"``, its signals (:data:`pdamper.studies.store.SIGNALS`).
    ``until_steady``: stop the run early at this error of eta* (:func:`pdamper.run.run_case`);
    ``checked``: the case was checked already (a point of a :class:`SweepSpec`).

    The mode is classified on a coarse trajectory the run records for it (50 frames/s,
    :data:`pdamper.run.MODE_FPS`; not stored).

    A numerically failed case is not an exception for the sweep: it returns ``failed`` with
    the message, so the other cases go on and the failure is reported.
    """
    from ..errors import SimulationError
    from ..run import run_case

    try:
        res = run_case(case, until_steady=until_steady, checked=checked)
    except SimulationError as exc:
        return {"failed": str(exc)}
    return _summary(res, keep)


def run_many(cases, keep: str = "signals", until_steady: float | None = None, checked: bool = False) -> list[dict]:
    """:func:`run_one` of every case of ``cases``, the GPU's cases together in one batch
    (:func:`pdamper.run.run_cases`); a failed case is ``{"failed": message}``."""
    from ..run import run_cases

    return [{"failed": str(r)} if isinstance(r, Exception) else _summary(r, keep)
            for r in run_cases(cases, until_steady=until_steady, checked=checked)]


def _summary(res, keep: str) -> dict:
    """What the store keeps of a run (:func:`run_one`)."""
    from .store import signal_arrays

    s = res.summary()
    out = {
        "eta_star": s["eta_star"],
        "energy_per_cycle_J": s["energy_per_cycle_J"],
        "ledger_dissipated_per_cycle_J": s["ledger_dissipated_per_cycle_J"],
        "energy_balance_error": s["energy_balance_error"],
        "velocity_amplitude_m_s": float(res.analysis.velocity_amplitude_m_s) if res.analysis is not None else math.nan,
        "effective_mass_kg": s["effective_mass_kg"],
        "equivalent_damping_N_s_per_m": s["equivalent_damping_N_s_per_m"],
        "container_mass_kg": s["container_mass_kg"],
        "eta_star_error": s.get("eta_star_error", math.nan),
        "steady": float(s["steady"]) if "steady" in s else math.nan,
        "cycles_run": s.get("cycles_run", math.nan),
        "steps": int(s["steps"]),
        "wall_time_s": s["wall_time_s"],
        "mode": s.get("mode", "unknown"),
        "mode_features": s.get("mode_features", {}),
    }
    if keep != "none":
        out["signals"] = signal_arrays(res.signals, res.energy, keep)
    return out


def run_cases_of(items, run, on_result, **kw):
    """Run the ``(key, point, seed, case)`` items, points of a :class:`SweepSpec` (checked when it
    was made; ``run`` is told so too, and what their check warned of is said first: ``spec``, or
    ``specs`` by item, in ``kw``): the GPU's cases in batches
    (:func:`~pdamper.studies.executor.execute_batches` over :func:`run_many`), the others on the
    Dask executor (:func:`~pdamper.studies.executor.execute` of ``run``, a one-case function);
    ``kw`` are the executor's options (``workers``, ``scheduler``, ``progress``, ``total``, ``done``,
    ``costs``, ``keep``, ``until_steady``)."""
    import functools

    from ..run import on_gpu
    from .executor import execute, execute_batches

    import warnings

    keep = kw.pop("keep", "signals")
    until_steady = kw.pop("until_steady", None)
    spec = kw.pop("spec", None)
    said = []
    for spec, it in zip(kw.pop("specs", None) or [spec] * len(items), items):
        said += [s for s in (spec.cautions([it[1]]) if spec is not None else ()) if s not in said]
    for category, message in said:
        warnings.warn(message, category, stacklevel=3)
    gpu = [it for it in items if on_gpu(it[3])]
    cpu = [it for it in items if not on_gpu(it[3])]
    if gpu:
        from ..run import check_device

        check_device("cuda")
        execute_batches(gpu, functools.partial(run_many, keep=keep, until_steady=until_steady, checked=True),
                        on_result,
                        progress=kw.get("progress"), total=kw.get("total"), done=kw.get("done", 0),
                        costs=kw.get("costs"))
    if cpu:
        execute(cpu, run, on_result, **kw)


def theory_attrs(case: Case) -> dict:
    """The theory's numbers for a base case: N_p,max, the clearance h and X_opt (dataset attributes)."""
    from .. import theory
    from ..analysis.modes import case_clearance, floor_capacity

    _, h = case_clearance(case)
    return {"max_particles": int(floor_capacity(case)), "clearance_m": h,
            "x_opt_m": float(theory.optimal_stroke(h)) if math.isfinite(h) and h > 0 else float("nan")}


def add_theory(ds, base: Case):
    """Put the theory's X_opt on ``ds`` as a variable ``x_opt`` [m] over the axes other than the
    stroke (a filling, a container size or a radius moves X_opt; the stroke does not), when the
    sweep has such axes; a stroke sweep keeps the attribute ``x_opt_m`` alone."""
    import xarray as xr

    dims = [d for d in ds["eta_star"].dims if d not in ("seed", "stroke")]
    if not dims:
        return ds
    keys = [ds[d].attrs.get("config_key", d) for d in dims]
    grids = np.meshgrid(*[ds[d].values for d in dims], indexing="ij")
    xo = np.full(grids[0].shape, np.nan)
    for idx in np.ndindex(xo.shape):
        point = {k: g[idx].item() for k, g in zip(keys, grids)}
        try:
            xo[idx] = theory_attrs(replace(base, point))["x_opt_m"]
        except InputError:
            pass  # a point that is no valid case has no X_opt
    ds["x_opt"] = xr.DataArray(xo, dims=dims, attrs={"units": "m", "long_name": "optimal stroke X_opt (theory)"})
    return ds


def run_sweep(spec: SweepSpec, path, *, workers: int | None = None, scheduler: str | None = None,
              progress: bool | None = None, keep: str = "signals", history: str | None = None, repair: bool = False,
              until_steady: float | None = None):
    """Run every case of ``spec`` not yet in the store at ``path``; return the results dataset.

    Cases already in the store are not run again (resume after an interruption). Each case is
    written to the store as soon as it finishes. ``workers`` local processes (default: all
    cores) or an existing Dask cluster at ``scheduler``. ``keep``: what of each case's signals
    the store keeps (:data:`pdamper.studies.store.KEEP`). ``history``: the command line, for the
    dataset's ``history`` attribute. A case file that is not a case record is set aside (renamed
    ``.bad``, warned) and its case computed again; ``repair`` rebuilds a lost ``store.json`` from
    ``spec`` and the case files. ``until_steady``: every case stops early at this error of eta*
    (:func:`pdamper.run.run_case`; the store keeps the setting and refuses to mix).
    """
    import functools

    from .cost import finished, learned_costs
    from .store import ResultStore

    import warnings

    from ..run import on_gpu

    if scheduler is None and not on_gpu(spec.base):  # local worker processes (a GPU batch runs in this one)
        from .executor import check_main_guard

        check_main_guard("run_sweep")  # before the store is made: an unguarded script leaves nothing behind
    store = ResultStore.create_or_open(path, spec, attrs=theory_attrs(spec.base), history=history, repair=repair,
                                       until_steady=until_steady)
    spec = store.on_grid(spec)
    for f, why in store.set_aside_bad():
        warnings.warn(f"{f}: not a case record ({why}); set aside as {Path(f).name}.bad, the case is computed again",
                      stacklevel=2)
    items = spec.items()
    todo = [(k, p, s, spec.case(p, s)) for k, p, s in items if not store.has(k)]
    if todo:
        costs = learned_costs(todo, {}, {None: finished(store, spec)} if len(todo) < len(items) else {})
        run = functools.partial(run_one, keep=keep, until_steady=until_steady, checked=True)
        run_cases_of(todo, run, store.save, workers=workers, scheduler=scheduler, progress=progress, total=len(items),
                     done=len(items) - len(todo), costs=costs, keep=keep, until_steady=until_steady, spec=spec)
    ds = add_theory(store.dataset(), store.case())
    store.write_outputs(ds)
    return ds


def open_results(path):
    """The results of a sweep as an ``xarray.Dataset``: ``path`` is a store directory or a
    ``results.nc`` file. Nothing is written (a store opened while its sweep runs shows the cases
    finished so far)."""
    from ..io.files import read_dataset
    from .store import ResultStore

    p = checked_file(path, "results file or store directory", directory_ok=True,
                     missing="{path}: no such results file or store directory")
    if p.is_dir():
        store = ResultStore.open(p)
        ds = store.dataset()
        if "x_opt_m" not in ds.attrs:  # a store of an earlier pdamper keeps no theory numbers
            ds.attrs.update(theory_attrs(store.case()))
        return add_theory(ds, store.case())
    return read_dataset(p, "a sweep's results.nc")
