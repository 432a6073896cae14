"""The paper's studies (SPEC Sect. 5), each a set of labelled settings swept over strokes.

Every study is a list of ``(label, Case)`` settings built from the paper's four cases (Table 1
materials, mu = 0.1, 0.1 deg tilt; the same as ``examples/*.toml``) with one thing changed;
:func:`run_study` sweeps them all on one cluster and returns one dataset with a ``setting``
dimension (strokes x seeds per setting, each setting its own resumable store).
"""

from __future__ import annotations

import dataclasses
import math
import re
from pathlib import Path

from ..contact import ConstantRestitution, ThorntonRestitution
from ..errors import InputError
from ..geometry import Cylinder
from ..materials import Material

__all__ = ["STUDIES", "study_settings", "run_study"]

def _example(name: str):
    """The paper's case ``cuboid_36``, ``cuboid_44``, ``cylinder_30`` or ``cylinder_42``: Table 1
    materials, mu = 0.1, eps = 0.9, 0.1 deg tilt, 2 Hz, 20 cycles (the defaults of
    :mod:`pdamper.params`; ``examples/<name>.toml`` spell out the same cases)."""
    from ..params import Case, Container, ParticleSet

    shape, n = name.split("_")
    container = Container(geometry=Cylinder()) if shape == "cylinder" else Container()
    return Case(particles=(ParticleSet(count=int(n)),), container=container)


def _with(case, **changes):
    """``case`` with dotted keys replaced (``contact.friction``, ``particles.radius``), by the one
    override mechanism of pdamper (:func:`pdamper.config.with_overrides`)."""
    from ..config import with_overrides

    return with_overrides(case, changes)


def _material(case, **changes):
    m = case.particles[0].material
    return _with(case, **{"particles.material": Material(name=f"{m.name}-mod", **{
        "youngs_modulus": m.youngs_modulus, "poisson_ratio": m.poisson_ratio, "density": m.density, **changes})})


def _tilt(case, axis: int, deg: float):
    t = [math.radians(0.1)] * 3
    t[axis] = math.radians(deg)
    return _with(case, **{"container.tilt": tuple(t)})


def _fig4():
    return [("N_p = 36", _example("cuboid_36")), ("N_p = 44", _example("cuboid_44"))]


def _friction():
    return [(f"{n}, mu = {mu:g}", _with(_example(f"cuboid_{n}"), **{"contact.friction": mu}))
            for n in (36, 44) for mu in (0.01, 0.1, 1.0)]


def _modulus():
    return [(f"E = {e:g} GPa", _material(_example("cuboid_36"), youngs_modulus=e * 1e9)) for e in (3, 208, 405)]


def _density():
    return [(f"rho = {r:g} kg/m3", _material(_example("cuboid_36"), density=float(r))) for r in (1400, 7900, 19250)]


def _restitution():
    base = _example("cuboid_36")
    out = [(f"eps = {e:g}", _with(base, **{"contact.restitution": ConstantRestitution(value=e)}))
           for e in (0.8, 0.9, 0.95)]
    # velocity dependent: elastic-plastic (Thornton) with a hardened-steel yield pressure
    out.append(("eps(v), Thornton p_y = 2 GPa",
                _with(base, **{"contact.restitution": ThorntonRestitution(yield_pressure=2e9)})))
    return out


def _radius():
    return [(f"r = 2.5 mm, N_p = {n}", _with(_with(_example("cuboid_36"), **{"particles.radius": 0.0025}),
                                             **{"particles.count": n}))
            for n in (144, 176)]


def _tilt_study():
    out = []
    for n in (36, 44):
        base = _example(f"cuboid_{n}")
        out.append((f"{n}, baseline 0.1 deg", base))
        out += [(f"{n}, 3 deg about {ax}", _tilt(base, i, 3.0)) for i, ax in enumerate("xyz")]
    return out


def _cylinder():
    return [("cylinder N_p = 30", _example("cylinder_30")), ("cylinder N_p = 42", _example("cylinder_42")),
            ("cuboid N_p = 36", _example("cuboid_36")), ("cuboid N_p = 44", _example("cuboid_44"))]


def _cylinder_tilt():
    out = []
    for n in (30, 42):
        base = _example(f"cylinder_{n}")
        out.append((f"{n}, baseline 0.1 deg", base))
        out += [(f"{n}, 3 deg about {ax}", _tilt(base, i, 3.0)) for i, ax in ((0, "x"), (2, "z"))]
    return out


#: Study name -> (builder of the settings, what it shows).
STUDIES = {
    "fig4": (_fig4, "Fig. 4: eta*(X), DEM vs theory, cuboid with 36 and 44 spheres"),
    "friction": (_friction, "Fig. 6: friction mu = 0.01, 0.1, 1 (36 and 44 spheres)"),
    "modulus": (_modulus, "Sect. 6.1: Young's modulus of the spheres 3, 208, 405 GPa"),
    "density": (_density, "Sect. 6.1: density of the spheres 1400, 7900, 19250 kg/m^3"),
    "restitution": (_restitution, "Sect. 6.1: COR 0.8, 0.9, 0.95 and velocity dependent"),
    "radius": (_radius, "Sect. 6.1: r = 2.5 mm with 144 and 176 spheres (N_p,max = 192)"),
    "tilt": (_tilt_study, "Fig. 7: tilt of 3 deg about x, y, z (36 and 44 spheres)"),
    "cylinder": (_cylinder, "Fig. 9: cylinder with 30 and 42 spheres vs the cuboid"),
    "cylinder-tilt": (_cylinder_tilt, "Fig. 10: cylinder tilted 3 deg about x and z"),
}


def study_settings(name: str):
    """The ``(label, Case)`` settings of study ``name``."""
    try:
        build, _ = STUDIES[name]
    except KeyError:
        import difflib

        near = difflib.get_close_matches(name, STUDIES, n=1)
        hint = f"; did you mean {near[0]!r}?" if near else ""
        raise InputError(f"unknown study {name!r}{hint} Studies: {', '.join(STUDIES)}") from None
    return build()


def _slug(label: str) -> str:
    return re.sub(r"[^A-Za-z0-9.]+", "_", label).strip("_")


def run_study(name, out, *, strokes, seeds, cycles=None, drop_cycles=None, workers=None, scheduler=None,
              progress=None, only=None, keep="signals"):
    """Sweep every setting of study ``name`` (one store per setting under ``out``) on one
    cluster; return the combined dataset with a ``setting`` dimension. ``only``: a list of
    setting labels to run (default: all)."""
    import numpy as np
    import xarray as xr

    import functools

    from .executor import execute
    from .store import ResultStore
    from .sweep import SweepSpec, run_one, theory_attrs

    settings = study_settings(name)
    if only is not None:
        unknown = set(only) - {lbl for lbl, _ in settings}
        if unknown:
            raise InputError(f"study {name!r} has no setting {sorted(unknown)}")
        settings = [(lbl, c) for lbl, c in settings if lbl in only]
    out = Path(out)
    stores, items, total = [], [], 0
    for label, case in settings:
        if cycles is not None:
            case = dataclasses.replace(case, cycles=cycles)
        if drop_cycles is not None:
            case = dataclasses.replace(case, drop_cycles=drop_cycles)
        spec = SweepSpec(base=case, strokes=strokes, seeds=seeds)
        store = ResultStore.create_or_open(out / _slug(label), spec, attrs=theory_attrs(case))
        stores.append((label, store))
        for k, p, s in spec.items():
            total += 1
            if not store.has(k):
                items.append((f"{_slug(label)}--{k}", p, s, spec.case(p, s)))
    by_slug = {_slug(label): store for label, store in stores}

    def save(key, point, seed, result):
        slug, k = key.split("--", 1)
        by_slug[slug].save(k, point, seed, result)

    if items:
        execute(items, functools.partial(run_one, keep=keep), save, workers=workers, scheduler=scheduler,
                progress=progress, total=total, done=total - len(items))
    parts = []
    for label, store in stores:
        ds = store.dataset()
        store.write_outputs(ds)
        ds = ds.assign_coords(setting=label).expand_dims("setting")
        ds["clearance"] = ("setting", [ds.attrs["clearance_m"]], {"units": "m"})
        parts.append(ds)
    combined = xr.concat(parts, dim="setting", combine_attrs="drop_conflicts")
    combined.attrs["study"] = name
    combined.attrs["title"] = STUDIES[name][1]
    combined.attrs["configs"] = "\n\n".join(f"# setting: {lbl}\n{st.meta['config']}" for lbl, st in stores)
    combined["x_opt"] = ("setting", np.array([p.attrs["x_opt_m"] for p in parts]), {"units": "m"})
    buf = combined.to_netcdf(engine="h5netcdf")
    from ..io.files import atomic_write

    atomic_write(out / "study.nc", bytes(buf))
    return combined
