"""The unknowns of an ensemble: a file of distributions over case keys (``U.toml``), its Latin
hypercube samples, and a case at one sample.

The file (docs/ensembles.md, docs/config.md) has one ``[[unknown]]`` table per unknown::

    [[unknown]]
    key = "structure.stiffness_scale"
    distribution = "normal"
    mean = 1.0
    std = 0.05

    [[unknown]]
    key = "container.tilt"
    distribution = "uniform"
    low = "0deg"
    high = "0.2deg"

    [[unknown]]
    key = "load.file"
    distribution = "choice"
    values = ["rec1.AT2", "rec2.AT2"]    # relative to this file's folder

Distributions (:data:`DISTRIBUTIONS`): ``normal`` (``mean``, ``std``), ``lognormal`` (``mean``,
``std`` of the quantity itself, > 0), ``uniform`` (``low``, ``high``), ``truncated`` (a normal
``mean``, ``std`` cut to ``low`` .. ``high``), ``choice`` (``values = [...]``, each equally
likely). Values take units as a config file does (``"0.1deg"``, ``"5mm"``); a whole-number key
(``particles.count``, ``initial.seed``) takes whole numbers: ``uniform`` draws each of ``low`` ..
``high`` (both included) equally often, the others are rounded to the nearest whole number; a
text key (``load.file``, ``numerics.integrator``) takes a ``choice``.

Keys: every single-valued config key (``contact.friction``, ``particles.count``,
``container.length``, ``container.tilt`` -- one angle about every axis --, ``initial.seed``,
``structure.stiffness_scale``, ``structure.mass_scale``, ``structure.damping_ratio``, the
``[load]``'s ``scale`` and ``file``, ...), and

- ``contact.pair[A,B].friction`` / ``contact.pair[A,B].restitution`` -- one material pair's
  (``[[contact.pair]]``; made when the case has none for that pair);
- ``structure.modes[K].frequency`` / ``.damping_ratio`` (or ``modal_mass``, ``damper``,
  ``force``, ``response``) -- mode K (0-based, as pdamper's messages count ``structure.modes``)
  of a structure whose modes are given as data.

:func:`sample` draws N samples by a Latin hypercube (:class:`scipy.stats.qmc.LatinHypercube`,
seeded: the same file, N and seed give the same samples) mapped through each distribution's
inverse CDF (:mod:`scipy.stats`); :func:`sample_case` is the base case at one sample, its values
set as ``--set`` sets them (read and checked exactly as in a config file).
"""

from __future__ import annotations

import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..config import MODE_KEY as _MODE, PAIR_KEY as _PAIR, case_with_keys
from ..errors import InputError, shown

__all__ = ["Unknown", "Unknowns", "Samples", "sample", "sample_case", "DISTRIBUTIONS", "KeyKind", "key_kind",
           "variable_name"]

#: The distributions of an unknown and the parameters each takes.
DISTRIBUTIONS = {
    "normal": ("mean", "std"),
    "lognormal": ("mean", "std"),
    "uniform": ("low", "high"),
    "truncated": ("mean", "std", "low", "high"),
    "choice": ("values",),
}
_PARAMS = ("mean", "std", "low", "high", "values")
_TABLE_KEYS = ("key", "distribution") + _PARAMS



# ----------------------------------------------------------------------------- what a key holds

@dataclass(frozen=True)
class KeyKind:
    """What an unknown's key holds: ``kind`` ``"number"``, ``"whole"`` or ``"text"``, its
    ``dimension`` (a :data:`pdamper.units.DIMENSIONS` name, None for a plain number), its SI
    ``unit`` in words (messages; None), ``units`` as a dataset writes them (CF), and ``file``: the
    values are file names (relative to the unknowns' file)."""

    kind: str
    dimension: str | None = None
    unit: str | None = None
    units: str = "1"
    file: bool = False


#: CF units of the schema's dimensions (as the result store writes them).
_CF = {"length": "m", "time": "s", "frequency": "Hz", "mass": "kg", "angle": "rad", "force": "N",
       "velocity": "m s-1", "acceleration": "m s-2", "pressure": "Pa", "density": "kg m-3"}


def _of_spec(spec) -> KeyKind:
    if spec.kind in ("text", "flag") or spec.choices:
        return KeyKind("text")
    if spec.kind == "whole":
        return KeyKind("whole")
    if spec.dimension not in (None, "dimensionless"):
        return KeyKind("number", spec.dimension, units=_CF.get(spec.dimension, "1"))
    return KeyKind("number", None, spec.unit, units=spec.unit.replace("/", " ") + "-1" if spec.unit and "/" in
                   spec.unit else (spec.unit or "1"))


def _load_kind(key: str) -> KeyKind | None:
    """The kind of a ``[load]`` key, from the registered load kinds' fields (``file``: file names)."""
    from ..schema import plain_fields
    from ..structure.loads import LOADS

    if key == "file":
        return KeyKind("text", file=True)
    for cls in LOADS.values():
        for f, s in plain_fields(cls):
            if (s.key or f.name) == key and s.kind in ("number", "whole", "text", "flag"):
                return _of_spec(s)
    return None


def key_kind(key: str) -> KeyKind:
    """What the unknown's ``key`` holds (:class:`KeyKind`), or an :class:`InputError` naming the
    keys an unknown may have."""
    from ..config import SECTIONS, key_spec
    from ..structure.modal import MODE_KEYS

    key = str(key).strip()
    if _PAIR.match(key):
        return KeyKind("number")
    m = _MODE.match(key)
    if m:
        if m.group(2) not in MODE_KEYS:
            raise InputError(f"{key!r}: a mode has {', '.join(MODE_KEYS)}, not {m.group(2)!r}")
        dim = MODE_KEYS[m.group(2)][0]
        return KeyKind("number", None if dim == "dimensionless" else dim, units=_CF.get(dim, "1"))
    if key.startswith(("contact.pair", "structure.modes")):
        raise InputError(f"{key!r}: write a material pair's key as contact.pair[steel,pvc].friction (or "
                         ".restitution), a mode's as structure.modes[0].frequency (0-based)")
    section, _, name = key.partition(".")
    if section == "load":
        if name not in SECTIONS["load"]:
            key_spec(key)  # the unknown-key message, with a suggestion
        kind = _load_kind(name)
        if kind is None:
            raise InputError(f"{key!r} is not a single value of a [load] (a list or a table); an unknown takes "
                             "load.scale, load.file, load.duration, ... (one value)")
        return kind
    try:
        return _of_spec(key_spec(key))
    except InputError as exc:
        raise InputError(str(exc).replace("it cannot be a sweep axis", "it cannot be an unknown")) from None


def variable_name(key: str) -> str:
    """The dataset variable of an unknown: its key with every run of other characters than letters
    and digits as one ``_`` (``contact.pair[steel,pvc].friction`` -> ``contact_pair_steel_pvc_friction``)."""
    return re.sub(r"[^A-Za-z0-9]+", "_", key).strip("_")


# ----------------------------------------------------------------------------- one unknown

def _shown(v, limit: int = 80) -> str:
    """A value as the user wrote it in TOML (text quoted, numbers as typed), cut to ``limit`` characters."""
    if isinstance(v, str):
        out = repr(v)
    elif isinstance(v, bool):
        out = "true" if v else "false"
    elif isinstance(v, (list, tuple)):
        out = "[" + ", ".join(_shown(x, limit) for x in v) + "]"
    elif isinstance(v, dict):
        out = "{" + ", ".join(f"{k if str(k).isidentifier() else repr(str(k))} = {_shown(x, limit)}"
                              for k, x in v.items()) + "}"
    elif isinstance(v, int) and v.bit_length() > 200:  # str() of a huge int raises beyond 4300 digits
        out = f"a whole number of about {int(v.bit_length() * 0.30103)} digits"
    else:
        out = repr(v) if isinstance(v, float) else str(v)
    return out if len(out) <= limit else out[:limit - 3] + "..."


@dataclass(frozen=True, kw_only=True)
class Unknown:
    """One unknown: a case ``key``, its ``distribution`` (:data:`DISTRIBUTIONS`) and the
    distribution's parameters in SI (``mean``, ``std``, ``low``, ``high``; ``values`` of a choice).
    Parameters may be given with units (``mean="0.1deg"``); ``where`` names it in messages (the
    file and the table's number). Checked when made: the parameters the distribution needs and no
    others, std > 0, low < high, a lognormal's mean > 0, a choice's values distinct."""

    key: str
    distribution: str
    mean: float | None = None
    std: float | None = None
    low: float | None = None
    high: float | None = None
    values: tuple = ()
    where: str = "unknown"

    def __post_init__(self):
        w = f"{self.where} (key = {self.key!r})" if isinstance(self.key, str) else self.where
        if not isinstance(self.key, str) or not self.key.strip():
            raise InputError(f"{self.where}: key = {_shown(self.key)}; give the case key it is about, e.g. "
                             "key = \"contact.friction\"")
        object.__setattr__(self, "key", self.key.strip())
        try:
            kind = key_kind(self.key)
        except InputError as exc:
            why = str(exc).removeprefix(f"{self.key!r}: ")
            raise InputError(f"{self.where}: key = {self.key!r}: {why}") from None
        d = self.distribution
        if not isinstance(d, str) or d not in DISTRIBUTIONS:
            import difflib

            near = difflib.get_close_matches(d, list(DISTRIBUTIONS), n=1, cutoff=0.5) if isinstance(d, str) else []
            hint = f"did you mean {near[0]!r}? " if near else ""
            raise InputError(f"{w}: distribution = {_shown(d)}; {hint}choose one of "
                             + ", ".join(repr(k) for k in DISTRIBUTIONS))
        needs = DISTRIBUTIONS[d]
        given = {p for p in _PARAMS if (self.values if p == "values" else getattr(self, p)) not in (None, ())}
        extra = sorted(given - set(needs), key=_PARAMS.index)
        if extra:
            raise InputError(f"{w}: a {d} distribution takes {', '.join(needs)}, not {', '.join(extra)}")
        missing = [p for p in needs if p not in given]
        if missing:
            raise InputError(f"{w}: a {d} distribution needs {', '.join(needs)}; {', '.join(missing)} "
                             f"{'is' if len(missing) == 1 else 'are'} missing, e.g. {_example(d, kind)}")
        if kind.kind == "text" and d != "choice":
            raise InputError(f"{w}: {self.key} is a text (a file, a name): give distribution = \"choice\" with "
                             "values = [...]")
        if d == "choice":
            vals = self.values
            if isinstance(vals, (str, dict)) or not isinstance(vals, (list, tuple)) or not vals:
                raise InputError(f"{w}: values = {_shown(vals)}; give a list of one or more values, e.g. "
                                 f"{_example(d, kind)}")
            read = tuple(self._read(v, kind, f"values[{k}]", w) for k, v in enumerate(vals))
            if len(set(read)) != len(read):
                raise InputError(f"{w}: values = {_shown(list(vals))} lists a value twice; give each once")
            object.__setattr__(self, "values", read)
        else:
            raw = {p: getattr(self, p) for p in needs}  # as written, for messages
            for p in needs:
                object.__setattr__(self, p, self._read(getattr(self, p), kind, p, w, number=True))
            if "std" in needs and not self.std > 0:
                raise InputError(f"{w}: std = {_shown(raw['std'])}; must be > 0 (a fixed value is a --set, not an "
                                 "unknown)")
            if "low" in needs and not self.low < self.high:
                raise InputError(f"{w}: low = {_shown(raw['low'])} and high = {_shown(raw['high'])}; need low < high")
            if d == "lognormal" and not self.mean > 0:
                raise InputError(f"{w}: mean = {_shown(raw['mean'])}; a lognormal's mean must be > 0 (its values are)")
        object.__setattr__(self, "_kind", kind)

    @staticmethod
    def _read(v, kind: KeyKind, name: str, w: str, number: bool = False):
        """One parameter or value, read as the key's values are (SI; whole; text)."""
        from ..units import parse_quantity, to_si

        label = f"{w}: {name}"
        if kind.kind == "text" and not number:
            if isinstance(v, bool):
                return v
            if not isinstance(v, str) or not v.strip():
                raise InputError(f"{label} = {_shown(v)}; give a text in quotes, e.g. \"gear\"")
            return v
        if isinstance(v, bool) or isinstance(v, (list, dict)) or v is None:
            unit = f" with a unit, e.g. {_unit_example(kind)}" if kind.dimension else ""
            raise InputError(f"{label} = {_shown(v)}; give a number{unit}")
        if isinstance(v, int) and abs(v) > 2**63:  # beyond any float a case holds (and str() of it may fail)
            raise InputError(f"{label} = {_shown(v)}; give a number a case can hold, e.g. {_unit_example(kind) if kind.dimension else '1.0'}")
        if kind.kind == "whole" and not number:
            if isinstance(v, float) and v.is_integer():
                v = int(v)
            if not isinstance(v, int):
                raise InputError(f"{label} = {_shown(v)}; the key takes whole numbers: give one, e.g. 3")
            return v
        try:
            if kind.dimension is not None:
                out = parse_quantity(v, kind.dimension, name=label)
            elif kind.unit is not None and isinstance(v, str):
                out = to_si(v, None, unit=kind.unit, name=label)
            else:
                out = parse_quantity(v, "dimensionless", name=label)
        except InputError as exc:
            raise InputError(" ".join(str(exc).split())) from None
        if isinstance(out, int) and abs(out) > 2**53 or not math.isfinite(float(out)):
            raise InputError(f"{label} = {_shown(v)}; give a finite number")
        return float(out) if kind.kind == "number" else out

    @property
    def kind(self) -> KeyKind:
        """What the key holds (:class:`KeyKind`)."""
        return self._kind

    def ppf(self, u: np.ndarray) -> list:
        """The values at the probabilities ``u`` (each in (0, 1)): the distribution's inverse CDF
        (:mod:`scipy.stats`); whole numbers for a whole-number key, the listed values of a choice."""
        from scipy import stats

        u = np.asarray(u, dtype=float)
        d = self.distribution
        if d == "choice":
            idx = np.minimum((u * len(self.values)).astype(int), len(self.values) - 1)
            return [self.values[i] for i in idx]
        if self.kind.kind == "whole" and d == "uniform":
            lo, hi = math.ceil(self.low - 1e-9), math.floor(self.high + 1e-9)
            if hi < lo:
                raise InputError(f"{self.where} (key = {self.key!r}): no whole number lies between low = "
                                 f"{self.low:g} and high = {self.high:g}")
            return [int(v) for v in stats.randint(lo, hi + 1).ppf(u)]
        if d == "normal":
            x = stats.norm(loc=self.mean, scale=self.std).ppf(u)
        elif d == "lognormal":  # mean and std of the quantity: sigma^2 = ln(1 + cv^2), mu = ln(mean) - sigma^2/2
            s2 = math.log1p((self.std / self.mean) ** 2)
            x = stats.lognorm(s=math.sqrt(s2), scale=self.mean * math.exp(-s2 / 2.0)).ppf(u)
        elif d == "uniform":
            x = stats.uniform(loc=self.low, scale=self.high - self.low).ppf(u)
        else:  # truncated normal
            a, b = (self.low - self.mean) / self.std, (self.high - self.mean) / self.std
            x = stats.truncnorm(a, b, loc=self.mean, scale=self.std).ppf(u)
        if self.kind.kind == "whole":
            return [int(round(float(v))) for v in x]
        return [float(v) for v in x]

    def describe(self) -> str:
        """One line: the key and its distribution, in SI."""
        if self.distribution == "choice":
            shown = ", ".join(Path(v).name if self.kind.file else f"{v:g}" if isinstance(v, float) else str(v)
                              for v in self.values)
            return f"{self.key}: one of {shown}"
        unit = f" {self.kind.units}" if self.kind.units not in ("1", "") else ""
        p = DISTRIBUTIONS[self.distribution]
        return f"{self.key}: {self.distribution} " + ", ".join(f"{k} = {getattr(self, k):.4g}{unit}" for k in p)

    def to_dict(self) -> dict:
        """The table of the unknown in SI (what a store keeps and a file holds)."""
        out = {"key": self.key, "distribution": self.distribution}
        for p in DISTRIBUTIONS[self.distribution]:
            out[p] = list(self.values) if p == "values" else getattr(self, p)
        return out


def _unit_example(kind: KeyKind) -> str:
    """An example value of the key's dimension as a person types it ("'3deg'")."""
    from ..units import _example

    return _example(kind.dimension).split(" or ")[0]


def _example(d: str, kind: KeyKind) -> str:
    """The parameters of distribution ``d`` as a file writes them, for messages."""
    if d == "choice":
        return 'values = ["rec1.AT2", "rec2.AT2"]' if kind.kind == "text" else "values = [1, 2, 3]"
    v = _unit_example(kind).replace("'", '"') if kind.dimension else "1.0"
    return {"normal": f"mean = {v}, std = ...", "lognormal": f"mean = {v}, std = ...",
            "uniform": f"low = {v}, high = ...", "truncated": f"mean = {v}, std = ..., low = ..., high = ..."}[d]


# ----------------------------------------------------------------------------- the file

@dataclass(frozen=True)
class Unknowns:
    """The unknowns of an ensemble (:class:`Unknown` each, in the file's order) and the file they
    were read from (``source``, for messages; ``folder`` resolves relative file names)."""

    unknowns: tuple
    source: str = "unknowns"

    def __post_init__(self):
        items = tuple(self.unknowns)
        if not items:
            raise InputError(f"{self.source}: no unknowns; give one or more [[unknown]] tables with key = ... and "
                             "distribution = ...")
        if not all(isinstance(u, Unknown) for u in items):
            raise InputError(f"{self.source}: unknowns must be Unknown(...) objects")
        seen = {}
        for k, u in enumerate(items, 1):
            if u.key in seen:
                raise InputError(f"{self.source}: [[unknown]] #{k} (key = {u.key!r}) repeats #{seen[u.key]}; give "
                                 "each key once")
            seen[u.key] = k
        object.__setattr__(self, "unknowns", items)

    def __iter__(self):
        return iter(self.unknowns)

    def __len__(self):
        return len(self.unknowns)

    @property
    def keys(self) -> tuple:
        """The unknowns' keys, in order."""
        return tuple(u.key for u in self.unknowns)

    def to_list(self) -> list:
        """Every unknown's table (SI)."""
        return [u.to_dict() for u in self.unknowns]

    @classmethod
    def from_tables(cls, tables, *, source: str = "unknowns", folder=None) -> "Unknowns":
        """Unknowns from a list of tables as a file has them (``{"key": ..., "distribution": ...,
        ...}``); ``folder`` resolves the relative file names of a ``load.file`` choice."""
        if isinstance(tables, dict) or not isinstance(tables, (list, tuple)):
            raise InputError(f"{source}: unknown must be [[unknown]] tables (an array of tables), got "
                             f"{_shown(tables)}")
        out = []
        for k, t in enumerate(tables, 1):
            where = f"{source}: [[unknown]] #{k}"
            if not isinstance(t, dict):
                raise InputError(f"{where} = {_shown(t)}; give a table with key = ... and distribution = ...")
            foreign = [x for x in t if x not in _TABLE_KEYS]
            if foreign:
                from ..schema import suggest

                raise InputError(f"{where}: unknown entry {foreign[0]!r}; " + suggest(foreign[0], _TABLE_KEYS))
            for need in ("key", "distribution"):
                if need not in t:
                    raise InputError(f"{where}: {need} is missing; e.g. key = \"contact.friction\", "
                                     "distribution = \"normal\", mean = 0.1, std = 0.02")
            kw = {p: t[p] for p in _PARAMS if p in t}
            if "values" in kw:
                kw["values"] = _files(kw["values"], t.get("key"), folder, where)
            out.append(Unknown(key=t["key"], distribution=t["distribution"], where=where, **kw))
        return cls(tuple(out), source=source)

    @classmethod
    def read(cls, path) -> "Unknowns":
        """The unknowns of the file ``path`` (``U.toml``, the module docstring); every error one line
        naming the file, the table's number and key, the value as written and what is allowed."""
        from ..config import parse_toml
        from ..errors import read_text_file, shown_path

        p, text = read_text_file(path, "unknowns' file (--uncertain)")
        src = shown_path(p)
        data = parse_toml(text, source=src)
        foreign = [k for k in data if k != "unknown"]
        if foreign:
            raise InputError(f"{src}: unknown entry {_shown(foreign[0])}; the file holds [[unknown]] tables only")
        if "unknown" not in data:
            raise InputError(f"{src}: no [[unknown]] tables; give one per unknown, e.g. [[unknown]] key = "
                             "\"structure.stiffness_scale\", distribution = \"normal\", mean = 1.0, std = 0.05")
        return cls.from_tables(data["unknown"], source=src, folder=p.parent)


def _files(values, key, folder, where):
    """A ``load.file`` choice's file names made absolute (relative to ``folder``), each found."""
    if key != "load.file" or not isinstance(values, list):
        return values
    out = []
    for k, v in enumerate(values):
        if not isinstance(v, str) or not v.strip():
            raise InputError(f"{where} (key = 'load.file'): values[{k}] = {_shown(v)}; give a file name in quotes")
        from ..errors import checked_file

        f = Path(v)
        if not f.is_absolute() and folder is not None:
            f = Path(folder) / f
        try:
            f = checked_file(f, "record file", missing="no such file" + (
                f" (looked in {folder})" if folder is not None and not Path(v).is_absolute() else ""))
        except InputError as exc:
            raise InputError(f"{where} (key = 'load.file'): values[{k}] = {_shown(v)}: {exc}") from None
        out.append(str(f.resolve()))
    return out


# ----------------------------------------------------------------------------- the samples

@dataclass(frozen=True)
class Samples:
    """N samples of the unknowns: ``u`` the Latin hypercube's points in [0, 1)^d (N x d), ``columns``
    the values of each unknown (a tuple per key, in the unknowns' order), the ``seed``."""

    unknowns: Unknowns
    u: np.ndarray
    columns: dict
    seed: int

    @property
    def n(self) -> int:
        return int(self.u.shape[0])

    def point(self, i: int) -> dict:
        """Sample ``i``'s values: ``{key: value}``."""
        return {k: self.columns[k][i] for k in self.unknowns.keys}

    def points(self) -> list:
        """Every sample's values, in order."""
        return [self.point(i) for i in range(self.n)]


def sample(unknowns: Unknowns, n: int, seed: int = 0) -> Samples:
    """``n`` samples of ``unknowns`` by a Latin hypercube (:class:`scipy.stats.qmc.LatinHypercube`
    seeded by ``seed``, not scrambled within its strata beyond scipy's default; each unknown's n
    strata of probability 1/n hit exactly once), mapped through each distribution's inverse CDF:
    the same unknowns, ``n`` and ``seed`` give the same samples."""
    from scipy.stats import qmc

    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise InputError(f"--samples {shown(n)}: give a whole number >= 1 of samples, e.g. 64")
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise InputError(f"the samples' seed {shown(seed)}: give a whole number >= 0")
    if not isinstance(unknowns, Unknowns):
        unknowns = Unknowns(tuple(unknowns))
    u = qmc.LatinHypercube(d=len(unknowns), seed=np.random.default_rng(int(seed))).random(int(n))
    columns = {x.key: tuple(x.ppf(u[:, j])) for j, x in enumerate(unknowns)}
    return Samples(unknowns=unknowns, u=u, columns=columns, seed=int(seed))


def sample_case(base, values: dict, *, label: str = "sample"):
    """The case ``base`` with the unknowns' ``values`` (``{key: value}``, SI) set, each read and
    checked as a config file's (:func:`pdamper.config.case_with_keys`); an error names ``label``
    (which sample) and the values."""
    return case_with_keys(base, values, label=label)
