"""Shared fixture of the CLI tests: the tiny DEM config (8 spheres, 3 cycles)."""

import pytest

from dem_fixtures import TINY_CONFIG  # noqa: E402


@pytest.fixture(scope="module")
def tiny(tmp_path_factory):
    """The tiny config file (written once per test module)."""
    path = tmp_path_factory.mktemp("cfg") / "tiny.toml"
    path.write_text(TINY_CONFIG)
    return path
