"""Plausibility of a case before anything is simulated: sizes against each other, the drive's
acceleration, whole cycles for the analysis, and the memory a run will need.

A bare number in a config is SI (metres, hertz): ``stroke = 13`` is a 13 m stroke. Such a value
fails deep inside a run ("the run became unstable"); here it is caught first, with the fix:
"drive.stroke = 13 m is 108 times the container's length 0.12 m; did you mean '13mm'?".
Lift-off (a peak acceleration above g) is allowed, and said (a warning).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

from ._deprecated import renamed_keyword
from .errors import InputError
from .schema import spec_of

__all__ = ["check_case", "memory_needed", "LiftOffWarning"]

#: Largest plausible container dimension and sphere radius [m].
_MAX_SIZE, _MAX_RADIUS = 5.0, 0.5
#: Largest plausible peak drive acceleration [g].
_MAX_ACCEL_G = 50.0


class LiftOffWarning(UserWarning):
    """The drive's peak acceleration exceeds g: the bed leaves the floor (the paper's laws assume A < g)."""


def _mm_hint(value: float, upper: float) -> str:
    """' did you mean '13mm'?' when the number read as millimetres would be plausible."""
    return f"; did you mean '{value:g}mm'?" if 1e-3 * value <= upper else ""


def check_case(case, *, analyze: bool = False, analyse: bool | None = None) -> None:
    """Raise :class:`InputError` for a case that cannot be meant as written; warn at lift-off.

    ``analyze``: the run is analyzed by the complex power method, so it needs at least one whole
    cycle after the dropped ones (a warning when it has exactly one); ``analyse`` is its
    deprecated spelling.
    """
    analyze = renamed_keyword("check_case", "analyse", "analyze", analyse, analyze)
    geo = case.container.geometry
    # every length field of the shape, as its config key
    dims = {f.name: getattr(geo, f.name) for f in dataclasses.fields(geo)
            if spec_of(f).dimension == "length" and isinstance(getattr(geo, f.name), (int, float))}
    for k, v in dims.items():
        if v > _MAX_SIZE:
            raise InputError(f"container.{k} = {v:g} m is not a damper container (a number without a unit is "
                             f"metres){_mm_hint(v, _MAX_SIZE)}")
    r = max(p.radius for p in case.particles)
    if r > _MAX_RADIUS:
        raise InputError(f"particles.radius = {r:g} m (a number without a unit is metres){_mm_hint(r, _MAX_RADIUS)}")
    lo, hi = geo.bounding_box()
    height = float(hi[1] - lo[1])
    across = float(min(hi[0] - lo[0], hi[2] - lo[2]))
    if 2 * r > min(height, across):
        raise InputError(f"particles.radius = {r * 1e3:g} mm: a sphere of diameter {2e3 * r:g} mm does not fit in the "
                         f"container ({'height' if height <= across else 'width'} {min(height, across) * 1e3:g} mm); "
                         "give a smaller radius or a larger container")
    d = case.drive
    if d.stroke is not None and d.frequency is not None:
        L = geo.drive_length
        if d.stroke > 2 * L:
            raise InputError(f"drive.stroke = {d.stroke:g} m is {d.stroke / L:.3g} times the container's length "
                             f"{L:g} m (a number without a unit is metres){_mm_hint(d.stroke, 2 * L)}")
        accel = d.stroke * (2 * math.pi * d.frequency) ** 2
        g = case.gravity if case.gravity > 0 else 9.81
        if accel > _MAX_ACCEL_G * g:
            raise InputError(f"the drive's peak acceleration X (2 pi f)^2 = {accel / g:.3g} g (X = {d.stroke * 1e3:g} mm, "
                             f"f = {d.frequency:g} Hz) is beyond any damper test; check drive.stroke and drive.frequency "
                             "(a number without a unit is SI: m, Hz)")
        if accel > g and d.vertical_share == 0.0:
            warnings.warn(f"the drive's peak acceleration {accel / g:.2g} g exceeds g: the bed lifts off the floor "
                          "(the paper's laws assume A < g); the run goes on", LiftOffWarning, stacklevel=3)
        if analyze:
            whole = math.floor(case.cycles + 1e-9) - case.drop_cycles
            if whole < 1:
                raise InputError(f"run.cycles = {case.cycles:g} leaves no whole cycle after the {case.drop_cycles} "
                                 f"dropped (the analysis uses whole cycles); run at least {case.drop_cycles + 1} "
                                 "cycles or drop fewer")
            if whole == 1:
                warnings.warn(f"only one cycle is analysed (run.cycles = {case.cycles:g}, {case.drop_cycles} dropped): "
                              "eta* has no spread to judge steadiness by; run more cycles", UserWarning, stacklevel=3)


def memory_needed(case, frames_per_second: float = 0.0) -> float:
    """Bytes the recorded arrays of a run take: the signals and the energy ledger at the sample
    rate, and the trajectory frames (9 numbers per sphere and frame)."""
    duration = case.duration + case.initial.settle_time
    samples = duration * case.recording.sample_rate
    frames = duration * max(frames_per_second, case.recording.trajectory_fps)
    return 8.0 * (samples * (5 + 8) + frames * case.n_particles * 9)


def check_memory(case, frames_per_second: float = 0.0) -> None:
    """Refuse a run whose recorded arrays cannot fit in the memory available now, with the numbers."""
    need = memory_needed(case, frames_per_second)
    try:
        import psutil

        free = float(psutil.virtual_memory().available)
    except ImportError:  # pragma: no cover - psutil comes with dask distributed
        return
    if need > 0.8 * free:
        raise InputError(f"this run would record {need / 2**30:.3g} GiB ({case.cycles:g} cycles at "
                         f"{case.recording.sample_rate:g} samples/s) but {free / 2**30:.3g} GiB are free; run fewer "
                         "cycles or record fewer samples (recording.sample_rate)")
