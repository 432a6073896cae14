"""docs/cli.md shows what the commands really print: every help block equals ``--help``, every
example that needs no simulation prints what the page shows."""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import pytest
from click.testing import CliRunner

from pdamper.cli import main
from script_loader import load_script

ROOT = Path(__file__).resolve().parents[2]
CLI_MD = ROOT / "docs" / "cli.md"

cli_help = load_script("tools/cli_help.py")

#: Examples that run the DEM: too slow to repeat here (their numbers are measured, see the page).
SIMULATED = ("pdamper run ",)


def test_every_command_has_its_real_help_on_the_page():
    problems = cli_help.problems(CLI_MD.read_text(encoding="utf-8"))
    assert not problems, "; ".join(problems) + " -- run 'python tools/cli_help.py'"


def test_the_check_finds_a_stale_block():
    text = CLI_MD.read_text(encoding="utf-8").replace("Show the version and exit.", "Show the version.", 1)
    assert "help block of 'pdamper' differs from 'pdamper --help'" in cli_help.problems(text)
    text = text.replace("<!-- help: pdamper validate -->", "", 1)
    assert "no help block for 'pdamper validate'" in cli_help.problems(text)


def _examples():
    """(command, shown output) of every '$ pdamper ...' line in a text block of docs/cli.md."""
    text = CLI_MD.read_text(encoding="utf-8")
    out = []
    for block in re.findall(r"```text\n(.*?)```", text, re.S):
        lines = [ln.strip() for ln in block.splitlines()]
        starts = [i for i, ln in enumerate(lines) if ln.startswith("$ pdamper")]
        for k, i in enumerate(starts):
            end = starts[k + 1] if k + 1 < len(starts) else len(lines)
            out.append((lines[i][2:], [ln for ln in lines[i + 1:end] if ln]))
    return out


EXAMPLES = _examples()


def test_examples_were_found():
    assert len(EXAMPLES) >= 5 and any(c.startswith("pdamper design") for c, _ in EXAMPLES)


@pytest.mark.parametrize("command,shown", [e for e in EXAMPLES if not e[0].startswith(SIMULATED)],
                         ids=[e[0][:60] for e in EXAMPLES if not e[0].startswith(SIMULATED)])
def test_example_prints_what_the_page_shows(command, shown):
    result = CliRunner().invoke(main, shlex.split(command)[1:], prog_name="pdamper")
    printed = [ln.strip() for ln in result.output.splitlines() if ln.strip()]
    assert printed == shown, f"'{command}' now prints:\n" + "\n".join(printed)
