"""Shared pieces of the CLI: the command group, the quantity parameter type, error handling."""

from __future__ import annotations

import contextlib
import functools
import json
import os
import sys

import click

from .._version import __version__

import warnings  # noqa: E402


def _format_warning(message, category, filename, lineno, line=None):
    """On the command line a warning is one line, 'warning: ...', without a source path."""
    return f"warning: {message}\n"


warnings.formatwarning = _format_warning
from ..io.files import json_safe
from ..errors import InputError, SimulationError, shown
from ..units import parse_quantity

__all__ = ["main", "OneLineCommand", "Quantity", "ShapeChoice", "parse_set", "parse_sizes", "user_errors", "echo_json", "fail",
           "renamed", "until_steady_option", "device_option"]

# Raised when a group is called without arguments (click >= 8.2): it carries the help text,
# which must be shown as it is, not squeezed into one error line.
_HELP_ERRORS = tuple(e for e in (getattr(click.exceptions, "NoArgsIsHelpError", None),) if e)


class _OneLineUsage:
    """Mixin: click usage errors become one ``Error: ...`` line on stderr with exit code 2."""

    def parse_args(self, ctx, args):
        try:
            return super().parse_args(ctx, args)
        except _HELP_ERRORS:
            raise
        except click.UsageError as exc:
            fail(exc.format_message())


class OneLineCommand(_OneLineUsage, click.Command):
    """A command whose usage errors print one ``Error: ...`` line on stderr, with exit code 2.

    Click would print the usage and a "Try ... --help" hint above the message; for a bad
    value (``--length 12kg``), an unknown option or a missing argument we print only the
    message. It is the default class of every ``@main.command``.
    """


class _Group(_OneLineUsage, click.Group):
    """Command group that turns user-fixable errors into one-line messages with exit code 2.

    Its commands are :class:`OneLineCommand` s; an unknown command or group option is one
    line too.
    """

    command_class = OneLineCommand

    def resolve_command(self, ctx, args):
        try:
            return super().resolve_command(ctx, args)
        except click.UsageError as exc:
            fail(exc.format_message())

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
            v = parse_quantity(value, self.dimension, name=label)
        except InputError as exc:
            # A UsageError (not BadParameter, which would prefix "Invalid value for ...") so the
            # message, which already names the option, is printed once; OneLineCommand makes it
            # one line, and outside pdamper's group click still exits with code 2.
            raise click.UsageError(" ".join(str(exc).split()), ctx) from None
        if self.dimension == "length" and v > 5.0:  # a bare number is metres: 120 is a 120 m container
            raise click.UsageError(f"{label} {value} is {v:g} m, not a damper's size (a number without a unit is "
                                   f"metres); did you mean '{value}mm'?", ctx)
        return v

    def get_metavar(self, param, ctx=None):  # noqa: D401 - click API
        return self.dimension.upper()


class ShapeChoice(click.Choice):
    """The container shapes registered when asked (:data:`pdamper.geometry.SHAPES`): a shape
    registered after the command was built is a choice too."""

    def __init__(self):
        super().__init__((), case_sensitive=True)

    @property
    def choices(self):
        from ..geometry import SHAPES

        return tuple(SHAPES)

    @choices.setter
    def choices(self, value):  # click sets it in __init__; the registry is the answer
        pass


def parse_set(items) -> dict:
    """``["drive.stroke=3mm", "particles.count=8"]`` -> ``{"drive.stroke": "3mm", "particles.count": 8}``.

    The value is read as a TOML value when it is one (``8``, ``0.5``, ``true``, ``[1, 2]``,
    ``"text"``), otherwise kept as text (``3mm``, ``verlet``; also a numeral of more digits than
    Python reads, 4,300: it is then the text, which the key's reader refuses or reads as a name).
    """
    import tomllib

    out = {}
    for item in items:
        key, sep, value = str(item).partition("=")
        key, value = key.strip(), value.strip()
        if not sep or not key:
            raise InputError(f"--set {shown(item)}: write it as section.key=value, e.g. --set numerics.integrator=gear")
        try:
            out[key] = tomllib.loads(f"v = {value}")["v"]
        except ValueError:  # not TOML (tomllib.TOMLDecodeError), or a numeral int() refuses (> 4300 digits)
            out[key] = value
    return out


def parse_sizes(items) -> dict:
    """``--size KEY=VALUE`` items (``side=35mm``): [container] keys of a shape beyond the named
    options, their values as given (the shape reads them with units)."""
    from ..errors import InputError

    out = {}
    for item in items or ():
        key, eq, value = str(item).partition("=")
        if not eq or not key.strip() or not value.strip():
            raise InputError(f"--size {shown(item)}: write KEY=VALUE, a [container] key of the shape, e.g. side=35mm")
        out[key.strip()] = value.strip()
    return out


def size_option(key: str, named: dict) -> str:
    """The option that sets the [container] key ``key``: ``named``'s, else ``--size key=VALUE``."""
    return named.get(key, f"--size {key}=VALUE")


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
    click.echo(json.dumps(json_safe(obj), indent=2, sort_keys=False))




@contextlib.contextmanager
def fraction_bar(desc: str, total: float, unit: str, enabled: bool):
    """A tqdm bar on stderr driven by a fraction done: yields ``progress(fraction)`` (a no-op when
    not ``enabled``) and closes the bar on exit. ``total`` in ``unit`` (cycles, seconds) is what
    the bar counts up to."""
    if not enabled:
        yield lambda fraction: None
        return
    from tqdm import tqdm

    try:
        size = os.get_terminal_size(sys.stderr.fileno())
    except (OSError, ValueError):
        size = os.terminal_size((0, 0))
    known = size.columns > 0 and size.lines > 0  # a pty may report 0 x 0; tqdm would then print nothing
    bar = tqdm(total=total, unit=unit, file=sys.stderr, desc=desc, dynamic_ncols=known,
               ncols=None if known else 80, nrows=None if known else 24, leave=False,
               bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.3g}/{total:.3g} {unit} [{elapsed}<{remaining}]")

    def progress(fraction):
        bar.n = fraction * total
        bar.refresh()

    try:
        yield progress
    finally:
        bar.close()


def column_options(func):
    """The options that map a record's columns (``--time-column`` ... ``--acceleration-column``);
    the command receives them as ``columns`` (role -> name) and ``motion`` (the chosen motion or None)."""
    names = ("time_column", "force_column", "position_column", "velocity_column", "acceleration_column")

    @functools.wraps(func)
    def wrapper(*args, **kw):
        given = {n[:-len("_column")]: kw.pop(n) for n in names}
        chosen = [m for m in ("position", "velocity", "acceleration") if given[m]]
        if len(chosen) > 1:
            raise InputError("give only one of --position-column, --velocity-column, --acceleration-column "
                             f"(got {', '.join('--' + m + '-column' for m in chosen)})")
        return func(*args, columns={r: n for r, n in given.items() if n}, motion=chosen[0] if chosen else None, **kw)

    for role, text in reversed((("time", "Name of the time column (default: time)."),
                                ("force", "Name of the force column (default: force)."),
                                ("position", "Use this column as the position."),
                                ("velocity", "Use this column as the velocity."),
                                ("acceleration", "Use this column as the acceleration."))):
        wrapper = click.option(f"--{role}-column", metavar="NAME", help=text)(wrapper)
    return wrapper


def until_steady_option(func):
    """``--until-steady TOL`` of run, sweep and study (:func:`pdamper.run.run_case`'s ``until_steady``)."""
    from ..analysis.steady import MIN_STEADY_CYCLES

    return click.option(
        "--until-steady", "until_steady", type=click.FloatRange(min=0, min_open=True), metavar="TOL",
        help="Stop a case early once its record is steady and eta*'s standard error over the analysed cycles is "
             f"at most TOL (e.g. 0.01), after at least {MIN_STEADY_CYCLES} analysed cycles; never beyond the "
             "configured cycles. Default: the paper's protocol, all cycles.")(func)


def device_option(func):
    """``--device cpu|cuda`` of run, sweep, study and calibrate (``numerics.device``)."""
    return click.option(
        "--device", type=click.Choice(["cpu", "cuda"]), default=None,
        help="Where the DEM runs: cpu (default) or cuda, the GPU engine: every case of the batch advanced together "
             "on one NVIDIA GPU, each with its own adaptive Gear step (or Verlet's) (needs numba-cuda: pip install -e \".[gpu]\"; docs/engine.md).")(func)


def renamed(new_value, old_value, *, new: str, old: str):
    """The value of option ``new``, or of its old name ``old`` (hidden) with a one-line warning on
    stderr; both given is an error. See docs/names.md."""
    if old_value is None:
        return new_value
    if new_value is not None:
        raise InputError(f"{old} is the old name of {new}; give {new} only")
    click.echo(f"warning: {old} is deprecated; use {new} (same meaning)", err=True)
    return old_value
