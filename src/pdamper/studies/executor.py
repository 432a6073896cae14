"""Where the cases of a study run: an embedded local Dask cluster (all cores, nothing to start)
or an existing Dask distributed cluster given by its scheduler address.

Both paths submit the same function on the same cases, so the same seeds give the same
numbers either way. Results are handed back one by one as cases finish (``as_completed``),
so the caller can store each at once; on Ctrl-C the pending cases are cancelled and the
cluster shut down, and nothing already stored is lost.

Faults (tests/studies/test_cluster_faults.py): a worker that dies (killed, out of memory) takes its
running case with it; Dask runs that case again on another worker (up to
``distributed.scheduler.allowed-failures`` times), the same seed giving the same numbers, and
:func:`execute` reports the cases that ran again (a :class:`RetryWarning`). A scheduler that goes
away cancels the pending cases: an :class:`~pdamper.errors.InputError` says how many finished
(stored by the caller) and how to resume.
"""

from __future__ import annotations

import logging
import os
import warnings

__all__ = ["execute", "execute_batches", "RetryWarning", "GPU_CHUNK", "check_main_guard", "unguarded_main_line",
           "in_main_guard"]

#: Cases of one GPU batch at most (a study's cases run in chunks of this many, each stored as it
#: finishes; 2048 blocks fill an H100's 132 multiprocessors many times over).
GPU_CHUNK = 2048


class RetryWarning(UserWarning):
    """Cases ran again after their Dask worker died; their results are those of the run that finished."""


def in_main_guard(tree, line: int) -> bool:
    """True when ``line`` of the module ``tree`` lies in an ``if __name__ == "__main__":`` block."""
    import ast

    def is_main_test(test) -> bool:
        if not (isinstance(test, ast.Compare) and len(test.ops) == 1 and isinstance(test.ops[0], ast.Eq)):
            return False
        sides = [test.left, test.comparators[0]]
        return (any(isinstance(x, ast.Name) and x.id == "__name__" for x in sides)
                and any(isinstance(x, ast.Constant) and x.value == "__main__" for x in sides))

    return any(isinstance(node, ast.If) and is_main_test(node.test) and node.lineno <= line <= node.end_lineno
               for node in ast.walk(tree))


def unguarded_main_line():
    """``(script, line)`` when the running script (``python script.py``) calls this at its top level
    outside ``if __name__ == "__main__":``, else None. Local Dask workers are started by spawning
    processes, and each one imports the script again: unguarded, every worker would run the sweep
    once more and die ("Nanny failed to start", ~200 lines of traceback, an empty store). A notebook,
    ``python -c`` or an interactive session has no script to import and passes."""
    import ast
    import sys

    main = sys.modules.get("__main__")
    script = getattr(main, "__file__", None)
    if not script or getattr(sys, "ps1", None) is not None:
        return None
    frame = sys._getframe(1)
    line = None
    while frame is not None:  # the outermost frame running the script's own top level
        if frame.f_code.co_name == "<module>" and frame.f_globals.get("__name__") == "__main__":
            line = frame.f_lineno
        frame = frame.f_back
    if line is None:
        return None
    try:
        with open(script, encoding="utf-8") as fh:
            tree = ast.parse(fh.read())
    except (OSError, SyntaxError, ValueError, UnicodeError):
        return None  # the script cannot be read back: say nothing rather than guess
    return None if in_main_guard(tree, line) else (script, line)


def check_main_guard(what: str = "run_sweep") -> None:
    """An :class:`~pdamper.errors.InputError` of one line, with the fix, when :func:`unguarded_main_line`
    finds the script's call outside the ``__main__`` guard (before any process or store is made)."""
    from ..errors import InputError, shown_path

    found = unguarded_main_line()
    if found is not None:
        script, line = found
        raise InputError(f"{shown_path(script)}, line {line}: {what} runs its cases in worker processes, which import "
                         "the script again; put the call under 'if __name__ == \"__main__\":' (docs/sweeps.md), or "
                         "give scheduler=... of a running Dask cluster")


def _client(workers, scheduler):
    from dask.distributed import Client, LocalCluster

    from ..errors import InputError

    if scheduler:
        try:
            return Client(scheduler, timeout="10s", set_as_default=False), None
        except (OSError, TimeoutError) as exc:
            raise InputError(f"--scheduler {scheduler}: cannot reach a Dask scheduler there ({exc}); "
                             "start one with 'dask scheduler' and 'dask worker ADDRESS', or leave "
                             "--scheduler out to use the local cores") from None
    n = workers or os.cpu_count() or 1
    if n < 1:
        raise InputError(f"--workers {workers}: need at least 1")
    check_main_guard("the sweep")
    import dask

    # one case per worker at a time: the rest wait at the scheduler in priority order (longest
    # first) instead of in a busy worker's own queue, where the last of them would keep one worker
    # busy while another idles
    with dask.config.set({"distributed.scheduler.worker-saturation": 1.0}):
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=":0",
                               silence_logs=logging.ERROR)
    # not the process's default client: a user's own Client (a notebook's Client(LocalCluster()))
    # stays the one their dask code uses, during and after the sweep
    return Client(cluster, set_as_default=False), cluster


def execute(items, fn, on_result, *, workers=None, scheduler=None, progress=None, total=None, done=0, costs=None):
    """Run ``fn(case)`` for every ``(key, point, seed, case)`` of ``items``; call
    ``on_result(key, point, seed, result)`` as each finishes (``point``: the case's ``{key: value}``
    on the sweep's grid).

    The cases start longest first (``costs``: ``{key: expected cost}``, default
    :func:`pdamper.studies.cost.expected_cost` of each case), each with a Dask priority by that
    rank, and a local cluster hands a worker its next case only when it is free (worker
    saturation 1.0), so the last cases to start are the short ones and no worker waits at the end
    while another still works through a queue. The order changes no number: every case is
    independent and seeded.

    ``progress``: show a bar (cases done / total, rate, time left) on stderr; default: when
    stderr is a terminal or in Jupyter.

    Returns ``{"retried": {key: times}}``: the cases that ran again after their worker died (also
    warned, :class:`RetryWarning`).
    """
    from concurrent.futures import CancelledError

    from dask.distributed import as_completed

    from ..errors import InputError
    from ._progress import progress_bar, show_progress

    progress = show_progress(progress)
    client, cluster = _client(workers, scheduler)
    bar = progress_bar(total=total or len(items), initial=done, unit="case", desc="sweep", disable=not progress,
                       dynamic_ncols=True)
    from .cost import ranked

    order = ranked(items, costs)
    futures = {client.submit(fn, it[3], key=f"pdamper-{it[0]}", pure=False, priority=len(order) - rank): it
               for rank, it in enumerate(order)}
    finished = 0
    try:
        try:
            for fut in as_completed(futures, loop=client.loop):
                key, point, seed, _ = futures[fut]
                on_result(key, point, seed, fut.result())
                finished += 1
                bar.update(1)
        except CancelledError as exc:
            if client.status == "running":
                raise  # cancelled by someone, not by a lost scheduler
            raise InputError(
                f"the Dask scheduler {scheduler or '(local)'} went away after {finished} of {len(futures)} cases "
                f"({' '.join(str(exc).split())[:160]}); the {finished} finished are stored: re-run the same "
                "command to resume (without --scheduler to use this machine's cores)") from None
        retried = _retries(client, [f.key for f in futures])
    finally:
        for fut in futures:
            if not fut.done():
                fut.cancel()
        bar.close()
        client.close(timeout=10 if client.status == "running" else 2)
        if cluster is not None:
            cluster.close()
    if retried:
        listed = ", ".join(f"{k.removeprefix('pdamper-')} ({n}x)" for k, n in sorted(retried.items()))
        warnings.warn(f"{len(retried)} case(s) ran again after their Dask worker died: {listed}; each result is that "
                      "of the run that finished (same seed, same numbers)", RetryWarning, stacklevel=2)
    return {"retried": {k.removeprefix("pdamper-"): n for k, n in retried.items()}}


def _retries(client, keys) -> dict:
    """``{task key: times its worker died under it}`` for the tasks that were retried (the scheduler's
    "suspicious" count); empty if the scheduler cannot say."""
    wanted = set(keys)

    def count(dask_scheduler=None):  # runs on the scheduler (a closure: pickled by value)
        out = {}
        for k in wanted:
            ts = dask_scheduler.tasks.get(k)
            if ts is not None and getattr(ts, "suspicious", 0):
                out[k] = int(ts.suspicious)
        return out

    try:
        return client.run_on_scheduler(count)
    except Exception:  # an older or foreign scheduler: no report, the results stand
        return {}


def execute_batches(items, batch, on_result, *, progress=None, total=None, done=0, costs=None, chunk=None):
    """Run ``batch(cases) -> results`` (one result per case, in order) over ``items`` in chunks of at
    most ``chunk`` cases (default :data:`GPU_CHUNK`) and call ``on_result(key, point, seed, result)``
    for every case of a chunk as soon as the chunk finishes: the GPU engine's path
    (:func:`pdamper.run.run_cases`), where one batch advances many cases at once.

    The cases are ranked longest first (``costs``, as :func:`execute`) and cut into chunks of
    similar cost (a batch lasts as long as its longest case). If a chunk fails (a GPU that runs out
    of memory or faults), every case of the chunks before it is stored already; the error says how
    many and how to resume.
    """
    from ..errors import InputError
    from ._progress import progress_bar, show_progress
    from .cost import ranked

    progress = show_progress(progress)
    order = ranked(items, costs)
    size = max(1, int(chunk or os.environ.get("PDAMPER_GPU_CHUNK") or GPU_CHUNK))
    parts = -(-len(order) // size)
    per = -(-len(order) // max(parts, 1)) if order else 1
    bar = progress_bar(total=total or len(items), initial=done, unit="case", desc="sweep (GPU)",
                       disable=not progress, dynamic_ncols=True)
    finished = 0
    try:
        for start in range(0, len(order), per):
            part = order[start:start + per]
            try:
                results = batch([it[3] for it in part])
            except InputError:
                raise
            except Exception as exc:  # the GPU ran out of memory or faulted: say so, keep what is stored
                raise InputError(f"the GPU batch of {len(part)} case{'s' if len(part) != 1 else ''} failed after "
                                 f"{finished} of {len(order)} cases "
                                 f"were stored ({type(exc).__name__}: {' '.join(str(exc).split())[:200]}); re-run the "
                                 "same command to resume (smaller batches: PDAMPER_GPU_CHUNK=256), or run on the CPU "
                                 "without --device cuda") from None
            for (key, point, seed, _), res in zip(part, results):
                on_result(key, point, seed, res)
                finished += 1
                bar.update(1)
    finally:
        bar.close()
    return {"retried": {}}
