"""``pdamper decay`` and ``pdamper response``: JSON, table, plot, one-line errors."""

import json
from pathlib import Path

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
