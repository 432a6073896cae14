"""The damper's fields from a real (tiny) sweep store and from a measured campaign, through the
Python API and the CLI; the netCDF round trip with its provenance; bad sources."""

from __future__ import annotations

import json
import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from click.testing import CliRunner  # noqa: E402

from dem_fixtures import TINY_CONFIG  # noqa: E402
from pdamper.cli import main  # noqa: E402
from pdamper.config import load_case  # noqa: E402
from pdamper.errors import InputError  # noqa: E402
from pdamper.studies import Axis, ResultStore, SweepSpec, open_results, run_sweep  # noqa: E402
from pdamper.studies.fields import build_fields, load_fields, write_fields  # noqa: E402

STROKES, FREQS = (0.002, 0.012), (2.0, 3.0)


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    """A real sweep: 8 spheres, 3 cycles, 2 strokes x 2 frequencies x 2 seeds."""
    d = tmp_path_factory.mktemp("fields")
    (d / "tiny.toml").write_text(TINY_CONFIG)
    spec = SweepSpec(base=load_case(d / "tiny.toml"), axes=[Axis(key="drive.stroke", values=STROKES),
                                                            Axis(key="drive.frequency", values=FREQS)], seeds=(0, 1))
    run_sweep(spec, d / "store", workers=1, progress=False)
    return d / "store"


@pytest.mark.slow
def test_fields_of_a_sweep_keep_its_mean_spread_modes_and_provenance(store, tmp_path):
    ds = open_results(store)
    fields = build_fields(store, command="pdamper fields test")
    f = fields.dataset
    assert list(f.amplitude.values) == list(STROKES) and list(f.frequency.values) == list(FREQS)
    for name in ("eta_star", "energy_per_cycle", "effective_mass", "equivalent_damping"):
        v = ds[name].transpose("stroke", "frequency", "seed").values
        assert np.isfinite(v).all()
        np.testing.assert_allclose(f[name].values, v.mean(axis=2), rtol=1e-12)
        np.testing.assert_allclose(f[f"{name}_std"].values, v.std(axis=2, ddof=1), rtol=1e-9, atol=1e-15)
        np.testing.assert_array_equal(f[f"{name}_min"].values, v.min(axis=2))
        np.testing.assert_array_equal(f[f"{name}_max"].values, v.max(axis=2))
    np.testing.assert_array_equal(f.seeds.values, 2)
    assert set(np.unique(f["mode"].values)) <= set(np.unique(ds["mode"].values))
    # the interpolation gives the nodes back
    for i, X in enumerate(STROKES):
        for j, fr in enumerate(FREQS):
            assert fields.at(X, fr).eta_star == pytest.approx(float(f.eta_star[i, j]), rel=1e-12)
    # the file, and back
    write_fields(fields, tmp_path / "F.nc")
    back = load_fields(tmp_path / "F.nc")
    for name in f.data_vars:
        np.testing.assert_array_equal(back.dataset[name].values, f[name].values)
    a = back.dataset.attrs
    assert a["source_kind"] == "sweep" and a["source"] == str(store.resolve())
    assert a["source_config"] == ds.attrs["config"] and "count = 8" in a["source_config"]
    assert a["command"] == "pdamper fields test" and a["pdamper_version"] and a["source_history"]
    assert a["bed_mass_kg"] == pytest.approx(ds.attrs["bed_mass_kg"]) and a["format"] == "pdamper-damper-fields/1"
    assert back.at(0.005, 2.5).eta_star == pytest.approx(fields.at(0.005, 2.5).eta_star, rel=1e-15)


def test_the_cli_writes_and_draws_the_fields_of_a_store(store, tmp_path):
    out = CliRunner().invoke(main, ["fields", str(store), "--out", str(tmp_path / "F.nc"), "--json"])
    assert out.exit_code == 0, out.output
    rep = json.loads(out.stdout)
    assert rep["source_kind"] == "sweep" and rep["amplitudes_m"] == list(STROKES) and rep["frequencies_hz"] == list(FREQS)
    assert rep["seeds_max"] == 2
    ds = open_results(store)
    np.testing.assert_allclose(rep["eta_star"], ds.eta_star.mean("seed").transpose("stroke", "frequency").values)
    assert "fields" in load_fields(tmp_path / "F.nc").dataset.attrs["command"]
    out = CliRunner().invoke(main, ["plot", "fields", str(tmp_path / "F.nc"), "--out", str(tmp_path / "F.png")])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "F.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    # a fields file is not a source, a store is not a fields file
    out = CliRunner().invoke(main, ["fields", str(tmp_path / "F.nc"), "--out", str(tmp_path / "G.nc")])
    assert out.exit_code == 2 and "already a damper-fields file" in out.output
    out = CliRunner().invoke(main, ["plot", "fields", str(store / "results.nc")])
    assert out.exit_code == 2 and "not a damper-fields file" in out.output


def test_a_stroke_only_store_takes_the_case_frequency(tmp_path):
    spec = SweepSpec(base=load_case(_tiny(tmp_path), {"drive.frequency": 3.0}), strokes=STROKES, seeds=(0,))
    ds = run_sweep(spec, tmp_path / "store", workers=1, progress=False)
    assert "frequency" not in ds.dims
    fields = build_fields(tmp_path / "store")
    assert list(fields.frequencies) == [3.0]
    for X in STROKES:
        assert fields.at(X).eta_star == pytest.approx(float(ds.eta_star.sel(stroke=X, seed=0)), rel=1e-12)
    del ds.attrs["frequency_hz"]
    ds.to_netcdf(tmp_path / "nofreq.nc", engine="h5netcdf")
    with pytest.raises(InputError, match="no 'frequency' dimension and no frequency_hz"):
        build_fields(tmp_path / "nofreq.nc")


def test_an_empty_store_and_an_unknown_folder_are_clear_errors(tmp_path):
    case = load_case(_tiny(tmp_path))
    spec = SweepSpec(base=case, axes=[Axis(key="drive.stroke", values=STROKES), Axis(key="drive.frequency", values=FREQS)],
                     seeds=(0,))
    ResultStore.create_or_open(tmp_path / "empty", spec)
    with pytest.raises(InputError, match="no finished point"):
        build_fields(tmp_path / "empty")
    (tmp_path / "nothing").mkdir()
    out = CliRunner().invoke(main, ["fields", str(tmp_path / "nothing"), "--out", str(tmp_path / "F.nc")])
    assert out.exit_code == 2 and "neither a sweep store" in out.output
    out = CliRunner().invoke(main, ["fields", str(tmp_path / "nope"), "--out", str(tmp_path / "F.nc")])
    assert out.exit_code == 2 and "no such store" in out.output


def _tiny(d):
    p = d / "tiny.toml"
    p.write_text(TINY_CONFIG)
    return p


M, C, K = 0.149, 4.0, 30.0


def test_fields_of_a_measured_multi_frequency_campaign(tmp_path):
    """Records of F = m x'' + c x' + k x at 2 strokes x 3 frequencies: m_eff = m - k/Omega^2, c_eq = c."""
    rig = tmp_path / "rig"
    rig.mkdir()
    for f in (1.5, 2.0, 3.0):
        w = 2 * math.pi * f
        t = np.arange(int(12 * 1000 / f)) / 1000.0
        for X in (0.005, 0.012):
            x = X * np.sin(w * t)
            force = M * -w**2 * x + C * X * w * np.cos(w * t) + K * x
            np.savetxt(rig / f"x{X * 1e3:g}mm_f{f:g}.csv", np.column_stack([t, force, x]), delimiter=",",
                       header="time [s],force [N],position [m]", comments="", fmt="%.17g")
    out = CliRunner().invoke(main, ["campaign", str(rig), "--bed-mass", "149g", "--out", str(tmp_path / "camp")])
    assert out.exit_code == 0, out.output
    out = CliRunner().invoke(main, ["fields", str(tmp_path / "camp"), "--out", str(tmp_path / "F.nc"), "--json"])
    assert out.exit_code == 0, out.output
    assert json.loads(out.stdout)["source_kind"] == "campaign"
    fields = load_fields(tmp_path / "F.nc")
    np.testing.assert_allclose(fields.frequencies, [1.5, 2.0, 3.0], rtol=1e-6)
    np.testing.assert_allclose(fields.amplitudes, [0.005, 0.012], rtol=1e-6)
    assert fields.dataset.attrs["source_kind"] == "campaign" and not fields.jumps()
    for fr in fields.frequencies:
        w = 2 * math.pi * fr
        for X in fields.amplitudes:
            v = fields.at(X, fr)
            assert v.effective_mass_kg == pytest.approx(M - K / w**2, rel=1e-6)
            assert v.equivalent_damping_N_s_per_m == pytest.approx(C, rel=1e-6)
            assert v.energy_per_cycle_J == pytest.approx(math.pi * C * w * X**2, rel=1e-6)
    # between the frequencies m - k/Omega^2 rises, and so does the interpolation, between its nodes
    fs = np.linspace(fields.frequencies[0], fields.frequencies[-1], 50)
    m = np.array([fields.at(0.008, fr).effective_mass_kg for fr in fs])
    assert np.all(np.diff(m) > 0)
    exact = M - K / (2 * math.pi * fs) ** 2
    # three nodes in f for a curve in 1/f^2: PCHIP is off by at most 7.35 g (4.9 % of m) between them
    assert np.max(np.abs(m - exact)) < 0.05 * M


def test_another_swept_key_is_fixed_with_sel(store, tmp_path):
    ds = open_results(store)
    two = ds.expand_dims(friction=[0.1, 0.2]).copy(deep=True)
    two["eta_star"] = two.eta_star * two.friction  # a different eta* per friction
    two.to_netcdf(tmp_path / "results.nc", engine="h5netcdf")
    out = CliRunner().invoke(main, ["fields", str(tmp_path / "results.nc"), "--out", str(tmp_path / "F.nc")])
    assert out.exit_code == 2 and "vary friction besides" in out.output and "--sel friction=VALUE" in out.output
    out = CliRunner().invoke(main, ["fields", str(tmp_path / "results.nc"), "--sel", "friction=0.19",
                                    "--out", str(tmp_path / "F.nc")])
    assert out.exit_code == 0, out.output
    f = load_fields(tmp_path / "F.nc").dataset
    np.testing.assert_allclose(f.eta_star.values, 0.2 * ds.eta_star.mean("seed").transpose("stroke", "frequency").values,
                               rtol=1e-12)
    assert f.attrs["selected"] == "friction = 0.2"  # the value taken, nearest to the one asked
