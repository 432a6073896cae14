"""``pdamper validate``: the paper-level checks, as a table and docs/validation.md."""

from __future__ import annotations

from pathlib import Path

import click

from .codes import settings_line
from .common import echo_json, main, user_errors
from .run import parse_set

__all__ = ["validate_command"]


@main.command("validate", short_help="Run the paper-level validation and report pass/fail per check.")
@click.option("--quick", is_flag=True, help="12 strokes and 8 cycles per study (a rough first look).")
@click.option("--seeds", type=click.IntRange(min=1), default=1, show_default=True, help="Seeds per stroke.")
@click.option("--fig4-seeds", type=click.IntRange(min=1), default=3, show_default=True,
              help="Seeds per stroke for Fig. 4, whose checks judge the seed mean (--quick: --seeds).")
@click.option("--out", type=click.Path(), default="validation", show_default=True, help="Directory of the study stores.")
@click.option("--report", type=click.Path(dir_okay=False),
              help="Markdown report to write, its figures beside it in img/validation/ [default: <out>/validation.md; "
                   "the project's own page: --report docs/validation.md].")
@click.option("--workers", type=click.IntRange(min=1), help="Local worker processes (default: all cores).")
@click.option("--scheduler", metavar="tcp://HOST:PORT", help="Run on an existing Dask cluster.")
@click.option("--part", type=click.Choice(["paper", "vertical"]), default="paper", show_default=True,
              help="paper: the checks against the paper; vertical: a vertically driven bed against the bouncing "
                   "law (its own section of the report, beyond the paper).")
@click.option("--set", "settings", multiple=True, metavar="SECTION.KEY=VALUE",
              help="Override a config key in every study's settings, e.g. --set contact.tangential=spring "
                   "(repeatable; as pdamper study --set). Give another --out than the default law's.")
@click.option("--json", "as_json", is_flag=True, help="Print the checks as JSON.")
@user_errors
def validate_command(quick, seeds, fig4_seeds, out, report, workers, scheduler, part, settings, as_json):
    """Run the paper-level validation (Fig. 4, friction, tilt, E, rho, eps) and report pass/fail.

    Takes tens of minutes on two cores (--quick: a few); resumable like every study. --part vertical
    compares a vertical drive with the bouncing law instead (about 10 minutes with 2 seeds).
    """
    from ..plotting.sweep import sweep_figure
    from ..studies.validate import run_validation, write_report

    overrides = parse_set(settings)
    sets = "".join(f" --set {item}" for item in settings)
    if part == "vertical":
        _vertical(quick, max(seeds, 2) if not quick else seeds, out, report, workers, scheduler, as_json, overrides,
                  sets)
        return

    checks, datasets, seconds = run_validation(out, quick=quick, seeds=seeds, fig4_seeds=None if quick else fig4_seeds,
                                               workers=workers, scheduler=scheduler,
                                               progress=False if as_json else None, overrides=overrides)
    report, img = _report_paths(report, out)
    figures = []
    for name, ds in datasets.items():
        f = img / f"{name}.png"
        sweep_figure(ds, f)
        figures.append((ds.attrs.get("title", name), f.relative_to(report.parent).as_posix()))
    cmd = "pdamper validate" + (" --quick" if quick else "") + (f" --seeds {seeds}" if seeds != 1 else "") \
        + (f" --fig4-seeds {fig4_seeds}" if fig4_seeds != 3 and not quick else "") + sets
    write_report(report, checks, figures, cmd, seconds)
    if as_json:
        echo_json({"checks": [c.__dict__ for c in checks], "passed": sum(c.passed for c in checks),
                   "total": len(checks), "report": str(report), "seconds": seconds})
        return
    w = max(len(c.name) for c in checks)
    for line in settings_line(settings):
        click.echo(line.strip())
    for c in checks:
        click.echo(f"{'PASS' if c.passed else 'FAIL'}  {c.name:<{w}}  expected {c.expected}; measured {c.measured}")
    click.echo(f"{sum(c.passed for c in checks)} of {len(checks)} checks pass ({seconds / 60:.1f} min); report: {report}")


def _vertical(quick, seeds, out, report, workers, scheduler, as_json, overrides, sets):
    """``--part vertical``: the study, the table, the figure and the report's section."""
    from ..plotting.validation import bouncing_figure
    from ..studies.validate import run_vertical, vertical_section, write_section

    rows, h, case, _, seconds = run_vertical(out, seeds=seeds, quick=quick, workers=workers, scheduler=scheduler,
                                             progress=False if as_json else None, overrides=overrides)
    report, img = _report_paths(report, out)
    bouncing_figure(rows, h, img / "vertical.png")
    cmd = "pdamper validate --part vertical" + (" --quick" if quick else "") + (f" --seeds {seeds}" if seeds != 2 else "") + sets
    write_section(report, vertical_section(rows, h, case, (img / "vertical.png").relative_to(report.parent).as_posix(),
                                           cmd, seconds))
    if as_json:
        echo_json({"clearance_m": h, "rows": rows, "report": str(report), "seconds": seconds})
        return
    for r in rows:
        law = f"{r['eta_law']:.3f}" if r["eta_law"] == r["eta_law"] else "  -  "
        click.echo(f"X = {r['stroke_m'] * 1e3:6.3g} mm  Gamma = {r['intensity']:5.3g}  eta* DEM {r['eta_dem']:.3f} "
                   f"({r['eta_min']:.3f}-{r['eta_max']:.3f})  bouncing law {law}")
    click.echo(f"clearance h = {h * 1e3:.2f} mm (settled bed to lid); report: {report}")


def _report_paths(report, out):
    """The report's path (default ``<out>/validation.md``) and its figures' folder beside it,
    ``img/validation/``, made."""
    report = Path(report) if report else Path(out) / "validation.md"
    img = report.parent / "img" / "validation"
    img.mkdir(parents=True, exist_ok=True)
    return report, img
