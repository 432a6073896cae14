"""A sweep beside the user's own Dask client (issue 42): ``Client(LocalCluster())`` open in the
process, as in any Jupyter session using Dask. Before the mend, every case was computed and stored
and then writing ``results.nc`` died ("Semaphore or Lock ... not known"): xarray asked the user's
client for a distributed write lock on an in-memory buffer."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from dem_fixtures import TINY_CONFIG
from pdamper.config import load_case
from pdamper.studies import SweepSpec, run_sweep

pytestmark = pytest.mark.cluster


@pytest.mark.slow
def test_a_sweep_with_the_users_client_open_writes_its_results_and_leaves_the_client_as_it_was(tmp_path):
    from dask.distributed import Client, LocalCluster, get_client

    cfg = tmp_path / "tiny.toml"
    cfg.write_text(TINY_CONFIG)
    spec = SweepSpec(base=load_case(cfg), strokes=(0.006, 0.012), seeds=(0,))
    reference = run_sweep(spec, tmp_path / "alone", workers=1, progress=False, keep="none")
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster, \
            Client(cluster) as client:
        ds = run_sweep(spec, tmp_path / "beside", workers=1, progress=False, keep="none")
        # the user's client is still the process's default and still computes
        assert get_client() is client
        assert client.submit(sum, [1, 2, 3]).result() == 6
    written = xr.load_dataset(tmp_path / "beside" / "results.nc", engine="h5netcdf")
    np.testing.assert_array_equal(written.eta_star.values, reference.eta_star.values)
    np.testing.assert_array_equal(ds.eta_star.values, reference.eta_star.values)
    assert np.all(np.isfinite(written.eta_star.values))
