"""Synthesise a force/motion record, write it as a CSV with units, and analyse it.

The "damper" is a viscous dashpot ``F = c v`` on a container of mass ``m_c`` driven at
``x_c = X sin(Omega t)``; the force sensor adds white noise. The complex power method
(paper Sect. 4.1) must give the dashpot's energy per cycle, ``pi c Omega X^2``: the
container's inertia ``m_c x_c''`` does no work over whole cycles and the noise averages out.

Run it from the repository root::

    python examples/analyze_record.py                 # writes viscous_record.csv
    python examples/analyze_record.py out/rec.csv     # or where you like
    pdamper analyze viscous_record.csv --bed-mass 149g   # the same from the command line
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

from pdamper import analyze_record
from pdamper.io.records import read_record

FREQUENCY = 2.0        # drive frequency f [Hz]
STROKE = 0.012         # X [m]
DAMPING = 4.0          # c [N s/m]
CONTAINER_MASS = 0.5   # m_c [kg]
BED_MASS = 0.149       # m_bed [kg], only scales eta*
SAMPLE_RATE = 1000.0   # [Hz], as the paper's test rig
CYCLES = 20
NOISE = 0.05           # standard deviation of the force noise [N]


def synthesise(seed: int = 1):
    """Time [s], force [N] and position [m] of the dashpot record."""
    omega = 2 * math.pi * FREQUENCY
    t = np.arange(int(CYCLES * SAMPLE_RATE / FREQUENCY)) / SAMPLE_RATE
    x = STROKE * np.sin(omega * t)
    v = STROKE * omega * np.cos(omega * t)
    a = -STROKE * omega**2 * np.sin(omega * t)
    noise = np.random.default_rng(seed).normal(0.0, NOISE, t.size)
    force = DAMPING * v + CONTAINER_MASS * a + noise
    return t, force, x


def write_csv(path: Path, t, force, x) -> Path:
    """The record in ms, N and mm, with the units in the header as a test rig would write it."""
    path.parent.mkdir(parents=True, exist_ok=True)
    np.savetxt(path, np.column_stack([t * 1e3, force, x * 1e3]), delimiter=",",
               header="time [ms],force [N],position [mm]", comments="", fmt="%.10g")
    return path


def main(argv: list[str]) -> int:
    path = write_csv(Path(argv[1] if len(argv) > 1 else "viscous_record.csv"), *synthesise())
    rec = read_record(path)                       # back in SI: s, N, m
    result = analyze_record(rec.time, rec.force, position=rec.position, bed_mass=BED_MASS)

    exact = math.pi * DAMPING * (2 * math.pi * FREQUENCY) * STROKE**2
    print(f"wrote {path} ({len(rec)} samples: {', '.join(rec.headers.values())})")
    print(f"drive frequency      {result.frequency_hz:.6f} Hz (detected from the position)")
    print(f"cycles used          {result.cycles_used} (first {result.cycles_dropped} dropped)")
    print(f"energy per cycle     {result.energy_per_cycle_J * 1e3:.4f} mJ "
          f"(dashpot: pi c Omega X^2 = {exact * 1e3:.4f} mJ, "
          f"{100 * (result.energy_per_cycle_J / exact - 1):+.3f} %)")
    print(f"mean-power check     {result.mean_power_check_J * 1e3:.4f} mJ (<F v> T)")
    print(f"eta*                 {result.eta_star:.4f} (bed mass {BED_MASS * 1e3:g} g)")
    print(f"cycle-energy spread  {100 * result.cycle_energy_spread:.2f} % "
          "(relative standard deviation of the used cycles)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
