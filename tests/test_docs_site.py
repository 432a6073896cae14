"""The documentation site (mkdocs.yml) builds with warnings as errors and documents the public API."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

import pdamper

ROOT = Path(__file__).resolve().parents[1]

pytest.importorskip("mkdocs", reason="the docs tools: pip install -e '.[test]'")
pytest.importorskip("mkdocstrings_handlers.python", reason="the docs tools: pip install -e '.[test]'")


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("site")
    proc = subprocess.run([sys.executable, "-m", "mkdocs", "build", "--strict", "--config-file",
                           str(ROOT / "mkdocs.yml"), "--site-dir", str(out)],
                          cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, f"mkdocs build --strict failed:\n{proc.stderr[-4000:]}"
    return out


@pytest.mark.slow
def test_every_docs_page_is_in_the_site(site):
    for md in (ROOT / "docs").rglob("*.md"):
        rel = md.relative_to(ROOT / "docs").with_suffix("")
        page = site / ("index.html" if rel.name == "index" and rel.parent == Path(".") else
                       rel.parent / ("" if rel.name == "index" else rel.name) / "index.html")
        assert page.is_file(), f"{md} was not built into {page}"


def test_every_docs_page_is_in_the_navigation():
    """A page left out of mkdocs.yml's nav is built but reachable by no menu (docs/names.md was)."""
    nav = (ROOT / "mkdocs.yml").read_text(encoding="utf-8").split("\nnav:", 1)[1].split("\nmarkdown_extensions:")[0]
    listed = set(re.findall(r":\s*(\S+\.md)\s*$", nav, flags=re.M))
    pages = {md.relative_to(ROOT / "docs").as_posix() for md in (ROOT / "docs").rglob("*.md")}
    assert pages - listed == set(), f"docs pages missing from mkdocs.yml's nav: {sorted(pages - listed)}"


def test_api_reference_documents_every_public_name(site):
    html = "".join(p.read_text(encoding="utf-8") for p in (site / "api").rglob("*.html"))
    anchors = set(re.findall(r'id="(pdamper[\w.]*)"', html))
    documented = {a.rsplit(".", 1)[-1] for a in anchors}
    missing = [n for n in pdamper.__all__ if n not in documented and n != "__version__"]
    assert not missing, f"public names without an API reference entry: {missing}"
    # a docstring really was rendered, not only a heading
    assert "X_opt" in (site / "api" / "theory" / "index.html").read_text(encoding="utf-8")
    assert ":class:" not in html and ":func:" not in html, "Sphinx roles left in the API reference"
    assert "SPEC" not in html, "the API reference cites an internal document (a docstring says 'SPEC')"


def test_docs_cite_no_internal_documents():
    skip = set()
    for md in (ROOT / "docs").rglob("*.md"):
        if md.name in skip:
            continue
        text = md.read_text(encoding="utf-8")
        for pattern in (r"SPEC", r"\bissue \d+", r"\bthe lead\b"):
            hit = re.search(pattern, text)
            assert hit is None, f"{md.name} cites an internal document: {text[max(0, hit.start() - 60):hit.end() + 40]!r}"
