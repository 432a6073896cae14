"""Plausibility of a case before anything is simulated: sizes against each other, the drive's
acceleration, whole cycles for the analysis, and the memory a run will need.

A bare number in a config is SI (metres, hertz): ``stroke = 13`` is a 13 m stroke. Such a value
fails deep inside a run ("the run became unstable"); here it is caught first, with the fix:
"drive.stroke = 13 m is 108 times the container's length 0.12 m; did you mean '13mm'?". The same
for the container's sizes, the radii, the jitter, the settling time ('100' s: "did you mean '100ms'?") and
the drive's direction (an angle beyond a turn).
Lift-off (a peak acceleration above g) is allowed, and said (a warning); so is a bed stacked in
layers with nothing but round-off to break its symmetry (:class:`SymmetricBedWarning`).
"""

from __future__ import annotations

import dataclasses
import math
import warnings

from ._deprecated import renamed_keyword
from .errors import InputError
from .schema import spec_of
from .units import thousandth_hint

__all__ = ["check_case", "memory_needed", "LiftOffWarning", "SymmetricBedWarning", "symmetric_stack"]

#: Largest plausible container dimension and sphere radius, smallest sphere radius [m].
_MAX_SIZE, _MAX_RADIUS, _MIN_RADIUS = 5.0, 0.5, 1e-6
#: Densest packing of equal spheres (Kepler): no bed fills more of its container.
_DENSEST = math.pi / (3 * math.sqrt(2))
#: Largest plausible peak drive acceleration [g].
_MAX_ACCEL_G = 50.0


class LiftOffWarning(UserWarning):
    """The drive's peak acceleration exceeds g: the bed leaves the floor (the paper's laws assume A < g)."""


class SymmetricBedWarning(UserWarning):
    """A bed of several layers stacked sphere on sphere in a container without tilt: it has two
    states (a crystal that only the symmetry keeps, and the melted bed), and which one a run lands
    on is picked by round-off, the seed and the tangential law (docs/crosscheck.md)."""


#: Longest plausible settling time [s]: a bed settles under gravity in well under a second.
_MAX_SETTLE = 10.0
#: Standard gravity [m/s^2]: the unit of "g" in the acceleration limits (whatever the case's gravity).
_G0 = 9.81


def _check_lengths(case, dims: dict) -> None:
    """Lengths that a bare number (metres) makes absurd: container sizes, radii, jitter, settling time."""
    for k, v in dims.items():
        if v > _MAX_SIZE:
            raise InputError(f"container.{k} = {v:g} m is not a damper container (a number without a unit is "
                             f"metres){thousandth_hint(v, _MAX_SIZE)}")
    for p in case.particles:
        if p.radius > _MAX_RADIUS:
            raise InputError(f"particles.radius = {p.radius:g} m (a number without a unit is metres)"
                             f"{thousandth_hint(p.radius, _MAX_RADIUS)}")
        if p.radius < _MIN_RADIUS:
            raise InputError(f"particles.radius = {p.radius:g} m is below {_MIN_RADIUS * 1e6:g} um: not a damper "
                             "particle (a number without a unit is metres; the paper's spheres have 5 mm)")
    _check_fit(case)
    lo, hi = case.container.geometry.bounding_box()
    floor = float(min(hi[0] - lo[0], hi[2] - lo[2]))
    jitter = case.initial.jitter
    if jitter > floor:
        raise InputError(f"initial.jitter = {jitter:g} m is larger than the container's floor ({floor * 1e3:g} mm "
                         f"across); it shifts each sphere by a small random amount (a number without a unit is "
                         f"metres){thousandth_hint(jitter, floor)}")
    settle = case.initial.settle_time
    if settle > _MAX_SETTLE:
        raise InputError(f"initial.settle_time = {settle:g} s: a bed settles under gravity in well under a second "
                         f"(default 0.1 s; at most {_MAX_SETTLE:g} s; a number without a unit is seconds)"
                         f"{thousandth_hint(settle, _MAX_SETTLE, 'ms')}")


def _check_fit(case) -> None:
    """Each sphere fits in the container, and all of them together (by volume, at the densest packing)."""
    geo = case.container.geometry
    r = max(p.radius for p in case.particles)
    lo, hi = geo.bounding_box()
    spans = {"length": hi[0] - lo[0], "height": hi[1] - lo[1], "width": hi[2] - lo[2]}
    key = min(spans, key=spans.get)
    if 2 * r > spans[key]:
        # the shape's own key that sets this span (a cylinder's radius sets twice itself)
        fields = {f.name: getattr(geo, f.name) for f in dataclasses.fields(geo) if spec_of(f).dimension == "length"}
        own = next((f"container.{k} = {v * 1e3:g} mm" for k, v in fields.items()
                    if math.isclose(v, spans[key]) or math.isclose(2 * v, spans[key])),
                   f"its inside is {spans[key] * 1e3:g} mm across")
        raise InputError(f"particles.radius = {r * 1e3:g} mm: a sphere of diameter {2e3 * r:g} mm does not fit in the "
                         f"container ({own}); give a smaller radius or a larger container")
    volume = geo.volume()
    beds = sum(p.count * 4.0 / 3.0 * math.pi * p.radius ** 3 for p in case.particles)
    if beds > _DENSEST * volume:
        n = sum(p.count for p in case.particles)
        sizes = ", ".join(f"container.{f.name} = {getattr(geo, f.name) * 1e3:g} mm" for f in dataclasses.fields(geo)
                          if spec_of(f).dimension == "length" and isinstance(getattr(geo, f.name), (int, float)))
        radii = ", ".join(sorted({f"{p.radius * 1e3:g}" for p in case.particles}))
        raise InputError(f"particles.count = {n:g} of particles.radius = {radii} mm: the spheres' volume is "
                         f"{beds / volume:.3g} times the container's ({volume * 1e6:.3g} cm^3: {sizes}); no packing "
                         "fits them; give fewer or smaller spheres or a larger container")


def _check_angles(case) -> None:
    """Drive directions within one turn (a larger angle is a typo or a number meant in degrees as radians)."""
    angle = case.drive.angle
    if abs(angle) > 2 * math.pi:
        section = case.drive.config_section
        hint = f"; did you mean '{angle:g}deg'?" if abs(angle) <= 360 else ""
        raise InputError(f"{section}.angle = {angle:g} rad is beyond a full turn (|angle| <= 2 pi rad = 360 deg); "
                         f"it is the drive's direction in the horizontal plane (a number without a unit is "
                         f"radians){hint}")


def symmetric_stack(case) -> int:
    """The layers of the case's initial block when they are stacked sphere on sphere on a lattice
    and nothing breaks its symmetry (no tilt: every angle of ``container.tilt`` 0; the block's
    lattice, not given positions); 0 otherwise (one layer, a tilt, a scatter, given positions)."""
    from .initial import floor_capacity

    init = case.initial
    if (init.positions is not None or init.arrangement != "block" or init.layers != "auto"
            or any(a != 0.0 for a in case.container.tilt)):
        return 0
    per_layer = floor_capacity(case.container, max(p.radius for p in case.particles))
    n = sum(p.count for p in case.particles)
    return int(math.ceil(n / per_layer)) if 0 < per_layer < n else 0


def _symmetric_warning(case) -> None:
    layers = symmetric_stack(case)
    if layers < 2:
        return
    warnings.warn(f"the bed is stacked in {layers} layers, sphere on sphere, in a container without tilt "
                  "(container.tilt = 0): nothing but round-off breaks the lattice's symmetry, and such a bed has two "
                  "states, a crystal of stacked columns that no real container keeps and the melted bed, with "
                  "different eta* (0.58 and 0.77 at 12 mm on examples/vertical_96.toml); with "
                  "contact.tangential = 'tanh' (the default) the seed picks one (up to 0.09 apart), with 'spring' the "
                  "crystal stands. Keep the paper's tilt (container.tilt = '0.1deg', the default) for the melted bed "
                  "every code agrees on (docs/crosscheck.md)", SymmetricBedWarning, stacklevel=4)


def check_case(case, *, analyze: bool = False, analyse: bool | None = None) -> None:
    """Raise :class:`InputError` for a case that cannot be meant as written; warn at lift-off and
    of a symmetric stacked bed (:func:`symmetric_stack`).

    ``analyze``: the run is analysed by the complex power method, so it needs at least one whole
    cycle after the dropped ones (a warning when it has exactly one); ``analyse`` is its
    deprecated spelling.
    """
    analyze = renamed_keyword("check_case", "analyse", "analyze", analyse, analyze)
    geo = case.container.geometry
    # every length field of the shape, as its config key
    dims = {f.name: getattr(geo, f.name) for f in dataclasses.fields(geo)
            if spec_of(f).dimension == "length" and isinstance(getattr(geo, f.name), (int, float))}
    _check_lengths(case, dims)
    _check_angles(case)
    _symmetric_warning(case)
    d = case.drive
    d.check_scale(geo.drive_length)  # the drive's own sizes against the container's (a stroke, a swing)
    if d.stroke is not None and d.frequency is not None:
        w = 2 * math.pi * d.frequency
        accel = d.stroke * w * w  # inf, not OverflowError, for an absurd frequency
        if accel > _MAX_ACCEL_G * _G0:
            raise InputError(f"the drive's peak acceleration X (2 pi f)^2 = {accel / _G0:.3g} g (X = {d.stroke * 1e3:g} "
                             f"mm, f = {d.frequency:g} Hz) is beyond any damper test; check drive.stroke and "
                             "drive.frequency (a number without a unit is SI: m, Hz)")
        g = case.gravity if case.gravity > 0 else _G0
        if accel > g and d.vertical_share == 0.0:  # a drive with a vertical part lifts the bed by design
            warnings.warn(f"the drive's peak acceleration {accel:.3g} m/s^2 ({accel / _G0:.2g} g) exceeds gravity "
                          f"({g:g} m/s^2): the bed "
                          "lifts off the floor (the paper's laws assume A < g); the run goes on", LiftOffWarning,
                          stacklevel=3)
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
