"""The unknowns of an ensemble (pdamper.studies.unknowns): the file read as written, its Latin
hypercube samples (each stratum of every marginal hit once; the same file, N and seed give the same
samples), the distributions' inverse CDFs, and a case at a sample (every value reaching the model
it is about)."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from scipy import stats

from pdamper.config import load_case
from pdamper.errors import InputError
from pdamper.studies.unknowns import Unknown, Unknowns, sample, sample_case, variable_name

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"

#: examples/unknowns/frame_quake.toml (a normal, a uniform, a truncated normal, an angle, whole numbers)
#: and a lognormal of a material pair and a choice of records.
TABLES = tomllib.loads((EXAMPLES / "unknowns" / "frame_quake.toml").read_text())["unknown"] + [
    {"key": "contact.pair[steel,pvc].friction", "distribution": "lognormal", "mean": 0.1, "std": 0.03},
    {"key": "load.file", "distribution": "choice", "values": ["quake_synthetic.csv", "quake_synthetic.AT2"]}]


@pytest.fixture
def unknowns():
    return Unknowns.from_tables(TABLES, source="U.toml", folder=EXAMPLES)


def _cdf(u: Unknown):
    """The distribution's CDF (scipy), written out here from the file's parameters."""
    if u.distribution == "normal":
        return stats.norm(u.mean, u.std).cdf
    if u.distribution == "uniform":
        return stats.uniform(u.low, u.high - u.low).cdf
    if u.distribution == "truncated":
        return stats.truncnorm((u.low - u.mean) / u.std, (u.high - u.mean) / u.std, loc=u.mean, scale=u.std).cdf
    s2 = math.log(1 + (u.std / u.mean) ** 2)
    return stats.lognorm(math.sqrt(s2), scale=u.mean / math.sqrt(1 + (u.std / u.mean) ** 2)).cdf


def test_the_file_reads_with_units_in_si(unknowns):
    by = {u.key: u for u in unknowns}
    assert by["container.tilt"].high == pytest.approx(math.radians(0.2), rel=1e-15)
    assert (by["contact.pair[steel,pvc].friction"].mean, by["contact.pair[steel,pvc].friction"].std) == (0.1, 0.03)
    assert by["load.file"].values == (str(EXAMPLES / "quake_synthetic.csv"), str(EXAMPLES / "quake_synthetic.AT2"))
    assert variable_name("contact.pair[steel,pvc].friction") == "contact_pair_steel_pvc_friction"


@pytest.mark.parametrize("n", [1, 7, 64])
def test_every_stratum_of_every_marginal_is_hit_once(unknowns, n):
    s = sample(unknowns, n, seed=11)
    for j, u in enumerate(unknowns):
        assert sorted(np.floor(s.u[:, j] * n).astype(int)) == list(range(n))  # the hypercube itself
        x = np.asarray(s.columns[u.key], dtype=object)
        if u.distribution in ("normal", "uniform", "truncated", "lognormal") and u.kind.kind == "number":
            # mapped through the inverse CDF: the CDF of the values is the hypercube's coordinate again
            np.testing.assert_allclose(_cdf(u)(x.astype(float)), s.u[:, j], rtol=1e-9, atol=1e-12)
    seeds = np.asarray(s.columns["initial.seed"])
    if n == 64:  # a thousand whole numbers, 0 ... 999 both included: each of 64 strata of 15.6 numbers once
        strata = np.floor(seeds / (1000 / 64)).astype(int)
        assert sorted(strata) == list(range(64)) and seeds.min() >= 0 and seeds.max() <= 999
        files = s.columns["load.file"]
        assert sorted(files.count(f) for f in set(files)) == [32, 32]


def test_the_same_file_n_and_seed_give_the_same_samples(unknowns):
    a = sample(unknowns, 16, seed=3)
    assert a.points() == sample(Unknowns.from_tables(TABLES, folder=EXAMPLES), 16, seed=3).points()
    path = EXAMPLES / "unknowns" / "frame_quake.toml"
    assert sample(Unknowns.read(path), 16, seed=3).points() == sample(Unknowns.read(path), 16, seed=3).points()
    assert sample(unknowns, 16, seed=4).points() != a.points()


def test_a_case_at_a_sample_carries_every_value(unknowns):
    base = load_case(EXAMPLES / "frame_quake.toml")
    s = sample(unknowns, 4, seed=0)
    for i in range(4):
        v = s.point(i)
        c = sample_case(base, v)
        assert c.drive.natural_frequency == pytest.approx(3.0 * math.sqrt(v["structure.stiffness_scale"]), rel=1e-12)
        assert c.container.tilt == (v["container.tilt"],) * 3 and c.contact.friction == v["contact.friction"]
        assert c.contact.friction_for("steel", "pvc") == v["contact.pair[steel,pvc].friction"]
        assert c.drive.load.scale == v["load.scale"] and c.drive.load.file == v["load.file"]
        assert c.initial.seed == v["initial.seed"] and c.drive.load.duration == base.drive.load.duration


def test_a_pair_and_a_mode_of_data_are_set_in_their_tables():
    base = load_case(EXAMPLES / "mast_modal.toml")
    c = sample_case(base, {"contact.pair[steel,pvc].friction": 0.3, "contact.pair[pvc,steel].restitution": 0.7,
                           "structure.modes[1].frequency": 13.0, "structure.modes[0].damping_ratio": 0.02})
    assert c.contact.friction_for("pvc", "steel") == 0.3 and c.contact.restitution_for("steel", "pvc").value == 0.7
    assert c.contact.friction == base.contact.friction
    assert c.drive.mode_frequencies[1] == 13.0 and c.drive.mode_damping_ratios[0] == 0.02
    assert c.drive.mode_frequencies[0] == base.drive.mode_frequencies[0]
    with pytest.raises(InputError, match=r"structure.modes\[5\].frequency: the structure has 2 modes"):
        sample_case(base, {"structure.modes[5].frequency": 13.0})
    with pytest.raises(InputError, match="an FE structure's modes follow from its matrices: give structure.stiffness_scale"):
        sample_case(load_case(EXAMPLES / "mast_fe.toml"), {"structure.modes[0].frequency": 2.0})


def test_a_sample_that_makes_no_case_names_the_sample_and_the_fix():
    base = load_case(EXAMPLES / "cuboid_36.toml")
    with pytest.raises(InputError, match=r"sample 3 \(contact.friction = -0.02\) is not a valid case: .*friction.*"
                                         "must be >= 0.*truncated"):
        sample_case(base, {"contact.friction": -0.02}, label="sample 3")


#: (file text, what the message must say): each one line, the file, the table's number and key, the value
#: as written, what is allowed.
BAD = [
    ('[[unknown]]\nkey = "contact.frcition"\ndistribution = "normal"\nmean = 0.1\nstd = 0.01',
     ["#1", "contact.frcition", "did you mean 'friction'"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "gauss"\nmean = 0.1\nstd = 0.01',
     ["#1", "distribution = 'gauss'", "'normal'", "'choice'"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "normal"\nmean = 0.1',
     ["#1 (key = 'contact.friction')", "needs mean, std; std is missing"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "uniform"\nlow = 0.2\nhigh = 0.1',
     ["low = 0.2 and high = 0.1", "need low < high"]),
    ('[[unknown]]\nkey = "container.tilt"\ndistribution = "uniform"\nlow = "0dego"\nhigh = "1deg"',
     ["#1 (key = 'container.tilt')", "low", "'0dego'", "angle"]),
    ('[[unknown]]\nkey = "container.length"\ndistribution = "normal"\nmean = "120mm"\nstd = "2kg"',
     ["std", "'2kg' is not a length"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "normal"\nmean = 0.1\nstd = 0.01\nlow = 0',
     ["a normal distribution takes mean, std, not low"]),
    ('[[unknown]]\nkey = "numerics.integrator"\ndistribution = "uniform"\nlow = 0\nhigh = 1',
     ["text", "choice"]),
    ('[[unknown]]\nkey = "particles.count"\ndistribution = "choice"\nvalues = [30, 30.5]',
     ["values[1] = 30.5", "whole numbers"]),
    ('[[unknown]]\nkey = "load.file"\ndistribution = "choice"\nvalues = ["nowhere.AT2"]',
     ["values[0] = 'nowhere.AT2': no such file"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "lognormal"\nmean = -0.1\nstd = 0.01',
     ["lognormal's mean must be > 0"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "normal"\nmean = 0.1\nstd = 0',
     ["std = 0; must be > 0"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "normal"\nmean = 0.1\nstd = 0.01\n'
     '[[unknown]]\nkey = "contact.friction"\ndistribution = "uniform"\nlow = 0\nhigh = 1', ["#2", "repeats #1"]),
    ('[[unknown]]\nkey = "contact.friction"\ndistribution = "normal"\nmaen = 0.1\nstd = 0.01',
     ["#1", "unknown entry 'maen'", "did you mean 'mean'"]),
    ('[unknown]\nkey = "contact.friction"', ["[[unknown]] tables"]),
    ('title = "x"', ["unknown entry 'title'"]),
    ('', ["no [[unknown]] tables"]),
    ('[[unknown]\nkey = 1', ["invalid TOML"]),
    ('[[unknown]]\nkey = "drive.stroke[0]"\ndistribution = "normal"\nmean = 1\nstd = 1', ["drive.stroke[0]"]),
    ('[[unknown]]\nkey = "structure.modes[0].mass"\ndistribution = "normal"\nmean = 1\nstd = 1',
     ["a mode has frequency, damping_ratio, modal_mass"]),
    ('[[unknown]]\nkey = "load.time"\ndistribution = "normal"\nmean = 1\nstd = 1', ["not a single value"]),
    ('[[unknown]]\nkey = 3\ndistribution = "normal"\nmean = 1\nstd = 1', ["#1: key = 3"]),
]


@pytest.mark.parametrize("text, words", BAD, ids=[w[0][:30] for _, w in BAD])
def test_a_broken_file_is_one_line_naming_what_is_wrong(tmp_path, text, words):
    p = tmp_path / "U.toml"
    p.write_text(text)
    with pytest.raises(InputError) as info:
        Unknowns.read(p)
    msg = str(info.value)
    assert msg.startswith(str(p)) and "\n" not in msg and "np.float" not in msg, msg
    for w in words:
        assert w in msg, (w, msg)


def test_a_missing_or_unreadable_file_is_one_line(tmp_path):
    with pytest.raises(InputError, match=r"unknowns' file \(--uncertain\) not found: .*nothing.toml"):
        Unknowns.read(tmp_path / "nothing.toml")
    with pytest.raises(InputError, match="is a directory; give the unknowns' file"):
        Unknowns.read(tmp_path)
    (tmp_path / "bin.toml").write_bytes(b"\xff\xfe\x00[[unknown]]")
    with pytest.raises(InputError, match=r"cannot read unknowns' file \(--uncertain\) .*bin.toml: byte 0 is not UTF-8"):
        Unknowns.read(tmp_path / "bin.toml")
