"""pdamper: design and simulate horizontally driven particle dampers.

Core objects
------------
- :mod:`pdamper.theory` -- the paper's closed forms: clearance, scattered and
  rolling collect-and-collide laws, X_opt, eta*_max, the bouncing law, operating bounds.
- :mod:`pdamper.analysis` -- the complex power method on any force/motion record.
- :mod:`pdamper.units` -- quantities with units at the edges (``"120mm"``).
- :class:`pdamper.errors.InputError` -- every user-fixable problem.

Reference: "Energy dissipation in horizontally driven particle dampers of low
acceleration intensities" (Nonlinear Dynamics); equation numbers ``(n)`` in the
docstrings refer to it.
"""

from __future__ import annotations

__version__ = "0.1.0"

from .errors import InputError, PdamperError, SimulationError  # noqa: E402
from .units import parse_quantity  # noqa: E402

__all__ = ["__version__", "InputError", "PdamperError", "SimulationError", "parse_quantity"]
