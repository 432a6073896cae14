"""Re-analysis of a sweep from its kept signals, without simulating.

Each case a sweep stored with its signals (``cases/<key>.signals.nc``: the 1 kHz driving force,
the container motion and the ledger's dissipated energy) is analysed again by the complex power
method (:func:`pdamper.run.analyze_signals`) with other analysis settings, e.g. more cycles
dropped. With the settings of the run the numbers are the run's, bit for bit: the same function
on the same arrays. The motion mode, the step count and the energy balance are the run's.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from ..errors import InputError, shown

__all__ = ["reanalyze"]


def reanalyze(path, *, drop_cycles: int | None = None):
    """The results of the store at ``path`` analysed again from the kept signals; returns the
    dataset (as :func:`pdamper.open_results`, with ``drop_cycles`` and a ``reanalysed`` count in
    its attributes). Cases without kept signals keep their stored numbers and are counted in the
    attribute ``not_reanalysed``. Writes nothing."""
    from ..recorders.energy import EnergyLedger
    from ..recorders.signals import Signals
    from ..run import analyze_signals
    from ..schema import replace
    from .store import ResultStore
    from .sweep import add_theory, theory_attrs

    store = ResultStore.open(path)
    base = store.case()
    if drop_cycles is not None:
        if isinstance(drop_cycles, bool) or not isinstance(drop_cycles, int) or drop_cycles < 0:
            raise InputError(f"drop_cycles = {shown(drop_cycles)}; must be a whole number >= 0")
        if drop_cycles >= base.cycles:
            raise InputError(f"drop_cycles = {drop_cycles} leaves nothing of the {base.cycles:g} cycles each case ran; "
                             f"drop fewer than {base.cycles:g}")
        base = dataclasses.replace(base, drop_cycles=drop_cycles)
    done, missing, out = 0, 0, []
    for rec in store.records():
        rec = dict(rec)
        sig = None if "failed" in rec else store.signals(rec.get("key", ""))
        if sig is None:
            missing += "failed" not in rec
            out.append(rec)
            continue
        case = replace(base, rec["point"])
        signals = Signals(**{k: sig[k].values for k in ("time", "time_end", "force", "velocity", "position")})
        a = analyze_signals(case, signals)
        zeros = np.zeros_like(sig["ledger_dissipated"].values)
        ledger = EnergyLedger(time=sig["ledger_time"].values, kinetic=zeros, rotational=zeros, potential=zeros,
                              elastic=zeros, work=zeros, damping=sig["ledger_dissipated"].values, friction=zeros)
        rec.update(eta_star=float(a.eta_star), energy_per_cycle_J=float(a.energy_per_cycle_J),
                   velocity_amplitude_m_s=float(a.velocity_amplitude_m_s),
                   effective_mass_kg=float(a.effective_mass_kg),
                   equivalent_damping_N_s_per_m=float(a.equivalent_damping_N_s_per_m),
                   container_mass_kg=float(case.container.mass),
                   ledger_dissipated_per_cycle_J=ledger.dissipated_per_cycle(case),
                   eta_star_error=float(a.eta_star_error), steady=float(a.steady))
        out.append(rec)
        done += 1
    ds = store.dataset(records=out)
    ds.attrs.update(theory_attrs(store.case()))
    ds = add_theory(ds, store.case())
    ds.attrs.update({"drop_cycles": int(base.drop_cycles), "reanalysed": done, "not_reanalysed": missing})
    ds.attrs["history"] += f"\nreanalysed from the kept signals with drop_cycles = {base.drop_cycles}"
    return ds
