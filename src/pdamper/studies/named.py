"""Studies: labelled settings swept over the same axes, read from study files.

A study file (TOML) says what a study is: its title, the axes every setting is swept over
(``vary``, as ``pdamper sweep --vary``), the figure it wants, and its settings -- each a paper
case (``base = "cuboid_36"``) or a config file (``config = "my_case.toml"``, relative to the study
file) with keys set as in a config file (``set = { "contact.friction" = 0.01 }``) and optionally
the panel of the figure it is drawn in (two fillings: two panels, (a) and (b), as the paper's
figures). The paper's nine studies are study files shipped with pdamper
(``pdamper/studies/data/<name>.toml``; :data:`STUDIES`); a user writes their own the same way::

    title = "friction of my damper"
    vary = ["drive.stroke=2mm:40mm:12"]

    [[setting]]
    label = "mu = 0.05"
    config = "my_damper.toml"
    set = { "contact.friction" = 0.05 }

:func:`run_study` sweeps every setting on one cluster (each setting its own resumable store) and
returns one dataset with a ``setting`` dimension (and a ``panel`` coordinate along it).
"""

from __future__ import annotations

import dataclasses
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

from ..errors import InputError, checked_file, shown, shown_path, unreadable_file

__all__ = ["STUDIES", "PAPER_STUDIES", "Study", "load_study", "study_settings", "run_study", "PAPER_CASES",
           "describe_overrides"]

_DATA = Path(__file__).parent / "data"
#: The paper's four cases a setting can start from (``base = ...``).
PAPER_CASES = ("cuboid_36", "cuboid_44", "cylinder_30", "cylinder_42")
_STUDY_KEYS = ("title", "figure", "vary", "setting")
_SETTING_KEYS = ("label", "base", "config", "set", "panel")
FIGURES = ("sweep",)


def _example(name: str):
    """The paper's case ``cuboid_36``, ``cuboid_44``, ``cylinder_30`` or ``cylinder_42``: Table 1
    materials, mu = 0.1, eps = 0.9, 0.1 deg tilt, 2 Hz, 20 cycles (the defaults of
    :mod:`pdamper.params`; ``examples/<name>.toml`` spell out the same cases)."""
    from ..geometry import SHAPES
    from ..params import Case, Container, ParticleSet

    shape, n = name.split("_")
    container = Container(geometry=SHAPES[shape]())  # the paper's size is each shape's default
    return Case(particles=(ParticleSet(count=int(n)),), container=container)


@dataclass(frozen=True)
class Study:
    """A study read from its file: title, axes (``--vary`` texts), figure and
    ``(label, case, panel)`` settings."""

    name: str
    title: str
    vary: tuple
    figure: str
    settings: tuple
    source: str
    #: ``(label, keys)`` pairs: the config keys each setting's ``set`` names (they tell the settings apart).
    set_keys: tuple = ()


def _suggest(word, allowed) -> str:
    import difflib

    near = difflib.get_close_matches(str(word), list(allowed), n=1, cutoff=0.5)
    return f"did you mean {near[0]!r}? " if near else ""


def load_study(name_or_path) -> Study:
    """The study ``name_or_path``: a name of :data:`STUDIES` or the path of a study file."""
    from ..config import load_case
    from ..schema import replace

    from ..config import parse_toml

    text = str(name_or_path)
    path = Path(text)
    try:
        known, found = (_DATA / f"{text}.toml").exists(), path.exists()
    except (OSError, ValueError):  # a name the system refuses (too long, a NUL character)
        known, found = False, False
        if text.endswith(".toml"):
            checked_file(path, "study file")
    if not text.endswith(".toml") and known:
        path = _DATA / f"{text}.toml"
    elif not found:
        if text.endswith(".toml"):
            raise InputError(f"study file not found: {shown_path(path)}")
        raise InputError(f"unknown study {shown(text)}; {_suggest(text, STUDIES)}Studies: {', '.join(STUDIES)} "
                         "(or give the path of a study file, NAME.toml)")
    path = checked_file(path, "study file")  # a folder or a pipe named NAME.toml: one line, not a wait
    where = shown_path(path) if path.parent != _DATA else f"study {path.stem!r}"
    try:
        data = parse_toml(path.read_text(encoding="utf-8"), source=where)
    except (OSError, UnicodeError) as exc:
        raise unreadable_file(path, exc, "study file") from None
    for key in data:
        if key not in _STUDY_KEYS:
            raise InputError(f"{where}: unknown key {shown(key)}; {_suggest(key, _STUDY_KEYS)}allowed: "
                             + ", ".join(_STUDY_KEYS))
    vary = data.get("vary", ["drive.stroke=0.5mm:50mm:40"])
    if isinstance(vary, str):
        vary = [vary]
    if not isinstance(vary, list) or not all(isinstance(v, str) for v in vary):
        raise InputError(f"{where}: vary = {shown(vary)} must be a list of 'KEY=VALUES' texts, e.g. "
                         "['drive.stroke=0.5mm:50mm:40']")
    figure = data.get("figure", "sweep")
    if figure not in FIGURES:
        raise InputError(f"{where}: figure = {shown(figure)}; choose one of {', '.join(map(repr, FIGURES))}")
    rows = data.get("setting", [])
    if not isinstance(rows, list) or not rows:
        raise InputError(f"{where}: no settings; give one or more [[setting]] tables with label = ... and "
                         "base = 'cuboid_36' (or config = 'case.toml')")
    settings, labels, set_keys = [], set(), []
    for k, row in enumerate(rows):
        what = f"{where}, setting #{k + 1}"
        if not isinstance(row, dict):
            raise InputError(f"{what}: must be a table")
        for key in row:
            if key not in _SETTING_KEYS:
                raise InputError(f"{what}: unknown key {shown(key)}; {_suggest(key, _SETTING_KEYS)}allowed: "
                                 + ", ".join(_SETTING_KEYS))
        label = row.get("label")
        if not isinstance(label, str) or not label:
            raise InputError(f"{what}: give it a label = '...'")
        if label in labels:
            raise InputError(f"{what}: the label {shown(label)} is used twice")
        labels.add(label)
        if ("base" in row) == ("config" in row):
            raise InputError(f"{what} ({label}): give exactly one of base = 'cuboid_36' (a paper case: "
                             f"{', '.join(PAPER_CASES)}) or config = 'case.toml'")
        if "base" in row:
            if row["base"] not in PAPER_CASES:
                raise InputError(f"{what} ({label}): base = {shown(row['base'])} is not a paper case; "
                                 f"{_suggest(row['base'], PAPER_CASES)}choose one of {', '.join(PAPER_CASES)}")
            case = _example(row["base"])
        else:
            cfg = Path(row["config"])
            case = load_case(cfg if cfg.is_absolute() else path.parent / cfg)
        sets = row.get("set", {})
        if not isinstance(sets, dict):
            raise InputError(f"{what} ({label}): set = {shown(sets)} must be a table of config keys, e.g. "
                             "{ \"contact.friction\" = 0.01 }")
        try:
            case = replace(case, sets)
        except InputError as exc:
            raise InputError(f"{what} ({label}): {exc}") from None
        settings.append((label, case, str(row.get("panel", ""))))
        set_keys.append((label, tuple(sets)))
    return Study(name=path.stem, title=str(data.get("title", path.stem)), vary=tuple(vary), figure=figure,
                 settings=tuple(settings), source=str(path), set_keys=tuple(set_keys))


def _builder(name):
    return lambda: [(label, case) for label, case, _ in load_study(name).settings]


def _title(path: Path) -> str:
    return str(tomllib.loads(path.read_text(encoding="utf-8")).get("title", path.stem))


#: The paper's nine studies, in its order (the study files beyond the paper follow them in STUDIES).
PAPER_STUDIES = ("fig4", "friction", "modulus", "density", "restitution", "radius", "tilt", "cylinder", "cylinder-tilt")
#: Study name -> (builder of the settings, what it shows): the paper's studies and the shipped ones
#: beyond it (``vertical``), from their files.
STUDIES = {p.stem: (_builder(p.stem), _title(p))
           for p in sorted(_DATA.glob("*.toml"),
                           key=lambda p: (PAPER_STUDIES.index(p.stem) if p.stem in PAPER_STUDIES else 99, p.stem))}


def study_settings(name: str):
    """The ``(label, Case)`` settings of study ``name`` (a name or a study file)."""
    return [(label, case) for label, case, _ in load_study(name).settings]


def describe_overrides(overrides: dict) -> str:
    """``{"contact.tangential": "spring"}`` -> ``"contact.tangential = spring"`` (several: joined
    with ", "), as a study's title and dataset say them."""
    return ", ".join(f"{k} = {v}" for k, v in overrides.items())


def _check_overrides(study: Study, overrides: dict, axes) -> None:
    """Refuse an override of a key the study varies or one of its settings sets."""
    varied = {a.key for a in axes}
    for key in overrides:
        if key in varied:
            hint = " (give --strokes instead)" if key == "drive.stroke" else ""
            raise InputError(f"--set {key}: study {shown(study.name)} varies {key}; it cannot be set for every "
                             f"setting{hint}")
        for label, keys in study.set_keys:
            if key in keys:
                raise InputError(f"--set {key}: setting {shown(label)} of study {shown(study.name)} sets {key} itself; "
                                 "setting it for every setting would erase what the study compares (write "
                                 "your own study file instead, docs/sweeps.md)")


def _overridden(case, overrides: dict, label: str):
    """``case`` with the command's overrides set; an error names the setting."""
    from ..schema import replace

    if not overrides:
        return case
    try:
        return replace(case, overrides)
    except InputError as exc:
        raise InputError(f"--set, setting {shown(label)}: {exc}") from None


def _slug(label: str) -> str:
    return re.sub(r"[^A-Za-z0-9.]+", "_", label).strip("_")


def run_study(name, out, *, strokes=None, seeds, cycles=None, drop_cycles=None, workers=None, scheduler=None,
              progress=None, only=None, keep="signals", until_steady=None, device=None, overrides=None):
    """Sweep every setting of study ``name`` (a name of :data:`STUDIES` or a study file; one store
    per setting under ``out``) on one cluster; return the combined dataset with a ``setting``
    dimension. ``strokes`` replaces the study's stroke axis; ``only``: a list of setting labels
    to run (default: all); ``until_steady``: every case stops early at this error of eta*
    (:func:`pdamper.run.run_case`); ``device``: ``"cuda"`` runs every case of every setting
    together on the GPU engine (:func:`pdamper.run.run_cases`); ``overrides``: config keys set in
    every setting's case (``{"contact.tangential": "spring"}``, ``pdamper study --set``), after the
    setting's own ``set``. A key the study varies or a setting sets is refused (it would erase what
    the study compares). The overrides are part of each store's configuration: a store made
    without them (or with others) is refused, never mixed."""
    import functools

    import numpy as np
    import xarray as xr

    from .cost import finished, learned_costs
    from .store import ResultStore
    from .sweep import STROKE, SweepSpec, add_theory, parse_axis, run_cases_of, run_one, theory_attrs

    study = load_study(name)
    settings = list(study.settings)
    if only is not None:
        unknown = set(only) - {lbl for lbl, _, _ in settings}
        if unknown:
            raise InputError(f"study {shown(study.name)} has no setting {sorted(unknown)}")
        settings = [s for s in settings if s[0] in only]
    axes = [parse_axis(v) for v in study.vary]
    overrides = dict(overrides or {})
    _check_overrides(study, overrides, axes)
    if strokes is not None:
        axes = [a for a in axes if a.key != STROKE]
    out = Path(out)
    stores, items, total, group_of, measured, specs = [], [], 0, {}, {}, []
    if device is not None:
        from ..run import check_device, on_device

        check_device(device)
    for label, case, _ in settings:
        case = _overridden(case, overrides, label)
        if device is not None:
            case = on_device(case, device)
        if cycles is not None:
            case = dataclasses.replace(case, cycles=cycles)
        if drop_cycles is not None:
            case = dataclasses.replace(case, drop_cycles=drop_cycles)
        spec = SweepSpec(base=case, axes=axes, strokes=strokes, seeds=seeds)
        store = ResultStore.create_or_open(out / _slug(label), spec, attrs=theory_attrs(case), until_steady=until_steady)
        spec = store.on_grid(spec)
        stores.append((label, store, case))
        todo = [(k, p, s) for k, p, s in spec.items() if not store.has(k)]
        total += len(spec.items())
        for k, p, s in todo:
            items.append((f"{_slug(label)}--{k}", p, s, spec.case(p, s)))
            specs.append(spec)
            group_of[items[-1][0]] = label
        if len(todo) < len(spec.items()):  # resumed: its finished cases tell how long this setting's take
            measured[label] = finished(store, spec)
    by_slug = {_slug(label): store for label, store, _ in stores}

    def save(key, point, seed, result):
        slug, k = key.split("--", 1)
        by_slug[slug].save(k, point, seed, result)

    if items:
        run_cases_of(items, functools.partial(run_one, keep=keep, until_steady=until_steady, checked=True), save,
                     workers=workers, scheduler=scheduler, progress=progress, total=total, done=total - len(items),
                     costs=learned_costs(items, group_of, measured), keep=keep, until_steady=until_steady, specs=specs)
    panels = {label: panel for label, _, panel in settings}
    parts = []
    for label, store, case in stores:
        ds = add_theory(store.dataset(), store.case())
        store.write_outputs(ds)
        ds = ds.assign_coords(setting=label).expand_dims("setting")
        ds["clearance"] = ("setting", [ds.attrs["clearance_m"]], {"units": "m"})
        parts.append(ds)
    combined = xr.concat(parts, dim="setting", combine_attrs="drop_conflicts")
    combined = combined.assign_coords(panel=("setting", [panels[str(s)] for s in combined.setting.values]))
    combined.attrs["study"] = study.name
    combined.attrs["title"] = study.title + (f" ({describe_overrides(overrides)})" if overrides else "")
    if overrides:
        combined.attrs["overrides"] = describe_overrides(overrides)
    combined.attrs["configs"] = "\n\n".join(f"# setting: {lbl}\n{st.meta['config']}" for lbl, st, _ in stores)
    combined["x_opt"] = ("setting", np.array([p.attrs["x_opt_m"] for p in parts]), {"units": "m"})
    from ..io.files import write_dataset

    write_dataset(out / "study.nc", combined)
    return combined
