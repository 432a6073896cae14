"""The lines that ``pdamper transient``, ``response`` and ``design`` print about the numbers codes ask
for, the damper as an equivalent TMD and the structure's modes (:mod:`pdamper.analysis.codes`,
:mod:`pdamper.analysis.tmd`); the ``--limit`` option. Printing only: the numbers come from the
studies' summaries."""

from __future__ import annotations

import math

import click

__all__ = ["limit_option", "codes_lines", "tmd_lines", "mode_lines", "settings_line"]


def limit_option(func):
    """``--limit KEY=VALUE`` (repeatable): the limits of :func:`pdamper.analysis.codes.parse_limits`."""
    return click.option(
        "--limit", "limits", multiple=True, metavar="KEY=VALUE",
        help="A limit to judge the response by, per dof or storey, with and without the damper (repeatable): "
             "drift=0.5% (peak inter-storey drift ratio; needs [structure] storey_heights), residual_drift=0.2%, "
             "acceleration=0.15m/s^2 (peak absolute floor acceleration; 0.015g is 0.015 g_n), "
             "rms_acceleration=0.05m/s^2.")(func)


def _num(x, fmt: str = ".4g") -> str:
    return "n/a" if x is None or not math.isfinite(x) else format(x, fmt)


def _pct(x, fmt: str = ".3g") -> str:
    return "n/a" if x is None or not math.isfinite(x) else f"{100 * x:{fmt}}"


def _verdict_cells(c: dict, key: str, k: int) -> str:
    v = c["limits"].get(key)
    if v is None or "verdict" not in v:
        return ""
    return f"  {v['verdict'][k] + ' / ' + v['verdict_bare'][k]:>15}"


def _limit_head(c: dict, keys) -> str:
    out = ""
    for key in keys:
        v = c["limits"].get(key)
        if v is not None and "verdict" in v:
            shown = f"{100 * v['limit']:.3g} %" if key.endswith("drift") else f"{v['limit']:.3g}"
            out += f"  {('<= ' + shown + ' w/wo'):>15}"
    return out


def codes_lines(c: dict, *, over: str = "over the record") -> list[str]:
    """The tables of a summary's ``codes`` (:func:`pdamper.analysis.codes.code_summary`): every dof's
    absolute floor acceleration and every storey's drift ratio with and without the damper, their
    ratios and each limit's verdict (with / without)."""
    acc_keys = [k for k in ("acceleration", "rms_acceleration") if k in c["limits"]]
    lines = [f"  floor accelerations [m/s^2] {over}, {c['acceleration_note']}; ratio = with / without:",
             f"  {'dof':>9}  {'peak':>9}  {'bare':>9}  {'ratio':>6}  {'rms':>9}  {'bare':>9}  {'ratio':>6}"
             + _limit_head(c, acc_keys)]
    for k, d in enumerate(c["dofs"]):
        lines.append(f"  {str(d):>9}  {_num(c['acceleration_peak_m_s2'][k]):>9}  "
                     f"{_num(c['acceleration_peak_bare_m_s2'][k]):>9}  {_num(c['acceleration_peak_reduction'][k], '.3g'):>6}"
                     f"  {_num(c['acceleration_rms_m_s2'][k]):>9}  {_num(c['acceleration_rms_bare_m_s2'][k]):>9}  "
                     f"{_num(c['acceleration_rms_reduction'][k], '.3g'):>6}"
                     + "".join(_verdict_cells(c, key, k) for key in acc_keys))
    if c.get("storeys") is None:
        lines.append(f"  drift ratios: {c['storeys_note']}")
    else:
        drift_keys = [k for k in ("drift", "residual_drift") if k in c["limits"]]
        resid = "drift_ratio_residual" in c
        lines.append(f"  inter-storey drift ratios [%] {over} (drift / storey height"
                     + (f"; residual: the mean over the last {c['residual_window_s']:.3g} s" if resid else "") + "):")
        lines.append(f"  {'storey':>9}  {'between':>15}  {'h [m]':>6}  {'peak':>8}  {'bare':>8}  {'ratio':>6}  "
                     f"{'rms':>8}  {'bare':>8}" + (f"  {'residual':>8}  {'bare':>8}" if resid else "")
                     + _limit_head(c, drift_keys))
        for j, name in enumerate(c["storeys"]):
            low, upper = (str(b) for b in c["storey_between"][j])
            line = (f"  {str(name):>9}  {low + ' - ' + upper:>15}  {c['storey_heights_m'][j]:6.3g}  "
                    f"{_pct(c['drift_ratio_peak'][j]):>8}  {_pct(c['drift_ratio_peak_bare'][j]):>8}  "
                    f"{_num(c['drift_ratio_peak_reduction'][j], '.3g'):>6}  {_pct(c['drift_ratio_rms'][j]):>8}  "
                    f"{_pct(c['drift_ratio_rms_bare'][j]):>8}")
            if resid:
                line += f"  {_pct(c['drift_ratio_residual'][j]):>8}  {_pct(c['drift_ratio_residual_bare'][j]):>8}"
            lines.append(line + "".join(_verdict_cells(c, key, j) for key in drift_keys))
    for key, v in c["limits"].items():
        shown = f"{100 * v['limit']:.3g} %" if key.endswith("drift") else f"{v['limit']:.3g} m/s^2"
        if "verdict" not in v:
            lines.append(f"  limit {key} <= {shown}: not judged ({v['note']})")
            continue
        where = "storey" if key.endswith("drift") else "dof"
        over_d = [str(x) for x, y in zip(v["labels"], v["verdict"]) if y == "exceed"]
        over_b = [str(x) for x, y in zip(v["labels"], v["verdict_bare"]) if y == "exceed"]
        say = lambda met, over: ("met" if met else f"not met ({where} {', '.join(over)} exceed)"  # noqa: E731
                                 if over else "not judged everywhere (n/a)")
        lines.append(f"  limit {v['what']} <= {shown}: with the damper {say(v['met'], over_d)}; "
                     f"without {say(v['met_bare'], over_b)}")
    return lines


def tmd_lines(tmds: list) -> list[str]:
    """The damper(s) as equivalent TMDs (:func:`pdamper.analysis.tmd.tmd_numbers`), mode by mode, beside
    Den Hartog's optimal TMD of the same mass ratio."""
    lines = []
    for t in tmds:
        fit = t.get("fit") or {}
        at = f" at {t['at_frequency_hz']:.5g} Hz" if "at_frequency_hz" in t and math.isfinite(t["at_frequency_hz"]) else ""
        ratio = t["equivalent_mass_kg"] / t["bed_mass_kg"] if t["bed_mass_kg"] > 0 else math.nan
        r2 = fit.get("r2", math.nan)
        lines.append(f"  the damper as an equivalent TMD: the bed's force fitted by a mass m_a = "
                     f"{_num(1e3 * t['equivalent_mass_kg'])} g ({_num(ratio, '.3g')} m_bed) and a dashpot c_a = "
                     f"{_num(t['equivalent_damping_N_s_per_m'], '.3g')} N s/m over {t.get('fit_over', 'the record')}{at}"
                     + (f" (R^2 {r2:.3f})" if math.isfinite(r2) else "") + ":")
        cols = ("mode", "f [Hz]", "zeta", "Q", "mu bed", "mu_a", "detuning", "zeta_a", "Q with", "| DH f_opt",
                "zeta_opt", "zeta_eq", "share")
        lines.append("  " + "  ".join(f"{c:>9}" for c in cols))
        for k, mode in enumerate(t["modes"]):
            cells = (str(mode), f"{t['frequency_hz'][k]:.5g}", _pct(t["damping_ratio"][k]) + " %",
                     _num(t["q"][k], ".3g"), _pct(t["mass_ratio"][k]) + " %", _pct(t["effective_mass_ratio"][k]) + " %",
                     _pct(t["detuning"][k]) + " %", _pct(t["added_damping_ratio"][k]) + " %",
                     _num(t["q_with_damper"][k], ".3g"), f"| {t['den_hartog_tuning'][k]:.4f}",
                     _pct(t["den_hartog_damping_ratio"][k]) + " %", _pct(t["den_hartog_equivalent_damping_ratio"][k]) + " %",
                     _pct(t["share_of_den_hartog"][k]) + " %")
            lines.append("  " + "  ".join(f"{c:>9}" for c in cells))
        p = t.get("from_peak_ratio")
        if p:
            lines.append(f"  from the resonant amplitudes (ratio {_num(p['peak_ratio'], '.3g')}): mode {p['mode']} "
                         f"added damping ratio {_pct(p['added_damping_ratio'])} %, detuning {_pct(p['detuning'])} % "
                         f"(to the grid's {_num(p['grid_step_hz'], '.3g')} Hz)"
                         + ("" if p.get("steady", True) else "; the damped peak is a transient: not its steady value"))
    if lines:
        lines.append("  (mu = m phi_d^2 / m_k, the bed's and the fitted m_a's; zeta_a = phi_d^2 c_a / (2 sqrt(k_k "
                     "(m_k + phi_d^2 m_a))); Den Hartog's (DH) optimal TMD of mass ratio mu bed: f_opt = 1/(1 + mu), "
                     "zeta_opt = sqrt(3 mu / (8 (1 + mu)^3)), worth zeta_eq = 1 / (2 sqrt(1 + 2/mu)); share = zeta_a / "
                     "zeta_eq; docs/structure.md)")
    return lines


def mode_lines(modes: dict, *, limit: int = 6) -> list[str]:
    """The structure's modes (:func:`pdamper.studies.structure_base.mode_table`): frequency, damping
    ratio and shape at the damper (with the mode's mass there), the first ``limit``."""
    n = len(modes["frequency_hz"])
    parts = [f"{k + 1}: {modes['frequency_hz'][k]:.5g} Hz, zeta {100 * modes['damping_ratio'][k]:.3g} %, phi_d "
             f"{modes['phi_damper'][k]:.4g} ({modes['mass_at_damper_kg'][k]:.4g} kg at the damper)"
             for k in range(min(n, limit))]
    more = f"; and {n - limit} more" if n > limit else ""
    return [f"  modes                 " + "; ".join(parts) + more]


def settings_line(settings) -> list[str]:
    """The ``--set`` overrides as given, one line (none without them)."""
    items = [str(s).strip() for s in settings or ()]
    return [f"  --set                 {', '.join(items)}"] if items else []
