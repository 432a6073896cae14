"""Write the real ``--help`` output of every pdamper command into docs/cli.md.

docs/cli.md marks each help block with a comment line right above its fence::

    <!-- help: pdamper theory -->
    ```text
    Usage: pdamper theory [OPTIONS]
    ...
    ```

``python tools/cli_help.py`` rewrites every marked block from click (78 columns, as on an
80-column terminal); ``--check`` only reports blocks that differ and commands without a block,
with exit code 1 (tests/cli/test_cli_docs.py runs the same check).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import click
from click.testing import CliRunner

CLI_MD = Path(__file__).resolve().parents[1] / "docs" / "cli.md"
WIDTH = 78  # click's width on an 80-column terminal
_BLOCK = re.compile(r"(<!-- help: (?P<cmd>pdamper[^>]*?) -->\n```text\n)(?P<body>.*?)(```)", re.S)


def commands() -> list[str]:
    """Every command line with a help text: 'pdamper', 'pdamper run', 'pdamper plot modes', ..."""
    from pdamper.cli import main

    out = []

    def walk(cmd: click.Command, path: list[str]):
        out.append(" ".join(path))
        if isinstance(cmd, click.Group):
            for name in sorted(cmd.commands):
                walk(cmd.commands[name], [*path, name])

    walk(main, ["pdamper"])
    return out


def help_text(command: str) -> str:
    """``COMMAND --help`` as click prints it, with the program named 'pdamper'."""
    from pdamper.cli import main

    args = command.split()[1:]
    result = CliRunner().invoke(main, [*args, "--help"], prog_name="pdamper", terminal_width=WIDTH)
    if result.exit_code != 0:
        raise RuntimeError(f"'{command} --help' failed ({result.exit_code}): {result.output}")
    return result.output


def render(text: str) -> str:
    """docs/cli.md text with every marked help block replaced by the real help."""
    return _BLOCK.sub(lambda m: m.group(1) + help_text(m.group("cmd")) + m.group(4), text)


def problems(text: str) -> list[str]:
    """What is out of date in ``text``: blocks that differ from the real help, commands without a block."""
    found = {m.group("cmd"): m.group("body") for m in _BLOCK.finditer(text)}
    out = [f"no help block for '{c}'" for c in commands() if c not in found]
    out += [f"'{c}' is not a command" for c in found if c not in commands()]
    out += [f"help block of '{c}' differs from '{c} --help'" for c, body in found.items()
            if c in commands() and body != help_text(c)]
    return out


def main(argv: list[str]) -> int:
    text = CLI_MD.read_text(encoding="utf-8")
    if "--check" in argv:
        issues = problems(text)
        for p in issues:
            print(f"docs/cli.md: {p}", file=sys.stderr)
        return 1 if issues else 0
    new = render(text)
    if new != text:
        CLI_MD.write_text(new, encoding="utf-8")
    missing = [p for p in problems(new) if p.startswith("no help block")]
    for p in missing:
        print(f"docs/cli.md: {p} (add '<!-- help: CMD -->' and an empty ```text block)", file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
