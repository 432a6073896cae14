"""Exceptions that speak to the user.

Every problem a user can fix (a bad argument, a malformed record, a non-physical
parameter) raises :class:`InputError`. Its message names what is wrong, the value
seen and what is allowed; the CLI prints it on one line and exits with code 2.
A simulation that goes numerically unstable raises :class:`SimulationError`
with the time, the particle and a suggested fix.
"""

from __future__ import annotations

__all__ = ["PdamperError", "InputError", "SimulationError"]


class PdamperError(Exception):
    """Base class of every error pdamper raises on purpose."""


class InputError(PdamperError, ValueError):
    """Bad input: the message says which field, what value, and what is allowed."""


class SimulationError(PdamperError, RuntimeError):
    """A run that cannot continue (instability, NaN); the message suggests a fix."""
