"""What an ensemble says (pdamper.analysis.ensemble), on synthetic samples whose answer is known: the
share meeting a target and its Wilson interval (the textbook formula; its coverage over many
ensembles of a known share), percentiles, and the rank correlation of a monotone and of an
irrelevant unknown."""

from __future__ import annotations

import math

import numpy as np
import pytest

from pdamper.analysis.ensemble import percentiles, rank_importance, share_meeting


def _wilson(k, n, z=1.959963984540054):
    """The Wilson score interval, Brown, Cai & DasGupta (2001) eq. (4)."""
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return centre - half, centre + half


@pytest.mark.parametrize("k, n", [(45, 64), (0, 64), (64, 64), (3, 10), (1, 1)])
def test_the_share_and_its_interval_are_wilsons(k, n):
    values = np.r_[np.full(k, 0.5), np.full(n - k, 0.9)]
    s = share_meeting(values, 0.7)
    lo, hi = _wilson(k, n)
    assert (s["met"], s["samples"], s["share"]) == (k, n, k / n) and s["method"] == "wilson"
    assert s["low"] == pytest.approx(max(lo, 0.0), abs=1e-12) and s["high"] == pytest.approx(min(hi, 1.0), abs=1e-12)


def test_a_failed_sample_does_not_meet_the_target():
    s = share_meeting([0.5, np.nan, 0.6, 0.9], 0.7)
    assert (s["met"], s["samples"]) == (2, 4)


def test_the_interval_covers_a_known_share_as_often_as_it_says():
    """4000 ensembles of 64 samples, each sample meeting the target with probability 0.8: the 95 %
    interval holds 0.8 in about 95 % of them (Wilson's coverage at n = 64, p = 0.8 is 0.94-0.96)."""
    rng = np.random.default_rng(7)
    p, n, m = 0.8, 64, 4000
    ratio = np.where(rng.random((m, n)) < p, 0.6, 0.8)  # a sample meets "ratio <= 0.7" with probability p
    covered = 0
    for row in ratio:
        s = share_meeting(row, 0.7)
        covered += s["low"] <= p <= s["high"]
    assert 0.93 <= covered / m <= 0.97


def test_percentiles_of_a_known_sample_per_dof_and_without_the_failed():
    x = np.column_stack([np.arange(101.0), 2 * np.arange(101.0)])
    x[7, 0] = np.nan
    q = percentiles(x)
    assert q["p50"][1] == 100.0 and q["p05"][1] == 10.0 and q["p95"][1] == 190.0
    assert q["p50"][0] == pytest.approx(np.percentile(np.delete(np.arange(101.0), 7), 50))
    assert math.isnan(percentiles(np.full(5, np.nan))["p50"])


def test_the_ranking_finds_the_unknown_that_moves_the_result():
    rng = np.random.default_rng(3)
    n = 64
    stiff, noise, rec = rng.uniform(0.8, 1.2, n), rng.uniform(0, 1, n), rng.choice(["a.AT2", "b.AT2"], n)
    ratio = 0.7 - 0.3 * np.tanh(5 * (stiff - 1.0)) + 0.01 * rng.standard_normal(n)  # monotone, falling, not linear
    ranks = rank_importance({"noise": noise, "structure.stiffness_scale": stiff, "load.file": rec}, ratio,
                            order={"load.file": ["a.AT2", "b.AT2"]})
    assert ranks[0]["key"] == "structure.stiffness_scale" and ranks[0]["rho"] < -0.95
    assert all(abs(r["rho"]) < 0.35 for r in ranks[1:])
    flat = rank_importance({"x": np.ones(n)}, ratio)
    assert math.isnan(flat[0]["rho"])
