"""Ensembles over the unknowns (pdamper.studies.ensemble): each sample against its closed form, the
store's sample dimension and its summary on a synthetic ensemble, and faults: kill -9 loses no
finished sample and recomputes none; a GPU that fails mid-ensemble is one line and keeps what
finished.

**The closed form.** A locked bed (a row of spheres wall to wall, tests/studies/test_transient.py) is
a rigid mass at the damper; under a harmonic force from rest the structure without the bed and with
it (mass M + m_bed, the same dashpot) are damped oscillators whose response is textbook
(:func:`pdamper.theory.oscillator_response`), at every sample's stiffness K * stiffness_scale."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest
from ensemble_helpers import STIFFNESS, synthetic_store
from sweep_helpers import kill_after

from dem_fixtures import locked_case
from pdamper.config import loads_case
from pdamper.errors import InputError
from pdamper.studies.ensemble import (EnsembleSpec, EnsembleStore, damper_point, open_ensemble, run_ensemble,
                                      summarize)
from pdamper.studies.unknowns import Unknown, Unknowns, sample
from pdamper.theory import oscillator_response

FORCED = 'mass = "2kg"\nnatural_frequency = "3Hz"\ndamping_ratio = 0.02\nforce_amplitude = "1N"\nforce_frequency = "3Hz"'


def _forced_locked_bed():
    text = locked_case("", structure=FORCED, text=True).split("[load]")[0]
    return loads_case(text + "[run]\ncycles = 3\n")  # 1 s of the force from rest


def _peak(case, scale: float, added: float) -> float:
    """The closed form's largest |x| over the run: the oscillator of K * scale carrying ``added`` [kg]
    with the structure's own dashpot, from rest under F0 sin(2 pi f t) (a grid of 0.05 ms)."""
    s = case.drive
    k = s.stiffness * scale
    c = 2.0 * s.damping_ratio * math.sqrt(k * s.mass)  # the ratio kept when K is scaled: the dashpot moves
    m = s.mass + added
    t = np.linspace(0.0, case.duration, 20_001)  # both ends: the swing still grows at the end
    x, _, _ = oscillator_response(t, mass=m, stiffness=k, damping_ratio=c / (2.0 * math.sqrt(k * m)),
                                  force_amplitude=s.force_amplitude, force_frequency=s.force_frequency)
    return float(np.max(np.abs(x)))


@pytest.mark.slow
def test_every_sample_is_its_closed_form_with_and_without_the_bed(tmp_path):
    base = _forced_locked_bed()
    ds = run_ensemble(base, STIFFNESS, 4, tmp_path / "store", study="transient", workers=1, progress=False)
    scales = sample(STIFFNESS, 4, seed=0).columns["structure.stiffness_scale"]
    np.testing.assert_array_equal(ds["structure_stiffness_scale"].values, scales)
    assert ds.peak.dims == ("sample", "dof") and ds.sizes["sample"] == 4 and not ds.failed.any()
    for i, scale in enumerate(scales):
        bare, locked = _peak(base, scale, 0.0), _peak(base, scale, base.bed_mass)
        # sampled at 1 kHz: the sampled peak of a 3 Hz swing is within (2 pi 3 / 1000)^2 / 8 = 4e-5 of it
        assert float(ds.peak_bare[i, 0]) == pytest.approx(bare, rel=1e-4)
        assert float(ds.peak[i, 0]) == pytest.approx(locked, rel=1e-3)  # the locked bed's contact compliance
        assert float(ds.peak_ratio[i, 0]) == pytest.approx(locked / bare, rel=1e-3)
    # the spread of the samples is the physics': the stiffest sample moves least without the bed
    assert np.argmin(ds.peak_bare.values[:, 0]) == int(np.argmax(scales))
    s = summarize(ds, target_peak_ratio=float(np.median(ds.peak_ratio.values)))
    assert s["peak_ratio"]["p50"] == [pytest.approx(float(np.median(ds.peak_ratio.values)))]
    assert s["targets"]["peak_ratio"]["met"] == 2 and s["ranking"]["peak_ratio"][0]["key"] == "structure.stiffness_scale"


def test_a_response_sample_is_its_run_responses_peaks_per_dof():
    """A response sample (no executor: the sample function itself) reports per dof the largest
    amplitude over the grid with the damper over the bare closed form's largest on the same grid."""
    from pdamper.studies.ensemble import _Response
    from pdamper.studies.structure import run_response

    case = loads_case(locked_case("", structure=FORCED.replace("1N", "0.3N"), text=True).split("[load]")[0]
                      + "[run]\ncycles = 4\n")
    rec = _Response(None, (2.9, 3.1), None, 2, 1)(case)
    s = run_response(case, (2.9, 3.1), force_amplitude=0.3, measure_cycles=2, workers=1, progress=False).summary
    damped, bare = np.max(s["response_amplitude_m"], axis=1), np.max(s["response_amplitude_bare_m"], axis=1)
    np.testing.assert_allclose(rec["peak_m"], damped, rtol=0)  # the same seeded runs, bit for bit
    np.testing.assert_allclose(rec["peak_ratio"], damped / bare, rtol=1e-15)
    assert rec["rms_ratio"] == rec["peak_ratio"] and rec["damper_peak_ratio"] == s["peak_reduction"]


def test_the_share_meeting_a_target_and_its_interval_on_a_synthetic_ensemble(tmp_path):
    rng = np.random.default_rng(5)
    ratios = [(float(a), float(b)) for a, b in zip(rng.uniform(0.5, 0.9, 40), rng.uniform(0.4, 0.8, 40))]
    ratios[3] = None  # a failed sample meets no target
    spec, store = synthetic_store(tmp_path, ratios)
    ds = store.dataset()
    assert ds.peak_ratio.dims == ("sample", "dof") and ds.dof.values.tolist() == ["damper", "response"]
    assert int(ds.failed.sum()) == 1 and math.isnan(float(ds.peak_ratio[3, 0]))
    s = summarize(ds, target_peak_ratio=0.7, target_rms_ratio=0.6)
    ok = [r for r in ratios if r is not None]
    met = sum(max(r) <= 0.7 for r in ok)  # every dof at or below the target
    t = s["targets"]["peak_ratio"]
    assert (t["met"], t["samples"], t["share"]) == (met, 40, met / 40)
    from scipy.stats import binomtest

    ci = binomtest(met, 40).proportion_ci(0.95, method="wilson")
    assert (t["low"], t["high"]) == (pytest.approx(ci.low), pytest.approx(ci.high)) and t["low"] < met / 40 < t["high"]
    assert t["per_dof"] == [sum(r[k] <= 0.7 for r in ok) / 40 for k in (0, 1)]
    both = sum(max(r) <= 0.7 and 0.9 * max(r) <= 0.6 for r in ok)
    assert s["targets"]["both"]["met"] == both
    p = np.percentile(np.array(ok), [5, 50, 95], axis=0)
    np.testing.assert_allclose(np.array([s["peak_ratio"][k] for k in ("p05", "p50", "p95")]), p, rtol=1e-12)
    # the dataset written and read back is the store's
    store.write_outputs(ds)
    back = open_ensemble(tmp_path / "store" / "results.nc")
    np.testing.assert_array_equal(back.peak_ratio.values, ds.peak_ratio.values)
    assert "peak_ratio[damper] [1]" not in (tmp_path / "store" / "results.csv").read_text().splitlines()[0]
    assert "peak_ratio[response]" in (tmp_path / "store" / "results.csv").read_text().splitlines()[0]


def test_the_store_refuses_another_ensemble_naming_the_difference(tmp_path):
    spec, store = synthetic_store(tmp_path, [(0.5, 0.5)] * 3)
    again = EnsembleSpec(base=spec.base, unknowns=STIFFNESS, samples=4, study="transient", dofs=("damper", "response"))
    with pytest.raises(InputError, match="another ensemble \\(3 samples there, 4 now: a Latin hypercube of another N"):
        EnsembleStore.create_or_open(tmp_path / "store", again)
    other = Unknowns((Unknown(key="structure.stiffness_scale", distribution="normal", mean=1.0, std=0.2),))
    with pytest.raises(InputError, match="other unknowns"):
        EnsembleStore.create_or_open(tmp_path / "store", EnsembleSpec(base=spec.base, unknowns=other, samples=3,
                                                                       study="transient", dofs=("damper", "response")))
    assert len(EnsembleStore.create_or_open(tmp_path / "store", spec).records()) == 3  # the same one reopens


def test_the_damper_point_s_ratios_are_judged_as_one_dof_with_their_shares_and_ranking(tmp_path):
    # sample i: the damper point's peak ratio 0.5 + 0.1 i (RMS 0.9 of it), the response dof 0.95 everywhere
    _, store = synthetic_store(tmp_path, [(0.5 + 0.1 * i, 0.95) for i in range(5)])
    at = damper_point(store.dataset())
    assert at.peak_ratio.dims == ("sample", "dof") and at.dof.values.tolist() == ["damper"]
    assert at.peak_ratio.values[:, 0].tolist() == [0.5 + 0.1 * i for i in range(5)]
    assert at.rms_ratio.values[:, 0] == pytest.approx([0.9 * (0.5 + 0.1 * i) for i in range(5)])
    s = summarize(at, target_peak_ratio=0.75, target_rms_ratio=0.6)
    # the damper point's: 0.5, 0.6, 0.7 meet 0.75 (the response dof's 0.95 would meet none); RMS 0.45, 0.54 meet 0.6
    assert (s["targets"]["peak_ratio"]["met"], s["targets"]["rms_ratio"]["met"], s["targets"]["both"]["met"]) == (3, 2, 2)
    assert s["dofs"] == ["damper"] and s["peak_ratio"]["p50"] == [pytest.approx(0.7)]
    with pytest.raises(InputError, match="has no damper point's peak and RMS ratios"):
        damper_point(store.dataset().drop_vars("damper_rms_ratio"))


U_TINY = """
[[unknown]]
key = "contact.friction"
distribution = "uniform"
low = 0.05
high = 0.3

[[unknown]]
key = "initial.seed"
distribution = "uniform"
low = 0
high = 99
"""


@pytest.mark.slow
def test_kill_minus_nine_loses_no_finished_sample_and_recomputes_none(tiny_config, tmp_path):
    (tmp_path / "U.toml").write_text(U_TINY)
    args = ["run", str(tiny_config), "--uncertain", str(tmp_path / "U.toml"), "--samples", "4", "--workers", "1",
            "--json"]
    store = tmp_path / "store"
    cmd = [sys.executable, "-m", "pdamper.cli", *args, "--store", str(store)]
    got = kill_after(cmd, store, cases=1)
    assert 1 <= len(got) < 4
    for blob in got.values():
        assert "values" in json.loads(blob)  # whole, with its sample's values
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    after = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    assert len(after) == 4 and all(after[k] == v for k, v in got.items())  # the killed run's samples not rewritten
    s = json.loads(out.stdout)["ensemble"]
    assert s["samples"] == s["finished"] == 4 and set(s["eta_star"]) == {"p05", "p50", "p95"}
    # the numbers of each sample are those of that sample's case run alone
    from pdamper.run import run_case

    ds = open_ensemble(store)
    spec = EnsembleSpec(base=loads_case(tiny_config.read_text()), unknowns=tmp_path / "U.toml", samples=4)
    for i in (0, 3):
        assert run_case(spec.case(i)).summary()["eta_star"] == float(ds.eta_star[i])


def test_a_gpu_that_fails_mid_ensemble_is_one_line_and_keeps_what_finished(tiny_config, tmp_path, monkeypatch):
    """The GPU engine's batch path (execute_batches) with a stand-in GPU: cases 'on the device' run on
    the CPU in batches of 2, the second batch runs out of memory; the first batch is stored, the error
    is one line, the resumed ensemble computes only the rest."""
    from pdamper import run as run_module

    (tmp_path / "U.toml").write_text(U_TINY)
    monkeypatch.setenv("PDAMPER_GPU_CHUNK", "2")
    real, real_on_gpu, calls = run_module.run_cases, run_module.on_gpu, []
    monkeypatch.setattr(run_module, "on_gpu", lambda case: True)
    monkeypatch.setattr(run_module, "check_device", lambda device: None)

    def flaky(cases, **kw):
        calls.append(len(cases))
        if len(calls) == 2:
            raise MemoryError("CUDA_ERROR_OUT_OF_MEMORY: out of memory")
        with monkeypatch.context() as m:  # the stand-in GPU: the batch on the CPU
            m.setattr(run_module, "on_gpu", real_on_gpu)
            return real(cases, **kw)

    monkeypatch.setattr(run_module, "run_cases", flaky)
    base = loads_case(tiny_config.read_text())
    with pytest.raises(InputError) as info:
        run_ensemble(base, tmp_path / "U.toml", 4, tmp_path / "store", progress=False)
    msg = str(info.value)
    assert "\n" not in msg and "the GPU batch of 2 cases failed after 2 of 4 cases were stored" in msg
    assert "CUDA_ERROR_OUT_OF_MEMORY" in msg and "re-run the same command to resume" in msg
    stored = {f.name: f.read_bytes() for f in (tmp_path / "store" / "cases").glob("*.json")}
    assert len(stored) == 2
    ds = run_ensemble(base, tmp_path / "U.toml", 4, tmp_path / "store", progress=False)
    assert calls == [2, 2, 2] and not ds.failed.any() and np.isfinite(ds.eta_star.values).all()
    assert all((tmp_path / "store" / "cases" / k).read_bytes() == v for k, v in stored.items())


@pytest.mark.slow
@pytest.mark.cluster
def test_an_ensemble_on_a_dask_scheduler_gives_the_numbers_of_the_local_cores(tiny_config, tmp_path):
    """The same samples on a Dask cluster given by its address (``--scheduler``) and on the local
    cores: every sample's eta* and steps bit for bit."""
    from dask.distributed import LocalCluster

    (tmp_path / "U.toml").write_text(U_TINY)
    base = loads_case(tiny_config.read_text())
    local = run_ensemble(base, tmp_path / "U.toml", 2, tmp_path / "local", workers=1, progress=False)
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        remote = run_ensemble(base, tmp_path / "U.toml", 2, tmp_path / "remote", scheduler=cluster.scheduler_address,
                              progress=False)
    for name in ("eta_star", "steps", "contact_friction", "initial_seed"):
        np.testing.assert_array_equal(remote[name].values, local[name].values)
    assert np.isfinite(remote.eta_star.values).all()
