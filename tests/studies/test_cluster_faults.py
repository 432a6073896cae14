"""Faults on a Dask cluster (issue 24): a worker killed in the middle of a study, and a scheduler that
goes away. Real processes (a LocalCluster with worker processes; a ``dask scheduler`` and a
``dask worker`` started as commands), tiny cases (8 spheres, 3 cycles): under a minute in all.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

from dem_fixtures import TINY_CONFIG
from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies import ResultStore, SweepSpec, run_sweep
from pdamper.studies.executor import RetryWarning

pytestmark = pytest.mark.cluster

STROKES = (0.004, 0.008, 0.012, 0.016)


@pytest.fixture(scope="module")
def spec(tmp_path_factory):
    cfg = tmp_path_factory.mktemp("cfg") / "tiny.toml"
    cfg.write_text(TINY_CONFIG)
    return SweepSpec(base=load_case(cfg), strokes=STROKES, seeds=(0,))


@pytest.fixture(scope="module")
def undisturbed(spec, tmp_path_factory):
    """The same study on one local process, nothing disturbed."""
    return run_sweep(spec, tmp_path_factory.mktemp("ref") / "store", workers=1, progress=False, keep="none")


def _when_cases(store, n, action, timeout=120.0):
    """Run ``action()`` in a thread once ``n`` case files are in ``store``."""
    def watch():
        deadline = time.time() + timeout
        while time.time() < deadline and len(list((store / "cases").glob("*.json"))) < n:
            time.sleep(0.02)
        action()

    t = threading.Thread(target=watch, daemon=True)
    t.start()
    return t


@pytest.mark.slow
def test_a_worker_killed_mid_study_is_retried_and_the_numbers_are_bit_identical(spec, undisturbed, tmp_path):
    from dask.distributed import Client, LocalCluster

    store = tmp_path / "store"
    killed = []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster, set_as_default=False) as spy:
        def kill_a_busy_worker():
            deadline = time.time() + 60
            while time.time() < deadline:  # a worker in the middle of a case
                busy = [w for w, keys in spy.processing().items() if keys]
                if busy:
                    pid = spy.run(os.getpid, workers=busy[:1])[busy[0]]
                    os.kill(pid, signal.SIGKILL)
                    killed.append((busy[0], spy.processing().get(busy[0])))
                    return
                time.sleep(0.01)

        watcher = _when_cases(store, 1, kill_a_busy_worker)
        with pytest.warns(RetryWarning, match=r"case\(s\) ran again after their Dask worker died: X0\.\d+_seed0 \(1x\)"):
            ds = run_sweep(spec, store, scheduler=cluster.scheduler_address, progress=False, keep="none")
        watcher.join()
    assert killed, "no worker was busy to kill"
    for name in ("eta_star", "energy_per_cycle", "steps"):  # bit-identical per case
        np.testing.assert_array_equal(ds[name].values, undisturbed[name].values)
    assert len(list((store / "cases").glob("*.json"))) == len(STROKES)


def _start(cmd, **kw):
    return subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True, **kw)


@pytest.mark.slow
def test_a_scheduler_that_goes_away_is_a_clear_error_and_the_store_resumes_locally(spec, undisturbed, tmp_path):
    info = tmp_path / "scheduler.json"
    dask = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
    scheduler = _start(dask + ["--scheduler-file", str(info), "--port", "0", "--dashboard-address", ":0"])
    worker = None
    try:
        deadline = time.time() + 30
        while not info.exists() and time.time() < deadline:
            time.sleep(0.05)
        time.sleep(0.2)
        address = json.loads(info.read_text())["address"]
        worker = _start([sys.executable, "-m", "distributed.cli.dask_worker", "--scheduler-file", str(info),
                         "--nthreads", "1", "--nworkers", "1", "--no-dashboard"])
        store = tmp_path / "store"
        watcher = _when_cases(store, 1, lambda: os.killpg(scheduler.pid, signal.SIGKILL))
        with pytest.raises(InputError, match=rf"the Dask scheduler {address} went away after [1-3] of 4 cases .*"
                                             "finished are stored: re-run the same command to resume"):
            run_sweep(spec, store, scheduler=address, progress=False, keep="none")
        watcher.join()
    finally:
        for p in (scheduler, worker):
            if p is not None:
                try:
                    os.killpg(p.pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
                p.wait()
    before = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    assert 1 <= len(before) < 4 and len(ResultStore.open(store).records()) == len(before)
    ds = run_sweep(spec, store, workers=1, progress=False, keep="none")  # resumed on this machine
    after = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    assert len(after) == 4 and all(after[k] == v for k, v in before.items())  # nothing finished recomputed
    for name in ("eta_star", "energy_per_cycle", "steps"):
        np.testing.assert_array_equal(ds[name].values, undisturbed[name].values)
