"""The lines ``pdamper decay`` and ``pdamper response`` print (:mod:`pdamper.cli.structure`): a DEM
response's table, a dof's, a stepped sine's, a response from the fields, the numbers codes ask for."""

from __future__ import annotations

from .codes import codes_lines, tmd_lines

__all__ = ["transient_words"]


def _codes_text(s: dict) -> list[str]:
    """A response's numbers codes ask for and its damper as an equivalent TMD (:mod:`.codes`)."""
    return codes_lines(s["codes"], over="(the largest over the frequencies)") + tmd_lines(s["tmd_equivalent"])


def _dem_lines(s: dict, config, f0: float, prediction: bool) -> list[str]:
    """The table of a DEM response (``s``: its summary)."""
    from ..studies.structure import frequency_format

    mark = lambda k: "" if s["steady"][k] else " *"  # noqa: E731
    hz = frequency_format(s["frequencies_hz"])
    lines = [f"pdamper response {config}  (F0 = {f0:.4g} N, {s['particles']} spheres, "
             f"{100 * s['mass_ratio']:.3g} % of M; {s['measure_cycles']} of {s['cycles']:g} cycles measured, "
             f"from {s['start']})",
             f"  {'f [Hz]':>8}  {'damper [mm]':>12}  {'bare [mm]':>10}  {'bare run [mm]':>13}  {'solid mass [mm]':>15}"
             + ("  fields [mm]" if prediction else "")]
    for k, f in enumerate(s["frequencies_hz"]):
        line = (f"  {hz(f):>8}  {1e3 * s['damper_amplitude_m'][k]:10.4g}{mark(k):2}  {1e3 * s['amplitude_bare_m'][k]:10.4g}  "
                f"{1e3 * s['amplitude_bare_run_m'][k]:11.4g}{'' if s['bare_run_steady'][k] else ' *':2}  "
                f"{1e3 * s['amplitude_solid_mass_m'][k]:15.4g}")
        if prediction:
            line += "  " + _branches_mm(s["fields_prediction"]["damper_amplitude_m"][k])
        lines.append(line)
    ratio = (f"ratio {s['peak_reduction']:.3g}" if s["peak_steady"]
             else f"no ratio: the damped peak is a transient ({transient_words(s)})")
    lines.append(_peak_line(s, hz) + ratio)
    if not all(s["steady"]) or not all(s["bare_run_steady"]):
        lines.append(f"  * not steady: the amplitude over the last period (or the last half of the measured ones) "
                     f"differs from the one before by more than {100 * s['steady_tolerance']:g} %; a bare run: "
                     "more than that from its steady closed form (a transient; run more --cycles or --start bare|fields)")
    lines.append(f"  energy balance error (worst point) {s['energy_balance_error_max']:.2g}; "
                 f"DEM time {s['wall_time_s']:.3g} s")
    for f, msg in s["failed"].items():
        lines.append(f"  failed at {f} Hz: {msg}")
    return lines


def _dof_lines(s: dict) -> list[str]:
    """Each dof asked for (--dofs): its largest amplitude over the frequencies with the damper (the
    largest stable branch) and without, and where."""
    import numpy as np

    from ..studies.structure import frequency_format

    hz = frequency_format(s["frequencies_hz"])
    top = lambda v: max(v) if isinstance(v, list) and v else (v if not isinstance(v, list) else float("nan"))  # noqa: E731
    lines = [f"  every dof asked for ({s['method']}): the largest amplitude over these frequencies",
             f"  {'dof':>9}  {'damper [mm]':>11}  {'at f [Hz]':>9}  {'bare [mm]':>10}  {'at f [Hz]':>9}"]
    for d, amp, bare in zip(s["dofs"], s["response_amplitude_m"], s["response_amplitude_bare_m"]):
        a = [top(v) for v in amp]
        k = int(np.nanargmax(a)) if np.any(np.isfinite(a)) else 0
        kb = int(np.argmax(bare))
        lines.append(f"  {str(d):>9}  {1e3 * a[k]:11.4g}  {hz(s['frequencies_hz'][k]):>9}  {1e3 * bare[kb]:10.4g}  "
                     f"{hz(s['frequencies_hz'][kb]):>9}")
    return lines


def _sweep_lines(s: dict, config) -> list[str]:
    """The table of a stepped sine (``s``: its summary), in the sweep's order, and its jumps."""
    from ..analysis.decay import JUMP, amplitude_jumps
    from ..studies.structure import frequency_format

    hz = frequency_format(s["frequencies_hz"])
    lines = [f"pdamper response {config} --sweep {s['sweep']}  (F0 = {s['force_amplitude_N']:.4g} N, "
             f"{s['particles']} spheres, {100 * s['mass_ratio']:.3g} % of M; {s['cycles']:g} periods a step, the last "
             f"{s['measure_cycles']} fitted; the state carried)",
             f"  {'f [Hz]':>8}  {'damper [mm]':>12}  {'bare [mm]':>10}  {'bare sweep [mm]':>15}  {'solid mass [mm]':>15}"]
    x = s["damper_amplitude_m"]
    for k, f in enumerate(s["frequencies_hz"]):
        lines.append(f"  {hz(f):>8}  {1e3 * x[k]:10.4g}{'' if s['steady'][k] else ' *':2}  "
                     f"{1e3 * s['amplitude_bare_m'][k]:10.4g}  {1e3 * s['amplitude_bare_sweep_m'][k]:15.4g}  "
                     f"{1e3 * s['amplitude_solid_mass_m'][k]:15.4g}")
    for fa, fb, xa, xb in amplitude_jumps(s["frequencies_hz"], x):
        lines.append(f"  a step of more than {100 * JUMP:g} % between {hz(fa)} and {hz(fb)} Hz: {1e3 * xa:.4g} -> "
                     f"{1e3 * xb:.4g} mm (a jump, or a transient: see the bare sweep)")
    lines.append(f"  peak with damper {1e3 * s['peak_damped_m']:.4g} mm at {hz(s['peak_damped_frequency_hz'])} Hz; "
                 f"without {1e3 * s['resonance_bare_m']:.4g} mm at its resonance {s['resonance_bare_frequency_hz']:.5g} "
                 f"Hz: ratio {s['peak_reduction']:.3g}; the bare stepped sine against its closed form: "
                 f"{s['bare_sweep_vs_closed_form_max_error']:.2g}")
    if not all(s["steady"]):
        lines.append(f"  * not steady: the two halves of the measured periods differ by more than "
                     f"{100 * s['steady_tolerance']:g} % (run more --cycles a step)")
    lines.append(f"  energy balance error {s['energy_balance_error']:.2g}; DEM {s['duration_s']:.4g} s simulated in "
                 f"{s['wall_time_s']:.3g} s")
    return lines


def transient_words(s: dict) -> str:
    """Why the damped peak of a DEM response ``s`` is not steady: the checks that failed, with
    their numbers and the limit (:func:`pdamper.studies.structure.steadiness`)."""
    k = s["frequencies_hz"].index(s["peak_damped_frequency_hz"])
    tol = s["steady_tolerance"]
    checks = [("over the last period", s["last_period_change"][k]),
              ("between the two halves of the measured periods", s["window_change"][k])]
    failed = [f"changed {100 * v:.2g} % {what}" for what, v in checks if not v <= tol]
    return "; ".join(failed or ["its run failed"]) + f", beyond the {100 * tol:g} % limit"


def _peak_line(s: dict, hz) -> str:
    """The damped peak against the bare structure's resonance (its closed-form peak, not the grid's
    largest bare value)."""
    return (f"  peak with damper {1e3 * s['peak_damped_m']:.4g} mm at {hz(s['peak_damped_frequency_hz'])} Hz; without "
            f"{1e3 * s['resonance_bare_m']:.4g} mm at its resonance {s['resonance_bare_frequency_hz']:.5g} Hz "
            f"({1e3 * s['peak_bare_m']:.4g} mm on this grid): ")


def _branches_mm(v) -> str:
    """A frequency's stable amplitudes in mm: one number, or the branches joined by ' / '."""
    vals = v if isinstance(v, list) else [v]
    return " / ".join(f"{1e3 * x:.4g}" for x in vals) if vals else "none"


def _fields_lines(s, config, f0, fields_path, plot) -> list[str]:
    lines = [f"pdamper response {config} --fields {fields_path}  (F0 = {f0:.4g} N, {s['particles']} spheres, "
             f"{100 * s['mass_ratio']:.3g} % of M; harmonic balance, stable branches)",
             f"  {'f [Hz]':>8}  {'damper [mm]':>16}  {'response [mm]':>16}  {'bare [mm]':>10}  {'solid mass [mm]':>15}"]
    from ..studies.structure import frequency_format

    hz = frequency_format(s["frequencies_hz"])
    for k, f in enumerate(s["frequencies_hz"]):
        lines.append(f"  {hz(f):>8}  {_branches_mm(s['damper_amplitude_m'][k]):>16}  "
                     f"{_branches_mm(s['response_point_amplitude_m'][k]):>16}  {1e3 * s['amplitude_bare_m'][k]:10.4g}  "
                     f"{1e3 * s['amplitude_solid_mass_m'][k]:15.4g}")
    lines.append(_peak_line(s, hz) + f"ratio {s['peak_reduction']:.3g}")
    if s["jump_frequencies_hz"]:
        lines.append("  jumps (the stable branches change) at " +
                     ", ".join(f"{f:.5g} Hz" for f in s["jump_frequencies_hz"]))
    if s["extrapolated"]:
        lines.append("  warning: some solutions lie outside the fields' box (--extrapolate: end values continued)")
    lines.append(f"  solve time {1e3 * s['solve_time_median_s']:.3g} ms per frequency (median); fields {s['fields_box']}")
    if plot:
        lines.append(f"  wrote {plot}")
    return lines
