"""Shared pieces of the CLI: the command group, the quantity parameter type, error handling."""

from __future__ import annotations

import functools
import json
import sys

import click

from .. import __version__
from ..errors import InputError, SimulationError
from ..units import parse_quantity

__all__ = ["main", "Quantity", "user_errors", "echo_json"]


class _Group(click.Group):
    """Command group that turns user-fixable errors into one-line messages with exit code 2."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except (InputError, SimulationError) as exc:
            fail(str(exc))


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(__version__, prog_name="pdamper")
def main():
    """pdamper: design and simulate horizontally driven particle dampers.

    Quantities accept units as you type them (120mm, 2Hz, 3deg, 149g) or plain SI.
    """


class Quantity(click.ParamType):
    """A click parameter that reads a physical quantity with units and returns SI floats."""

    name = "quantity"

    def __init__(self, dimension: str):
        self.dimension = dimension

    def convert(self, value, param, ctx):
        if isinstance(value, float):
            return value
        label = f"--{param.name.replace('_', '-')}" if param is not None else self.dimension
        try:
            return parse_quantity(value, self.dimension, name=label)
        except InputError as exc:
            # BadParameter exits with code 2; we want the message only once.
            raise click.UsageError(str(exc), ctx) from None

    def get_metavar(self, param, ctx=None):  # noqa: D401 - click API
        return self.dimension.upper()


def user_errors(func):
    """Decorator for command bodies: InputError/SimulationError become ``Error: msg`` and exit 2."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        try:
            return func(*args, **kwargs)
        except (InputError, SimulationError) as exc:
            fail(str(exc))

    return wrapper


def fail(message: str, code: int = 2):
    """Print ``Error: message`` on one line to stderr and exit with ``code`` (no traceback)."""
    click.echo(f"Error: {' '.join(str(message).split())}", err=True)
    sys.exit(code)


def echo_json(obj) -> None:
    """Print one JSON object (NaN/inf written as null) to stdout."""
    click.echo(json.dumps(_clean(obj), indent=2, sort_keys=False))


def _clean(obj):
    import math

    import numpy as np

    if isinstance(obj, dict):
        return {str(k): _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return [_clean(v) for v in obj.tolist()]
    if isinstance(obj, (np.floating, float)):
        v = float(obj)
        return v if math.isfinite(v) else None
    if isinstance(obj, np.integer):
        return int(obj)
    if isinstance(obj, np.bool_):
        return bool(obj)
    return obj
