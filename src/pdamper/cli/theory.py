"""``pdamper theory``: the paper's design numbers for one damper, as a table, JSON or plots."""

from __future__ import annotations

import math

import click

from .._version import __version__
from .. import theory as th  # its formulas load on first use (scipy)
from ..errors import InputError
from .common import Quantity, ShapeChoice, echo_json, main, parse_sizes, renamed, size_option, user_errors

__all__ = ["theory_command"]

#: The options of ``pdamper theory`` that set a [container] key (any other: ``--size KEY=VALUE``).
_SIZE_OPTIONS = {"length": "--length", "radius": "--container-radius"}


@main.command("theory")
@click.option("--shape", type=ShapeChoice(), default="cuboid", show_default=True,
              help="Container shape (any registered shape); its L along the drive is the shape's (the cylinder's "
                   "L = 2R).")
@click.option("--length", type=Quantity("length"),
              help="Cuboid: inner length along the drive, e.g. 120mm.")
@click.option("--container-radius", type=Quantity("length"),
              help="Cylinder: inner radius, e.g. 39mm.")
@click.option("--radius", type=Quantity("length"), hidden=True, help="Old name of --container-radius.")
@click.option("--size", "sizes", multiple=True, metavar="KEY=VALUE",
              help="Another [container] key of the shape, e.g. --size side=35mm (repeatable).")
@click.option("--particles", type=int, required=True, help="Number of spheres N_p.")
@click.option("--max-particles", type=int, required=True,
              help="Spheres that cover the floor in one layer, N_p,max.")
@click.option("--frequency", type=Quantity("frequency"), required=True,
              help="Drive frequency, e.g. 2Hz.")
@click.option("--tilt", type=Quantity("angle"),
              help="Container tilt, e.g. 3deg (a bare number is radians).")
@click.option("--gravity", type=Quantity("acceleration"), default=th.GRAVITY, show_default=True,
              help="Gravitational acceleration [m/s^2].")
@click.option("--bed-mass", type=Quantity("mass"),
              help="Mass of all spheres, e.g. 149g; adds energies per cycle in J.")
@click.option("--stroke", type=Quantity("length"),
              help="An operating stroke to evaluate, e.g. 15mm.")
@click.option("--kappa", type=float, default=1.0, show_default=True,
              help="Scaling factor of the scattered law (8).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (SI units).")
@click.option("--plot", type=click.Path(dir_okay=False),
              help="Write the eta*(X) figure of the laws (.png, .svg, .pdf), the strokes beyond lift-off "
                   "(A >= g) shaded and, with --tilt, those below the tilt bound.")
@click.option("--fig5", type=click.Path(dir_okay=False),
              help="Write the paper's Fig. 5 (rolling bed over the phase) at --stroke, "
                   "else at X_opt.")
@user_errors
def theory_command(shape, length, container_radius, radius, sizes, particles, max_particles, frequency, tilt,
                   gravity, bed_mass, stroke, kappa, as_json, plot, fig5):
    """Clearance, optimal stroke X_opt, eta*_max and the operating bounds (paper Sect. 5).

    Example: pdamper theory --length 120mm --particles 36 --max-particles 48 --frequency 2Hz
    """
    radius = renamed(container_radius, radius, new="--container-radius", old="--radius")
    result = _compute(shape=shape, length=length, radius=radius, sizes=parse_sizes(sizes), particles=particles,
                      max_particles=max_particles, frequency=frequency, tilt=tilt,
                      gravity=gravity, bed_mass=bed_mass, stroke=stroke, kappa=kappa)
    written = []
    if plot:
        from ..plotting.theory import theory_figure

        theory_figure(result["clearance_m"], kappa=kappa, operating_stroke=stroke, path=plot,
                      liftoff_stroke=result["max_stroke_no_liftoff_m"],
                      tilt_stroke=result.get("min_stroke_tilt_m") if tilt else None)
        written.append(plot)
    if fig5:
        from ..plotting.theory import rolling_phase_figure

        at = stroke if stroke is not None and stroke >= result["x_opt_m"] else result["x_opt_m"]
        # X_opt/h recomputed from X_opt and h can fall an ulp below X_OPT_OVER_H: clamp.
        rolling_phase_figure(max(at / result["clearance_m"], th.X_OPT_OVER_H), path=fig5)
        written.append(fig5)
    result["plots"] = written
    if as_json:
        echo_json(result)
    else:
        click.echo(_table(result))


def _compute(*, shape, length, radius, particles, max_particles, frequency, tilt, gravity,
             bed_mass, stroke, kappa, sizes=None) -> dict:
    from ..geometry import shape_from_keys, sizing_keys

    given = {"length": length, "radius": radius, **(sizes or {})}
    geo = shape_from_keys(shape, given, option=lambda k: size_option(k, _SIZE_OPTIONS))
    big_l = geo.drive_length
    h = th.clearance(big_l, particles, max_particles)
    if h == 0:
        raise InputError(f"particles = {particles} fill the floor (max_particles = "
                         f"{max_particles}): the clearance is 0 and the bed cannot collect and collide; use fewer "
                         "particles")
    x_opt = th.optimal_stroke(h)
    a_opt = th.acceleration_amplitude(x_opt, frequency)
    x_lift = th.max_stroke_no_liftoff(frequency, gravity=gravity)
    out = {
        "version": __version__,
        "shape": shape,
        "length_m": big_l,
        "container": {k: v for k, v in given.items() if v is not None and k in sizing_keys(type(geo))},
        "container_radius_m": radius,
        "radius_m": radius,  # deprecated: the old key of container_radius_m
        "particles": particles,
        "max_particles": max_particles,
        "frequency_hz": frequency,
        "gravity_m_s2": gravity,
        "tilt_rad": tilt,
        "bed_mass_kg": bed_mass,
        "kappa": kappa,
        "clearance_m": h,
        "x_opt_m": x_opt,
        "x_opt_over_h": th.X_OPT_OVER_H,
        "eta_max": th.ETA_MAX,
        "eta_scattered_at_x_opt": th.eta_scattered(x_opt, h, kappa),
        "velocity_at_x_opt_m_s": th.velocity_amplitude(x_opt, frequency),
        "accel_at_x_opt_m_s2": a_opt,
        "max_stroke_no_liftoff_m": x_lift,
        "x_opt_bouncing_m": th.optimal_stroke_bouncing(h),
        "eta_max_bouncing": th.ETA_MAX_BOUNCING,
    }
    warnings = []
    if x_opt >= x_lift:
        f_max = math.sqrt(gravity / x_opt) / (2 * math.pi)
        warnings.append(
            f"X_opt = {x_opt * 1e3:.4g} mm needs A = {a_opt:.4g} m/s^2 >= g = {gravity:.4g} m/s^2: "
            f"the bed lifts off before the optimum and the rolling law does not hold; use a "
            f"frequency below {f_max:.3g} Hz or a smaller clearance (more particles)")
    if bed_mass is not None:
        out["energy_per_cycle_at_x_opt_J"] = th.energy_per_cycle_rolling(
            x_opt, h, frequency=frequency, bed_mass=bed_mass)
        out["energy_per_cycle_at_x_opt_j"] = out["energy_per_cycle_at_x_opt_J"]  # deprecated old key
    if tilt is not None:
        a_min = th.min_acceleration_tilt(tilt, gravity=gravity)
        out["min_accel_tilt_m_s2"] = a_min
        out["min_stroke_tilt_m"] = th.min_stroke_tilt(tilt, frequency, gravity=gravity)
        tilt_text = f"{math.degrees(tilt):.3g} deg"
        if tilt > 0 and a_opt <= a_min:
            warnings.append(
                f"at X_opt A = {a_opt:.3g} m/s^2 does not exceed g tan({tilt_text}) = {a_min:.3g} "
                "m/s^2: the bed stays at the low wall (paper Sect. 6.2); level the container or "
                "raise the frequency")
        elif tilt > 0 and a_opt < th.TILT_MARGIN * a_min:
            warnings.append(
                f"tilt-sensitive: at X_opt A = {a_opt:.3g} m/s^2 is only {a_opt / a_min:.2g} times "
                f"g tan({tilt_text}) = {a_min:.3g} m/s^2 (want >> 1, say >= {th.TILT_MARGIN:g}); "
                "expect a lower eta* peak at a larger stroke (paper Sect. 6.2)")
    if stroke is not None:
        out.update(_at_stroke(stroke, h, frequency, bed_mass, kappa, x_opt))
        if stroke >= x_lift:
            warnings.append(f"stroke {stroke * 1e3:.4g} mm reaches A >= g: the bed lifts off and "
                            "these laws do not hold")
        if tilt is not None and stroke <= out["min_stroke_tilt_m"]:
            warnings.append(f"stroke {stroke * 1e3:.4g} mm is below the tilt bound "
                            f"{out['min_stroke_tilt_m'] * 1e3:.4g} mm: the bed stays at the low "
                            "wall")
    out["warnings"] = warnings
    return out


def _at_stroke(stroke, h, frequency, bed_mass, kappa, x_opt) -> dict:
    regime = "rolling collect-and-collide" if stroke >= x_opt else "scattered"
    eta = th.eta_theory(stroke, h, kappa)
    out = {
        "stroke_m": stroke,
        "regime": regime,
        "accel_at_stroke_m_s2": th.acceleration_amplitude(stroke, frequency),
        "eta_at_stroke": eta,
        "eta_rolling_at_stroke": th.eta_rolling(stroke, h),
        "eta_scattered_at_stroke": th.eta_scattered(stroke, h, kappa),
        "eta_bouncing_at_stroke": th.eta_bouncing(stroke, h),
        "impact_phase_rad": th.impact_phase_rolling(stroke, h),
    }
    if bed_mass is not None:
        v = th.velocity_amplitude(stroke, frequency)
        out["energy_per_cycle_at_stroke_J"] = math.pi * bed_mass * v**2 * eta  # eqs. (4), (5)
        out["energy_per_cycle_at_stroke_j"] = out["energy_per_cycle_at_stroke_J"]  # deprecated old key
    return out


def _table(r: dict) -> str:
    mm = lambda x: f"{x * 1e3:.4g} mm"  # noqa: E731
    sizes = ", ".join(f"{k} = {mm(v) if isinstance(v, float) else v}" for k, v in r["container"].items())
    rows = [
        ("container", f"{r['shape']}, L = {mm(r['length_m'])}", f"{sizes} (L: its length along the drive)"),
        ("particles", f"{r['particles']} of {r['max_particles']}", "one layer"),
        ("frequency", f"{r['frequency_hz']:.4g} Hz", ""),
        ("clearance h", mm(r["clearance_m"]), "eq. (6)"),
        ("optimal stroke X_opt", mm(r["x_opt_m"]), f"eq. (17), X_opt/h = {r['x_opt_over_h']:.5f}"),
        ("max reduced loss factor", f"{r['eta_max']:.4f}", "eq. (16), 20/(7 pi), at X_opt"),
        ("velocity at X_opt", f"{r['velocity_at_x_opt_m_s']:.4g} m/s", "V = X Omega"),
        ("acceleration at X_opt", f"{r['accel_at_x_opt_m_s2']:.4g} m/s^2",
         f"A = X Omega^2 = {r['accel_at_x_opt_m_s2'] / r['gravity_m_s2']:.3g} g"),
        ("max stroke, no lift-off", mm(r["max_stroke_no_liftoff_m"]), "A < g"),
    ]
    if "energy_per_cycle_at_x_opt_J" in r:
        rows.append(("energy per cycle at X_opt", f"{r['energy_per_cycle_at_x_opt_J']:.4g} J",
                     f"eq. (15), m_bed = {r['bed_mass_kg'] * 1e3:.4g} g"))
    rows += [
        ("bouncing X_opt", mm(r["x_opt_bouncing_m"]), "h/pi, block without rolling"),
        ("bouncing eta*_max", f"{r['eta_max_bouncing']:.4f}", "4/pi"),
    ]
    if r["tilt_rad"] is not None:
        deg = math.degrees(r["tilt_rad"])
        rows += [
            ("min. acceleration, tilt", f"{r['min_accel_tilt_m_s2']:.4g} m/s^2",
             f"g tan({deg:.3g} deg), Sect. 6.2"),
            ("min. stroke, tilt", mm(r["min_stroke_tilt_m"]), "A cos a > g sin a"),
        ]
    if "stroke_m" in r:
        rows += [
            (f"at stroke {mm(r['stroke_m'])}", r["regime"], ""),
            ("  acceleration", f"{r['accel_at_stroke_m_s2']:.4g} m/s^2", ""),
            ("  eta* (paper's laws)", f"{r['eta_at_stroke']:.4f}",
             "eq. (14)" if r["regime"].startswith("rolling")
             else f"eq. (8), kappa = {r['kappa']:g}"),
            ("  eta* bouncing", _num(r["eta_bouncing_at_stroke"]), "for comparison"),
        ]
        if "energy_per_cycle_at_stroke_J" in r:
            rows.append(("  energy per cycle", f"{r['energy_per_cycle_at_stroke_J']:.4g} J", ""))
    width = max(len(label) for label, _, _ in rows) + 2
    vwidth = max(len(value) for _, value, _ in rows) + 2
    lines = [f"{label:<{width}}{value:<{vwidth}}{note}".rstrip() for label, value, note in rows]
    lines += [f"warning: {w}" for w in r["warnings"]]
    lines += [f"wrote {p}" for p in r["plots"]]
    return "\n".join(lines)


def _num(x: float) -> str:
    return "n/a (stroke below its optimum)" if math.isnan(x) else f"{x:.4f}"
