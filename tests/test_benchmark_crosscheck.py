"""benchmarks/crosscheck.py without running a simulation: the laws it sets, the settling spread of
``--settle-step``, and the table's difference with its standard error (a closed form)."""

import math

import pytest

from script_loader import load_script


@pytest.fixture(scope="module")
def crosscheck():
    return load_script("benchmarks/crosscheck.py")


@pytest.mark.parametrize("law", ["tanh", "spring", "spring_tdoff", "spring_tsuji"])
def test_each_law_sets_the_contact_keys_it_names(crosscheck, law):
    case = crosscheck.with_law(crosscheck.build_case("vertical96", 12.0, 1, "paper", "case"), law)
    for key, value in crosscheck.PDAMPER_LAWS[law].items():
        assert getattr(case.contact, key.split(".")[1]) == value


def test_an_unknown_law_is_none_not_an_error(crosscheck):
    assert crosscheck.with_law(crosscheck.build_case("baffled", 5.38, 1, "none", "case"), "no-such-law") is None


def test_the_tanh_runs_keep_their_record_keys(crosscheck):
    """The paper's law writes no ``tangential`` key, so a run stored before the spring existed is
    found again (the key hashes the config)."""
    spec = {"code": "pdamper", "law": "tanh", "case": "vertical96", "stroke_mm": 12.0, "seed": 1, "tilt": "paper",
            "friction": "case"}
    _, config, key = crosscheck.prepare(spec, 1e-6)
    assert "tangential" not in config["config"]["contact"]
    _, _, spring_key = crosscheck.prepare({**spec, "law": "spring"}, 1e-6)
    assert key != spring_key and key.startswith("pdamper/vertical96_X12mm_s1_tilt-paper_tanh_")


def test_settle_step_lengthens_the_settling_of_seed_k_by_k_minus_1_steps(crosscheck):
    base = crosscheck.build_case("baffled", 3.28, 1, "paper", "case").initial.settle_time
    for seed in (1, 2, 3):
        case = crosscheck.build_case("baffled", 3.28, seed, "paper", "case", settle_step=0.01)
        assert case.initial.settle_time == pytest.approx(base + (seed - 1) * 0.01, abs=1e-15)


def test_the_table_difference_and_its_standard_error(crosscheck):
    """LIGGGHTS minus a law: the difference of the seed means, with sqrt(s1^2/n1 + s2^2/n2)."""
    def rec(code, law, seed, eta):
        return {"spec": {"code": code, "law": law, "case": "vertical96", "friction": "case", "stroke_mm": 12.0,
                         "tilt": "none", "seed": seed}, "result": {"eta_star": eta}}
    lig, tanh = [0.58, 0.77, 0.70], [0.69, 0.74, 0.77]
    records = [rec("liggghts", "liggghts", k + 1, e) for k, e in enumerate(lig)] + \
        [rec("pdamper", "tanh", k + 1, e) for k, e in enumerate(tanh)]
    md, rows = crosscheck.table(records)

    def sd(v):
        m = sum(v) / len(v)
        return math.sqrt(sum((x - m) ** 2 for x in v) / (len(v) - 1))
    diff = sum(lig) / 3 - sum(tanh) / 3
    se = math.sqrt(sd(lig) ** 2 / 3 + sd(tanh) ** 2 / 3)
    assert f"{diff:+.3f} ± {se:.3f}" in md.splitlines()[-1]
    assert {r["law"]: r["seeds"] for r in rows} == {"liggghts": 3, "tanh": 3}
