"""Cases scheduled by their cost: the a-priori ranking, learning from finished cases, and that the
order in which cases run changes no number."""

from __future__ import annotations

import dataclasses

import pytest

from pdamper.config import load_case
from pdamper.schema import replace
from pdamper.studies.cost import expected_cost, learned_costs, ranked
from pdamper.studies.named import study_settings
from pdamper.studies.sweep import run_one

X = {"drive.stroke": 0.005}


def _settings(study):
    return {label: replace(case, X) for label, case in study_settings(study)}


def test_the_known_long_poles_rank_first():
    """The benchmark's sample of the paper (docs/performance.md): r = 2.5 mm beds, then mu = 1, then
    the paper's 44 and 36 spheres; the small spheres' 176 above their 144."""
    radius, friction, fig4 = _settings("radius"), _settings("friction"), _settings("fig4")
    order = [radius["r = 2.5 mm, N_p = 176"], radius["r = 2.5 mm, N_p = 144"], friction["44, mu = 1"],
             friction["36, mu = 1"], fig4["N_p = 44"], fig4["N_p = 36"]]
    costs = [expected_cost(c) for c in order]
    assert costs == sorted(costs, reverse=True)
    assert expected_cost(friction["36, mu = 0.01"]) <= expected_cost(fig4["N_p = 36"])


def test_cost_grows_with_the_stroke_the_run_length_and_the_modulus():
    base = _settings("fig4")["N_p = 36"]
    strokes = [expected_cost(replace(base, {"drive.stroke": x})) for x in (0.001, 0.005, 0.02, 0.05)]
    assert strokes == sorted(strokes) and len(set(strokes)) == 4
    assert expected_cost(dataclasses.replace(base, cycles=40)) > expected_cost(base)
    soft = _settings("modulus")["E = 3 GPa"]
    assert expected_cost(soft) < expected_cost(base)


def test_ranked_puts_the_longest_first_and_keeps_ties_in_order(tiny_config):
    base = load_case(tiny_config)
    items = [(f"k{i}", {"drive.stroke": x}, 0, replace(base, {"drive.stroke": x}))
             for i, x in enumerate((0.002, 0.02, 0.002, 0.01))]
    assert [it[0] for it in ranked(items)] == ["k1", "k3", "k0", "k2"]
    assert [it[0] for it in ranked(items, {"k0": 3.0, "k1": 1.0, "k2": 3.0, "k3": 2.0})] == ["k0", "k2", "k3", "k1"]


def test_finished_cases_rescale_their_setting(tiny_config):
    """A resumed study: a setting whose finished cases took 10x the model's estimate ranks its
    remaining cases 10x up; a setting with nothing finished takes the median ratio."""
    base = load_case(tiny_config)
    a, b = replace(base, {"drive.stroke": 0.01}), replace(base, {"drive.stroke": 0.02})
    items = [("a1", {}, 0, a), ("b1", {}, 0, b), ("c1", {}, 0, a)]
    measured = {"A": [(a, 10.0 * expected_cost(a))], "B": [(b, 1.0 * expected_cost(b))]}
    costs = learned_costs(items, {"a1": "A", "b1": "B", "c1": "C"}, measured)
    assert costs["a1"] == pytest.approx(10 * expected_cost(a))
    assert costs["b1"] == pytest.approx(expected_cost(b))
    assert costs["c1"] == pytest.approx(5.5 * expected_cost(a))  # the median of 10 and 1
    assert learned_costs(items, {}, {}) == {k: expected_cost(c) for k, _, _, c in items}


def test_the_order_of_execution_changes_no_number(tiny_config):
    """Each case is independent and seeded: run in either order, every summary is the same."""
    base = load_case(tiny_config)
    cases = {x: replace(base, {"drive.stroke": x, "initial.settle_time": 0.01}) for x in (0.004, 0.013)}

    def summaries(order):
        out = {}
        for x in order:
            r = run_one(cases[x], keep="none")
            out[x] = {k: v for k, v in r.items() if k != "wall_time_s"}
        return out

    assert summaries([0.004, 0.013]) == summaries([0.013, 0.004])
