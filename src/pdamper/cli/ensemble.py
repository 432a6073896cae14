"""``--uncertain U.toml --samples N``: the ensemble over the unknowns of ``run``, ``sweep``,
``response`` and ``transient`` (:func:`pdamper.studies.ensemble.run_ensemble`): the options, and the
report (text or JSON ``ensemble = {samples, peak_ratio, rms_ratio, eta_star, ...}``)."""

from __future__ import annotations

import functools
import sys
from dataclasses import dataclass
from pathlib import Path

import click

from ..errors import InputError
from .common import echo_json

__all__ = ["uncertain_options", "EnsembleOptions", "run_uncertain"]

#: Samples of an ensemble without --samples.
DEFAULT_SAMPLES = 32


@dataclass(frozen=True)
class EnsembleOptions:
    """The ensemble options of a command (None where the command does not have them)."""

    uncertain: str
    samples: int
    sample_seed: int
    store: str | None
    tornado: str | None
    workers: int | None = None
    scheduler: str | None = None
    target_peak_ratio: float | None = None
    target_rms_ratio: float | None = None
    target_eta_star: float | None = None


_NAMES = ("uncertain", "samples", "sample_seed", "store", "tornado", "target_peak_ratio", "target_rms_ratio",
          "target_eta_star")


def uncertain_options(*, executor: bool = True, ratios: bool = False, eta: bool = False, store: bool = True,
                      store_default: str = "<config name>_ensemble"):
    """The options of an ensemble, passed to the command as ``ensemble`` (an :class:`EnsembleOptions`,
    None without ``--uncertain``): ``executor`` adds ``--workers`` and ``--scheduler`` (a command that has
    its own passes them in), ``ratios`` the targets of the peak and RMS ratios, ``eta`` the target of
    eta*, ``store`` the store's ``--store`` (a sweep's is its ``--out``; ``store_default`` its default
    in words)."""

    def deco(func):
        # only the options added here: a command's own options of the same name (design's targets) stay its own
        mine = (["uncertain", "samples", "sample_seed", "tornado"] + ["store"] * store
                + ["target_peak_ratio", "target_rms_ratio"] * ratios + ["target_eta_star"] * eta)

        @functools.wraps(func)
        def wrapper(*args, **kw):
            given = {n: kw.pop(n, None) for n in mine}
            given.update({n: None for n in _NAMES if n not in mine})
            own = {} if not executor else {"workers": kw.pop("ens_workers", None),
                                           "scheduler": kw.pop("ens_scheduler", None)}
            if given["uncertain"] is None:
                extra = [f"--{n.replace('_', '-')}" for n in _NAMES[1:] if given[n] is not None]
                if extra:
                    raise InputError(f"{', '.join(extra)} belong{'s' if len(extra) == 1 else ''} to an ensemble: "
                                     "give --uncertain U.toml (the unknowns) with " + ("it" if len(extra) == 1 else "them"))
                return func(*args, ensemble=None, **kw)
            opts = EnsembleOptions(samples=given["samples"] or DEFAULT_SAMPLES,
                                   sample_seed=given["sample_seed"] or 0,
                                   **{n: given[n] for n in _NAMES if n not in ("samples", "sample_seed")}, **own)
            return func(*args, ensemble=opts, **kw)

        opts = [
            click.option("--uncertain", type=click.Path(dir_okay=False), metavar="U.toml",
                         help="An ensemble over the unknowns of U.toml (one [[unknown]] table each: key, "
                              "distribution, its parameters; docs/ensembles.md): the case at --samples Latin "
                              "hypercube samples, resumable, summarised as percentiles, shares and a ranking."),
            click.option("--samples", type=click.IntRange(min=1),
                         help=f"Samples of the ensemble (default {DEFAULT_SAMPLES}); the same file, number and "
                              "--sample-seed give the same samples."),
            click.option("--sample-seed", type=click.IntRange(min=0), help="Seed of the Latin hypercube (default 0)."),
            click.option("--tornado", type=click.Path(dir_okay=False),
                         help="With --uncertain: write the tornado chart of which unknowns matter (png, svg, pdf)."),
        ]
        if store:
            opts.append(click.option("--store", type=click.Path(file_okay=False),
                                     help="With --uncertain: the ensemble's result store (default: "
                                          f"{store_default}); re-running resumes it."))
        if executor:
            opts += [click.option("--workers", "ens_workers", type=click.IntRange(min=1),
                                  help="With --uncertain: local worker processes (default: all cores)."),
                     click.option("--scheduler", "ens_scheduler", metavar="tcp://HOST:PORT",
                                  help="With --uncertain: run the samples on an existing Dask cluster.")]
        if ratios:
            opts += [click.option("--target-peak-ratio", type=click.FloatRange(min=0, min_open=True),
                                  help="With --uncertain: the share of samples whose peak ratio (with / without "
                                       "the damper) is at most this at every reported dof, with its interval."),
                     click.option("--target-rms-ratio", type=click.FloatRange(min=0, min_open=True),
                                  help="With --uncertain: the share of samples whose RMS ratio is at most this.")]
        if eta:
            opts.append(click.option("--target-eta-star", type=click.FloatRange(min=0),
                                     help="With --uncertain: the share of samples whose eta* is at least this."))
        for o in reversed(opts):
            wrapper = o(wrapper)
        return wrapper

    return deco


def run_uncertain(opts: EnsembleOptions, base, config, *, study: str, as_json: bool, command: str | None = None,
                  plot=None, out=None,
                  axes=(), dofs=None, frequencies=None, force_amplitude=None, measure_cycles: int = 8, mode: int = 1,
                  until_steady=None, workers=None, scheduler=None) -> None:
    """Run the ensemble of ``base`` (the command's case) and print its report; ``plot`` the ratio's
    (eta*'s) CDF against the target, ``opts.tornado`` the tornado chart."""
    import warnings

    from ..plotting.figure import check_path
    from ..studies.ensemble import run_ensemble, summarize, summary_lines

    workers = workers if workers is not None else opts.workers
    scheduler = scheduler if scheduler is not None else opts.scheduler
    if workers and scheduler:
        raise InputError("--workers and --scheduler exclude each other: local processes, or a Dask cluster")
    check_path(plot)
    check_path(opts.tornado)
    store = Path(out or opts.store or f"{Path(config).stem}_ensemble")
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = run_ensemble(base, opts.uncertain, opts.samples, store, seed=opts.sample_seed, study=study, axes=axes,
                          dofs=dofs, frequencies=frequencies, force_amplitude=force_amplitude,
                          measure_cycles=measure_cycles, mode=mode, until_steady=until_steady, workers=workers,
                          scheduler=scheduler, progress=None if not as_json else False,
                          history="pdamper " + " ".join(sys.argv[1:]))
    said = []
    for w in caught:
        if str(w.message) not in said:
            said.append(str(w.message))
            click.echo(f"warning: {w.message}", err=True)
    s = summarize(ds, target_peak_ratio=opts.target_peak_ratio, target_rms_ratio=opts.target_rms_ratio,
                  target_eta_star=opts.target_eta_star)
    if plot:
        from ..plotting.ensemble import cdf_figure

        target = opts.target_peak_ratio if "peak_ratio" in ds else opts.target_eta_star
        cdf_figure(ds, plot, target=target)
    if opts.tornado:
        from ..plotting.ensemble import tornado_figure

        tornado_figure(ds, opts.tornado)
    paths = {"store": str(store), "results_nc": str(store / "results.nc"), "results_csv": str(store / "results.csv"),
             "plot": plot, "tornado": opts.tornado}
    if as_json:
        echo_json({"config": str(config), "ensemble": s, **paths})
        return
    lines = [f"pdamper {command or study} {config} --uncertain {opts.uncertain} --samples {opts.samples}"]
    lines += summary_lines(s)
    lines.append(f"  results               {paths['results_nc']} (xarray), {paths['results_csv']}"
                 + "".join(f"; figure: {p}" for p in (plot, opts.tornado) if p))
    click.echo("\n".join(lines))
