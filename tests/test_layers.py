"""The layers hold: the import-linter contracts of pyproject.toml (docs/architecture.md, "The floors")."""

from __future__ import annotations

import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

pytest.importorskip("importlinter")  # in the test extra; CI has it

ROOT = Path(__file__).parents[1]


def _lint(config: Path) -> tuple[bool, str]:
    """Run import-linter (as `lint-imports --config CONFIG` does) in a fresh process."""
    code = ("import sys; from importlinter.cli import lint_imports_command; "
            f"sys.argv = ['lint-imports', '--no-logo', '--no-cache', '--config', {str(config)!r}]; "
            "lint_imports_command()")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=300)
    return out.returncode == 0, out.stdout + out.stderr


def test_every_contract_of_pyproject_is_kept():
    ok, out = _lint(ROOT / "pyproject.toml")
    assert ok, out
    n = len(tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"])
    assert f"Contracts: {n} kept, 0 broken." in out


def test_a_broken_rule_is_reported(tmp_path):
    """The check can fail: the simulation does import the kernels, so forbidding it breaks."""
    cfg = tmp_path / "contracts.toml"
    cfg.write_text('[tool.importlinter]\nroot_package = "pdamper"\n\n'
                   '[[tool.importlinter.contracts]]\nname = "simulation without kernels"\ntype = "forbidden"\n'
                   'source_modules = ["pdamper.simulation"]\nforbidden_modules = ["pdamper.kernels"]\n')
    ok, out = _lint(cfg)
    assert not ok and "simulation without kernels BROKEN" in out


def test_the_layers_name_every_subpackage_and_module():
    """A new top-level module must be placed in a layer (else no rule covers it)."""
    contracts = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["importlinter"]["contracts"]
    layers = next(c for c in contracts if c["type"] == "layers")["layers"]
    named = {m.strip().split(".", 1)[1] for layer in layers for m in layer.split("|")}
    src = ROOT / "src" / "pdamper"
    tops = {p.stem for p in src.glob("*.py") if not p.stem.startswith("_")} | {
        p.name for p in src.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    assert tops - named == set(), f"not in any layer: {sorted(tops - named)}"
