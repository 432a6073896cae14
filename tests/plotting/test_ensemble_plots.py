"""The ensemble's figures (pdamper.plotting.ensemble), drawn from a synthetic ensemble whose ratios are
a known function of its unknowns: the CDF's steps are the share of samples at or below, the tornado
ranks the unknown that moves the ratio first."""

from __future__ import annotations

import numpy as np

from ensemble_helpers import synthetic_store
from pdamper.studies.unknowns import Unknown, Unknowns

TWO = Unknowns((Unknown(key="structure.stiffness_scale", distribution="uniform", low=0.9, high=1.1),
                Unknown(key="contact.friction", distribution="uniform", low=0.05, high=0.2)))


def _ratio(values):
    """The peak ratio falls with the stiffness and ignores the friction."""
    r = 0.8 - 2.0 * (values["structure.stiffness_scale"] - 1.0)
    return (r, r - 0.05)


def test_the_cdf_steps_are_the_shares_and_the_target_is_drawn(tmp_path):
    from pdamper.plotting.ensemble import cdf_figure

    _, store = synthetic_store(tmp_path, _ratio, unknowns=TWO, samples=20)
    ds = store.dataset()
    fig = cdf_figure(ds, tmp_path / "cdf.png", target=0.8)
    assert (tmp_path / "cdf.png").stat().st_size > 10_000
    lines = {ln.get_label(): ln for ln in fig.axes[0].get_lines()}
    x, y = lines["dof damper"].get_xdata(), lines["dof damper"].get_ydata()
    np.testing.assert_array_equal(x[1:], np.sort(ds.peak_ratio.sel(dof="damper").values))
    np.testing.assert_allclose(y[1:], np.arange(1, 21) / 20)
    assert "largest over the dofs" in lines  # the one that decides the target
    said = [t.get_text() for t in fig.axes[0].texts]
    met = int((ds.peak_ratio.max("dof") <= 0.8).sum())
    assert any(f"met by {met} of 20 samples" in t and "Wilson" in t for t in said), said


def test_the_tornado_puts_the_unknown_that_moves_the_ratio_on_top(tmp_path):
    from pdamper.plotting.ensemble import tornado_figure

    _, store = synthetic_store(tmp_path, _ratio, unknowns=TWO, samples=30)
    fig = tornado_figure(store.dataset(), tmp_path / "tornado.png")
    assert (tmp_path / "tornado.png").stat().st_size > 10_000
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_yticklabels()]
    assert labels[-1] == "structure.stiffness_scale"  # the top row
    texts = [t.get_text() for t in ax.texts]
    assert "rho -1.00" in texts
    stiff = [p for p in ax.patches if abs(p.get_y() + p.get_height() / 2 - (len(labels) - 1)) < 1e-9]
    widths = sorted(p.get_width() for p in stiff)
    assert widths[0] < -0.05 and widths[-1] > 0.05  # the stiff third lower, the soft third higher
