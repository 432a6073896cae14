"""benchmarks/walk_levels.py: the level rule of the GPU's implicit pair walk on beds whose levels
are known by hand, the touching pairs it counts, and one short fig4 case on the CPU engine."""

import numpy as np
import pytest

from script_loader import load_script

R = 0.005
TOUCH = 2 * R * (1 - 1e-4)  # centres 1 um closer than touching


@pytest.fixture(scope="module")
def walk():
    return load_script("benchmarks/walk_levels.py")


def test_a_chain_is_one_row_a_level_and_disjoint_pairs_share_one(walk):
    assert walk.levels_of([(0, 1), (1, 2), (2, 3)]) == [1, 2, 3]
    assert walk.levels_of([(0, 1), (2, 3), (4, 5)]) == [1, 1, 1]
    # a square: (0,1) first; (0,2) and (1,3) after it, side by side; (2,3) after both
    assert walk.levels_of([(0, 1), (0, 2), (1, 3), (2, 3)]) == [1, 2, 2, 3]


def test_touching_pairs_of_a_frame_in_the_kernels_order(walk):
    square = np.array([[0, R, 0], [TOUCH, R, 0], [0, R, TOUCH], [TOUCH, R, TOUCH]])
    assert walk.rows_and_levels(square, np.full(4, R)) == (4, 3)  # the diagonals do not touch
    apart = np.array([[0, R, 0], [TOUCH, R, 0], [0.1, R, 0], [0.1 + TOUCH, R, 0]])
    assert walk.rows_and_levels(apart, np.full(4, R)) == (2, 1)
    assert walk.rows_and_levels(np.array([[0, R, 0], [0.1, R, 0]]), np.full(2, R)) == (0, 0)


def test_one_short_case_counts_its_frames(walk):
    out = walk.count(walk.fig4_cases()[41][2], 1.0, 50.0)
    assert out["frames"] >= 10 and out["steps"] > 0
    assert 0 < out["levels_mean"] <= out["rows_mean"] and out["levels_max"] <= out["rows_max"]
    assert 0 < out["levels_per_row"] <= 1


def test_a_case_beyond_fig4_is_refused_saying_the_range(walk, capsys):
    with pytest.raises(SystemExit) as err:
        walk.main(["--cases", "80"])
    assert err.value.code == 2 and "fig4 has cases 0-79" in capsys.readouterr().err
