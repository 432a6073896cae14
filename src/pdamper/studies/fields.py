"""The damper's fields from a sweep store or a measured campaign, and their netCDF file.

:func:`build_fields` reads a source -- a sweep's result store (or its ``results.nc``) swept over
``drive.stroke`` and ``drive.frequency`` (or over the stroke alone), or a ``pdamper campaign``
dataset (its ``campaign.nc`` or the folder holding it) -- and makes a
:class:`pdamper.analysis.fields.DamperFields` with its provenance (the source's kind and path,
its configuration and history, the command, the pdamper version). :func:`write_fields` writes it
as CF netCDF, :func:`load_fields` reads it back.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..analysis.fields import FORMAT, DamperFields
from ..errors import InputError, checked_file, shown, shown_path

__all__ = ["build_fields", "write_fields", "load_fields", "open_source"]


def open_source(path):
    """(results dataset, kind) of ``path``: kind ``"sweep"`` (a store directory or its
    ``results.nc``) or ``"campaign"`` (a ``campaign.nc`` or the folder holding one)."""
    from .sweep import open_results

    p = checked_file(path, "store, campaign or results file", directory_ok=True,
                     missing="{path}: no such store, campaign or results file")
    if p.is_dir():
        if (p / "store.json").exists():
            return open_results(p), "sweep"
        if (p / "campaign.nc").exists():
            p = p / "campaign.nc"
        else:
            raise InputError(f"{p}: neither a sweep store (no store.json) nor a campaign folder (no campaign.nc); "
                             "give the --out of 'pdamper sweep' or of 'pdamper campaign'")
    if not p.exists():
        raise InputError(f"{p}: no such store, campaign or results file")
    ds = _read_netcdf(p)
    if ds.attrs.get("format") == FORMAT:
        raise InputError(f"{p}: this is already a damper-fields file; draw it with 'pdamper plot fields {p}'")
    if ds.attrs.get("kind") == "campaign":
        return ds, "campaign"
    if "varied_keys" in ds.attrs and "stroke" in ds.dims:
        return ds, "sweep"
    raise InputError(f"{p}: not the results of a sweep (no varied_keys attribute) nor a campaign (kind = 'campaign'); "
                     "give a sweep store, its results.nc, or a campaign.nc")


def build_fields(source, *, sel: dict | None = None, command: str | None = None) -> DamperFields:
    """The fields of ``source`` (module docstring). ``sel``: ``{dimension: value}`` fixing the
    other dimensions of a sweep (nearest value), e.g. ``{"friction": 0.1}``. ``command``: the
    command line kept as provenance."""
    from .._version import __version__

    ds, kind = open_source(source)
    chosen = []
    for dim, value in (sel or {}).items():
        if dim not in ds.dims:
            raise InputError(f"--sel {dim}: not a dimension of {source}; it has {', '.join(map(str, ds.dims))}")
        ds = ds.sel({dim: value}, method="nearest" if isinstance(value, float) else None)
        chosen.append(f"{dim} = {ds[dim].values.item()!r}")
        ds = ds.drop_vars(dim)
    attrs = {"source_kind": kind, "source": str(Path(source).resolve()),
             "command": command or f"pdamper {__version__}: build_fields({str(source)!r})"}
    if chosen:
        attrs["selected"] = ", ".join(chosen)  # the values taken (the nearest to those asked)
    fields = DamperFields.from_results(ds, attrs=attrs)
    bed = fields.bed_mass
    if not (math.isfinite(bed) and bed > 0):
        raise InputError(f"{source}: no bed mass (attribute bed_mass_kg); eta* and m_eff / m_bed need it")
    return fields


def write_fields(fields: DamperFields, path) -> Path:
    """Write the fields as CF netCDF to ``path`` (atomically); returns the path."""
    from ..io.files import write_dataset

    path = Path(path)
    if path.suffix.lower() != ".nc":
        raise InputError(f"--out {shown(str(path))}: a fields file is netCDF; end its name with .nc")
    if not path.parent.is_dir():
        raise InputError(f"--out {shown(str(path))}: folder {shown(str(path.parent))} does not exist")
    return write_dataset(path, fields.dataset)


def load_fields(path) -> DamperFields:
    """The fields of a file written by :func:`write_fields` (``pdamper fields --out``)."""
    p = checked_file(path, "fields file", missing="{path}: no such fields file; make one with 'pdamper fields STORE "
                                                   f"--out {shown_path(Path(str(path)).name)}'")
    ds = _read_netcdf(p)
    if ds.attrs.get("format") != FORMAT:
        raise InputError(f"{p}: not a damper-fields file (format {shown(ds.attrs.get('format'))}, expected {shown(FORMAT)}); "
                         "make one with 'pdamper fields STORE --out F.nc'")
    try:
        return DamperFields(ds)
    except InputError as exc:
        raise InputError(f"{shown_path(p)}: {exc}") from None


def _read_netcdf(p: Path):
    from ..io.files import read_dataset

    return read_dataset(p, "a sweep's results, a campaign or a fields file")
