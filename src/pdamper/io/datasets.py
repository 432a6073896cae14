"""One run as an ``xarray.Dataset``: what :meth:`pdamper.run.RunResult.to_dataset` returns.

The Dataset labels what a run recorded, as a scientist would store it (CF-style ``units`` and
``long_name`` on every variable, the case in the attributes):

- dimension ``time`` [s], the centre of each sample interval, its coordinate (``time_end``, the
  interval's end, beside it): the driving force ``force`` [N] and the container motion
  ``velocity`` [m s-1] (interval means) and ``position`` [m] (at the centre), as
  :class:`~pdamper.recorders.signals.Signals`; the energy ledger ``energy_<part>`` [J] at the
  interval ends (:class:`~pdamper.recorders.energy.EnergyLedger`: every array it holds, so parts
  a newer ledger adds come along); on a coupled structure ``structure_<quantity>`` at the
  interval ends too (displacement [m], velocity [m s-1], work and losses [J]; the modal
  coordinates along ``mode``);
- dimensions ``frame_time`` [s], ``sphere`` and ``axis`` (x, y, z; container frame) when the run
  recorded a trajectory: ``sphere_position`` [m], ``sphere_velocity`` [m s-1], ``sphere_spin``
  [rad s-1], ``sphere_radius`` [m], ``container_position`` [m], ``container_velocity`` [m s-1];
- attributes: ``config`` (the case as a config file: ``pdamper.config.loads_case(ds.attrs["config"])``
  is the case again), ``case`` (its one-line description), the run's summary numbers (``eta_star``,
  ``energy_per_cycle_J``, ``steps`` ...) and ``pdamper_version``.

Nothing here knows the simulator: the arrays are taken as they are (duck-typed), so this module
stays in :mod:`pdamper.io`; the Dataset is written with :func:`pdamper.io.files.write_dataset`.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

__all__ = ["run_dataset"]

_SIGNALS = {"force": ("N", "driving force on the container along the drive, interval mean"),
            "velocity": ("m s-1", "container velocity along the drive, interval mean"),
            "position": ("m", "container position along the drive at the interval centre")}
_STRUCTURE_UNITS = {"displacement": "m", "velocity": "m s-1", "response_displacement": "m", "external_work": "J",
                    "damping_loss": "J", "mechanical_energy": "J", "modal_coordinates": "1"}
_TRAJECTORY = {"position": ("sphere_position", "m", "sphere centre, container frame"),
               "velocity": ("sphere_velocity", "m s-1", "sphere velocity, container frame"),
               "spin": ("sphere_spin", "rad s-1", "sphere angular velocity, container frame"),
               "container_position": ("container_position", "m", "container displacement x_c d"),
               "container_velocity": ("container_velocity", "m s-1", "container velocity v_c d")}


def _attr(value):
    """A value a netCDF attribute holds (numbers, text), or None to leave it out."""
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        return float(value) if math.isfinite(value) else None
    if isinstance(value, str):
        return value
    return None


def run_dataset(*, signals, energy, trajectory=None, structure=None, config_text: str = "", summary=None,
                description: str = "", version: str = ""):
    """The Dataset of one run (module docstring) from its recorded parts: ``signals`` (time,
    time_end, force, velocity, position), the energy ``ledger`` (a dataclass of arrays over its
    ``time``), the ``trajectory`` dict or None, the ``structure`` record or None, the case's config
    text, the summary dict and the description of the case."""
    import xarray as xr

    t = np.asarray(signals.time, dtype=float)
    n = t.size
    coords = {"time": ("time", t, {"units": "s", "long_name": "centre of the sample interval"}),
              "time_end": ("time", np.asarray(signals.time_end, dtype=float),
                           {"units": "s", "long_name": "end of the sample interval"})}
    data = {name: ("time", np.asarray(getattr(signals, name), dtype=float), {"units": u, "long_name": ln})
            for name, (u, ln) in _SIGNALS.items()}
    for f in dataclasses.fields(energy):
        v = getattr(energy, f.name)
        if f.name != "time" and isinstance(v, np.ndarray) and v.shape == (n,):
            data[f"energy_{f.name}"] = ("time", v, {"units": "J", "long_name": f"energy ledger: {f.name}, so far "
                                                                             "(at the interval end)"})
    attrs = {"title": "one pdamper run", "Conventions": "CF-1.8", "config": config_text, "case": description,
             "pdamper_version": version}
    if structure is not None:
        for f in dataclasses.fields(structure):
            v = getattr(structure, f.name)
            if f.name == "time" or v is None:
                continue
            if isinstance(v, np.ndarray) and v.ndim >= 1 and v.shape[0] == n:
                dims = ("time",) if v.ndim == 1 else ("time", "mode")
                data[f"structure_{f.name}"] = (dims, v, {"units": _STRUCTURE_UNITS.get(f.name, "1"),
                                                         "long_name": f"structure: {f.name.replace('_', ' ')} "
                                                                      "(at the interval end)"})
            elif _attr(v) is not None:
                attrs[f"structure_{f.name}"] = _attr(v)
    if trajectory is not None:
        frames = np.asarray(trajectory["time"], dtype=float)
        coords["frame_time"] = ("frame_time", frames, {"units": "s", "long_name": "time of the trajectory frame"})
        coords["axis"] = ("axis", np.array(["x", "y", "z"]), {"long_name": "container frame axis (y up)"})
        for key, (name, unit, long_name) in _TRAJECTORY.items():
            if key in trajectory:
                v = np.asarray(trajectory[key], dtype=float)
                dims = ("frame_time", "sphere", "axis") if v.ndim == 3 else ("frame_time", "axis")
                data[name] = (dims, v, {"units": unit, "long_name": long_name})
        if "radius" in trajectory:
            data["sphere_radius"] = ("sphere", np.asarray(trajectory["radius"], dtype=float),
                                     {"units": "m", "long_name": "sphere radius"})
    for k, v in (summary or {}).items():
        if k not in attrs and _attr(v) is not None:
            attrs[k] = _attr(v)
    return xr.Dataset(data, coords=coords, attrs=attrs)
