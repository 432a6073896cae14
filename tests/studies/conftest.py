import pytest

from dem_fixtures import TINY_CONFIG


@pytest.fixture
def tiny_config(tmp_path):
    p = tmp_path / "tiny.toml"
    p.write_text(TINY_CONFIG)
    return p

