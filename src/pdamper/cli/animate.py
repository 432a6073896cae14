"""``pdamper animate RUN_DIR`` and ``pdamper export RUN_DIR``: see a recorded run's motion.

``animate`` writes the animation (GIF, and MP4 when ffmpeg is installed), the sphere paths (the
paper's Fig. 3) and the bed against both walls (Fig. 5a); ``export`` writes the VTK time
series for ParaView. Both need a run directory recorded with ``pdamper run ... --trajectory
--out RUN_DIR``.
"""

from __future__ import annotations

from pathlib import Path

import click

from ..errors import InputError
from .common import echo_json, main, user_errors

__all__ = ["animate_command", "export_command", "load_trajectory_run"]


def load_trajectory_run(run_dir):
    """The stored run of ``run_dir``, refusing one without a trajectory with the way to record it."""
    from ..rundir import FILES, read_run

    run = read_run(run_dir)
    if run.trajectory is None:
        raise InputError(f"{run_dir} has no particle trajectory ({FILES['trajectory']}); record one with "
                         f"'pdamper run {Path(run_dir) / FILES['config']} --trajectory --out {run_dir}'")
    return run


@main.command("animate")
@click.argument("run_dir", metavar="RUN_DIR", type=click.Path(file_okay=False))
@click.option("--out", "out", type=click.Path(dir_okay=False),
              help="Write only this animation file (.gif or .mp4) instead of RUN_DIR/animation.gif (+ .mp4).")
@click.option("--speed", type=click.FloatRange(min=0, min_open=True), default=1.0, show_default=True,
              help="Playback speed: 1 real time, 0.5 slow motion.")
@click.option("--cycles", type=click.FloatRange(min=0, min_open=True),
              help="Animate only the last CYCLES drive cycles (default: the whole run).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (files written, mode).")
@user_errors
def animate_command(run_dir, out, speed, cycles, as_json):
    """Animate the recorded run RUN_DIR and draw its sphere paths and wall plot.

    Writes into RUN_DIR: animation.gif (top and side view of the moving container with the
    spheres), animation.mp4 when ffmpeg is installed, paths.png (top view of the sphere paths
    in the container frame, the paper's Fig. 3) and walls.png (the bed against both end walls
    over the drive cycles, Fig. 5a). RUN_DIR must hold a trajectory: record it with
    'pdamper run CONFIG.toml --trajectory --out RUN_DIR'.

    Example: pdamper animate runs/x15 --cycles 2 --speed 0.5
    """
    from ..analysis.modes import classify_trajectory
    from ..plotting.motion import animate, ffmpeg_available, paths_figure, walls_figure

    run = load_trajectory_run(run_dir)
    base = Path(run_dir)
    if out is not None:
        targets = [Path(out)]
    else:
        targets = [base / "animation.gif"] + ([base / "animation.mp4"] if ffmpeg_available() else [])
    written = []
    for target in targets:
        animate(run.trajectory, run.case, target, speed=speed, cycles=cycles)
        written.append(str(target))
    stroke = run.case.drive.stroke
    label = f"X = {stroke * 1e3:.3g} mm" if stroke else str(base.name)
    paths_figure([(label, run.trajectory, run.case)], base / "paths.png")
    walls_figure(run.trajectory, run.case, base / "walls.png")
    written += [str(base / "paths.png"), str(base / "walls.png")]
    try:
        mode = classify_trajectory(run.trajectory, run.case)[0]
    except ValueError:
        mode = None
    if as_json:
        echo_json({"run_dir": str(base), "files": written, "mode": mode, "mp4": ffmpeg_available()})
        return
    click.echo(f"pdamper animate {run_dir}: mode {mode}")
    for f in written:
        click.echo(f"  wrote {f}")
    if out is None and not ffmpeg_available():
        click.echo("  (no MP4: ffmpeg is not installed)")


@main.command("export")
@click.argument("run_dir", metavar="RUN_DIR", type=click.Path(file_okay=False))
@click.option("--out", "out", type=click.Path(file_okay=False), help="Output folder (default RUN_DIR/vtk).")
@click.option("--cycles", type=click.FloatRange(min=0, min_open=True),
              help="Export only the last CYCLES drive cycles (default: the whole run).")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (files written).")
@user_errors
def export_command(run_dir, out, cycles, as_json):
    """Write the recorded run RUN_DIR as a VTK time series for ParaView.

    One .vtp file per frame for the spheres (radius, velocity, spin) and for the container
    (its inner surface at its position), indexed by particles.pvd and container.pvd: open both
    in ParaView and press Play. RUN_DIR must hold a trajectory (pdamper run ... --trajectory
    --out RUN_DIR).

    Example: pdamper export runs/x15 --cycles 2
    """
    from ..io.vtk import write_case_vtk

    run = load_trajectory_run(run_dir)
    target = Path(out) if out else Path(run_dir) / "vtk"
    if target.exists() and not target.is_dir():
        raise InputError(f"--out {target}: is a file; give a folder")
    info = write_case_vtk(target, run.trajectory, run.case, cycles=cycles)
    if as_json:
        echo_json({"run_dir": str(run_dir), **info})
        return
    click.echo(f"pdamper export {run_dir}: {info['frames']} frames")
    click.echo(f"  {info['particles']}  (spheres: radius, velocity, spin)")
    click.echo(f"  {info['container']}  (container surface)")
    click.echo("  open both in ParaView, show the spheres as 'Point Gaussian' scaled by radius, press Play")
