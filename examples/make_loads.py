"""Writes the load files of the examples (docs/structure.md, "Loads in time"):

- ``hammer.csv``: a hammer-like blow, a 10 ms half sine of 300 N and a 60 N rebound, sampled every
  0.5 ms (``time [ms]``, ``force [N]``), for ``mast_hammer.toml``;
- ``quake_synthetic.csv`` and ``quake_synthetic.AT2``: one synthetic ground acceleration, 12 s at
  100 samples a second, in a CSV (``time [s]``, ``acceleration [g]``) and in the PEER NGA ``.AT2``
  layout, for ``frame_quake.toml`` and ``mast_quake.toml``;
- ``records/synthetic_1.AT2`` ... ``synthetic_7.AT2``: a suite of seven synthetic ground
  accelerations (seeds 11-17, soils of f_g 1.6-4 Hz, strong motion of 2-5 s), for
  ``frame_suite.toml`` (docs/structure.md, "Record suites").

The accelerogram is made here, not recorded: Gaussian noise through the Kanai-Tajimi filter of a
firm soil (f_g = 2.5 Hz, zeta_g = 0.6), under an envelope that rises over 1.5 s, holds 3 s and
decays (Jennings, Housner & Tsai 1968), seed 7, peak 0.1 g, its mean velocity removed so that the
ground comes to rest. It is no PEER record: the ``.AT2`` file only has that file layout (its first
line says so), so that pdamper's reader of PEER files can be tried on a file anyone may share.

    python examples/make_loads.py          # rewrites the three files beside this script
    python examples/make_loads.py DIR      # writes them into DIR instead
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
G = 9.80665


def hammer():
    t = np.arange(0.0, 0.05 + 1e-9, 5e-4)
    f = 300.0 * np.where(t < 0.01, np.sin(np.pi * t / 0.01), 0.0) - 60.0 * np.where(
        (t > 0.015) & (t < 0.025), np.sin(np.pi * (t - 0.015) / 0.01), 0.0)
    return t, f


#: The suite's records: (seed, f_g [Hz], zeta_g, strong motion [s]).
SUITE = ((11, 1.6, 0.6, 3.0), (12, 2.0, 0.5, 4.0), (13, 2.5, 0.6, 2.0), (14, 3.0, 0.4, 5.0), (15, 3.5, 0.6, 3.0),
         (16, 4.0, 0.5, 2.5), (17, 2.2, 0.7, 4.5))


def quake(seed: int = 7, dt: float = 0.01, duration: float = 12.0, peak_g: float = 0.1, ground_frequency: float = 2.5,
          ground_damping: float = 0.6, strong: float = 3.0):
    n = int(round(duration / dt))
    t = dt * np.arange(n + 1)
    rng = np.random.default_rng(seed)
    f = np.fft.rfftfreq(4 * n, dt)
    r2 = (f / ground_frequency) ** 2
    z2 = ground_damping**2
    kt = (1 + 4 * z2 * r2) / ((1 - r2) ** 2 + 4 * z2 * r2) * (f > 0.2) * (f < 20.0)
    noise = np.fft.irfft((rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) * np.sqrt(kt), 4 * n)
    a = noise[: n + 1]
    env = np.where(t < 1.5, (t / 1.5) ** 2, np.where(t < 1.5 + strong, 1.0, np.exp(-0.6 * (t - 1.5 - strong))))
    a = a * env
    a -= env * np.sum(a) / np.sum(env)  # no mean velocity left: the ground comes to rest
    a[0] = a[-1] = 0.0
    return t, a / np.max(np.abs(a)) * peak_g


def main(out: Path = HERE) -> None:
    t, f = hammer()
    (out / "hammer.csv").write_text("time [ms],force [N]\n" + "".join(f"{1e3 * a:.1f},{b:.4f}\n" for a, b in zip(t, f)))
    t, a = quake()
    (out / "quake_synthetic.csv").write_text(
        "# a synthetic ground acceleration (examples/make_loads.py), not a recorded one\n"
        "time [s],acceleration [g]\n" + "".join(f"{x:.2f},{y:.6f}\n" for x, y in zip(t, a)))
    lines = ["SYNTHETIC GROUND MOTION WRITTEN BY PDAMPER EXAMPLES/MAKE_LOADS.PY (NOT A PEER RECORD)",
             "Kanai-Tajimi filtered noise, f_g 2.5 Hz, zeta_g 0.6, seed 7, peak 0.1 g",
             "ACCELERATION TIME SERIES IN UNITS OF G",
             f"NPTS= {t.size:5d}, DT= {t[1] - t[0]:.4f} SEC"]
    rows = [" ".join(f"{v:14.7E}" for v in a[k:k + 5]) for k in range(0, a.size, 5)]
    (out / "quake_synthetic.AT2").write_text("\n".join(lines + rows) + "\n")
    (out / "records").mkdir(exist_ok=True)
    for k, (seed, fg, zg, strong) in enumerate(SUITE, start=1):
        t, a = quake(seed, ground_frequency=fg, ground_damping=zg, strong=strong)
        lines = ["SYNTHETIC GROUND MOTION WRITTEN BY PDAMPER EXAMPLES/MAKE_LOADS.PY (NOT A PEER RECORD)",
                 f"Kanai-Tajimi filtered noise, f_g {fg:g} Hz, zeta_g {zg:g}, seed {seed}, strong motion {strong:g} s, "
                 "peak 0.1 g", "ACCELERATION TIME SERIES IN UNITS OF G", f"NPTS= {t.size:5d}, DT= {t[1] - t[0]:.4f} SEC"]
        rows = [" ".join(f"{v:14.7E}" for v in a[j:j + 5]) for j in range(0, a.size, 5)]
        (out / "records" / f"synthetic_{k}.AT2").write_text("\n".join(lines + rows) + "\n")


if __name__ == "__main__":
    main(Path(sys.argv[1]) if len(sys.argv) > 1 else HERE)
