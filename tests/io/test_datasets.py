"""One run as an xarray Dataset (RunResult.to_dataset, pdamper.io.datasets): the tiny DEM case (8 spheres,
3 cycles) with its trajectory, and a coupled structure; the Dataset holds the run's own arrays (bit for
bit), labelled: ``time`` its coordinate, units on every variable, the case in the attributes; and the
labels are the right ones: the container's position changes by the integral of its velocity, the
ledger's energy balances, and the case read back from the attributes is the case."""

from __future__ import annotations

import numpy as np
import pytest

from dem_fixtures import TINY_CONFIG
from pdamper.config import loads_case
from pdamper.io.files import netcdf_bytes, read_dataset
from pdamper.run import run_case
from pdamper.schema import replace


@pytest.fixture(scope="module")
def tiny_run():
    case = replace(loads_case(TINY_CONFIG), {"recording.trajectory_fps": 20.0})
    return run_case(case)


def test_the_dataset_of_a_run_holds_its_arrays_labelled(tiny_run, tmp_path):
    res = tiny_run
    ds = res.to_dataset()
    assert ds.force.dims == ("time",) and "time" in ds.indexes
    np.testing.assert_array_equal(ds.time.values, res.signals.time)
    np.testing.assert_array_equal(ds.time_end.values, res.signals.time_end)
    for name in ("force", "velocity", "position"):
        np.testing.assert_array_equal(ds[name].values, getattr(res.signals, name))
    for part in ("kinetic", "rotational", "potential", "elastic", "work", "damping", "friction"):
        np.testing.assert_array_equal(ds[f"energy_{part}"].values, getattr(res.energy, part))
        assert ds[f"energy_{part}"].attrs["units"] == "J"
    assert (ds.force.attrs["units"], ds.velocity.attrs["units"], ds.position.attrs["units"]) == ("N", "m s-1", "m")
    # the labels are right: the position changes by the integral of the interval-mean velocity
    dt = float(res.signals.time_end[0])
    moved = float(np.sum(ds.velocity.values) * dt)
    assert moved == pytest.approx(float(res.case.drive.motion(np.array([ds.time_end.values[-1]]))[0][0]), abs=1e-12)
    # and the ledger's parts balance as the run said (its balance error, from the Dataset's variables)
    mech = sum(ds[f"energy_{p}"].values for p in ("kinetic", "rotational", "potential", "elastic"))
    dissipated = ds.energy_damping.values + ds.energy_friction.values
    resid = mech - ds.energy_work.values + dissipated
    scale = max(np.max(np.abs(ds.energy_work.values)), np.max(dissipated))
    assert np.max(np.abs(resid - resid[0])) / scale == pytest.approx(res.energy.balance_error(), rel=1e-12)
    assert res.energy.balance_error() < 0.01
    # the trajectory, along its own times
    assert ds.sphere_position.dims == ("frame_time", "sphere", "axis") and ds.sphere_position.shape[1:] == (8, 3)
    np.testing.assert_array_equal(ds.sphere_position.values, res.trajectory["position"])
    np.testing.assert_array_equal(ds.frame_time.values, res.trajectory["time"])
    assert list(ds.axis.values) == ["x", "y", "z"] and ds.sphere_radius.attrs["units"] == "m"
    # the case and the summary in the attributes
    assert loads_case(ds.attrs["config"]) == res.case and ds.attrs["case"] == str(res.case)
    assert ds.attrs["eta_star"] == res.eta_star and ds.attrs["steps"] == res.steps and ds.attrs["pdamper_version"]
    # and it is a file: written and read back unchanged
    (tmp_path / "run.nc").write_bytes(netcdf_bytes(ds))
    back = read_dataset(tmp_path / "run.nc")
    np.testing.assert_array_equal(back.force.values, ds.force.values)
    assert back.attrs["config"] == ds.attrs["config"]


def test_a_structure_run_has_its_structure_in_the_dataset():
    from dem_fixtures import locked_case

    case = locked_case('kind = "force_history"\ntime = [0, 0.01, 0.02]\nforce = [0, 2, 0]\nduration = "0.1s"')
    res = run_case(case, analyze=False)
    ds = res.to_dataset()
    np.testing.assert_array_equal(ds.structure_displacement.values, res.structure.displacement)
    assert ds.structure_displacement.dims == ("time",) and ds.structure_displacement.attrs["units"] == "m"
    assert ds.attrs["structure_mass_kg"] == res.structure.mass_kg
    # the container rides on the structure: its position is the structure's displacement at the interval centres
    x_mid = 0.5 * (np.concatenate([[res.structure.x0_m], res.structure.displacement[:-1]]) + res.structure.displacement)
    np.testing.assert_allclose(ds.position.values, x_mid, rtol=0, atol=1e-12)
