"""The README keeps its promises: two set-up commands, CI runs the second, its examples run."""

from __future__ import annotations

import re
import shlex
import subprocess
import sys
from pathlib import Path

import pytest
from click.testing import CliRunner

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _section(title: str) -> str:
    m = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## |\Z)", README, flags=re.M | re.S)
    assert m, f"README has no section {title!r}"
    return m.group(1)


def _blocks(text: str, lang: str | None = None) -> list[str]:
    return [body for kind, body in re.findall(r"^```(\w*)\n(.*?)^```", text, flags=re.M | re.S)
            if lang is None or kind == lang]


def test_exactly_two_single_line_set_up_commands():
    blocks = _blocks(_section("Set up"))
    assert len(blocks) == 2
    for body in blocks:
        assert len(body.strip().splitlines()) == 1, body
    main_job, tests = (b.strip() for b in blocks)
    assert main_job.startswith("pip install -e . && pdamper ")
    assert tests == 'pip install -e ".[test]" -c constraints/test.txt && pytest'
    # No other install steps anywhere in the README.
    assert README.count("pip install") == 2
    assert "venv" not in README and "apt" not in README.split()


def test_ci_runs_the_second_set_up_command():
    ci = (ROOT / ".ci" / "run").read_text()
    commands = [ln.split("||")[0].strip() for ln in ci.splitlines()
                if ln.strip() and not ln.lstrip().startswith("#")]
    install = next(c for c in commands if "pip install" in c)
    assert shlex.split(install)[-4:] == ["-e", ".[test]", "-c", "constraints/test.txt"]
    assert any(shlex.split(c)[:3] == ["python", "-m", "pytest"] for c in commands)


def test_the_test_environment_is_pinned_for_every_dependency():
    """constraints/test.txt (tools/refresh_constraints.py) pins each package the test extra pulls in,
    so a fresh install gets the releases the suite passed with."""
    import tomllib

    from packaging.requirements import Requirement

    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    wanted = project["dependencies"] + project["optional-dependencies"]["test"]
    pins = {}
    for ln in (ROOT / "constraints" / "test.txt").read_text().splitlines():
        if ln.strip() and not ln.startswith("#"):
            name, _, version = ln.partition("==")
            assert version, f"constraints/test.txt: {ln!r} is not an exact pin"
            pins[name.lower().replace("_", "-")] = version
    for req in map(Requirement, wanted):
        name = req.name.lower().replace("_", "-")
        assert name in pins, f"{req.name} is a dependency but not pinned: run python tools/refresh_constraints.py"
        assert req.specifier.contains(pins[name], prereleases=True), (req, pins[name])


@pytest.mark.slow
def test_main_job_arguments_are_valid_and_the_figure_is_in_the_repo(tmp_path):
    """The main job's command line runs (cut down to one short case here; the full sweep is
    what the README promises a user, minutes on two cores) and writes its figure."""
    from pdamper.cli import main

    line = _blocks(_section("Set up"))[0].strip()
    args = shlex.split(line.split("&&", 1)[1])[1:]
    assert args[0] == "sweep" and args[args.index("--plot") + 1] == "sweep_36.png"
    args[args.index("--plot") + 1] = str(tmp_path / "sweep_36.png")
    args += ["--strokes", "13mm", "--cycles", "2.5", "--set", "run.drop_cycles=1", "--workers", "1",
             "--out", str(tmp_path / "store"), "--json"]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert (tmp_path / "sweep_36.png").stat().st_size > 10_000
    for img in ("sweep_36.png", "theory_36.png"):
        assert (ROOT / "docs" / "img" / img).exists()
        assert f"docs/img/{img}" in README


def test_quoted_theory_output_is_real():
    from pdamper.cli import main

    use = _section("Use")
    command = _blocks(use, "sh")[0].strip()
    quoted = _blocks(use, "text")[0].strip()
    result = CliRunner().invoke(main, shlex.split(command)[1:])
    assert result.exit_code == 0
    assert quoted in result.stdout


def test_quoted_analyze_output_is_real(tmp_path, monkeypatch):
    from pdamper.cli import main

    monkeypatch.chdir(tmp_path)  # the table's column widths depend on the path shown
    subprocess.run([sys.executable, str(ROOT / "examples" / "analyze_record.py"),
                    str(tmp_path / "viscous_record.csv")], check=True, capture_output=True)
    use = _section("Use")
    command = _blocks(use, "sh")[1].strip()
    quoted = _blocks(use, "text")[1].strip()
    args = shlex.split(command)[1:]
    result = CliRunner().invoke(main, args)
    assert result.exit_code == 0, result.output
    assert quoted in result.stdout


def test_documentation_links_exist():
    for target in re.findall(r"\]\(([^)#]+\.(?:md|png))\)", README) + ["LICENSE"]:
        assert (ROOT / target).exists(), target


@pytest.mark.slow
def test_python_api_example_runs(monkeypatch, capsys):
    code = _blocks(_section("Python API"), "python")[0]
    assert len([ln for ln in code.splitlines() if ln.strip()]) <= 6
    monkeypatch.chdir(ROOT)
    exec(compile(code, "README.md", "exec"), {})
    out = capsys.readouterr().out
    eta = float(re.search(r"eta\* = ([0-9.]+)", out).group(1))
    assert 0.3 < eta < 1.2, out


@pytest.mark.slow
def test_quoted_run_output_is_real():
    """The README's `pdamper run examples/cuboid_36.toml` line is what the command prints (20 cycles)."""
    from pdamper.cli import main

    use = _section("Use")
    i = next(k for k, b in enumerate(_blocks(use, "sh")) if b.strip().startswith("pdamper run "))
    command = _blocks(use, "sh")[i].strip()
    quoted = _blocks(use, "text")[i].strip()
    result = CliRunner().invoke(main, shlex.split(command.replace("examples/", str(ROOT / "examples") + "/"))[1:])
    assert result.exit_code == 0, result.output
    assert quoted in result.stdout


def test_the_list_of_docs_names_every_page():
    # issue 30: docs/fields.md and docs/reliability.md were missing from the list
    pages = sorted(p.name for p in (ROOT / "docs").glob("*.md") if p.name != "index.md")
    missing = [p for p in pages if f"(docs/{p})" not in README]
    assert not missing, f"README's list of docs lacks {missing}"
