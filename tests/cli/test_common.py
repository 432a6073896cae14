"""Every ``pdamper`` command reports usage errors as one ``Error:`` line with exit code 2."""

from __future__ import annotations

import subprocess
import sys

import click
import pytest
from pathlib import Path
from click.testing import CliRunner

from pdamper.cli import main
from pdamper.cli.common import OneLineCommand, Quantity, fail

THEORY = ["--length", "120mm", "--particles", "36", "--max-particles", "48", "--frequency", "2Hz"]

#: For each command: (arguments, a word the error line must contain).
#: A valid config, for the errors that need one to get that far.
EXAMPLE = str(Path(__file__).parents[2] / "examples" / "cuboid_36.toml")

BAD = {
    "theory": [
        (["--length", "12kg", *THEORY[2:]], "'12kg' is not a length"),
        (["--length", "5 percent", *THEORY[2:]], "'5 percent' is not a length"),
        ([*THEORY, "--tilt", "3mm"], "'3mm' is not an angle"),
        ([*THEORY, "--bogus"], "No such option"),
        (["--length", "120mm", "--max-particles", "48", "--frequency", "2Hz"],
         "Missing option '--particles'"),
        ([*THEORY[:-1]], "requires an argument"),
    ],
    "analyze": [
        (["record.csv", "--bed-mass", "149parsec"], "'149parsec' is not a mass"),
        (["record.csv", "--frequency", "2 percent"], "is not a frequency"),
        (["record.csv", "--bogus"], "No such option"),
        ([], "Missing argument 'RECORD'"),
    ],
    "run": [
        (["case.toml", "--stroke", "12kg"], "'12kg' is not a length"),
        (["case.toml", "--bogus"], "No such option"),
        ([], "Missing argument 'CONFIG.toml'"),
    ],
    "study": [
        (["frction"], "did you mean 'friction'"),
        (["fig4", "--bogus"], "No such option"),
        ([], "Missing argument 'NAME|FILE.toml'"),
    ],
    "validate": [
        (["--seeds", "0"], "0 is not in the range"),
        (["--bogus"], "No such option"),
        (["--out"], "requires an argument"),
    ],
    "sweep": [
        (["case.toml", "--seeds", "0"], "0 is not in the range"),
        (["case.toml", "--bogus"], "No such option"),
        ([], "Missing argument 'CONFIG.toml'"),
        ([EXAMPLE, "--vary", "drive.strok=1mm:2mm:2"], "did you mean 'stroke'"),
        ([EXAMPLE, "--vary", "drive.stroke=1mm:2mm"], "FIRST:LAST:COUNT"),
        ([EXAMPLE, "--vary", "particles.count=30:31:8"], "whole numbers do not fit"),
        ([EXAMPLE, "--vary", "contact.friction=1:2:3:cubic"], "is not 'log' or 'linear'"),
        ([EXAMPLE, "--vary", "drive.stroke=1s:2s:2"], "--vary drive.stroke (first)"),
    ],
    "campaign": [
        (["nofile.csv", "--bed-mass", "149g"], "record file not found"),
        (["x.csv", "--bed-mass", "3s"], "not a mass"),
        ([], "Missing argument 'RECORD...'"),
    ],
    "calibrate": [
        (["camp", EXAMPLE], "Missing option '--fit'"),
        (["camp", EXAMPLE, "--fit", "contact.friction"], "KEY=LOW:HIGH"),
        (["camp", EXAMPLE, "--fit", "contact.friction=0.01:1"], "no such results file"),
    ],
    "reanalyze": [
        (["nostore"], "no pdamper result store"),
        (["x", "--drop-cycles", "-1"], "is not in the range"),
        ([], "Missing argument 'STORE'"),
    ],
    "fields": [
        (["nostore", "--out", "F.nc"], "no such store, campaign or results file"),
        (["nostore"], "Missing option '--out'"),
        (["nostore", "--out", "F.nc", "--sel", "friction"], "write DIM=VALUE"),
        (["nostore", "--out", "F.nc", "--plot", "f.gif"], "unknown format '.gif'"),
        ([], "Missing argument 'STORE_OR_CAMPAIGN'"),
    ],
    "animate": [
        (["run_dir", "--speed", "0"], "0.0 is not in the range"),
        (["run_dir", "--bogus"], "No such option"),
        ([], "Missing argument 'RUN_DIR'"),
    ],
    "export": [
        (["run_dir", "--cycles", "0"], "0.0 is not in the range"),
        (["run_dir", "--bogus"], "No such option"),
        ([], "Missing argument 'RUN_DIR'"),
    ],
    "plot": [
        (["modes"], "Missing argument 'RESULTS...'"),
        (["modes", "results", "--bogus"], "No such option"),
        (["nosuch"], "No such command 'nosuch'"),
        (["map"], "Missing argument 'STORE'"),
        (["map", "nostore"], "no such results file or store directory"),
        (["fields"], "Missing argument 'F.nc'"),
        (["fields", "nofile.nc"], "no such fields file"),
    ],
    "decay": [
        (["case.toml", "--cycles", "0"], "is not in the range"),
        (["case.toml", "--bogus"], "No such option"),
        ([], "Missing argument 'CONFIG.toml'"),
    ],
    "response": [
        (["case.toml", "--force", "3mm"], "'3mm' is not a force"),
        (["case.toml", "--measure-cycles", "0"], "0 is not in the range"),
        ([], "Missing argument 'CONFIG.toml'"),
    ],
    "transient": [
        (["case.toml", "--seed", "-1"], "is not in the range"),
        (["case.toml", "--bogus"], "No such option"),
        ([], "Missing argument 'CONFIG.toml'"),
    ],
    "design": [
        (["--frequency", "2Hz", "--stroke", "10kg", "--sphere-radius", "5mm"], "'10kg' is not a length"),
        (["--stroke", "10mm", "--sphere-radius", "5mm"], "Missing option '--frequency'"),
        (["--frequency", "2Hz", "--stroke", "10mm", "--sphere-radius", "5mm", "--shape", "sphere"], "sphere"),
    ],
}


def test_every_command_is_covered():
    assert set(BAD) == set(main.commands)


def test_every_command_is_a_one_line_command():
    for name, cmd in main.commands.items():
        if isinstance(cmd, click.Group):  # a group of commands (pdamper plot ...): its own and theirs
            assert type(cmd) is type(main), name
            for sub, subcmd in cmd.commands.items():
                assert isinstance(subcmd, OneLineCommand), f"{name} {sub}"
        else:
            assert isinstance(cmd, OneLineCommand), name


def _check_one_line(result, expected):
    assert result.exit_code == 2, result.output
    assert result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1, result.stderr
    assert lines[0].startswith("Error: "), lines
    assert expected in lines[0], lines[0]
    assert "Traceback" not in result.output and "Usage:" not in result.output


@pytest.mark.parametrize("command,args,expected",
                         [(c, a, e) for c, cases in BAD.items() for a, e in cases])
def test_usage_errors_are_one_line(command, args, expected):
    _check_one_line(CliRunner().invoke(main, [command, *args]), expected)


@pytest.mark.parametrize("args,expected", [
    (["nosuchcommand"], "No such command 'nosuchcommand'"),
    (["--bogus"], "No such option"),
])
def test_group_level_errors_are_one_line(args, expected):
    _check_one_line(CliRunner().invoke(main, args), expected)


def test_help_is_still_help():
    for args in (["--help"], ["theory", "--help"], ["analyze", "-h"], ["run", "--help"]):
        result = CliRunner().invoke(main, args)
        assert result.exit_code == 0 and result.stdout.startswith("Usage:"), args


@pytest.mark.parametrize("command,args,expected", [
    ("theory", ["--length", "12kg", *THEORY[2:]], "'12kg' is not a length"),
    ("analyze", ["record.csv", "--bogus"], "No such option"),
    ("run", [], "Missing argument"),
])
def test_installed_entry_point(command, args, expected):
    """The real process: stderr is exactly one line, exit code 2, no traceback."""
    code = "import sys; from pdamper.cli import main; sys.argv[0] = 'pdamper'; main()"
    proc = subprocess.run([sys.executable, "-c", code, command, *args],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2, proc.stderr
    assert proc.stdout == ""
    lines = proc.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("Error: ") and expected in lines[0], proc.stderr


def test_fail_squeezes_the_message_onto_one_line(capsys):
    with pytest.raises(SystemExit) as exc:
        fail("first line\n   second line")
    assert exc.value.code == 2
    assert capsys.readouterr().err == "Error: first line second line\n"


def test_quantity_outside_pdamper_group_is_still_a_usage_error():
    @click.command()
    @click.option("--length", type=Quantity("length"))
    def cmd(length):
        click.echo(repr(length))

    ok = CliRunner().invoke(cmd, ["--length", "13mm"])
    assert ok.exit_code == 0 and ok.stdout.strip() == "0.013"
    bad = CliRunner().invoke(cmd, ["--length", "12kg"])
    assert bad.exit_code == 2 and "--length: '12kg' is not a length" in bad.stderr


def test_top_level_help_never_cuts_a_description_mid_word():
    """Each command's one-line description ends with a whole word and balanced brackets."""
    runner = CliRunner()
    out = runner.invoke(main, ["--help"]).output
    lines = [ln for ln in out.split("Commands:")[1].splitlines() if ln.strip()]
    for line in lines:
        desc = line.split(None, 1)[1]
        assert desc.count("(") == desc.count(")") or desc.endswith("..."), line
        assert not desc.rstrip(".").endswith(("e.g", "Fig", "i.e", "eq")), line
