"""Behaviour fingerprint of the DEM engine: run a fixed set of cases and save (or compare) every
recorded array, so that a refactor can show it changed nothing.

Usage::

    python benchmarks/fingerprint.py save  DIR     # run the cases, write DIR/<name>.npz
    python benchmarks/fingerprint.py compare A B   # compare two saved fingerprints

Cases (6 cycles of 2 Hz, 2 dropped, seed 0 unless said): the 36-sphere cuboid at 3, 14 and
30 mm (Gear), the 44-sphere cuboid at 20 mm with mu = 1 (Gear), the 30-sphere cylinder at 12 mm
(Gear), the 36-sphere cuboid at 14 mm with Verlet, with Thornton's restitution and a trajectory,
with Gonthier's damping as written and a per-pair friction, and the 36-sphere damper on the
example structure (free decay, Verlet). Each file holds the force and velocity signals, the seven
energy-ledger columns, the trajectory and the structure's motion where recorded, eta*, the step
count and the motion mode.

``compare`` prints, per case, whether every array is bit-identical, else the largest difference of
each array that differs and the change of eta*. It uses the public API only (``load_case``,
``run_case``), so the same script runs on the code before and after a change
(``PYTHONPATH=<old checkout>/src python benchmarks/fingerprint.py save old``).
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
EX = ROOT / "examples"

SHORT = {"run.cycles": 6, "run.drop_cycles": 2}

#: name -> (example file, overrides)
CASES = {
    "c36_3mm_gear": ("cuboid_36", {"drive.stroke": "3mm"}),
    "c36_14mm_gear": ("cuboid_36", {"drive.stroke": "14mm"}),
    "c36_30mm_gear": ("cuboid_36", {"drive.stroke": "30mm"}),
    "c44_20mm_mu1_gear": ("cuboid_44", {"drive.stroke": "20mm", "contact.friction": 1.0}),
    "cyl30_12mm_gear": ("cylinder_30", {"drive.stroke": "12mm"}),
    "c36_14mm_verlet": ("cuboid_36", {"drive.stroke": "14mm", "numerics.integrator": "verlet"}),
    "c36_14mm_thornton_traj": ("cuboid_36", {"drive.stroke": "14mm", "recording.trajectory_fps": 50,
                                             "contact.restitution": {"law": "thornton", "yield_pressure": "1.5GPa"}}),
    "c36_14mm_gonthier_pair": ("cuboid_36", {"drive.stroke": "14mm", "contact.damping": "gonthier",
                                             "contact.pair": [{"materials": ["steel", "pvc"], "friction": 0.2}]}),
    "structure36_decay_verlet": ("structure_36", {"run.cycles": 6, "run.drop_cycles": 0}),
}


def _arrays(res) -> dict:
    out = {"force": res.signals.force, "velocity": res.signals.velocity}
    for col in ("kinetic", "rotational", "potential", "elastic", "work", "damping", "friction"):
        out[f"energy_{col}"] = getattr(res.energy, col)
    if res.trajectory is not None:
        out["trajectory_position"] = res.trajectory["position"]
        out["trajectory_spin"] = res.trajectory["spin"]
    if res.structure is not None:
        out["structure_displacement"] = res.structure.displacement
        out["structure_velocity"] = res.structure.velocity
        out["structure_external_work"] = res.structure.external_work
        out["structure_damping_loss"] = res.structure.damping_loss
    out["eta_star"] = np.array(res.eta_star)
    out["steps"] = np.array(res.steps)
    out["mode"] = np.array(str(res.mode))
    return out


def save(directory: Path, only=None):
    from pdamper import load_case, run_case

    directory.mkdir(parents=True, exist_ok=True)
    for name, (example, over) in CASES.items():
        if only and name not in only:
            continue
        overrides = {**SHORT, **over} if "structure" not in example else over
        case = load_case(EX / f"{example}.toml", overrides)
        t = time.perf_counter()
        res = run_case(case)
        wall = time.perf_counter() - t
        np.savez(directory / f"{name}.npz", **_arrays(res))
        print(f"{name:28s} eta* {res.eta_star:.12g}  steps {res.steps:9d}  {wall:6.1f} s  mode {res.mode}")


def compare(a: Path, b: Path) -> int:
    differ = 0
    for fa in sorted(a.glob("*.npz")):
        fb = b / fa.name
        if not fb.exists():
            print(f"{fa.stem:28s} missing in {b}")
            differ += 1
            continue
        xa, xb = np.load(fa), np.load(fb)
        notes = []
        for key in sorted(set(xa.files) | set(xb.files)):
            if key not in xa.files or key not in xb.files:
                notes.append(f"{key}: only in one")
                continue
            u, v = xa[key], xb[key]
            if u.dtype.kind in "US":
                if not np.array_equal(u, v):
                    notes.append(f"{key}: {u} vs {v}")
            elif u.shape != v.shape:
                notes.append(f"{key}: shape {u.shape} vs {v.shape}")
            elif not np.array_equal(u, v, equal_nan=u.dtype.kind == "f"):
                notes.append(f"{key}: max |diff| {np.nanmax(np.abs(u - v)):.3g}")
        eta = f"eta* {float(xa['eta_star']):.12g} -> {float(xb['eta_star']):.12g}"
        if notes:
            differ += 1
            print(f"{fa.stem:28s} DIFFERS ({eta}): " + "; ".join(notes))
        else:
            print(f"{fa.stem:28s} bit-identical ({eta}, steps {int(xa['steps'])})")
    return 1 if differ else 0


def main(argv):
    if len(argv) >= 2 and argv[0] == "save":
        save(Path(argv[1]), set(argv[2:]) or None)
        return 0
    if len(argv) == 3 and argv[0] == "compare":
        return compare(Path(argv[1]), Path(argv[2]))
    print(__doc__)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
