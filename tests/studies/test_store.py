"""The result store: one atomic file per case, resume, refusal of another configuration,
and a real local Dask cluster (processes) behind the sweep."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from sweep_helpers import kill_after

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies import ResultStore, SweepSpec, open_results, run_sweep


def _spec(cfg, strokes=(0.002, 0.012), seeds=(0, 1), **over):
    return SweepSpec(base=load_case(cfg, over or None), strokes=strokes, seeds=seeds)


@pytest.mark.slow
def test_a_sweep_on_a_local_cluster_stores_every_case_and_resumes_without_recomputing(tiny_config, tmp_path):
    store = tmp_path / "store"
    ds = run_sweep(_spec(tiny_config), store, workers=2, progress=False)
    assert ds.eta_star.shape == (2, 2) and np.all(np.isfinite(ds.eta_star.values))
    assert ds.eta_star.attrs["units"] == "1" and ds.energy_per_cycle.attrs["units"] == "J"
    assert ds.stroke.attrs["units"] == "m"
    assert "[particles]" in ds.attrs["config"] and ds.attrs["pdamper_version"]
    files = sorted((store / "cases").glob("*.json"))
    assert len(files) == 4
    stamps = {f.name: f.stat().st_mtime_ns for f in files}
    # same command again: nothing is recomputed, the dataset is the same
    again = run_sweep(_spec(tiny_config), store, workers=2, progress=False)
    assert {f.name: f.stat().st_mtime_ns for f in (store / "cases").glob("*.json")} == stamps
    np.testing.assert_array_equal(again.eta_star.values, ds.eta_star.values)
    # one more seed: only the two new cases run
    more = run_sweep(_spec(tiny_config, seeds=(0, 1, 2)), store, workers=2, progress=False)
    assert more.eta_star.shape == (2, 3) and len(list((store / "cases").glob("*.json"))) == 6
    np.testing.assert_array_equal(more.eta_star.values[:, :2], ds.eta_star.values)
    # the files a user opens
    reopened = open_results(store)
    np.testing.assert_array_equal(reopened.eta_star.values, more.eta_star.values)
    nc = open_results(store / "results.nc")
    np.testing.assert_array_equal(nc.eta_star.values, more.eta_star.values)
    csv = (store / "results.csv").read_text().splitlines()
    assert csv[0].startswith("stroke [m],seed,eta_star [1],energy_per_cycle [J]") and len(csv) == 1 + 6
    assert csv[0].endswith(",failed,mode")
    # plain numbers that read back to the stored floats (numpy 2's repr says np.float64(...))
    row = csv[1].split(",")
    assert float(row[0]) == float(more.stroke.values[0]) and "np." not in csv[1]
    # every case has its motion mode, in the case file, the dataset and results.nc
    from pdamper.analysis.modes import MODES

    case_file = json.loads(next((store / "cases").glob("*.json")).read_text())
    assert case_file["mode"] in MODES and "sync" in case_file["mode_features"]
    assert set(nc["mode"].values.ravel()) <= set(MODES)
    assert all(line.rsplit(",", 1)[1] in MODES for line in csv[1:])


@pytest.mark.slow
def test_same_seeds_same_numbers_on_an_external_dask_cluster(tiny_config, tmp_path):
    from dask.distributed import LocalCluster

    spec = _spec(tiny_config, strokes=(0.012,), seeds=(0, 1))
    local = run_sweep(spec, tmp_path / "a", workers=1, progress=False)
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        remote = run_sweep(spec, tmp_path / "b", scheduler=cluster.scheduler_address, progress=False)
    np.testing.assert_array_equal(local.eta_star.values, remote.eta_star.values)
    np.testing.assert_array_equal(local.steps.values, remote.steps.values)


def test_a_store_of_another_configuration_is_refused_with_the_difference_named(tiny_config, tmp_path):
    store = tmp_path / "store"
    ResultStore.create_or_open(store, _spec(tiny_config))
    with pytest.raises(InputError, match=r"different configuration \(contact.friction = 0.1 there, 0.2 now\)"):
        ResultStore.create_or_open(store, _spec(tiny_config, **{"contact.friction": 0.2}))
    # strokes, seeds, the stroke of the config file and its seed do not count as configuration
    ResultStore.create_or_open(store, _spec(tiny_config, strokes=(0.005,), seeds=(4,),
                                            **{"drive.stroke": "9mm", "initial.seed": 3}))


def test_a_directory_that_is_not_a_store_is_refused(tiny_config, tmp_path):
    d = tmp_path / "busy"
    d.mkdir()
    (d / "thesis.tex").write_text("...")
    with pytest.raises(InputError, match="not a pdamper result store"):
        ResultStore.create_or_open(d, _spec(tiny_config))
    with pytest.raises(InputError, match="no pdamper result store"):
        open_results(d)


def test_a_partial_store_gives_nan_for_the_missing_cases(tiny_config, tmp_path):
    store = ResultStore.create_or_open(tmp_path / "s", _spec(tiny_config))
    store.save("X0.002_seed0", 0.002, 0, {"eta_star": 0.1, "energy_per_cycle_J": 1e-5})
    ds = store.dataset()
    assert ds.eta_star.sel(stroke=0.002, seed=0) == pytest.approx(0.1)
    assert np.isnan(ds.eta_star.sel(stroke=0.012, seed=1))


@pytest.mark.slow
def test_kill_minus_nine_loses_nothing_finished_and_the_rerun_completes(tiny_config, tmp_path):
    store = tmp_path / "store"
    cmd = [sys.executable, "-m", "pdamper.cli", "sweep", str(tiny_config), "--strokes", "1mm:20mm:6",
           "--seeds", "1", "--workers", "1", "--out", str(store), "--json"]
    done_before = kill_after(cmd, store)
    assert 2 <= len(done_before) < 6
    for blob in done_before.values():
        json.loads(blob)  # every stored case is whole
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    after = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    assert len(after) == 6
    assert all(after[k] == v for k, v in done_before.items())  # finished cases were not recomputed
    assert json.loads(out.stdout)["failed_cases"] == 0


def test_a_store_without_modes_opens_with_unknown_modes(tiny_config, tmp_path):
    # a store written before mode classification: its case files have no "mode"
    spec = _spec(tiny_config, strokes=(0.002, 0.012), seeds=(0,))
    store = ResultStore.create_or_open(tmp_path / "old", spec)
    store.save("X0.002_seed0", 0.002, 0, {"eta_star": 0.1, "energy_per_cycle_J": 1e-3, "steps": 10})
    store.save("X0.012_seed0", 0.012, 0, {"failed": "unstable"})
    ds = ResultStore.open(tmp_path / "old").dataset()
    assert ds["mode"].values.tolist() == [["unknown"], ["failed"]]
    assert not (tmp_path / "old" / "results.nc").exists()  # opening writes nothing
    ResultStore.open(tmp_path / "old").write_outputs(ds)
    again = open_results(tmp_path / "old" / "results.nc")
    assert again["mode"].values.tolist() == [["unknown"], ["failed"]]
    # a stroke asked for but not computed yet has an empty mode
    spec2 = _spec(tiny_config, strokes=(0.002, 0.012, 0.02), seeds=(0,))
    ds2 = ResultStore.create_or_open(tmp_path / "old", spec2).dataset()
    assert ds2["mode"].values.tolist() == [["unknown"], ["failed"], [""]]


@pytest.mark.slow
def test_a_store_heals_a_bad_case_file_and_a_lost_store_json(tiny_config, tmp_path):
    store = tmp_path / "store"
    spec = _spec(tiny_config, strokes=(0.002, 0.012), seeds=(0,))
    ds = run_sweep(spec, store, workers=1, progress=False, keep="none")
    good = sorted((store / "cases").glob("*.json"))
    assert len(good) == 2
    # valid JSON with the wrong content: set aside (renamed, warned) and computed again
    good[0].write_text('{"eta_star": "abc"}')
    with pytest.warns(UserWarning, match=r"not a case record .*set aside"):
        again = run_sweep(spec, store, workers=1, progress=False, keep="none")
    assert (store / "cases" / (good[0].name + ".bad")).exists()
    np.testing.assert_array_equal(again.eta_star.values, ds.eta_star.values)  # same seeds, same numbers
    # store.json deleted: refused with the way out, then rebuilt from the config and the case files
    (store / "store.json").unlink()
    with pytest.raises(InputError, match="--repair"):
        run_sweep(spec, store, workers=1, progress=False)
    stamps = {f.name: f.stat().st_mtime_ns for f in (store / "cases").glob("*.json")}
    repaired = run_sweep(spec, store, workers=1, progress=False, repair=True)
    assert {f.name: f.stat().st_mtime_ns for f in (store / "cases").glob("*.json")} == stamps  # nothing recomputed
    np.testing.assert_array_equal(repaired.eta_star.values, ds.eta_star.values)
    assert "rebuilt from 2 case files" in repaired.attrs["history"]


def test_a_stroke_typed_back_to_15_digits_is_the_stored_stroke_not_a_near_duplicate(tiny_config, tmp_path):
    """A log-spaced grid holds full-precision strokes; the same strokes typed back from a table are
    read to 15 significant digits and differ in their last bits. They are the stored points: the
    store keeps one value per stroke and the cases keep their keys (nothing computed twice)."""
    from pdamper.studies.sweep import parse_strokes

    case = load_case(tiny_config)
    grid = parse_strokes("4mm:12mm:3")
    typed = parse_strokes(",".join(f"{x * 1e3:.15g}mm" for x in grid) + ",20mm")
    assert not np.array_equal(typed[:3], grid)  # the typed strokes do differ in their last bits
    first = SweepSpec(base=case, strokes=grid)
    ResultStore.create_or_open(tmp_path / "s", first)
    again = SweepSpec(base=case, strokes=typed)
    store = ResultStore.create_or_open(tmp_path / "s", again)
    assert store.axes[0]["values"] == list(grid) + [0.02]
    on_grid = store.on_grid(again)
    assert on_grid.strokes == tuple(grid) + (0.02,)
    assert [k for k, _, _ in on_grid.items()][:3] == [k for k, _, _ in first.items()]


class _Softening:
    """A restitution law of a user's own: any object with restitution(speed)."""

    def restitution(self, speed):
        return 0.95 - 0.1 * np.tanh(np.asarray(speed, dtype=float))


def test_a_sweep_takes_a_users_restitution_law_as_its_table_and_runs_the_same_bits(tiny_config, tmp_path):
    """Issue 42: run_sweep refused a law of the user's own ("cannot write restitution law <... object
    at 0x...> to a config file"). It is swept as the table law of its values, which the store's config
    holds; the case runs to the bits of run_case with the user's object."""
    import dataclasses

    from pdamper import run_case
    from pdamper.config import loads_case
    from pdamper.contact import TabulatedRestitution

    base = load_case(tiny_config)
    base = dataclasses.replace(base, contact=dataclasses.replace(base.contact, restitution=_Softening()))
    spec = SweepSpec(base=base, strokes=(0.012,), seeds=(0,))
    assert spec.base.contact.restitution == TabulatedRestitution.from_law(_Softening())
    ds = run_sweep(spec, tmp_path / "store", workers=1, progress=False, keep="none")
    stored = json.loads((tmp_path / "store" / "store.json").read_text())["config"]
    assert loads_case(stored).contact.restitution == TabulatedRestitution.from_law(_Softening())
    own = run_case(dataclasses.replace(spec.case({"drive.stroke": 0.012}, 0), contact=base.contact))
    assert ds.eta_star.values.ravel().tolist() == [own.eta_star]
