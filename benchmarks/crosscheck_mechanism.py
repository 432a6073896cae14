"""Where a bed dissipates, and where its layers are: a diagnostic of a pdamper run.

Usage::

    python benchmarks/crosscheck_mechanism.py --results /work/crosscheck_results/mechanism \
        --strokes 9.55,12 --tilt both --seeds 1          # runs, stores npz + json, draws figures
    python benchmarks/crosscheck_mechanism.py --results DIR --figures-only

Nothing here touches pdamper's kernels. :class:`ContactDissipation` is a Python recorder (the
public protocol of :mod:`pdamper.recorders.base`) called at the end of every sample: it takes the
energy the run's own ledger says was dissipated in that interval, by normal damping and by
friction, and shares it among the contact classes (sphere-sphere, floor, lid, end walls x_min /
x_max, side walls z_min / z_max, baffles) in proportion to the rate at which each contact present
at either end of the interval dissipates, by pdamper's own laws, written out here in a small
numba loop (Hertz-Gonthier normal damping as ``pdamper.contact.hertz_gonthier.normal_force``,
``d = chi / v_in`` with ``chi`` from ``chi_for_restitution`` and ``v_in`` the approach speed at
the first sighting of the contact -- the larger of the approach rate then and at the sample
before --, raised by any faster one later and floored at ``contact.v_in_floor``, as the kernel
does; the tanh friction of eq. (2)). The shares therefore add up to the ledger exactly; what is
estimated is only how an interval with contacts of several classes is split. Only the default
tangential law ("tanh") is written out. To make that estimate good the run samples fast (``--sample-rate``, 100 kHz by default:
10 us, a third of a steel-steel impact), which changes the Gear integrator's step boundaries, not
the physics: the run's eta* is reported next to that of the same case at the usual 1 kHz.
The same rates integrated directly (without the ledger) are stored as a check of the estimate.

It also records the force of each wall class on the spheres along the drive, so the mean power
the container puts in through the floor, the lid and the other walls can be set beside the same
split of a LIGGGHTS run (``benchmarks/liggghts.py``, ``per_wall=True``).

The trajectory (``--fps`` frames a second) gives the layers: in each frame the spheres sorted by
height, the mean height of the lower and upper half, the column fraction, the share of upper
spheres whose centre lies within ``r/2`` horizontally of a lower sphere's (a sphere stacked on
another, as ``initial.layers = "auto"`` starts them), and the x-lattice order :func:`order`.
``--code liggghts,liggghts_tdoff`` runs the same case in LIGGGHTS instead (a mesh per wall, frames
dumped), ``--start dropped`` from a bed without columns (:func:`starting`).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from pathlib import Path

import numba
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if not os.environ.get("PYTHONPATH"):  # this tree's pdamper, unless PYTHONPATH names one
    sys.path.insert(0, str(ROOT / "src"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

CLASSES = ("sphere-sphere", "floor", "lid", "end walls", "side walls", "baffles")
_WALL_CLASS = {"floor": "floor", "lid": "lid", "x_min": "end walls", "x_max": "end walls",
               "z_min": "side walls", "z_max": "side walls"}


@numba.njit(cache=False)
def _contact_rates(k, chi, mu, tau, v_floor, delta, ddot, vin, vt):
    """(normal damping rate [W], friction rate [W], F_n [N], |F_t|/|v_t| [N s/m]) of one contact:
    eq. (1) with d = chi / v_in, clipped at zero as ``hertz_gonthier.normal_force``, and the tanh
    law of eq. (2) (numpy's tanh)."""
    fe = k * delta * math.sqrt(delta)
    dpar = chi / vin
    f = fe * (1.0 + dpar * ddot)
    fd = -fe if f < 0.0 else fe * dpar * ddot
    fn = max(f, 0.0)
    vts = math.sqrt(vt[0] * vt[0] + vt[1] * vt[1] + vt[2] * vt[2])
    frac = mu * math.tanh(tau * vts)
    return fd * ddot, frac * fn * vts, fn, frac * fn / max(vts, 1e-300)


@numba.njit(cache=False)
def _sample_rates(p, v, w, r, v_prev, s, nrm, wall_class, k_pp, chi_pp, mu_pp, k_w, chi_w, mu_w, tau, v_floor, d,
                  vin_pp, vin_w, out):
    """The rates of every contact at one sample, summed by class into ``out`` (3, classes): normal
    damping [W], friction [W], the force of the walls on the spheres along ``d`` [N]. ``vin_pp``,
    ``vin_w`` hold each contact's approach speed (0: no contact), updated here: at first sighting
    the larger of the approach rate now and at the sample before (the contact may have begun in
    between), raised by any faster approach later, floored at ``v_floor`` (as the kernel does)."""
    n = p.shape[0]
    vt = np.empty(3)
    for i in range(n):
        for j in range(i + 1, n):
            dx, dy, dz = p[j, 0] - p[i, 0], p[j, 1] - p[i, 1], p[j, 2] - p[i, 2]
            dist = math.sqrt(dx * dx + dy * dy + dz * dz)
            if dist >= r[i] + r[j]:
                vin_pp[i, j] = 0.0
                continue
            nx, ny, nz = dx / dist, dy / dist, dz / dist            # from i to j
            # contact-point velocity of i relative to j: v_i - v_j + w_i x (r_i n) + w_j x (r_j n)
            ax = w[i, 0] * r[i] + w[j, 0] * r[j]
            ay = w[i, 1] * r[i] + w[j, 1] * r[j]
            az = w[i, 2] * r[i] + w[j, 2] * r[j]
            vx = v[i, 0] - v[j, 0] + ay * nz - az * ny
            vy = v[i, 1] - v[j, 1] + az * nx - ax * nz
            vz = v[i, 2] - v[j, 2] + ax * ny - ay * nx
            ddot = vx * nx + vy * ny + vz * nz
            vin = max(vin_pp[i, j], ddot, v_floor)
            if vin_pp[i, j] == 0.0:
                vin = max(vin, (v_prev[i, 0] - v_prev[j, 0]) * nx + (v_prev[i, 1] - v_prev[j, 1]) * ny
                          + (v_prev[i, 2] - v_prev[j, 2]) * nz)
            vin_pp[i, j] = vin
            vt[0], vt[1], vt[2] = vx - ddot * nx, vy - ddot * ny, vz - ddot * nz
            pn, pf, fn, ft = _contact_rates(k_pp, chi_pp, mu_pp, tau, v_floor, r[i] + r[j] - dist, ddot, vin, vt)
            out[0, 0] += pn
            out[1, 0] += pf
    for i in range(n):
        for wl in range(s.shape[1]):
            if s[i, wl] >= r[i]:
                vin_w[i, wl] = 0.0
                continue
            nx, ny, nz = nrm[i, wl, 0], nrm[i, wl, 1], nrm[i, wl, 2]  # into the container
            # contact-point velocity, the wall at rest: v + w x (-r n)
            vx = v[i, 0] - r[i] * (w[i, 1] * nz - w[i, 2] * ny)
            vy = v[i, 1] - r[i] * (w[i, 2] * nx - w[i, 0] * nz)
            vz = v[i, 2] - r[i] * (w[i, 0] * ny - w[i, 1] * nx)
            ddot = -(vx * nx + vy * ny + vz * nz)
            vin = max(vin_w[i, wl], ddot, v_floor)
            if vin_w[i, wl] == 0.0:
                vin = max(vin, -(v_prev[i, 0] * nx + v_prev[i, 1] * ny + v_prev[i, 2] * nz))
            vin_w[i, wl] = vin
            vt[0], vt[1], vt[2] = vx + ddot * nx, vy + ddot * ny, vz + ddot * nz
            pn, pf, fn, ft = _contact_rates(k_w[wl], chi_w[wl], mu_w[wl], tau, v_floor, r[i] - s[i, wl], ddot, vin, vt)
            c = wall_class[wl]
            out[0, c] += pn
            out[1, c] += pf
            out[2, c] += fn * (nx * d[0] + ny * d[1] + nz * d[2]) - ft * (vt[0] * d[0] + vt[1] * d[1] + vt[2] * d[2])


class ContactDissipation:
    """A Python recorder: the dissipation of every sample interval by contact class (see the
    module docstring), and the force of each wall class on the spheres along the drive."""

    name = "contact_dissipation"
    channels = frozenset()
    every = 1

    def start(self, run) -> None:
        from pdamper.contact.hertz import hertz_stiffness
        from pdamper.contact.hertz_gonthier import chi_for_restitution
        from pdamper.materials import effective_modulus

        case = run.case
        if len(case.particles) != 1:
            raise ValueError("ContactDissipation handles one particle set")
        self.case, self.info = case, run
        c = case.contact
        pm = case.particles[0].material
        r = run.radius
        self.r, self.m = r, run.mass
        kinds, data, names = case.container.walls()
        self.kinds, self.data = np.ascontiguousarray(kinds), np.ascontiguousarray(data)
        self.wall_class = np.array([CLASSES.index(_WALL_CLASS.get(n, "baffles")) for n in names])
        mats = case.container.wall_material_list()

        def eps(a, b):
            own = [m.restitution for m in (a, b) if m.restitution is not None]
            pair = (a.name, b.name) in c.pair_restitution or (b.name, a.name) in c.pair_restitution
            law = c.restitution_for(a.name, b.name)
            return min(own) if own and not pair else float(law.value)

        self.k_pp = hertz_stiffness(effective_modulus(pm, pm), 0.5 * r[0])
        self.chi_pp = float(chi_for_restitution(eps(pm, pm), c.damping))
        self.mu_pp = c.friction_for(pm.name, pm.name)
        self.k_w = np.array([hertz_stiffness(effective_modulus(pm, m), r[0]) for m in mats])
        self.chi_w = np.array([float(chi_for_restitution(eps(pm, m), c.damping)) for m in mats])
        self.mu_w = np.array([float(c.friction_for(pm.name, m.name)) for m in mats])
        self.tau, self.v_floor = c.tau, c.v_in_floor
        self.vin_pp = np.zeros((r.size, r.size))
        self.vin_w = np.zeros((r.size, len(names)))
        self.v_prev = np.zeros((r.size, 3))
        self.prev = (0.0, 0.0)
        n = run.n_samples
        self.damping = np.zeros((n, len(CLASSES) + 1))   # the last column: unassigned
        self.friction = np.zeros((n, len(CLASSES) + 1))
        self.rates_prev = (np.zeros(len(CLASSES)), np.zeros(len(CLASSES)))
        self.direct = np.zeros((n, 2, len(CLASSES)))  # the rates times the interval, not shared out
        self.force = np.zeros((n, len(CLASSES)))      # force of each class on the spheres along d [N]
        self.k = 0

    def record(self, state) -> None:
        from pdamper.geometry.walls import wall_distances

        nc = len(CLASSES)
        s, nrm = wall_distances(self.kinds, self.data, np.ascontiguousarray(state.position))
        rates = np.zeros((3, nc))  # normal damping [W], friction [W], wall force along d [N]
        _sample_rates(state.position, state.velocity, state.spin, self.r, self.v_prev, s, nrm, self.wall_class,
                      self.k_pp, self.chi_pp, self.mu_pp, self.k_w, self.chi_w, self.mu_w, self.tau, self.v_floor,
                      state.direction, self.vin_pp, self.vin_w, rates)
        rates_n, rates_f = rates[0], rates[1]
        self.v_prev[:] = state.velocity
        self.rates_prev, rates_prev = (rates_n, rates_f), self.rates_prev
        dn, df = state.damping - self.prev[0], state.friction - self.prev[1]
        self.prev = (state.damping, state.friction)
        k = self.k
        if k < self.damping.shape[0]:
            # weights: the rates at both ends of the interval (a contact shorter than two
            # intervals is seen at one end at least); no contact at either end: unassigned
            wn, wf = rates_n + rates_prev[0], rates_f + rates_prev[1]
            for out, tot, wt in ((self.damping, dn, wn), (self.friction, df, wf)):
                if wt.sum() > 0:
                    out[k, :nc] = tot * wt / wt.sum()
                else:
                    out[k, nc] = tot
            self.direct[k, 0], self.direct[k, 1] = rates_n * self.info.interval, rates_f * self.info.interval
            self.force[k] = rates[2]
        self.k += 1

    def finalize(self, data) -> dict:
        return {"damping": self.damping, "friction": self.friction, "direct": self.direct, "force": self.force,
                "time_end": np.asarray(data.time_end)}


def layers(traj, radius: float) -> dict:
    """Per frame: the mean height of the lower and the upper half of the spheres [m], the lowest
    and highest centre [m], and the column fraction (module docstring)."""
    y = traj["position"][:, :, 1]
    by_height = np.argsort(y, axis=1)
    n = y.shape[1]
    lo_idx, hi_idx = by_height[:, : n // 2], by_height[:, n // 2:]
    ys = np.take_along_axis(y, by_height, axis=1)
    col = np.zeros(len(y))
    for f in range(len(y)):
        P = traj["position"][f]
        low, up = P[lo_idx[f]], P[hi_idx[f]]
        h = np.hypot(up[:, None, 0] - low[None, :, 0], up[:, None, 2] - low[None, :, 2])
        above = (up[:, None, 1] - low[None, :, 1]) > radius
        col[f] = np.mean(np.any((h < radius / 2) & above, axis=1))
    return {"lower": ys[:, : n // 2].mean(axis=1), "upper": ys[:, n // 2:].mean(axis=1), "bottom": ys[:, 0],
            "top": ys[:, -1], "columns": col, "order": order(traj["position"], radius)}


def order(position, radius: float) -> np.ndarray:
    """The x-lattice order of each frame, |mean_j exp(2 pi i x_j / (2 r))|: 1 when every sphere's
    centre sits on a lattice of pitch 2 r along the length (the 12 slots of vertical_96's floor,
    which its 12 x 4 bottom layer fills exactly), about 1/sqrt(N) (0.1) when the spheres are
    spread at random along it."""
    return np.abs(np.mean(np.exp(2j * np.pi * position[:, :, 0] / (2 * radius)), axis=1))


def fold(t, values, frequency, bins=40):
    """The mean of ``values`` (n, ...) over drive phase bins (t in s from the drive's start)."""
    ph = np.mod(t * frequency, 1.0)
    idx = np.minimum((ph * bins).astype(int), bins - 1)
    out = np.zeros((bins,) + np.shape(values)[1:])
    for b in range(bins):
        sel = idx == b
        if sel.any():
            out[b] = np.mean(values[sel], axis=0)
    return (np.arange(bins) + 0.5) / bins, out


def run_pdamper(stroke_mm, seed, tilt, sample_rate, fps, out: Path, law="tanh", friction="case", start="layers") -> dict:
    """One diagnostic pdamper run of vertical96. With the tanh law the ledger is split by contact
    class (:class:`ContactDissipation`); with another law (``crosscheck.PDAMPER_LAWS``) only the
    layers and the order are recorded: the split writes out the tanh friction only."""
    import crosscheck
    from pdamper.run import run_case
    from pdamper.schema import replace

    case = crosscheck.starting(crosscheck.build_case("vertical96", stroke_mm, seed, tilt, friction), start)
    case = crosscheck.with_law(case, law)
    if case is None:
        raise SystemExit(f"--law {law}: this pdamper has no such tangential law")
    fast = replace(case, {"recording.sample_rate": sample_rate, "recording.trajectory_fps": fps})
    t0 = time.perf_counter()
    split = law == "tanh"
    rec = ContactDissipation()
    res = run_case(fast, recorders=[rec] if split else [])
    tr = res.trajectory
    lay = layers(tr, case.particles[0].radius)
    f = case.drive.frequency
    e = res.energy
    ft = tr["time"]
    keep = ft > case.drop_cycles / f
    summary = {"stroke_mm": stroke_mm, "seed": seed, "tilt": tilt, "law": law, "friction": friction, "start": start,
               "sample_rate_hz": sample_rate, "eta_star": res.eta_star, "mode": res.mode,
               "ledger_per_cycle_J": e.dissipated_per_cycle(case), "energy_balance_error": e.balance_error(),
               "wall_time_s": time.perf_counter() - t0,
               "columns_mean": float(lay["columns"][keep].mean()),
               "columns_first_cycle": float(lay["columns"][ft < 1 / f].mean()),
               "order_end": float(lay["order"][-1]), "order_min": float(lay["order"].min()),
               "melt_cycle": _melt_cycle(ft, lay["order"], f)}
    arrays = {}
    if split:
        cd = res.recorded[rec.name]
        t_end = cd["time_end"]
        first = t_end > case.drop_cycles / f
        per_cycle = (case.cycles - case.drop_cycles)
        summary["per_cycle_J"] = {
            "damping": dict(zip(CLASSES + ("unassigned",), cd["damping"][first].sum(axis=0) / per_cycle)),
            "friction": dict(zip(CLASSES + ("unassigned",), cd["friction"][first].sum(axis=0) / per_cycle)),
            "direct_damping": dict(zip(CLASSES, cd["direct"][first, 0].sum(axis=0) / per_cycle)),
            "direct_friction": dict(zip(CLASSES, cd["direct"][first, 1].sum(axis=0) / per_cycle))}
        vel = res.signals.velocity
        summary["wall_power_W"] = {c: float(np.mean(cd["force"][first, k] * vel[first])) for k, c in enumerate(CLASSES)}
        arrays = {"time_end": t_end, "damping": cd["damping"], "friction": cd["friction"], "force": cd["force"]}
    out.mkdir(parents=True, exist_ok=True)
    tag = f"X{stroke_mm:g}_s{seed}_tilt-{tilt}_{law}" + ("" if friction == "case" else f"_mu{friction}") \
        + ("" if start == "layers" else f"_{start}")
    np.savez_compressed(out / f"{tag}.npz", **arrays, frame_time=ft, position=tr["position"].astype(np.float32),
                        velocity=tr["velocity"].astype(np.float32), container_position=tr["container_position"],
                        **{f"layer_{k}": v for k, v in lay.items()})
    (out / f"{tag}.json").write_text(json.dumps(summary, indent=1, default=float))
    return summary


def _melt_cycle(t, psi, frequency, threshold=0.5):
    """The drive cycle in which the x-lattice order first falls below ``threshold`` (None: it
    never does, the crystal held)."""
    below = np.flatnonzero(psi < threshold)
    return None if below.size == 0 else float(t[below[0]] * frequency)


def run_liggghts(stroke_mm, seed, tilt, variant, fps, out: Path, dt=1e-6, start="layers") -> dict:
    """The same case in LIGGGHTS (``variant``: a law of ``crosscheck.LIGGGHTS_LAWS``), a mesh per
    wall (the power put in through each) and frames at ``fps``: its layers and columns."""
    import crosscheck
    import liggghts

    case = crosscheck.starting(crosscheck.build_case("vertical96", stroke_mm, seed, tilt, "case"), start)
    tag = f"{variant}_X{stroke_mm:g}_s{seed}_tilt-{tilt}" + ("" if start == "layers" else f"_{start}")
    work = out / "liggghts_work" / tag
    t0 = time.perf_counter()
    opts = {"dt": dt, "per_wall": True, "dump_fps": fps, "model_options": crosscheck.LIGGGHTS_LAWS[variant]}
    if liggghts.finished(work):    # a run of this deck is there already: read it again
        info = liggghts.write_deck(case, work, **opts)
        res = liggghts.read_results(case, work, info)
    else:
        res = liggghts.run(case, work, **opts)
        info = liggghts.write_deck(case, work, **opts)
    tr = liggghts.read_dump(work, case, info, dt)
    lay = layers(tr, case.particles[0].radius)
    f = case.drive.frequency
    keep = tr["time"] > case.drop_cycles / f
    power: dict = {}
    for walls, p in res["wall_power_W"].items():
        c = _WALL_CLASS[walls]
        power[c] = power.get(c, 0.0) + p
    summary = {"code": variant, "stroke_mm": stroke_mm, "seed": seed, "tilt": tilt, "start": start,
               "eta_star": res["eta_star"], "energy_per_cycle_J": res["energy_per_cycle_J"], "wall_power_W": power,
               "columns_mean": float(lay["columns"][keep].mean()), "wall_time_s": time.perf_counter() - t0}
    x, _, _ = case.drive.motion(tr["time"])
    np.savez_compressed(out / f"{tag}.npz", frame_time=tr["time"], position=tr["position"].astype(np.float32),
                        container_position=x[:, None] * info["dvec"][None, :],
                        **{f"layer_{k}": v for k, v in lay.items()})
    (out / f"{tag}.json").write_text(json.dumps(summary, indent=1, default=float))
    return summary


def _load(results: Path, tag: str):
    f = results / f"{tag}.npz"
    return (np.load(f), json.loads((results / f"{tag}.json").read_text())) if f.exists() else (None, None)


def figures(results: Path, img: Path, strokes=(9.55, 12.0), seed=1, height=0.05, frequency=15.0) -> list[Path]:
    """The mechanism figures from the stored runs: the layers over the last cycles, the column
    fraction over the run, and the dissipation by contact class."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    img.mkdir(parents=True, exist_ok=True)
    runs = {(x, t): _load(results, f"X{x:g}_s{seed}_tilt-{t}_tanh") for x in strokes for t in ("paper", "none")}
    out = []
    # 1. where the layers are: the last three cycles, lab frame (y of the container + y in it)
    fig, axes = plt.subplots(len(strokes), 2, figsize=(10, 3.2 * len(strokes)), sharex=True, squeeze=False)
    for a, x in enumerate(strokes):
        for b, t in enumerate(("paper", "none")):
            ax = axes[a, b]
            d, js = runs[(x, t)]
            if d is None:
                ax.set_visible(False)
                continue
            ft = d["frame_time"]
            sel = ft > ft[-1] - 3.0 / frequency
            ph = ft[sel] * frequency
            yc = d["container_position"][sel, 1]
            ax.fill_between(ph, yc - 0.004, yc, color="0.6", label="floor")
            ax.fill_between(ph, yc + height, yc + height + 0.004, color="0.3", label="lid")
            for key, c, lab in (("lower", "C0", "lower 48 (mean)"), ("upper", "C3", "upper 48 (mean)")):
                ax.plot(ph, yc + d[f"layer_{key}"][sel], color=c, label=lab)
            ax.plot(ph, yc + d["layer_bottom"][sel], color="C0", lw=0.6, ls=":", label="lowest / highest sphere")
            ax.plot(ph, yc + d["layer_top"][sel], color="C3", lw=0.6, ls=":")
            psi = float(order(d["position"][sel], 0.005).mean())
            ax.set_title(f"X = {x:g} mm, {'0.1° tilt' if t == 'paper' else 'no tilt'}: η* = {js['eta_star']:.3f}, "
                         f"x-lattice order ψ = {psi:.2f}", fontsize=9)
            ax.set_ylabel("height, lab frame [m]")
            ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("time [drive cycles]")
    axes[-1, 1].set_xlabel("time [drive cycles]")
    handles, labels = axes[0, 0].get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=8, loc="lower center", ncol=5)
    fig.suptitle("vertical_96 in pdamper (tanh), seed 1: sphere centres over the last three cycles", fontsize=10)
    fig.tight_layout(rect=(0, 0.05, 1, 1))
    out.append(img / "crosscheck_vertical_layers.png")
    fig.savefig(out[-1], dpi=110)
    plt.close(fig)
    # 2. the x-lattice order over the run, both codes
    fig, ax = plt.subplots(figsize=(7.5, 3.6))
    curves = [(f"pdamper, X = {x:g} mm, {'0.1° tilt' if t == 'paper' else 'no tilt'}", runs[(x, t)])
              for x in strokes for t in ("paper", "none")]
    for variant, name in (("liggghts", "LIGGGHTS"), ("liggghts_tdoff", "LIGGGHTS tangential_damping off")):
        for x in strokes:
            for t in ("paper", "none"):
                for start in ("", "_dropped"):
                    curves.append((f"{name}, X = {x:g} mm, {'0.1° tilt' if t == 'paper' else 'no tilt'}"
                                   + (", dropped start" if start else ""),
                                   _load(results, f"{variant}_X{x:g}_s{seed}_tilt-{t}{start}")))
    for k, (label, (d, js)) in enumerate(c for c in curves if c[1][0] is not None):
        psi = d["layer_order"] if "layer_order" in d else order(d["position"], 0.005)
        ax.plot(d["frame_time"] * frequency, psi, lw=0.8, color=f"C{k}", ls="-" if "LIGGGHTS" not in label else "--",
                label=f"{label}: η* {js['eta_star']:.3f}")
    ax.set_xlabel("time [drive cycles]")
    ax.set_ylabel("x-lattice order ψ [-]")
    ax.set_ylim(0, 1.05)
    ax.set_title("ψ = |mean exp(2πi x / 2r)|: 1 = every sphere in one of the floor's 12 slots", fontsize=9)
    ax.legend(fontsize=6.5, loc="center right")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    out.append(img / "crosscheck_vertical_order.png")
    fig.savefig(out[-1], dpi=110)
    plt.close(fig)
    # 3. dissipation per cycle by contact class, and over the cycle
    fig, (ax, ax2) = plt.subplots(1, 2, figsize=(12, 4.2), gridspec_kw={"width_ratios": [1, 1.15]})
    labels = []
    keys = [k for k in runs if runs[k][1] is not None]
    colours = dict(zip(CLASSES, ("C0", "C1", "C2", "C4", "C5", "C6")))
    for i, k in enumerate(keys):
        js = runs[k][1]
        labels.append(f"{k[0]:g} mm\n{'tilt' if k[1] == 'paper' else 'no tilt'}\nη* {js['eta_star']:.3f}")
        y0 = 0.0
        for c in CLASSES:
            for part, hatch in (("damping", None), ("friction", "//")):
                v = js["per_cycle_J"][part][c]
                if v <= 1e-6:
                    continue
                ax.bar(i, v, bottom=y0, color=colours[c], hatch=hatch, edgecolor="k", lw=0.3,
                       label=f"{c}, {'normal damping' if hatch is None else 'friction'}" if i == 0 else None)
                y0 += v
    ax.set_xticks(range(len(keys)), labels, fontsize=8)
    ax.set_ylabel("dissipated per cycle [J]")
    ax.set_title("by contact class (pdamper tanh, seed 1)", fontsize=9)
    ax.set_ylim(0, 1.9 * ax.get_ylim()[1])
    ax.legend(fontsize=6.5, loc="upper left", ncol=2)
    x = max(strokes)
    for t, ls in (("paper", "-"), ("none", "--")):
        d, js = runs[(x, t)]
        if d is None:
            continue
        te = d["time_end"]
        dt = np.diff(np.concatenate([[0.0], te]))
        keep = te > 4.0 / frequency
        rate = (d["damping"] + d["friction"])[:, :len(CLASSES)] / dt[:, None]
        ph, folded = fold(te[keep], rate[keep], frequency, bins=50)
        for k, c in enumerate(CLASSES):
            if folded[:, k].max() > 0.05:
                ax2.plot(ph, folded[:, k], color=colours[c], ls=ls,
                         label=f"{c}, {'tilt' if t == 'paper' else 'no tilt'}")
    ax2.set_xlabel("drive phase [cycles] (container at its lowest at 0.75)")
    ax2.set_ylabel("dissipation rate [W]")
    ax2.set_title(f"over the cycle, X = {x:g} mm (cycles 4-20 folded)", fontsize=9)
    ax2.legend(fontsize=6.5)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    out.append(img / "crosscheck_vertical_dissipation.png")
    fig.savefig(out[-1], dpi=110)
    plt.close(fig)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--results", type=Path, default=ROOT / "results" / "crosscheck" / "mechanism")
    ap.add_argument("--strokes", default="9.55,12")
    ap.add_argument("--seeds", default="1")
    ap.add_argument("--tilt", choices=("paper", "none", "both"), default="both")
    ap.add_argument("--friction", default="case")
    ap.add_argument("--law", default="tanh",
                    help="pdamper's tangential law (crosscheck.PDAMPER_LAWS; default tanh): another law "
                         "records the layers and the order only, not the split by contact class")
    ap.add_argument("--sample-rate", type=float, default=100e3)
    ap.add_argument("--fps", type=float, default=1000.0)
    ap.add_argument("--start", default="layers", help="layers (pdamper's stacked start) and/or dropped (no columns)")
    ap.add_argument("--code", default="pdamper",
                    help="pdamper and/or LIGGGHTS variants (liggghts, liggghts_tdoff), comma list")
    ap.add_argument("--figures", type=Path, default=None, help="draw the figures into this folder")
    ap.add_argument("--figures-only", action="store_true")
    args = ap.parse_args(argv)
    if args.figures_only:
        print(figures(args.results, args.figures or ROOT / "docs" / "img"))
        return
    tilts = ["paper", "none"] if args.tilt == "both" else [args.tilt]
    for x in (float(s) for s in args.strokes.split(",")):
        for seed in (int(s) for s in args.seeds.split(",")):
            for tilt in tilts:
                for start in args.start.split(","):
                    for code in args.code.split(","):
                        if code == "pdamper":
                            for fr in args.friction.split(","):
                                s = run_pdamper(x, seed, tilt, args.sample_rate, args.fps, args.results, law=args.law,
                                                friction=fr, start=start)
                                print(json.dumps(s, default=float), flush=True)
                        else:
                            s = run_liggghts(x, seed, tilt, code, args.fps, args.results, start=start)
                            print(json.dumps(s, default=float), flush=True)
    if args.figures:
        print(figures(args.results, args.figures))


if __name__ == "__main__":
    main()
