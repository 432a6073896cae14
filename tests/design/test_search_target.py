"""Design to a target (issue 30, item 5): the lightest filling whose resonant amplitude is at most a
given fraction of the bare structure's, against a brute-force scan of the same model; a target
that cannot be met names the bound to widen (pdamper.design.search)."""

import json
import math

import numpy as np
import pytest
from click.testing import CliRunner

from pdamper import theory as th
from pdamper.cli.common import main
from pdamper.design import auto_margin, design_for_structure, operating_points, structure_mode
from pdamper.errors import InputError
from pdamper.geometry import Cuboid

from design_helpers import F0, FRAME, SPHERE, frame


def brute_force(lengths, target, *, cap=math.inf, particles=(1, 10**6)):
    """Every (length, filling) of the range through the model itself (operating_points, refined):
    {(length, n): ratio} of the admissible ones (every stable solution rolling at >= the default
    margin of the filling times X_opt, no lift-off), the ratio the largest stable solution over the
    bare resonant amplitude."""
    md = structure_mode(frame())
    x_bare = F0 / (md.damping * 2 * math.pi * md.frequency)
    out = {}
    for big_l in lengths:
        n_max = Cuboid(length=float(big_l), width=0.0404).clearance_capacity(0.005)
        for n in range(max(1, particles[0]), min(n_max - 1, particles[1]) + 1):
            if n * SPHERE > cap:
                break
            x_opt = th.X_OPT_OVER_H * big_l * (1 - n / n_max)
            pts = [p for p in operating_points(md, F0, x_opt=x_opt, bed_mass=n * SPHERE) if p.stable]
            margin = auto_margin(n / n_max)
            if not pts or any(p.state != "rolling" or p.stroke_over_x_opt < margin for p in pts):
                continue
            top = max(pts, key=lambda p: p.stroke_m)
            if top.stroke_m * (2 * math.pi * top.frequency_hz) ** 2 >= th.GRAVITY:
                continue
            out[(float(big_l), n)] = top.stroke_m / x_bare
    return out


@pytest.mark.parametrize("target, kw", [(0.55, {}), (0.6, {"particles": (20, 40), "max_bed_mass": 0.14})])
def test_the_design_is_the_lightest_of_a_brute_force_scan(target, kw):
    lengths = np.round(np.linspace(0.110, 0.125, 16), 9)
    d = design_for_structure(frame(), force=F0, target_ratio=target, length_range=(0.110, 0.125), **kw)
    scan = brute_force(lengths, target, cap=kw.get("max_bed_mass", math.inf), particles=kw.get("particles", (1, 10**6)))
    meet = {key: r for key, r in scan.items() if r <= target}
    lightest = min(n for _, n in meet)
    best = min((r, key) for key, r in meet.items() if key[1] == lightest)
    assert d.filling.particles == lightest
    assert d.filling.length_m == pytest.approx(best[1][0], abs=1e-12)
    assert d.reduction == pytest.approx(best[0], rel=1e-9) and d.reduction <= target
    assert d.target_ratio == target and d.stroke_over_x_opt >= d.margin
    assert d.margin == auto_margin(d.filling.particles / d.filling.max_particles)
    # the next lighter filling: its best ratio misses the target (or it keeps no margin)
    lighter = [r for (_, n), r in scan.items() if n == lightest - 1]
    assert (d.lighter_ratio is None and not lighter) or d.lighter_ratio == pytest.approx(min(lighter), rel=1e-9)
    assert d.lighter_ratio is None or d.lighter_ratio > target
    # lighter than the design that minimises the amplitude in the same bounds, which damps more
    free = design_for_structure(frame(), force=F0, length_range=(0.110, 0.125), **kw)
    assert free.filling.bed_mass_kg >= d.filling.bed_mass_kg and free.reduction <= d.reduction


def test_a_target_that_cannot_be_met_names_the_bound_to_widen():
    # about the paper's container length: 0.45 needs ~56 spheres in ~170 mm
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--target-ratio", "0.45",
                                  "--length", "100mm:120mm"])
    assert r.exit_code == 2 and r.output.startswith("Error: --target-ratio 0.45") and r.output.count("\n") == 1
    assert "the best: 36 of 48 spheres" in r.output
    assert "widen the container's length (--length 50mm:240mm meets it" in r.output
    with pytest.raises(InputError, match=r"none keeps that margin\); raise max_bed_mass"):
        design_for_structure(frame(), force=F0, target_ratio=0.5, length_range=(0.14, 0.15), max_bed_mass=0.15)
    with pytest.raises(InputError, match=r"raise particles"):
        design_for_structure(frame(), force=F0, target_ratio=0.5, length_range=(0.14, 0.15), particles=(30, 40))
    with pytest.raises(InputError, match=r"neither containers of 70-300 mm meet it"):
        design_for_structure(frame(), force=F0, target_ratio=0.2, length_range=(0.14, 0.15))


@pytest.mark.parametrize("args, words", [
    (["--target-ratio", "1"], ["--target-ratio"]),
    (["--target-ratio", "0"], ["--target-ratio"]),
    (["--particles", "40:30", "--target-ratio", "0.5"], ["--particles 40:30", "LOW <= HIGH"]),
    (["--particles", "a:b"], ["--particles"]),
    (["--length", "120mm:80mm"], ["--length 120mm:80mm", "LOW <= HIGH"]),
    (["--length", "80mm:120mm", "--length-range", "80mm:120mm"], ["not both"]),
    (["--write-case", "out.txt"], ["--write-case", ".toml"]),
])
def test_bad_target_options_name_the_option(args, words):
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", *args])
    assert r.exit_code == 2, r.output
    assert all(w in r.output for w in words), r.output


def test_the_target_options_belong_to_the_structure_design():
    for args in (["--target-ratio", "0.5"], ["--particles", "30"], ["--write-case", "x.toml"], ["--length", "8cm:9cm"]):
        r = CliRunner().invoke(main, ["design", "--frequency", "2Hz", "--stroke", "10mm", "--sphere-radius", "5mm",
                                      *args])
        assert r.exit_code == 2 and "--structure" in r.output, r.output


def test_the_cli_prints_the_target_and_the_lighter_filling():
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--target-ratio", "0.6",
                                  "--length", "100mm:130mm", "--json"])
    assert r.exit_code == 0, r.output
    d = json.loads(r.stdout)
    assert d["target_ratio"] == 0.6 and d["reduction"] <= 0.6
    assert d["search"]["lengths_m"] == [0.1, 0.13] and d["search"]["length_steps"] == 31
    assert d["search"]["margin"] == "auto"
    text = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--target-ratio", "0.6",
                                     "--length", "100mm:130mm"]).output
    line = next(ln for ln in text.splitlines() if ln.strip().startswith("target:"))
    assert "ratio <= 0.6" in line and "lengths 100-130 mm" in line
    assert (f"one sphere fewer: at best ratio {d['lighter_ratio']:.3g}" in line if d["lighter_ratio"] is not None
            else "no lighter filling" in line)
    assert f"ratio {d['reduction']:.3g}" in text
