"""One warm-up of the kernel cache a test run (issue 41 item 3).

On a cold kernel cache every pytest-xdist worker compiles the same CPU kernels for itself (numba
compiles in the process that first calls a kernel; the cache is read only by later callers), so a
two-worker run compiles each of them twice, a minute of CPU each time. Before the workers start,
the controller (``conftest.pytest_configure``) runs this file in two processes, each running tiny
cases that compile half of the kernel variants the suite uses (Verlet and Gear, the tanh law and
the tangential spring, with and without the ledger by contact type, a bed on a structure under a
load in time); the workers then load them from the cache. Nothing else is shared: a variant the
warm-up does not reach is compiled by the worker that meets it, as before.

Skipped with ``PDAMPER_TEST_WARMUP=0``, without xdist workers (a single-process run compiles only
what its tests use) and when the cache holds the kernels already. ``python tests/kernel_warmup.py
PART PARTS`` runs part PART (0-based) of PARTS.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _cases():
    """``[(label, case, recorders)]``: the variants, cheapest to run, in the order they are shared out."""
    from dem_fixtures import locked_case
    from pdamper.params import Case, HarmonicDrive, ParticleSet
    from pdamper.recorders.contacts import ContactEnergyRecorder
    from pdamper.schema import replace

    rig = Case(particles=(ParticleSet(count=4),), drive=HarmonicDrive(stroke=0.01, frequency=2.0), cycles=1,
               drop_cycles=0)
    quake = locked_case('kind = "ground_acceleration"\ntime = [0, 0.05, 0.1]\nacceleration = [0, 0.5, 0]\n'
                        'duration = "0.1s"')
    out = []
    for method in ("verlet", "gear"):
        for law in ("tanh", "spring"):
            case = replace(rig, {"numerics.integrator": method, "contact.tangential": law})
            out.append((f"{method} {law}", case, ()))
            out.append((f"{method} {law} ledger by contact", case, (ContactEnergyRecorder(),)))
        out.append((f"{method} structure", replace(quake, {"numerics.integrator": method}), ()))
    return out


def run_part(part: int, parts: int) -> None:
    """Run the ``part``-th share of the variants (every ``parts``-th one from ``part`` on)."""
    import warnings

    from pdamper.run import run_case

    warnings.simplefilter("ignore")
    for label, case, recorders in _cases()[part::parts]:
        t = time.perf_counter()
        run_case(case, recorders=list(recorders))
        print(f"warm-up {label}: {time.perf_counter() - t:.1f} s", flush=True)


def needed() -> bool:
    """True when the kernel cache holds no copy of the Verlet or the Gear kernel."""
    from pdamper.engine.warmup import cold
    from pdamper.kernels.gear import run_gear
    from pdamper.kernels.verlet import run_verlet

    return cold(run_verlet) or cold(run_gear)


def warm(parts: int = 2) -> float:
    """Fill the kernel cache in ``parts`` processes at once; returns the wall time [s]. A part that
    fails says so on stderr and leaves its kernels to the tests (which then report the failure)."""
    t = time.perf_counter()
    env = {**os.environ, "PDAMPER_WARMUP": "0", "PYTHONPATH": os.pathsep.join(
        [str(HERE)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    procs = [subprocess.Popen([sys.executable, str(Path(__file__)), str(k), str(parts)], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True) for k in range(parts)]
    for p in procs:
        out, _ = p.communicate()
        if p.returncode:
            sys.stderr.write(f"kernel warm-up part failed (exit {p.returncode}); the tests compile for themselves:\n"
                             f"{out[-2000:]}\n")
    return time.perf_counter() - t


if __name__ == "__main__":
    sys.path.insert(0, str(HERE))
    run_part(int(sys.argv[1]), int(sys.argv[2]))
