"""Exceptions that speak to the user, and the two helpers every message is written with.

Every problem a user can fix (a bad argument, a malformed record, a non-physical
parameter) raises :class:`InputError`. Its message names what is wrong, the value
seen and what is allowed; the CLI prints it on one line and exits with code 2.
A simulation that goes numerically unstable raises :class:`SimulationError`
with the time, the particle and a suggested fix.

A message quotes a value with :func:`shown` (the value as written, cut to a few dozen characters
with its length said, numbers in plain digits: ``0.0``, never ``np.float64(0.0)``, never a 5,000-digit
numeral) and checks a file it is about to read with :func:`checked_file` (a name of any length or
encoding, a missing file or a directory give one line naming the file, not an ``OSError``).
"""

from __future__ import annotations

import errno
import math
import numbers
import os
import re
from pathlib import Path

__all__ = ["PdamperError", "InputError", "SimulationError", "shown", "shown_path", "checked_file", "resolved", "read_text_file",
           "unreadable_file"]


class PdamperError(Exception):
    """Base class of every error pdamper raises on purpose."""


class InputError(PdamperError, ValueError):
    """Bad input: the message says which field, what value, and what is allowed."""


class SimulationError(PdamperError, RuntimeError):
    """A run that cannot continue (instability, NaN); the message suggests a fix."""


_CONTROL = re.compile(r"[\x00-\x1f\x7f]")

#: Characters of a text (or digits of a numeral) a message quotes before it cuts.
SHOWN_LIMIT = 60


def _number(x) -> str:
    """A number in plain digits: a float in the shortest digits that read back to it, as a TOML
    file writes it (``-1.0``, ``0.01``, ``1e+300``, ``nan``); an integer of more than
    :data:`SHOWN_LIMIT` digits by its size (Python refuses to print one over 4,300 digits)."""
    if isinstance(x, numbers.Integral):
        x = int(x)
        if x.bit_length() > 3.33 * SHOWN_LIMIT:  # more digits than a message quotes (str() refuses > 4300)
            return f"{'-' if x < 0 else ''}an integer of about {int(x.bit_length() * math.log10(2)) + 1} digits"
        return str(x)
    return repr(float(x))


def shown(value, limit: int = SHOWN_LIMIT) -> str:
    """``value`` as an error message quotes it (the reader's ``{value!r}``, made safe):

    - a number in plain digits, numpy or not: ``np.float64(0.5)`` -> ``0.5``, ``np.int64(3)`` -> ``3``,
      ``True`` -> ``True``; an integer of thousands of digits by its size;
    - a text quoted as Python quotes it, cut after ``limit`` characters with its length said
      (``'aaaa...'... (5000 characters)``);
    - a list, tuple or table with its items shown the same way, at most 4 of them;
    - a numpy array by its first values and its size; anything else by its cut ``repr``.

    >>> import numpy as np
    >>> shown(np.float64(0.0)), shown(0.01), shown("13mm"), shown([np.int64(1), 2.5])
    ('0.0', '0.01', "'13mm'", '[1, 2.5]')
    >>> shown("x" * 100)
    "'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx'... (100 characters)"
    """
    if isinstance(value, bool) or value is None:
        return repr(value)
    if type(value).__module__ == "numpy" and getattr(value, "ndim", 1) == 0 and hasattr(value, "item"):
        value = value.item()  # a numpy scalar: the Python number it holds
        if isinstance(value, bool):
            return repr(value)
    if isinstance(value, numbers.Real):
        return _number(value)
    if isinstance(value, numbers.Complex):
        return f"{_number(value.real)}{'+' if value.imag >= 0 else '-'}{_number(abs(value.imag))}j"
    if isinstance(value, (str, bytes)):
        if len(value) <= limit:
            return repr(value)
        return f"{value[:limit]!r}... ({len(value)} {'characters' if isinstance(value, str) else 'bytes'})"
    if isinstance(value, (list, tuple)):
        inner = ", ".join(shown(v, limit) for v in value[:4]) + (f", ... ({len(value)} items)" if len(value) > 4 else "")
        return f"[{inner}]" if isinstance(value, list) else f"({inner}{',' if len(value) == 1 else ''})"
    if isinstance(value, dict):
        items = list(value.items())
        inner = ", ".join(f"{shown(k, limit)}: {shown(v, limit)}" for k, v in items[:4])
        return "{" + inner + (f", ... ({len(items)} keys)" if len(items) > 4 else "") + "}"
    if type(value).__module__ == "numpy" and hasattr(value, "tolist") and hasattr(value, "size"):
        flat = value.ravel()[:4].tolist() if value.size else []
        inner = ", ".join(shown(v, limit) for v in flat)
        return f"[{inner}{', ...' if value.size > 4 else ''}] ({value.size} values)"
    text = repr(value)
    return text if len(text) <= 2 * limit else f"{text[:2 * limit]}... ({len(text)} characters)"


def shown_path(path, limit: int = 2 * SHOWN_LIMIT) -> str:
    """A file's name as a message prints it: in full up to ``limit`` characters, else its start and
    its end around ``...`` with its length said (a 5,000-character name is not quoted whole); bytes
    that are not text (a name from a file system of another encoding) are shown escaped."""
    text = os.fsdecode(path) if isinstance(path, bytes) else str(path)
    text = text.encode("utf-8", "backslashreplace").decode("utf-8")  # bytes of another encoding, escaped
    text = _CONTROL.sub(lambda m: f"\\x{ord(m.group()):02x}", text)  # a newline in a name keeps the message one line
    if len(text) <= limit:
        return text
    half = limit // 2
    return f"{text[:half]}...{text[-half:]} ({len(text)} characters)"


def _os_words(exc: BaseException) -> str:
    """Why the system refuses a file name or a file, in words."""
    if isinstance(exc, ValueError):  # "embedded null byte"
        return "the file name holds a NUL character, which no file name can"
    if isinstance(exc, UnicodeError):
        return "the file name is not valid text in this system's encoding"
    no = getattr(exc, "errno", None)
    return {
        errno.ENAMETOOLONG: "the file name is too long for the file system "
                            f"(at most {_name_max()} characters a name, {_path_max()} a path)",
        errno.ENOENT: "no such file",
        errno.ENOTDIR: "a part of the path is not a folder",
        errno.EACCES: "permission denied",
        errno.EPERM: "permission denied",
        errno.ELOOP: "too many symbolic links (a link loop)",
        errno.EISDIR: "it is a directory",
        errno.EIO: "an input/output error of the device",
    }.get(no, getattr(exc, "strerror", None) or type(exc).__name__)


def _name_max() -> int:
    try:
        return os.pathconf("/", "PC_NAME_MAX")
    except (OSError, ValueError, AttributeError):
        return 255


def _path_max() -> int:
    try:
        return os.pathconf("/", "PC_PATH_MAX")
    except (OSError, ValueError, AttributeError):
        return 4096


def unreadable_file(path, exc: BaseException, what: str = "file") -> "InputError":
    """The :class:`InputError` of a file that cannot be opened or read (``exc`` the ``OSError``,
    ``ValueError`` or ``UnicodeError`` the system raised), naming it with :func:`shown_path`."""
    return InputError(f"cannot read the {what} {shown_path(path)}: {_os_words(exc)}")


def resolved(path, base=None) -> Path:
    """``path`` made absolute (relative to ``base``, default the working directory) and resolved
    where the system can; a name it refuses (a NUL character, too long, a link loop) is kept as
    given, for :func:`checked_file` to say what is wrong with it when it is read."""
    p = Path(os.fsdecode(path) if isinstance(path, bytes) else path).expanduser()
    p = p if p.is_absolute() else Path(base if base is not None else Path.cwd()) / p
    try:
        return p.resolve()
    except (OSError, RuntimeError, ValueError):
        return p


def checked_file(path, what: str = "file", *, directory_ok: bool = False, missing: str | None = None) -> Path:
    """``path`` as a :class:`~pathlib.Path` once it names an existing file (or a folder, with
    ``directory_ok``); else an :class:`InputError` naming it (``what``: ``"record file"``,
    ``"config file"``): not found (``missing``, a message with ``{path}`` in it, says it otherwise
    than "``what`` not found: ..."), a folder, or a name the system refuses (too long, a NUL
    character, bytes of another encoding, a link loop, no permission), never an ``OSError``."""
    try:
        p = Path(os.fsdecode(path) if isinstance(path, bytes) else path)
        st = os.stat(p)
    except FileNotFoundError:
        raise InputError(missing.replace("{path}", shown_path(path)) if missing else
                         f"{what} not found: {shown_path(path)}") from None
    except (OSError, ValueError, UnicodeError) as exc:
        raise unreadable_file(path, exc, what) from None
    import stat

    if stat.S_ISDIR(st.st_mode):
        if not directory_ok:
            raise InputError(f"{shown_path(path)} is a directory; give the {what}")
    elif not stat.S_ISREG(st.st_mode):  # reading a pipe would wait for a writer for ever
        raise InputError(f"{shown_path(path)} is not a regular file (a pipe, a device or a socket); give the {what}")
    return p


def read_text_file(path, what: str = "file") -> tuple[Path, str]:
    """``(path, its text)`` of the UTF-8 text file ``path`` (:func:`checked_file` first), or an
    :class:`InputError` naming it: not UTF-8 (the byte), or a file the system cannot read."""
    p = checked_file(path, what)
    try:
        return p, p.read_text(encoding="utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"cannot read {what} {shown_path(p)}: byte {exc.start} is not UTF-8 text; save it "
                         "as UTF-8") from None
    except OSError as exc:
        raise unreadable_file(p, exc, what) from None
