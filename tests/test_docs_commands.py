"""Every ``pdamper ...`` command line in README.md, docs/*.md and examples/README.md parses as the tool
parses it today (issue 24): the command exists, every option and value is accepted, and no old
(deprecated, hidden) option name is used. A dry parse (click's ``make_context``): nothing runs.
"""

from __future__ import annotations

import re
import shlex
from pathlib import Path

import click
import pytest

from pdamper.cli import main

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md", ROOT / "examples" / "README.md", *sorted((ROOT / "docs").glob("*.md"))]


def _command_lines(text: str) -> list[tuple[str, str]]:
    """``("command", line)`` of the ``pdamper ...`` lines of the fenced shell blocks (continuations
    joined, comments dropped) and of the ``$ pdamper ...`` lines of text blocks; ``("mention", span)``
    of inline code spans (often a fragment: ``pdamper run --out``)."""
    out = []
    for lang, body in re.findall(r"^```(\w*)\n(.*?)^```", text, flags=re.M | re.S):
        if lang not in ("", "sh", "bash", "console", "shell", "text"):
            continue
        body = re.sub(r"\\\n\s*", " ", body)
        for line in body.splitlines():
            line = line.strip()
            if lang in ("text", "console"):  # output shown: only the prompted lines are commands
                if not line.startswith("$ pdamper"):
                    continue
                line = line[2:]
            if line.startswith("pdamper ") or line == "pdamper":
                out.append(("command", line))
    out += [("mention", m) for m in re.findall(r"`(pdamper [^`]+)`", text) if "\n" not in m]
    return out


def _words(line: str) -> list[str]:
    line = line.split(" # ", 1)[0].split(" && ", 1)[0].split(" | ", 1)[0].split(" > ", 1)[0]
    return shlex.split(line, comments=False)


COMMANDS = sorted({(page.relative_to(ROOT).as_posix(), kind, line) for page in PAGES
                   for kind, line in _command_lines(page.read_text(encoding="utf-8"))})

#: Words that stand for something the reader fills in: such a line shows a form, not a command.
PLACEHOLDER = re.compile(r"^(\.\.\.|[A-Z][A-Z_]*[A-Z](\.(toml|csv|nc|png))?|<.*>|\[.*\]|.*\|.*)$")


def test_command_lines_were_found():
    pages = {p for p, _, _ in COMMANDS}
    assert sum(k == "command" for _, k, _ in COMMANDS) >= 40 and {"README.md", "examples/README.md", "docs/cli.md"} <= pages


def _dry_parse(words: list[str]):
    """Parse ``pdamper WORDS``: the group's own options, else the subcommand's; returns (the context
    parsed, the problem or None)."""
    if not words or words[0].startswith("-"):
        return main.make_context("pdamper", list(words), resilient_parsing=False), None
    name, *rest = words
    # the group's context settings (help_option_names) as click gives them: a context built without
    # them makes click cache each command's help option as a bare --help, and the help pages
    # printed later in the same process (tests/cli/test_cli_docs.py) would lose their '-h'
    with click.Context(main, info_name="pdamper", **main.context_settings) as group_ctx:
        cmd = main.get_command(group_ctx, name)
        if cmd is None:
            return None, f"no command {name!r}"
        if isinstance(cmd, click.Group) and rest and not rest[0].startswith("-"):
            sub, *rest = rest
            ctx = click.Context(cmd, info_name=name, parent=group_ctx)
            cmd, group_ctx = cmd.get_command(ctx, sub), ctx
            if cmd is None:
                return None, f"no command {name} {sub!r}"
        return cmd.make_context(name, rest, parent=group_ctx, resilient_parsing=False), None


@pytest.mark.parametrize("page, kind, line", COMMANDS, ids=[f"{p}: {c[:70]}" for p, _, c in COMMANDS])
def test_every_documented_command_line_parses_without_an_old_name(page, kind, line, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    words = _words(line)[1:]
    if (kind == "mention" or any(PLACEHOLDER.match(w) for w in words) or "--help" in words or "-h" in words
            or "--version" in words):
        # a form with placeholders (pdamper run CONFIG.toml [--out DIR]): the command and its options
        # must exist, the values are the reader's
        name = next((w for w in words if not w.startswith("-")), None)
        if name is not None:
            assert name in main.commands or PLACEHOLDER.match(name), f"{page}: {line!r}: no command {name!r}"
        if name in main.commands:
            cmd = main.commands[name]
            if isinstance(cmd, click.Group):
                sub = next((w for w in words[words.index(name) + 1:] if not w.startswith("-")), None)
                if sub in cmd.commands:
                    cmd = cmd.commands[sub]
            known = {o for p in cmd.params for o in (*p.opts, *p.secondary_opts)}
            hidden = {o for p in cmd.params if getattr(p, "hidden", False) for o in p.opts}
            for w in words:
                opt = w.split("=", 1)[0]
                if opt.startswith("--") and opt != "--help":
                    assert opt in known, f"{page}: {line!r}: {name} has no option {opt}"
                    if page != "docs/names.md":  # the page that lists the old names
                        assert opt not in hidden, f"{page}: {line!r}: {opt} is an old (deprecated) name"
        return
    try:
        ctx, problem = _dry_parse(words)
    except click.exceptions.Exit:
        return
    except SystemExit:  # pdamper's one-line usage error ("Error: ...", exit code 2)
        message = capsys.readouterr().err.strip()
        if "does not exist" in message:  # a file of the reader's (rig/campaign, record.csv)
            return
        raise AssertionError(f"{page}: {line!r}: {message}") from None
    except click.BadParameter as exc:
        if "does not exist" in str(exc):  # a file of the reader's (record.csv, runs/x20)
            return
        raise AssertionError(f"{page}: {line!r}: {exc.format_message()}") from None
    except click.UsageError as exc:
        raise AssertionError(f"{page}: {line!r}: {exc.format_message()}") from None
    assert problem is None, f"{page}: {line!r}: {problem}"
    hidden = [p.name for p in ctx.command.params if getattr(p, "hidden", False)
              and ctx.params.get(p.name) not in (None, False, (), p.default)]
    assert not hidden, f"{page}: {line!r}: uses the old (deprecated) option(s) {hidden}; see docs/names.md"
