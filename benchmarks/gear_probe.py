"""What sets Gear's step: an instrumented copy of ``run_gear`` that counts, per accepted step of the
driven run, the step length (log bins) and which degree of freedom gave the largest error estimate
(a sphere resting on the floor -- touching it with |v_y| < 5 mm/s --, one touching it while moving,
one off the floor; its position along y, along x/z, or its spin), whether that sphere touches
another sphere, and whether one of its pair contacts opened or closed within the step. ``--mode 1`` leaves the y error of the resting spheres out of the error control (the
most a floor held as a constraint could give the step control), ``--mode 2`` every error of the
resting spheres (unstable: shows the control is needed there), ``--mode 3`` adds a linearly
implicit normal force (the Hertz force of every touching pair and floor contact linearised in the
overlap at the corrected positions, stiffness only, one Gauss-Seidel sweep) inside Gear's step:
the second candidate of issue 23 in its simplest form.

    python benchmarks/gear_probe.py examples/cuboid_36.toml --stroke 3mm --cycles 6 [--mode 1]
                                    [--set numerics.gear_max_step=5e-4]

The copy is made from ``src/pdamper/kernels/gear.py`` at run time (this script stops if the lines
it instruments changed); with ``--mode 0`` it takes the same steps as the engine (same arithmetic).
A measurement tool, not part of pdamper: docs/integrators.md, "What caps the step below X_opt".
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import math
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

#: the error loop of run_gear runs from this line to the NaN check after it (replaced whole)
_ERR_START, _ERR_END = "        err = 0.0\n", "        if not (err < 1e300):"
_ERR_PROBE = """        err = 0.0
        arg = 0
        for i in range(n):
            resting = pos[i, 1] < rad[i] and math.fabs(vel[i, 1]) < vrest
            kind = 1 if resting else (2 if pos[i, 1] < rad[i] else 3)
            for c in range(3):
                if (mode == 1 and resting and c == 1) or (mode == 2 and resting):
                    pass
                elif math.fabs(dlt[i, c]) > err:
                    err = math.fabs(dlt[i, c])
                    arg = kind * 10 + c
                    arg_i = i
                if not (mode == 2 and resting) and math.fabs(dlt[i, 3 + c]) * rad[i] > err:
                    err = math.fabs(dlt[i, 3 + c]) * rad[i]
                    arg = kind * 10 + 3 + c
                    arg_i = i
"""
_ACC = """        # accept: correct the prediction into the Nordsieck vector
"""
_ACC_PROBE = """        if tn > 0.0:
            b = int(math.floor(math.log10(hs) * 10.0)) + 100
            probe[0, min(max(b, 0), 99)] += 1
            probe[1, arg] += 1
            probe[2, 0] += hs
            touch = 0
            changed = 0
            for i2 in range(n):
                for a2 in range(pairs.row[i2], pairs.row[i2 + 1]):
                    j2 = pairs.second[a2]
                    if i2 == arg_i or j2 == arg_i:
                        rr = (rad[i2] + rad[j2]) ** 2
                        dx = pos[i2, 0] - pos[j2, 0]
                        dy = pos[i2, 1] - pos[j2, 1]
                        dz = pos[i2, 2] - pos[j2, 2]
                        now = dx * dx + dy * dy + dz * dz < rr
                        dx = nord[0, i2, 0] - nord[0, j2, 0]
                        dy = nord[0, i2, 1] - nord[0, j2, 1]
                        dz = nord[0, i2, 2] - nord[0, j2, 2]
                        before = dx * dx + dy * dy + dz * dz < rr
                        if now:
                            touch = 1
                        if now != before:
                            changed = 1
            probe[2, 1 + touch] += 1
            probe[2, 3 + changed] += 1
        # accept: correct the prediction into the Nordsieck vector
"""
_IMPLICIT_NORMAL = '''

@njit
def _implicit_normal(bodies, dv, hs, pairs, walls):
    """Mode 3 of benchmarks/gear_probe.py: the Hertz normal force of every touching pair and floor
    contact linearised in the overlap at the corrected positions (stiffness only, dF/d delta =
    1.5 k delta^0.5; one Gauss-Seidel sweep), its change added to the position increments dv."""
    pos = bodies.position
    rad = bodies.radius
    inv_m = bodies.inv_mass
    c0h = 0.5 * hs * hs * GEAR_C[0]
    n = pos.shape[0]
    for a in range(pairs.row[n]):
        i = pairs.first[a]
        j = pairs.second[a]
        dx = pos[j, 0] - pos[i, 0]
        dy = pos[j, 1] - pos[i, 1]
        dz = pos[j, 2] - pos[i, 2]
        cut = rad[i] + rad[j]
        d2 = dx * dx + dy * dy + dz * dz
        if d2 >= cut * cut:
            continue
        dist = math.sqrt(d2)
        nx = dx / dist
        ny = dy / dist
        nz = dz / dist
        kl = 1.5 * pairs.stiffness[a] * math.sqrt(cut - dist)
        kk = inv_m[i] + inv_m[j]
        u = (dv[i, 0] - dv[j, 0]) * nx + (dv[i, 1] - dv[j, 1]) * ny + (dv[i, 2] - dv[j, 2]) * nz
        s = c0h * kl * kk
        du = -u * s / (1.0 + s)
        for c in range(3):
            nc = nx if c == 0 else (ny if c == 1 else nz)
            dv[i, c] += du * inv_m[i] / kk * nc
            dv[j, c] -= du * inv_m[j] / kk * nc
    floor = walls.floor
    if floor >= 0:
        for i in range(n):
            delta = rad[i] - pos[i, 1]
            if delta <= 0.0:
                continue
            kl = 1.5 * walls.stiffness[i, floor] * math.sqrt(delta)
            s = c0h * kl * inv_m[i]
            dv[i, 1] -= dv[i, 1] * s / (1.0 + s)
'''

_WRAP = '''

import numpy as _np
PROBE = _np.zeros((3, 100))
MODE = [0]
VREST = [5e-3]


def run_gear(span, bodies, gear, pairs, walls, search, table, drive, samples):
    return run_gear_probe(span, bodies, gear, pairs, walls, search, table, drive, samples, PROBE, MODE[0], VREST[0])
'''


def probe_module(where: Path):
    src = (ROOT / "src" / "pdamper" / "kernels" / "gear.py").read_text()
    for old in ("from ..jit import", "from .contact import", "from .drive import", "from .forces import",
                "from .neighbours import", "from .record import", "from .structure import"):
        assert old in src, f"kernels/gear.py changed: {old!r} not found; update benchmarks/gear_probe.py"
        src = src.replace(old, old.replace("from ..", "from pdamper.").replace("from .", "from pdamper.kernels."))
    i0 = src.index(_ERR_START)
    i1 = src.index(_ERR_END, i0)
    assert "math.fabs(dlt[i, c]) > err" in src[i0:i1], "kernels/gear.py changed: update benchmarks/gear_probe.py"
    src = src[:i0] + _ERR_PROBE + src[i1:]
    for old, new in ((_ACC, _ACC_PROBE),
                     ("def run_gear(span, bodies, gear, pairs, walls, search, table, drive, samples):",
                      "def run_gear_probe(span, bodies, gear, pairs, walls, search, table, drive, samples, probe, mode, "
                      "vrest):")):
        assert old in src, "kernels/gear.py changed: update benchmarks/gear_probe.py"
        src = src.replace(old, new)
    src = src.replace("        arg = 0\n", "        arg = 0\n        arg_i = 0\n", 1)
    call = "        dfx, dfy, dfz, dpf = _implicit_friction(bodies, dlt_x, dlt_a, hs, record, samples.split)\n"
    assert call in src, "kernels/gear.py changed: update benchmarks/gear_probe.py"
    src = src.replace(call, call + "        if mode == 3:\n            _implicit_normal(bodies, dlt_x, hs, pairs, walls)\n")
    src += _IMPLICIT_NORMAL
    f = where / "gear_probe_kernel.py"
    f.write_text(src + _WRAP)
    spec = importlib.util.spec_from_file_location("gear_probe_kernel", f)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _value(text: str):
    """A --set value: a number when it reads as one, else the text (a quantity such as "5mm")."""
    try:
        return int(text)
    except ValueError:
        try:
            return float(text)
        except ValueError:
            return text


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("config")
    ap.add_argument("--stroke", default="3mm")
    ap.add_argument("--cycles", type=float, default=6)
    ap.add_argument("--mode", type=int, default=0, choices=(0, 1, 2, 3))
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    args = ap.parse_args(argv)
    import pdamper.kernels.gear as kg
    from pdamper.config import load_case
    from pdamper.run import run_case
    from pdamper.schema import replace

    with tempfile.TemporaryDirectory() as tmp:
        gp = probe_module(Path(tmp))
        kg.run_gear = gp.run_gear
        gp.MODE[0] = args.mode
        sets = {k: _value(v) for k, v in (s.split("=", 1) for s in args.set)}
        case = replace(load_case(args.config), {"drive.stroke": args.stroke, "run.cycles": args.cycles, **sets})
        s = run_case(case).summary()
    p = gp.PROBE
    acc = p[0].sum()
    lab = {1: "resting on floor", 2: "on floor, moving", 3: "off floor"}
    share: dict = {}
    for k in range(100):
        if p[1, k]:
            w = lab[k // 10] + (" y" if k % 10 == 1 else (" x/z" if k % 10 in (0, 2) else " spin"))
            share[w] = share.get(w, 0) + p[1, k] / acc
    out = {"stroke": args.stroke, "mode": args.mode, "set": sets, "steps": s["steps"],
           "driven steps per s": round(acc / case.drive.duration(case.cycles)),
           "mean driven step [us]": round(p[2, 0] / acc * 1e6, 2),
           "largest error on a sphere touching another": round(p[2, 2] / acc, 3),
           "... whose pair contact opened or closed in the step": round(p[2, 4] / acc, 3),
           "eta*": s["eta_star"], "ledger error": s["energy_balance_error"],
           "largest error at": {k: round(v, 3) for k, v in sorted(share.items(), key=lambda kv: -kv[1])},
           "steps [us]: count": {f"{10 ** ((b - 100) / 10) * 1e6:.2g}-{10 ** ((b - 99) / 10) * 1e6:.2g}": int(p[0, b])
                                  for b in range(100) if p[0, b]}}
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
