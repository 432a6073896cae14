"""``pdamper decay`` and ``pdamper response``: JSON, table, plot, one-line errors."""

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from pdamper.cli.common import main

EXAMPLE = str(Path(__file__).resolve().parents[2] / "examples" / "structure_36.toml")
SMALL = ["--set", "particles.count=4"]


def run(args):
    return CliRunner().invoke(main, args)


def test_decay_json_table_and_plot(tmp_path):
    r = run(["decay", EXAMPLE, "--cycles", "2", *SMALL, "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["particles"] == 4 and s["zeta_bare_mean"] > 0.0049
    assert s["bare_vs_closed_form_max_error"] < 1e-4
    png = tmp_path / "decay.png"
    r = run(["decay", EXAMPLE, "--cycles", "2", *SMALL, "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "zeta without damper" in r.output and png.stat().st_size > 10_000


def test_response_table_and_plot(tmp_path):
    png = tmp_path / "resp.svg"
    r = run(["response", EXAMPLE, "--cycles", "4", "--measure-cycles", "2", "--frequencies", "2Hz", *SMALL,
             "--force", "0.2N", "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "peak with damper" in r.output and png.exists()


def test_one_line_errors():
    for args, word in ((["response", EXAMPLE, "--frequencies", "3Hz:1Hz:4"], "--frequencies"),
                       (["response", EXAMPLE, "--force", "2kg"], "--force"),
                       (["decay", EXAMPLE, "--set", "structure.damping_ratio=2"], "damping_ratio"),
                       (["decay", EXAMPLE, "--plot", "x.gif"], "unknown format"),
                       (["response", EXAMPLE, "--frequencies", "2Hz"], "--force")):
        r = run(args)
        assert r.exit_code == 2, (args, r.output)
        assert r.output.startswith("Error:") and word in r.output and len(r.output.strip().splitlines()) == 1


def test_x_opt_of_a_run_uses_the_clearance_count_of_the_studies():
    """`pdamper run` reports X_opt with the same N_p,max as the studies' store (48 for the paper's
    cylinder, not the 44 its floor packing holds)."""
    from pdamper import theory
    from pdamper.analysis.modes import case_clearance
    from pdamper.cli.structure import _x_opt
    from pdamper.config import load_case

    root = Path(__file__).resolve().parents[2] / "examples"
    for name, h_paper in (("cylinder_30", 0.02925), ("cylinder_42", 0.00975), ("cuboid_36", 0.030)):
        case = load_case(root / f"{name}.toml")
        assert case_clearance(case)[1] == pytest.approx(h_paper, rel=1e-9)
        assert _x_opt(case) == pytest.approx(theory.optimal_stroke(h_paper), rel=1e-9)
