"""Whether a change left the compiled kernels' machine code as it was: the step's cost then cannot
have changed, whatever a busy machine's timings say.

    python benchmarks/kernel_asm.py --baseline OLD_CHECKOUT/src [--case examples/cuboid_36.toml]

Compiles, in two fresh processes with empty kernel caches (numba does not show the code of a
cached function), the integrators of a short run of the case with velocity Verlet and with Gear --
the sources on ``PYTHONPATH`` (this checkout) and those of ``--baseline`` -- and compares the
x86 instructions of ``run_verlet``, ``run_gear`` and ``compute_forces`` with every function they compile
(the instructions of the assembly, not its data directives) with the symbols' mangled names, local
labels and addresses blanked (a renamed function or bundle changes those, not the code; a function
compiled but never called adds a data symbol, not an instruction). The kernel's Python entry wrapper
(numba's ``cpython.`` function, which unboxes the arguments once per call from Python) is compared
apart: a bundle with another field changes it, not the step. Prints, per kernel, the instruction
count of its compiled functions on each side and whether they are identical, and whether the
wrapper is. A
refactor that keeps the arithmetic and the data layout (a bundle of scalars that LLVM takes apart)
gives identical code; otherwise time it (``step_cost.py``, ``gear_step.py --baseline``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
KERNELS = ("run_verlet", "run_gear", "compute_forces")

_CHILD = r"""
import dataclasses, json, re, sys
from pdamper.config import load_case
from pdamper.schema import replace
from pdamper.simulation import Simulation
from pdamper.kernels import forces, gear, verlet

case = replace(load_case(sys.argv[1]), {"run.cycles": 0.05, "run.drop_cycles": 0})
for integrator in ("verlet", "gear"):
    Simulation(dataclasses.replace(case, numerics=dataclasses.replace(case.numerics, integrator=integrator))).run()

def blank(asm):
    # the instructions' symbols and labels blanked; the function names (".type NAME,@function" and
    # "NAME:") kept, so that the listing still splits into its functions
    lines = []
    for line in asm.splitlines():
        if line.startswith("\t") and not line.startswith("\t."):
            line = re.sub(r"_ZN[0-9A-Za-z_$.]+", "SYM", line)
            line = re.sub(r"\.L[A-Za-z0-9_$.]+", "LBL", line)
            line = re.sub(r"0x[0-9a-f]+", "HEX", line)
        lines.append(line)
    return "\n".join(lines)

out = {}
for name, d in (("run_verlet", verlet.run_verlet), ("run_gear", gear.run_gear), ("compute_forces", forces.compute_forces)):
    asm = "\n".join(blank(a) for a in d.inspect_asm().values())
    out[name] = asm
print(json.dumps(out))
"""


def assembly(src: str | None, case: Path) -> dict:
    """name -> blanked assembly of the kernels compiled from the sources ``src`` (None: as imported
    here), in a fresh process with an empty kernel cache."""
    env = dict(os.environ)
    if src:
        env["PYTHONPATH"] = src
    with tempfile.TemporaryDirectory() as cache:
        env["NUMBA_CACHE_DIR"] = cache
        r = subprocess.run([sys.executable, "-c", _CHILD, str(case)], env=env, capture_output=True, text=True,
                           check=True)
    return json.loads(r.stdout.splitlines()[-1])


def _functions(asm: str) -> tuple[list, list]:
    """(the compiled functions' instructions, the Python entry wrapper's) of an assembly listing, each a
    list of instruction lines per function in the listing's order (directives left out)."""
    compiled, wrapper = [], []
    for name in re.findall(r"\.type\s+(\S+),@function", asm):
        i = asm.index("\n" + name + ":")
        j = asm.find(".Lfunc_end", i)
        body = [line for line in asm[i:j if j > 0 else None].splitlines()[1:]
                if line.startswith("\t") and not line.startswith("\t.")]
        (wrapper if "cpython" in name else compiled).append(body)
    return compiled, wrapper


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--baseline", required=True, help="the other checkout's src folder")
    ap.add_argument("--case", type=Path, default=ROOT / "examples" / "cuboid_36.toml")
    args = ap.parse_args(argv)
    this = assembly(os.environ.get("PYTHONPATH"), args.case)
    base = assembly(args.baseline, args.case)
    differ = 0
    for name in KERNELS:
        (ca, wa), (cb, wb) = _functions(this[name]), _functions(base[name])
        same = ca == cb
        differ += not same
        n_a, n_b = sum(map(len, ca)), sum(map(len, cb))
        print(f"{name:16s} instructions this {n_a:6d} baseline {n_b:6d}  {'identical code' if same else 'CODE DIFFERS'}"
              f"; Python entry wrapper {'identical' if wa == wb else 'differs'}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
