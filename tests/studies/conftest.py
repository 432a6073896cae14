import pytest

TINY = """\
[particles]
count = 8
[drive]
stroke = "13mm"
frequency = "2Hz"
[initial]
settle_time = "50ms"
[run]
cycles = 3
drop_cycles = 1
"""


@pytest.fixture
def tiny_config(tmp_path):
    p = tmp_path / "tiny.toml"
    p.write_text(TINY)
    return p
