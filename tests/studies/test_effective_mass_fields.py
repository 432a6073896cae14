"""The effective mass and the equivalent damping in a campaign's dataset, a sweep's store, its
re-analysis and its map (the numbers themselves: tests/analysis/test_effective_mass.py)."""

from __future__ import annotations

import json
import math

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
from click.testing import CliRunner  # noqa: E402

from pdamper.cli import main  # noqa: E402
from pdamper.config import load_case  # noqa: E402
from pdamper.errors import InputError  # noqa: E402
from pdamper.plotting.map import map_figure  # noqa: E402
from pdamper.run import run_case  # noqa: E402
from pdamper.studies import Axis, SweepSpec, open_results, run_sweep  # noqa: E402
from pdamper.studies.reanalyze import reanalyze  # noqa: E402

M, C, K, M_C = 0.149, 4.0, 30.0, 0.08


def _rig(d, strokes=(0.005, 0.012), f=2.0):
    """Records of ``F = (m_c + m) x'' + c x' + k x`` at ``strokes``, 12 cycles at 1 kHz."""
    w = 2 * math.pi * f
    t = np.arange(int(12 * 1000 / f)) / 1000.0
    for X in strokes:
        x = X * np.sin(w * t)
        force = (M_C + M) * -w**2 * x + C * X * w * np.cos(w * t) + K * x
        np.savetxt(d / f"x{X * 1e3:g}mm.csv", np.column_stack([t, force, x]), delimiter=",",
                   header="time [s],force [N],position [m]", comments="", fmt="%.17g")
    return w


def test_a_campaign_reports_the_bed_effective_mass_and_damping_per_record(tmp_path):
    w = _rig(tmp_path)
    (tmp_path / "campaign.toml").write_text('bed_mass = "149g"\ncontainer_mass = "80g"\n')
    out = CliRunner().invoke(main, ["campaign", str(tmp_path), "--json", "--out", str(tmp_path / "camp")])
    assert out.exit_code == 0, out.output
    for r in json.loads(out.stdout)["records"]:
        assert r["effective_mass_kg"] == pytest.approx(M - K / w**2, rel=1e-9)
        assert r["equivalent_damping_N_s_per_m"] == pytest.approx(C, rel=1e-9)
    ds = open_results(tmp_path / "camp" / "campaign.nc")
    assert ds.effective_mass.attrs["units"] == "kg" and "container" in ds.effective_mass.attrs["long_name"]
    assert ds.equivalent_damping.attrs["units"] == "N s m-1"
    assert ds.attrs["container_mass_kg"] == pytest.approx(M_C)
    np.testing.assert_allclose(ds.effective_mass.values, M - K / w**2, rtol=1e-9)
    header = (tmp_path / "camp" / "campaign.csv").read_text().splitlines()[0].split(",")
    assert "effective_mass" in header and "equivalent_damping" in header
    # the option wins over the manifest: with no container mass removed, m_c stays in
    out = CliRunner().invoke(main, ["campaign", str(tmp_path), "--container-mass", "0g", "--json",
                                    "--out", str(tmp_path / "camp0")])
    assert json.loads(out.stdout)["records"][0]["effective_mass_kg"] == pytest.approx(M_C + M - K / w**2, rel=1e-9)
    ds0 = open_results(tmp_path / "camp0" / "campaign.nc")
    assert ds0.attrs["container_mass_kg"] == 0.0


def test_a_campaign_refuses_a_negative_container_mass(tmp_path):
    _rig(tmp_path, strokes=(0.005,))
    (tmp_path / "campaign.toml").write_text('bed_mass = "149g"\ncontainer_mass = "-80g"\n')
    out = CliRunner().invoke(main, ["campaign", str(tmp_path)])
    assert out.exit_code != 0 and "container mass" in out.output


@pytest.mark.slow
def test_a_sweep_store_keeps_them_with_cf_attributes_reanalyses_them_and_maps_them(tiny_config, tmp_path):
    m_c = 0.05
    base = load_case(tiny_config, {"container.mass": m_c})
    spec = SweepSpec(base=base, strokes=(0.002, 0.012), axes=[Axis(key="contact.friction", values=(0.1,))], seeds=(0,))
    ds = run_sweep(spec, tmp_path / "store", workers=1, progress=False)
    for name, units in (("effective_mass", "kg"), ("equivalent_damping", "N s m-1"), ("container_mass", "kg")):
        assert ds[name].attrs["units"] == units and ds[name].attrs["long_name"]
        assert ds[name].dims == ds.eta_star.dims and np.isfinite(ds[name].values).all()
    assert "container" in ds.effective_mass.attrs["long_name"]
    np.testing.assert_array_equal(ds.container_mass.values, m_c)
    # the stored numbers are the run's
    one = run_case(spec.case({"drive.stroke": 0.012, "contact.friction": 0.1}, 0))
    got = ds.sel(stroke=0.012, friction=0.1, seed=0)
    assert float(got.effective_mass) == one.effective_mass_kg
    assert float(got.equivalent_damping) == one.equivalent_damping_N_s_per_m
    assert one.analysis.total_effective_mass_kg - one.effective_mass_kg == pytest.approx(m_c, rel=1e-12)
    # re-analysis of the kept signals with the run's settings: the same numbers, bit for bit
    same = reanalyze(tmp_path / "store")
    for v in ("effective_mass", "equivalent_damping", "container_mass"):
        np.testing.assert_array_equal(same[v].values, ds[v].values)
    # the design map draws either
    out = CliRunner().invoke(main, ["plot", "map", str(tmp_path / "store"), "--quantity", "effective_mass",
                                    "--out", str(tmp_path / "meff.png")])
    assert out.exit_code == 0, out.output
    assert (tmp_path / "meff.png").stat().st_size > 10_000
    fig = map_figure(ds, quantity="equivalent_damping")
    assert "equivalent damping" in fig.axes[1].get_ylabel()
    with pytest.raises(InputError, match="choose one of eta_star, effective_mass"):
        map_figure(ds, quantity="mass")
    with pytest.raises(InputError, match="no effective_mass values"):
        map_figure(ds.drop_vars("effective_mass"), quantity="effective_mass")
    with pytest.raises(InputError, match="pdamper reanalyze"):  # a store of an older pdamper: all NaN
        map_figure(ds.assign(effective_mass=ds.effective_mass * np.nan), quantity="effective_mass")
