"""The validation checks judge the studies as SPEC Sect. 9 says (on synthetic datasets)."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from pdamper import theory
from pdamper.studies.sweep import stroke_grid
from pdamper.studies.validate import evaluate_checks, write_report

X = stroke_grid(0.5e-3, 50e-3, 40)


def _curve(h, peak=0.85, shift=1.1, low=0.1):
    """eta*: 'low' below shift X_opt, then the rolling law scaled so its start is 'peak'."""
    xo = theory.optimal_stroke(h)
    law = np.nan_to_num(theory.eta_rolling(X / shift, h))
    return np.where(X >= shift * xo, law * peak / theory.ETA_MAX, low)


def _study(curves: dict, clearances: dict):
    labels = list(curves)
    eta = np.array([curves[k] for k in labels])[:, :, None]
    return xr.Dataset({"eta_star": (("setting", "stroke", "seed"), eta),
                       "clearance": ("setting", [clearances[k] for k in labels])},
                      coords={"setting": labels, "stroke": X, "seed": [0]})


def _datasets(**bad):
    h36, h44 = 0.03, 0.01
    fig4 = _study({"N_p = 36": _curve(h36), "N_p = 44": _curve(h44, peak=0.8, shift=1.2)},
                  {"N_p = 36": h36, "N_p = 44": h44})
    fr = {}
    for n, h in ((36, h36), (44, h44)):
        for mu, pk, sh in ((0.01, 1.0, 1.05), (0.1, 0.85, 1.15), (1.0, 0.7, 1.6)):
            fr[f"{n}, mu = {mu:g}"] = (_curve(h, peak=pk, shift=sh), h)
    tilt = {"44, baseline 0.1 deg": (_curve(h44), h44),
            "44, 3 deg about z": (np.where(X <= 3e-3, 0.01, _curve(h44)), h44),
            # 36 spheres as the paper's Sect. 6.2 says: z held to 4 mm then rising, x 0.1-0.5 below 4 mm
            "36, baseline 0.1 deg": (_curve(h36), h36),
            "36, 3 deg about x": (np.where(X <= 4.5e-3, 0.25 * X / 4e-3, _curve(h36)), h36),
            "36, 3 deg about y": (_curve(h36, peak=0.82), h36),
            "36, 3 deg about z": (np.where(X <= 4e-3, 0.0, np.minimum(0.5, _curve(h36) + 0.45)), h36)}
    sens = {study: {lbl: (_curve(h36, peak=pk), h36) for lbl, pk in items}
            for study, items in {"modulus": [("E = 3 GPa", 0.83), ("E = 208 GPa", 0.85), ("E = 405 GPa", 0.86)],
                                 "density": [("rho = 1400 kg/m3", 0.84), ("rho = 7900 kg/m3", 0.85),
                                             ("rho = 19250 kg/m3", 0.80)],
                                 "restitution": [("eps = 0.8", 0.9), ("eps = 0.9", 0.85), ("eps = 0.95", 0.82)]}.items()}
    ds = {"fig4": fig4, "friction": _study({k: v[0] for k, v in fr.items()}, {k: v[1] for k, v in fr.items()}),
          "tilt": _study({k: v[0] for k, v in tilt.items()}, {k: v[1] for k, v in tilt.items()})}
    for study, items in sens.items():
        ds[study] = _study({k: v[0] for k, v in items.items()}, {k: v[1] for k, v in items.items()})
    ds.update(bad)
    return ds


def test_a_paper_like_result_passes_every_check():
    checks = evaluate_checks(_datasets())
    assert len(checks) == 16
    assert all(c.passed for c in checks), [c for c in checks if not c.passed]


def test_each_kind_of_miss_is_caught():
    d = _datasets()
    # a 36-sphere peak far too low
    d["fig4"] = d["fig4"].copy(deep=True)
    d["fig4"].eta_star.loc[dict(setting="N_p = 36")] *= 0.5
    # friction order broken: mu = 1 peaks higher than mu = 0.1 (36 spheres)
    d["friction"] = d["friction"].copy(deep=True)
    d["friction"].eta_star.loc[dict(setting="36, mu = 1")] *= 1.4
    # the tilted bed does not stay on the low wall
    d["tilt"] = d["tilt"].copy(deep=True)
    d["tilt"].eta_star.loc[dict(setting="44, 3 deg about z", stroke=X[X <= 3e-3])] = 0.3
    # 36 spheres about z not held below 4 mm, about x ~0 as about z, about y far below the baseline
    d["tilt"].eta_star.loc[dict(setting="36, 3 deg about z", stroke=X[X <= 4e-3])] = 0.2
    d["tilt"].eta_star.loc[dict(setting="36, 3 deg about x", stroke=X[X <= 4e-3])] = 0.01
    d["tilt"].eta_star.loc[dict(setting="36, 3 deg about y")] *= 0.5
    failed = {c.name for c in evaluate_checks(d) if not c.passed}
    assert {"Fig. 4, 36 spheres: peak", "Friction, 36 spheres", "Tilt 3 deg about z, 44 spheres",
            "Tilt 3 deg about z, 36 spheres: held", "Tilt 3 deg about x, 36 spheres",
            "Tilt 3 deg about y, 36 spheres"} <= failed
    assert "Friction, 44 spheres" not in failed and "Tilt 3 deg about z, 36 spheres: rise" not in failed


def test_the_report_is_a_markdown_table_with_the_command(tmp_path):
    checks = evaluate_checks(_datasets())
    path = tmp_path / "validation.md"
    write_report(path, checks, [("Fig. 4", "img/validation/fig4.png")], "pdamper validate", 61.0)
    text = path.read_text()
    assert "`pdamper validate`" in text and "16 of 16 checks pass" in text
    rows = [ln for ln in text.splitlines() if ln.startswith("| ") and "expected" not in ln]
    assert len(rows) == 16 and all(ln.count("|") == 5 for ln in rows)
    assert "![Fig. 4](img/validation/fig4.png)" in text


def test_an_override_of_the_stroke_is_refused_with_what_validate_runs_and_no_option_it_lacks(tmp_path):
    from pdamper.errors import InputError
    from pdamper.studies.validate import run_validation

    with pytest.raises(InputError) as err:
        run_validation(tmp_path, quick=True, overrides={"drive.stroke": "3mm"})
    msg = str(err.value)
    assert "paper's strokes" in msg and "give --strokes" not in msg
    assert not (tmp_path / "fig4").exists()  # refused before anything ran
