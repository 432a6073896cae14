"""The ``pdamper`` command line: thin commands over the public API.

Each command lives in its own module of this package and registers itself on
:data:`main` (as a :class:`~pdamper.cli.common.OneLineCommand`). Errors a user can
fix -- :class:`pdamper.errors.InputError` and click's usage errors (a bad unit, an
unknown option, a missing argument) -- are printed as one line ``Error: ...`` with
exit code 2, never as a traceback or a usage block.
"""

from __future__ import annotations

from .common import main

# Importing the command modules registers their commands on ``main``.
from . import theory as _theory  # noqa: F401,E402
from . import analyze as _analyze  # noqa: F401,E402
from . import run as _run  # noqa: F401,E402
from . import sweep as _sweep  # noqa: F401,E402
from . import study as _study  # noqa: F401,E402
from . import validate as _validate  # noqa: F401,E402
from . import animate as _animate  # noqa: F401,E402
from . import plot as _plot  # noqa: F401,E402
from . import structure as _structure  # noqa: F401,E402
from . import design as _design  # noqa: F401,E402
from . import reanalyze as _reanalyze  # noqa: F401,E402
from . import campaign as _campaign  # noqa: F401,E402
from . import calibrate as _calibrate  # noqa: F401,E402
from . import fields as _fields  # noqa: F401,E402
from . import transient as _transient  # noqa: F401,E402

__all__ = ["main"]
