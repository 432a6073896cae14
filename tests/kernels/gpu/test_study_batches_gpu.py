"""A study on the GPU engine runs in batches, each stored as it finishes
(:func:`pdamper.studies.executor.execute_batches`): a batch that faults costs only itself."""

import numpy as np
import pytest

from pdamper.errors import InputError
from pdamper.excitation import HarmonicDrive
from pdamper.materials import Material
from pdamper.params import Case, InitialState, Numerics, ParticleSet, Recording
from pdamper.studies import ResultStore, SweepSpec, run_sweep

SOFT = Material(name="soft", youngs_modulus=1e5, poisson_ratio=0.3, density=7800.0)


def _spec():
    """Three strokes of a two-sphere soft bed on the GPU: about 210 Verlet steps a case."""
    base = Case(particles=(ParticleSet(count=2, material=SOFT),), drive=HarmonicDrive(stroke=0.002, frequency=10.0),
                cycles=2, drop_cycles=1, recording=Recording(sample_rate=100.0),
                numerics=Numerics(integrator="verlet", time_step=1e-3, overlap_limit=0.4, device="cuda"),
                initial=InitialState(settle_time=0.01, seed=0))
    return SweepSpec(base=base, strokes=(0.001, 0.0015, 0.002), seeds=(0,))


@pytest.mark.filterwarnings("ignore:only one cycle is analysed")  # (two cycles, one dropped: short)
def test_a_gpu_batch_that_faults_keeps_the_batches_before_it_and_the_sweep_resumes(tmp_path, monkeypatch):
    """Batches of one case (PDAMPER_GPU_CHUNK=1), the second faulting as a GPU does (the engine's
    run_jobs raising numba-cuda's words for an illegal address): one clear error that says what is
    stored and how to resume; the first batch's case is in the store; the same command then runs
    the other two and leaves the stored one as it was."""
    import pdamper.engine.cuda as engine

    real = engine.run_jobs
    calls = []

    def faulting(jobs, **kwargs):
        calls.append(len(jobs))
        if len(calls) == 2:
            raise RuntimeError("[CUresult.CUDA_ERROR_ILLEGAL_ADDRESS] Call to cuCtxSynchronize results in "
                               "CUDA_ERROR_ILLEGAL_ADDRESS")
        return real(jobs, **kwargs)

    monkeypatch.setenv("PDAMPER_GPU_CHUNK", "1")
    monkeypatch.setattr(engine, "run_jobs", faulting)
    store = tmp_path / "store"
    with pytest.raises(
            InputError, match=r"the GPU batch of 1 case failed after 1 of 3 cases were stored \(RuntimeError: "
                              r".*CUDA_ERROR_ILLEGAL_ADDRESS\); re-run the same command to resume"):
        run_sweep(_spec(), store, workers=1, progress=False, keep="none")
    assert calls == [1, 1]
    assert len(ResultStore.open(store).records()) == 1
    stored = {f.name: f.read_bytes() for f in (store / "cases").glob("*.json")}
    assert len(stored) == 1
    monkeypatch.setattr(engine, "run_jobs", real)
    ds = run_sweep(_spec(), store, workers=1, progress=False, keep="none")
    assert len(ResultStore.open(store).records()) == 3
    assert {f.name: f.read_bytes() for f in (store / "cases").glob("*.json") if f.name in stored} == stored
    assert np.isfinite(ds.eta_star.values).all()
