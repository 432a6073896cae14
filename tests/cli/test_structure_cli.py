"""``pdamper decay`` and ``pdamper response``: JSON, table, plot, one-line errors."""

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from pdamper.cli.common import main

EXAMPLE = str(Path(__file__).resolve().parents[2] / "examples" / "structure_36.toml")
SMALL = ["--set", "particles.count=4"]


def run(args):
    return CliRunner().invoke(main, args)


def test_decay_json_table_and_plot(tmp_path):
    r = run(["decay", EXAMPLE, "--cycles", "2", *SMALL, "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["particles"] == 4 and s["zeta_bare_mean"] > 0.0049
    assert s["bare_vs_closed_form_max_error"] < 1e-4
    png = tmp_path / "decay.png"
    r = run(["decay", EXAMPLE, "--cycles", "2", *SMALL, "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "zeta without damper" in r.output and png.stat().st_size > 10_000
    assert r.output.splitlines()[1] == "  --set                 particles.count=4"  # the overrides echoed (issue 39)


def test_response_table_and_plot(tmp_path):
    png = tmp_path / "resp.svg"
    r = run(["response", EXAMPLE, "--cycles", "4", "--measure-cycles", "2", "--frequencies", "2Hz", *SMALL,
             "--force", "0.2N", "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert "peak with damper" in r.output and png.exists()
    assert r.output.splitlines()[1] == "  --set                 particles.count=4"
    # what codes ask for and the damper as a TMD, the largest over the frequencies (no storeys here)
    for words in ("floor accelerations [m/s^2] (the largest over the frequencies)",
                  "drift ratios: no drift ratios: give [structure] storey_heights", "the damper as an equivalent TMD",
                  "from the resonant amplitudes"):
        assert words in r.output, words


def test_one_line_errors():
    for args, word in ((["response", EXAMPLE, "--frequencies", "3Hz:1Hz:4"], "--frequencies"),
                       (["response", EXAMPLE, "--force", "2kg"], "--force"),
                       (["decay", EXAMPLE, "--set", "structure.damping_ratio=2"], "damping_ratio"),
                       (["decay", EXAMPLE, "--plot", "x.gif"], "unknown format"),
                       (["response", EXAMPLE, "--frequencies", "2Hz"], "--force"),
                       (["response", EXAMPLE, "--force", "0.2N", "--limit", "drift=1"], "did you mean drift=1%?"),
                       (["response", EXAMPLE, "--set", "structure.storey_height=-3m"], "storey_height")):
        r = run(args)
        assert r.exit_code == 2, (args, r.output)
        assert r.output.startswith("Error:") and word in r.output and len(r.output.strip().splitlines()) == 1


MAST_FE = str(Path(__file__).resolve().parents[2] / "examples" / "mast_fe.toml")
MAST_MODAL = str(Path(__file__).resolve().parents[2] / "examples" / "mast_modal.toml")


def test_run_on_a_structure_prints_its_amplitude_and_the_damper_stroke():
    r = run(["run", MAST_FE, "--cycles", "1", *SMALL])
    assert r.exit_code == 0, r.output
    assert "eta*" not in r.output
    for words in ("structure amplitude", "damper stroke", "coupled ledger error", "truncation error"):
        assert words in r.output, r.output
    r = run(["run", MAST_FE, "--cycles", "1", *SMALL, "--json"])
    s = json.loads(r.stdout)
    # released from 20 mm at the tip; the mid-height point moves ~0.34 of the tip (mode 1's shape)
    assert s["damper_stroke_max_m"] == pytest.approx(0.02, rel=1e-3)
    assert 0.25 < s["structure_amplitude_m"] / s["damper_stroke_m"] < 0.4
    assert s["modes_kept"] == 4 and s["truncation_error"] == pytest.approx(6.2e-4, rel=0.01)
    assert s["coupled_energy_balance_error"] < 5e-3
    # the single-mode example: the structure is its own response point
    r = run(["run", EXAMPLE, "--cycles", "1", *SMALL, "--json"])
    s = json.loads(r.stdout)
    assert s["structure_amplitude_m"] == s["damper_stroke_m"] and s["modes_kept"] == 1


@pytest.mark.slow
def test_decay_and_response_on_a_two_mode_structure():
    r = run(["decay", MAST_MODAL, "--cycles", "2", *SMALL, "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["modes_kept"] == 2 and s["bare_vs_closed_form_max_error"] < 1e-5
    assert s["energy_balance_error"] < 5e-3
    r = run(["response", MAST_MODAL, "--force", "0.4N", "--frequencies", "1.9Hz,2.015Hz", "--cycles", "4",
             "--measure-cycles", "2", *SMALL, "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    from pdamper.config import load_case

    st = load_case(MAST_MODAL).drive
    assert s["amplitude_bare_m"] == pytest.approx(st.steady_amplitude([1.9, 2.015], 0.4).tolist(), rel=1e-12)
    # the bed as a solid mass m_a at the tip, at f_1: mode 1 alone gives F0 / |k_1 - (m_1 + m_a) W^2 + i c_1 W|
    # (mode 2 adds at most F0/k_2 = 8 um, 3e-4 of it; 4e-5 measured)
    import math

    m1, w, ma = 7.984, 2 * math.pi * 2.015, s["bed_mass_kg"]
    k1 = m1 * (2 * math.pi * 2.0146) ** 2
    c1 = 2 * 0.005 * math.sqrt(k1 * m1)
    assert s["amplitude_solid_mass_m"][1] == pytest.approx(0.4 / abs(k1 - (m1 + ma) * w * w + 1j * c1 * w), rel=1e-3)
    assert all(a > 0 for a in s["damper_amplitude_m"]) and s["energy_balance_error_max"] < 5e-3
    assert s["amplitude_damped_m"] == s["damper_amplitude_m"]  # the old key, one release
    # every dof of the modes given as data, the same keys as the fields' response: the damper point's is the
    # damper's amplitude, the response point's the run's response column
    assert s["method"] == "dem" and s["dofs"] == ["damper", "force", "response"]
    assert s["response_amplitude_m"][0] == pytest.approx(s["damper_amplitude_m"], rel=1e-9)
    assert s["response_amplitude_m"][2] == pytest.approx(s["response_point_amplitude_m"], rel=1e-9)
    assert s["response_amplitude_bare_m"][0] == pytest.approx(s["amplitude_bare_m"], rel=1e-9)


def _step_fields_file(tmp_path):
    """Synthetic fields of the example's bed with a jump (tests/studies/test_structure_response_fields.py)."""
    import sys

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "studies"))
    from test_structure_response_fields import step_fields

    from pdamper.studies.fields import write_fields

    return str(write_fields(step_fields(), tmp_path / "step.nc"))


def test_response_from_fields_json_table_plot_and_refusal(tmp_path):
    nc = _step_fields_file(tmp_path)
    r = run(["response", EXAMPLE, "--fields", nc, "--force", "0.2N", "--frequencies", "1.9Hz:2.1Hz:21", "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    assert s["method"] == "fields" and len(s["frequencies_hz"]) == 21
    assert any(isinstance(v, list) and len(v) == 2 for v in s["response_point_amplitude_m"])
    # every dof (one mode: the structure itself, the damper point), as the DEM's keys
    flat = lambda vs: [x for v in vs for x in (v if isinstance(v, list) else [v])]  # noqa: E731
    assert s["dofs"] == [0] and flat(s["response_amplitude_m"][0]) == pytest.approx(flat(s["damper_amplitude_m"]),
                                                                                    rel=1e-12)
    assert len(s["jump_frequencies_hz"]) == 2
    png = tmp_path / "fields.png"
    r = run(["response", EXAMPLE, "--fields", nc, "--force", "0.2N", "--frequencies", "1.9Hz:2.1Hz:21",
             "--plot", str(png)])
    assert r.exit_code == 0, r.output
    assert " / " in r.output and "jumps (the stable branches change) at" in r.output
    assert png.stat().st_size > 10_000
    r = run(["response", EXAMPLE, "--fields", nc, "--force", "0.2N", "--frequencies", "1.8Hz"])
    assert r.exit_code != 0 and "at f = 1.8 Hz and F0 = 0.2 N the damper amplitude lies below X = 1 mm" in r.output
    r = run(["response", EXAMPLE, "--fields", nc, "--force", "0.2N", "--frequencies", "1.8Hz", "--extrapolate",
             "--json"])
    assert r.exit_code == 0 and json.loads(r.stdout)["extrapolated"] is True


def test_response_warns_when_the_grid_misses_the_resonance():
    r = run(["response", EXAMPLE, "--cycles", "3", "--measure-cycles", "1", "--frequencies", "3Hz", *SMALL,
             "--force", "0.2N"])
    assert r.exit_code == 0, r.output
    assert "warning: the frequencies 3.00-3.00 Hz lie above the resonance of mode 1 (between 1.99" in r.stderr
    assert "and 2 Hz, without the bed)" in r.stderr
    assert "* not steady" in r.output


# ------------------------------------------------------------------ what a designer tripped over (issue 30, item 6)

def test_response_forces_a_structure_the_file_leaves_at_rest(tmp_path):
    nc = _step_fields_file(tmp_path)
    rest = tmp_path / "rest.toml"  # force_amplitude = 0 N and no start: nothing moves it as written
    rest.write_text("\n".join(line for line in Path(EXAMPLE).read_text().splitlines()
                              if not line.startswith(("displacement", "force_frequency"))))
    r = run(["response", str(rest), "--fields", nc, "--force", "0.2N", "--frequencies", "1.95Hz:2.05Hz:5", "--json"])
    assert r.exit_code == 0, r.output
    assert json.loads(r.stdout)["force_amplitude_N"] == 0.2
    r = run(["response", str(rest), "--fields", nc, "--frequencies", "2Hz"])
    assert r.exit_code == 2 and "nothing moves it" in r.output  # without --force it is still refused


def test_response_ratio_is_against_the_resonance_and_the_table_shows_every_frequency(tmp_path):
    import numpy as np

    from pdamper.config import load_case

    nc = _step_fields_file(tmp_path)
    grid = ["1.9505Hz", "2.0005Hz", "2.0505Hz"]  # misses the bare peak (2 Hz less a hair)
    r = run(["response", EXAMPLE, "--fields", nc, "--force", "0.2N", "--frequencies", ",".join(grid), "--json"])
    assert r.exit_code == 0, r.output
    s = json.loads(r.stdout)
    s_bare = load_case(EXAMPLE).running_drive
    fine = np.linspace(1.99, 2.01, 20001)
    peak = float(np.max(s_bare.steady_amplitude(fine, 0.2)))
    assert s["resonance_bare_m"] == pytest.approx(peak, rel=1e-6) and s["resonance_bare_m"] > s["peak_bare_m"]
    assert s["peak_reduction"] == pytest.approx(s["peak_damped_m"] / s["resonance_bare_m"], rel=1e-12)
    assert s["peak_reduction_on_grid"] == pytest.approx(s["peak_damped_m"] / s["peak_bare_m"], rel=1e-12)
    table = run(["response", EXAMPLE, "--fields", nc, "--force", "0.2N", "--frequencies", ",".join(grid)]).output
    for f in ("1.9505", "2.0005", "2.0505"):
        assert f"  {f}  " in table
    assert f"ratio {s['peak_reduction']:.3g}" in table and "at its resonance" in table


def test_a_transient_peak_names_the_check_that_failed():
    from pdamper.cli.structure_text import transient_words

    s = {"frequencies_hz": [2.0], "peak_damped_frequency_hz": 2.0, "steady_tolerance": 0.02,
         "last_period_change": [0.0052], "window_change": [0.031]}
    words = transient_words(s)
    assert "changed 3.1 % between the two halves of the measured periods" in words and "2 % limit" in words
    assert "0.52" not in words  # the check that passed is not quoted as the reason


def test_several_forces_overlay_in_one_figure_and_json(tmp_path):
    nc = _step_fields_file(tmp_path)
    png = tmp_path / "two.png"
    r = run(["response", EXAMPLE, "--fields", nc, "--force", "0.1N", "--force", "0.2N", "--frequencies",
             "1.95Hz:2.05Hz:5", "--plot", str(png), "--json"])
    assert r.exit_code == 0, r.output
    out = json.loads(r.stdout)
    assert out["forces_N"] == [0.1, 0.2] and [x["force_amplitude_N"] for x in out["responses"]] == [0.1, 0.2]
    assert png.stat().st_size > 10_000
