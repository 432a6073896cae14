"""pdamper: design and simulate horizontally driven particle dampers.

Steel spheres rolling in one layer on the floor of a horizontally vibrated container: the
paper's closed forms, a DEM engine, and the complex power method for simulated and measured
force/motion records.

Core objects
------------
Describe a case (frozen, keyword-only dataclasses; SI units):

- :class:`Case` -- everything about one run: :class:`ParticleSet` (count, radius, material),
  :class:`Container` (geometry, wall material, tilt), the drive, :class:`ContactModel`
  (friction, restitution), :class:`Numerics` (integrator, time step, neighbour search),
  :class:`Recording` (sample rate, trajectories), :class:`InitialState` (block or scatter,
  jitter, seed), cycles and gravity.
- Geometry: :class:`Cuboid`, :class:`Cylinder`.
- Drive: :class:`HarmonicDrive` (``x_c = X sin(Omega t)``), :class:`SampledDrive` (a motion
  given as samples), :class:`Still`, :class:`CoupledStructure` (the container rides on a
  structure, two-way coupled), :class:`ModalStructure` (a structure of several modes).
- Materials: :class:`Material`, :data:`STEEL_S235`, :data:`PVC`.
- Restitution laws: :class:`ConstantRestitution`, :class:`TabulatedRestitution`,
  :class:`ThorntonRestitution`.

Run it:

- :func:`load_case` -- a TOML config file to a :class:`Case`.
- :func:`run_case` -> :class:`RunResult` (signals, energies, eta*, motion mode);
  :class:`Simulation` -- a case advanced in time, feeding recorders (:mod:`pdamper.recorders`),
  without analysis; :func:`run_cases` -- many cases, those with ``numerics.device = "cuda"``
  together on one GPU.
- :class:`SweepSpec`, :func:`run_sweep` -- a stroke sweep over seeds on all cores or a Dask
  cluster, written to a resumable store; :func:`open_results` -- its labelled dataset.
- :class:`Unknowns`, :func:`run_ensemble` -- the case at Latin hypercube samples of a file of
  distributions over its keys (``U.toml``), resumable, a ``sample`` dimension in its dataset;
  :func:`open_ensemble` -- that dataset.

Evaluate and design:

- :func:`analyze_record`, :func:`complex_power` -- energy per cycle and eta* of a
  force/motion record (paper eqs. 3-5).
- :mod:`theory` -- the paper's closed forms: clearance, scattered and rolling
  collect-and-collide laws, X_opt, eta*_max, the bouncing law, operating bounds.
- :func:`run_decay`, :func:`run_response` -- free decay and frequency response of a structure
  with and without the damper; :func:`design_filling` -- the filling for a stroke.
- :func:`parse_quantity` -- ``"120mm"`` -> ``0.12``.
- :class:`InputError` (bad input, one-line message), :class:`SimulationError` (a run that
  cannot continue).

``import pdamper`` is fast: the objects above are imported on first use (the DEM engine
needs numba, the theory and analysis scipy).

Example
-------
>>> import pdamper
>>> h = pdamper.theory.clearance(0.120, 36, 48)
>>> round(pdamper.theory.optimal_stroke(h) * 1e3, 2)
12.23

Reference: "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities" (Nonlinear Dynamics); equation numbers ``(n)`` in the docstrings refer to it.
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

from ._version import __version__

from .errors import InputError, PdamperError, SimulationError  # noqa: E402
from .units import parse_quantity  # noqa: E402

#: Public name -> module (relative to this package) it is imported from on first use;
#: ``None`` for a submodule.
_LAZY = {
    "Case": "params",
    "ParticleSet": "params",
    "Container": "params",
    "ContactModel": "params",
    "Numerics": "params",
    "Recording": "params",
    "InitialState": "params",
    "Cuboid": "geometry",
    "Cylinder": "geometry",
    "HarmonicDrive": "excitation",
    "SampledDrive": "excitation",
    "Still": "excitation",
    "CoupledStructure": "structure",
    "ModalStructure": "structure",
    "run_decay": "studies.structure",
    "run_response": "studies.structure",
    "design_filling": "design",
    "Material": "materials",
    "STEEL_S235": "materials",
    "PVC": "materials",
    "ConstantRestitution": "contact",
    "TabulatedRestitution": "contact",
    "ThorntonRestitution": "contact",
    "Simulation": "simulation",
    "RunResult": "run",
    "run_case": "run",
    "run_cases": "run",
    "load_case": "config",
    "complex_power": "analysis",
    "analyze_record": "analysis",
    "theory": None,
    "SweepSpec": "studies",
    "run_sweep": "studies",
    "open_results": "studies",
    "Unknowns": "studies.ensemble",
    "run_ensemble": "studies.ensemble",
    "open_ensemble": "studies.ensemble",
}

__all__ = [
    "__version__",
    # describe a case
    "Case", "ParticleSet", "Container", "ContactModel", "Numerics", "Recording", "InitialState",
    "Cuboid", "Cylinder",
    "HarmonicDrive", "SampledDrive", "Still", "CoupledStructure", "ModalStructure",
    "Material", "STEEL_S235", "PVC",
    "ConstantRestitution", "TabulatedRestitution", "ThorntonRestitution",
    # run it
    "load_case", "Simulation", "RunResult", "run_case", "run_cases",
    # sweep it
    "SweepSpec", "run_sweep", "open_results", "Unknowns", "run_ensemble", "open_ensemble",
    # evaluate and design
    "complex_power", "analyze_record", "theory", "run_decay", "run_response", "design_filling",
    # units and errors
    "parse_quantity", "InputError", "SimulationError", "PdamperError",
]


def __getattr__(name: str):
    """Import a public object on first use (PEP 562); see :data:`_LAZY`."""
    try:
        module = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}") from None
    if module is None:
        value = importlib.import_module(f".{name}", __name__)
    else:
        value = getattr(importlib.import_module(f".{module}", __name__), name)
    globals()[name] = value  # later look-ups skip this function
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # for type checkers and IDEs; at run time the names load lazily
    from . import theory
    from .analysis import analyze_record, complex_power
    from .config import load_case
    from .contact import ConstantRestitution, TabulatedRestitution, ThorntonRestitution
    from .design import design_filling
    from .excitation import HarmonicDrive, SampledDrive, Still
    from .structure import CoupledStructure, ModalStructure
    from .studies.ensemble import Unknowns, open_ensemble, run_ensemble
    from .studies.structure import run_decay, run_response
    from .geometry import Cuboid, Cylinder
    from .materials import PVC, STEEL_S235, Material
    from .params import (Case, ContactModel, Container, InitialState, Numerics, ParticleSet,
                         Recording)
    from .run import RunResult, run_case, run_cases
    from .simulation import Simulation
