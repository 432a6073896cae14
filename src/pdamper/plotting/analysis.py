"""Figure for one analysed record: the signals and the energy of every cycle.

Top panel: driving force and container velocity over time (two y axes), the
dropped cycles greyed and the FFT window shaded. Bottom panel: the energy put in
during each whole cycle, ``int F v dt`` (dropped cycles grey), with the complex
power result ``E~_diss = (2 pi / Omega) Re(P)`` (paper eq. 4) as a line across
the window. A flat row of bars on that line says the record is steady and the
method consistent.

Matplotlib is imported lazily and only through its object API with the Agg
canvas (no pyplot, no global state), so this is safe on headless machines and
in worker threads.
"""

from __future__ import annotations

import math

import numpy as np

from ..errors import InputError
from .figure import FORMATS, check_path, save

__all__ = ["plot_analysis", "FORMATS"]

_PREFIXES = ((1e3, "k"), (1.0, ""), (1e-3, "m"), (1e-6, "µ"), (1e-9, "n"))


def plot_analysis(result, path=None, *, title: str | None = None,
                  figsize=(8.0, 6.2), dpi: int = 150):
    """Draw the analysis of one record; save it if ``path`` is given.

    Parameters
    ----------
    result : pdamper.analysis.PowerResult
        From :func:`pdamper.analysis.complex_power` or
        :func:`~pdamper.analysis.analyze_record` with ``keep_signals=True`` (the default).
    path : str or os.PathLike, optional
        Output file; the extension chooses the format (``.png``, ``.svg``, ``.pdf``).
    title : str, optional
        Figure title (e.g. the record's file name).
    figsize : tuple of float
        Figure size [inch].
    dpi : int
        Resolution of raster output [dots per inch].

    Returns
    -------
    matplotlib.figure.Figure
    """
    path = check_path(path, create_folder=True)
    sig = result.signals
    if sig is None:
        raise InputError("the result carries no signals to plot; analyse with keep_signals=True")

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.patches import Patch

    fig = Figure(figsize=figsize, dpi=dpi, layout="constrained")
    FigureCanvasAgg(fig)
    ax_f, ax_e = fig.subplots(2, 1, sharex=True, height_ratios=(1.25, 1.0))

    period = result.period_s
    t = sig.time_s
    t_a, t_b = result.window_s
    starts = np.asarray(result.cycle_start_s)
    used = np.asarray(result.cycle_used, dtype=bool)
    grey, c_force, c_vel, c_used, c_line = "0.55", "tab:blue", "tab:orange", "tab:green", "black"

    # ---- top: force and velocity
    f_scale, f_unit = _prefix(np.max(np.abs(sig.force_N)), "N")
    v_scale, v_unit = _velocity_unit(np.max(np.abs(sig.velocity_m_s)))
    for ax in (ax_f, ax_e):
        if result.cycles_dropped:
            ax.axvspan(t[0], t_a, color=grey, alpha=0.15, lw=0)
        ax.axvspan(t_a, t_b, color=c_used, alpha=0.07, lw=0)
        for x in starts[1:]:
            ax.axvline(x, color="0.8", lw=0.5, zorder=0)
    ax_f.plot(t, sig.force_N / f_scale, color=c_force, lw=0.9)
    ax_f.set_ylabel(f"force F [{f_unit}]", color=c_force)
    ax_f.tick_params(axis="y", colors=c_force)
    ax_v = ax_f.twinx()
    ax_v.plot(t, sig.velocity_m_s / v_scale, color=c_vel, lw=1.2)
    ax_v.set_ylabel(f"velocity v [{v_unit}]" + ("" if sig.motion == "velocity"
                                                   else f" (from {sig.motion})"), color=c_vel)
    ax_v.tick_params(axis="y", colors=c_vel)
    ax_f.set_zorder(ax_v.get_zorder() + 1)     # force (with its impacts) drawn on top
    ax_f.patch.set_visible(False)
    _symmetric(ax_f, headroom=0.4)
    _symmetric(ax_v, headroom=0.4)
    ax_f.legend(handles=[
        Patch(color=grey, alpha=0.3, label=f"dropped ({result.cycles_dropped} cycles)"),
        Patch(color=c_used, alpha=0.2, label=f"FFT window ({result.cycles_used} whole cycles)"),
    ], loc="upper center", ncols=2, fontsize=8, framealpha=0.9)
    ax_f.set_title(f"f = {result.frequency_hz:.6g} Hz"
                   f"{' (detected)' if result.frequency_detected else ''}, "
                   f"|F*| = {result.force_amplitude_N / f_scale:.4g} {f_unit}, "
                   f"|V*| = {result.velocity_amplitude_m_s / v_scale:.4g} {v_unit}", fontsize=10)

    # ---- bottom: energy per cycle
    energies = np.asarray(result.cycle_energies_J)
    ref = max(np.max(np.abs(energies)) if energies.size else 0.0, abs(result.energy_per_cycle_J))
    e_scale, e_unit = _prefix(ref, "J")
    mids = starts + 0.5 * period
    ax_e.bar(mids[~used], energies[~used] / e_scale, width=0.8 * period, color=grey,
             label="dropped cycle")
    ax_e.bar(mids[used], energies[used] / e_scale, width=0.8 * period, color=c_used,
             alpha=0.85, label=r"cycle energy $\int F\,v\,\mathrm{d}t$")
    e_fft = result.energy_per_cycle_J / e_scale
    ax_e.hlines(e_fft, t_a, t_b, color=c_line, lw=1.6,
                label=(rf"$\tilde E_\mathrm{{diss}}$ = {e_fft:.4g} {e_unit} "
                       r"(complex power, eq. 4)"))
    ax_e.axhline(0.0, color="0.3", lw=0.6)
    ax_e.set_ylabel(f"energy per cycle [{e_unit}]")
    ax_e.set_xlabel("time t [s]")
    ax_e.set_xlim(t[0], t[-1])
    parts = [rf"$\langle F v\rangle T$ = {result.mean_power_check_J / e_scale:.4g} {e_unit}"]
    if math.isfinite(result.eta_star):
        parts.append(rf"$\eta^*$ = {result.eta_star:.3f} "
                     rf"($m_\mathrm{{bed}}$ = {1e3 * result.bed_mass_kg:.4g} g, eq. 5)")
    if math.isfinite(result.cycle_energy_spread):
        spread = 100 * result.cycle_energy_spread
        parts.append("cycle spread " + ("< 0.01 %" if spread < 0.01 else f"{spread:.2g} %"))
    ax_e.set_title(",   ".join(parts), fontsize=10)
    lo, hi = ax_e.get_ylim()
    lo = min(lo, 0.0)
    ax_e.set_ylim(lo, hi + 0.3 * (hi - lo))
    ax_e.legend(loc="upper center", fontsize=8, ncols=3, framealpha=0.9)

    if title:
        fig.suptitle(title, fontsize=11)
    if path is not None:
        save(fig, path, dpi)
    return fig


def _prefix(ref: float, unit: str) -> tuple[float, str]:
    """Scale and prefixed unit so that ``ref`` reads between 1 and 1000."""
    if not ref > 0.0 or not math.isfinite(ref):
        return 1.0, unit
    for scale, p in _PREFIXES:
        if ref >= scale:
            return scale, p + unit
    return _PREFIXES[-1][0], _PREFIXES[-1][1] + unit


def _velocity_unit(ref: float) -> tuple[float, str]:
    return (1.0, "m/s") if ref >= 0.5 or not ref > 0.0 else (1e-3, "mm/s")


def _symmetric(ax, headroom: float = 0.0) -> None:
    """Centre an axis on zero (twin axes then share the baseline), with room above for a legend."""
    lo, hi = ax.get_ylim()
    m = max(abs(lo), abs(hi))
    ax.set_ylim(-m, m * (1.0 + headroom))
