"""``pdamper transient`` over a suite of records (``[load] files = [...]``): one transient a record
(:func:`pdamper.studies.suite.run_suite`) and what engineers report over them; printing only."""

from __future__ import annotations

import math

__all__ = ["transient_suite", "suite_lines"]


def transient_suite(case, config, dofs, plot, as_json, limits=None) -> None:
    """Run the suite of ``case`` (``dofs``: the labels asked for; ``limits`` each record's codes
    limits, in its JSON) and print it; ``plot`` the figure."""
    from ..plotting.suite import suite_figure
    from ..studies.suite import run_suite
    from .transient import shown_run

    total = sum(load.duration for load in case.drive.load.records())
    shown_run("pdamper transient (suite)", total, lambda progress: run_suite(case, dofs=dofs, progress=progress, limits=limits),
              suite_figure, suite_lines, config, plot, as_json)


def suite_lines(s: dict, config) -> list[str]:
    """The tables of a suite (``s``: its summary): record by record at the damper point, then every
    dof's mean and 84th percentile over the records."""
    ratio = lambda r: "n/a" if r is None or not math.isfinite(r) else f"{r:.3g}"  # noqa: E731
    mm = lambda x: "n/a" if x is None else f"{1e3 * x:.4g}"  # noqa: E731
    sp = s.get("spectra")
    lines = [f"pdamper transient {config}: a suite of {s['records']} records, one coupled transient each",
             f"  damper                {s['particles']} spheres, {1e3 * s['bed_mass_kg']:.4g} g "
             f"({100 * s['mass_ratio']:.3g} % of M)"]
    if sp is not None:
        lines.append(f"  spectra               {100 * sp['damping']:g} %-damped PSA, first period "
                     f"{sp['first_period_s']:.4g} s ({sp['method']})")
    lines.append("  the damper point" + (" (relative to the ground)" if s["relative_to_ground"] else "")
                 + "; ratio = with / without the damper:")
    head = f"  {'record':<24}" + (f"{'PSA(T1) [g]':>12}" if sp is not None else "")
    lines.append(head + f"  {'peak [mm]':>10}  {'bare [mm]':>10}  {'ratio':>6}  {'rms [mm]':>10}  {'bare [mm]':>10}"
                 f"  {'ratio':>6}")
    for k, (name, r) in enumerate(zip(s["record_names"], s["runs"])):
        row = f"  {name[:24]:<24}" + (f"{sp['psa_at_first_period_m_s2'][k] / 9.80665:12.3g}" if sp is not None else "")
        lines.append(row + f"  {mm(r['damper_peak_m']):>10}  {mm(r['damper_peak_bare_m']):>10}  "
                     f"{ratio(r['damper_peak_reduction']):>6}  {mm(r['damper_rms_m']):>10}  "
                     f"{mm(r['damper_rms_bare_m']):>10}  {ratio(r['damper_rms_reduction']):>6}")
    st = s["statistics"]
    for what in ("mean", "p84"):
        label = "mean" if what == "mean" else "84th percentile"
        row = f"  {label:<24}" + (" " * 12 if sp is not None else "")
        lines.append(row + f"  {mm(st['damper_peak_m'][what]):>10}  {mm(st['damper_peak_bare_m'][what]):>10}  "
                     f"{ratio(st['damper_peak_reduction'][what]):>6}  {mm(st['damper_rms_m'][what]):>10}  "
                     f"{mm(st['damper_rms_bare_m'][what]):>10}  {ratio(st['damper_rms_reduction'][what]):>6}")
    lines.append(f"  ratio of the means    peak {ratio(s['damper_peak_ratio'])}, rms {ratio(s['damper_rms_ratio'])} "
                 "(the mean with the damper over the mean without: the codes' design value)")
    lines.append("  every dof" + (" (relative to the ground)" if s["relative_to_ground"] else "")
                 + ": mean and 84th percentile over the records (lognormal), ratio of the means")
    lines.append(f"  {'dof':>9}  {'peak mean':>10}  {'p84':>10}  {'bare mean':>10}  {'p84':>10}  {'ratio':>6}  "
                 f"{'rms mean':>10}  {'bare mean':>10}  {'ratio':>6}   [mm]")
    for k, d in enumerate(s["dofs"]):
        p84 = lambda key: None if st[key]["p84"] is None else st[key]["p84"][k]  # noqa: E731
        lines.append(f"  {str(d):>9}  {mm(st['peak_m']['mean'][k]):>10}  {mm(p84('peak_m')):>10}  "
                     f"{mm(st['peak_bare_m']['mean'][k]):>10}  {mm(p84('peak_bare_m')):>10}  "
                     f"{ratio(s['peak_ratio'][k]):>6}  {mm(st['rms_m']['mean'][k]):>10}  "
                     f"{mm(st['rms_bare_m']['mean'][k]):>10}  {ratio(s['rms_ratio'][k]):>6}")
    lines.append(f"  DEM                   {s['steps']:,} steps in {s['wall_time_s']:.3g} s over the records")
    if s.get("plot"):
        lines.append(f"  wrote {s['plot']}")
    return lines
