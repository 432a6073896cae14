"""Where the cases of a study run: an embedded local Dask cluster (all cores, nothing to start)
or an existing Dask distributed cluster given by its scheduler address.

Both paths submit the same function on the same cases, so the same seeds give the same
numbers either way. Results are handed back one by one as cases finish (``as_completed``),
so the caller can store each at once; on Ctrl-C the pending cases are cancelled and the
cluster shut down, and nothing already stored is lost.
"""

from __future__ import annotations

import logging
import os

__all__ = ["execute"]


def _client(workers, scheduler):
    from dask.distributed import Client, LocalCluster

    from ..errors import InputError

    if scheduler:
        try:
            return Client(scheduler, timeout="10s"), None
        except (OSError, TimeoutError) as exc:
            raise InputError(f"--scheduler {scheduler}: cannot reach a Dask scheduler there ({exc}); "
                             "start one with 'dask scheduler' and 'dask worker ADDRESS', or leave "
                             "--scheduler out to use the local cores") from None
    n = workers or os.cpu_count() or 1
    if n < 1:
        raise InputError(f"--workers {workers}: need at least 1")
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                           silence_logs=logging.ERROR)
    return Client(cluster), cluster


def _weight(point) -> float:
    """How long a case is expected to take, for ordering: the stroke (large strokes take longest)."""
    if isinstance(point, dict):
        return float(point.get("drive.stroke", 0.0)) if isinstance(point.get("drive.stroke"), (int, float)) else 0.0
    return float(point)


def execute(items, fn, on_result, *, workers=None, scheduler=None, progress=None, total=None, done=0):
    """Run ``fn(case)`` for every ``(key, point, seed, case)`` of ``items``; call
    ``on_result(key, point, seed, result)`` as each finishes (``point``: the case's ``{key: value}``
    on the sweep's grid).

    ``progress``: show a bar (cases done / total, rate, time left) on stderr; default: when
    stderr is a terminal or in Jupyter.
    """
    from dask.distributed import as_completed

    from ._progress import progress_bar, show_progress

    progress = show_progress(progress)
    client, cluster = _client(workers, scheduler)
    bar = progress_bar(total=total or len(items), initial=done, unit="case", desc="sweep", disable=not progress,
                       dynamic_ncols=True)
    # the longest cases (large strokes) first, for a balanced finish
    order = sorted(items, key=lambda it: -_weight(it[1]))
    futures = {client.submit(fn, it[3], key=f"pdamper-{it[0]}", pure=False): it for it in order}
    try:
        for fut in as_completed(futures):
            key, point, seed, _ = futures[fut]
            on_result(key, point, seed, fut.result())
            bar.update(1)
    finally:
        for fut in futures:
            if not fut.done():
                fut.cancel()
        bar.close()
        client.close()
        if cluster is not None:
            cluster.close()
