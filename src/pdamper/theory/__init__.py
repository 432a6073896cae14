"""The paper's closed forms, the bouncing law and the operating bounds.

Pure functions of SI floats or numpy arrays (a whole stroke sweep in one call); used as
design formulas, as test oracles for the DEM and as overlays on its plots. Equation numbers
refer to "Energy dissipation in horizontally driven particle dampers of low acceleration
intensities" (Nonlinear Dynamics), Sect. 5.

Clearance (:mod:`.clearance`)
    :func:`container_length` -- L [m] of a cuboid, or 2R of a cylinder;
    :func:`clearance` -- h = L (1 - N_p/N_p,max), eq. (6).
Scattered state (:mod:`.scattered`)
    :func:`eta_scattered` -- η* = κ X/h, eq. (8);
    :func:`energy_per_cycle_scattered` -- eqs. (4), (7).
Rolling collect-and-collide (:mod:`.rolling`)
    :func:`bed_velocity`, :func:`relative_velocity`, :func:`bed_position` -- eqs. (10), (11);
    :func:`clearance_over_stroke`, :func:`impact_phase_rolling` -- eq. (12) and its inverse;
    :func:`eta_rolling`, :func:`energy_per_cycle_rolling` -- eq. (14), NaN below X_opt;
    :func:`optimal_stroke`, :data:`X_OPT_OVER_H`, :data:`ETA_MAX` -- eqs. (15)-(17);
    :func:`eta_theory` -- the paper's combined curve of Fig. 4 (scattered, then rolling);
    :func:`rolling_mass_ratio` -- the rolling bed's effective mass over its mass (eqs. 10-12).
The damper's fields from the laws (:mod:`.fields`)
    :func:`closed_form_fields` -- eta* and m_eff/m_bed over s = X/X_opt, :data:`SCATTERED_MASS_RATIO`.
The energy balance at a structure's resonance (:mod:`.balance`, beyond the paper)
    :class:`Mode`, :func:`required_force`, :class:`OperatingPoint`, :func:`operating_points` --
    the force that holds the damper at a stroke, every stroke a force holds (the design's search).
The tuned mass damper (:mod:`.tmd`, Den Hartog 1956, Warburton 1982; beyond the paper)
    :func:`den_hartog_tuning`, :func:`den_hartog_damping`, :func:`den_hartog_peak`,
    :func:`den_hartog_equivalent_damping`, :func:`warburton_tuning`, :func:`warburton_damping`,
    :func:`added_mass_detuning` -- what a particle damper is compared with.
Bouncing collect-and-collide (:mod:`.bouncing`, beyond the paper)
    :func:`impact_phase_bouncing`, :func:`eta_bouncing`, :func:`energy_per_cycle_bouncing`,
    :func:`optimal_stroke_bouncing`, :data:`ETA_MAX_BOUNCING`.
Operating bounds (:mod:`.bounds`)
    :func:`angular_frequency`, :func:`velocity_amplitude`, :func:`acceleration_amplitude`,
    :func:`max_stroke_no_liftoff` (A < g), :func:`min_acceleration_tilt`,
    :func:`min_stroke_tilt` (A cos α > g sin α), :data:`GRAVITY`.
Block model (:mod:`.block_model`)
    :func:`integrate_rolling_block` -- the rolling block integrated in time, an oracle for (14).
Wall coatings (:mod:`.coating`, Meyer & Seifried 2023)
    :func:`hertz_contact_time`, :func:`wall_modulus_for_contact_time` -- Hertz's impact on a wall.
Structure without a damper (:mod:`.oscillator`, beyond the paper)
    :func:`natural_frequency`, :func:`free_decay`, :func:`steady_amplitude`,
    :func:`oscillator_response` -- the linear damped oscillator in closed form.

Examples
--------
>>> from pdamper import theory
>>> h = theory.clearance(0.120, 36, 48)
>>> round(theory.optimal_stroke(h) * 1e3, 2), round(theory.ETA_MAX, 4)
(12.23, 0.9095)
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING

# Imported with the package: the function ``clearance`` shares its name with its submodule, and binding it
# here keeps a later ``import pdamper.theory.clearance`` from shadowing it. (numpy only.)
from .clearance import SHAPES, clearance, container_length  # noqa: E402

#: Public name -> submodule that defines it. The other submodules are imported on first use
#: (PEP 562), so ``pdamper --help`` does not load scipy.
_WHERE = {
    "BlockImpact": "block_model", "integrate_rolling_block": "block_model",
    "ETA_MAX_BOUNCING": "bouncing", "energy_per_cycle_bouncing": "bouncing",
    "eta_bouncing": "bouncing", "impact_phase_bouncing": "bouncing",
    "optimal_stroke_bouncing": "bouncing",
    "GRAVITY": "bounds", "TILT_MARGIN": "bounds", "acceleration_amplitude": "bounds", "angular_frequency": "bounds",
    "max_stroke_no_liftoff": "bounds", "min_acceleration_tilt": "bounds",
    "min_stroke_tilt": "bounds", "velocity_amplitude": "bounds",
    "ETA_MAX": "rolling", "X_OPT_OVER_H": "rolling", "bed_position": "rolling",
    "bed_velocity": "rolling", "clearance_over_stroke": "rolling",
    "energy_per_cycle_rolling": "rolling", "eta_rolling": "rolling", "eta_theory": "rolling",
    "impact_phase_rolling": "rolling", "optimal_stroke": "rolling",
    "relative_velocity": "rolling", "rolling_mass_ratio": "rolling",
    "SCATTERED_MASS_RATIO": "fields", "closed_form_fields": "fields",
    "Mode": "balance", "OperatingPoint": "balance", "operating_points": "balance", "required_force": "balance",
    "energy_per_cycle_scattered": "scattered", "eta_scattered": "scattered",
    "HERTZ_TIME_FACTOR": "coating", "hertz_contact_time": "coating",
    "wall_modulus_for_contact_time": "coating",
    "natural_frequency": "oscillator", "free_decay": "oscillator", "steady_amplitude": "oscillator",
    "oscillator_response": "oscillator",
    "den_hartog_tuning": "tmd", "den_hartog_damping": "tmd", "den_hartog_peak": "tmd",
    "den_hartog_equivalent_damping": "tmd", "warburton_tuning": "tmd", "warburton_damping": "tmd",
    "added_mass_detuning": "tmd",
}
_SUBMODULES = frozenset(_WHERE.values())


def __getattr__(name: str):
    if name in _WHERE:
        value = getattr(importlib.import_module(f".{_WHERE[name]}", __name__), name)
    elif name in _SUBMODULES:
        value = importlib.import_module(f".{name}", __name__)
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(__all__))


if TYPE_CHECKING:  # for type checkers; at run time the names load on first use
    from .block_model import BlockImpact, integrate_rolling_block
    from .bouncing import (
        ETA_MAX_BOUNCING,
        energy_per_cycle_bouncing,
        eta_bouncing,
        impact_phase_bouncing,
        optimal_stroke_bouncing,
    )
    from .bounds import (
        GRAVITY,
        TILT_MARGIN,
        acceleration_amplitude,
        angular_frequency,
        max_stroke_no_liftoff,
        min_acceleration_tilt,
        min_stroke_tilt,
        velocity_amplitude,
    )
    from .rolling import (
        ETA_MAX,
        X_OPT_OVER_H,
        bed_position,
        bed_velocity,
        clearance_over_stroke,
        energy_per_cycle_rolling,
        eta_rolling,
        eta_theory,
        impact_phase_rolling,
        optimal_stroke,
        relative_velocity,
        rolling_mass_ratio,
    )
    from .fields import SCATTERED_MASS_RATIO, closed_form_fields
    from .balance import Mode, OperatingPoint, operating_points, required_force
    from .oscillator import free_decay, natural_frequency, oscillator_response, steady_amplitude
    from .scattered import energy_per_cycle_scattered, eta_scattered
    from .tmd import (
        added_mass_detuning,
        den_hartog_damping,
        den_hartog_equivalent_damping,
        den_hartog_peak,
        den_hartog_tuning,
        warburton_damping,
        warburton_tuning,
    )

__all__ = [
    "SHAPES",
    "container_length",
    "clearance",
    "eta_scattered",
    "energy_per_cycle_scattered",
    "X_OPT_OVER_H",
    "ETA_MAX",
    "bed_velocity",
    "relative_velocity",
    "bed_position",
    "clearance_over_stroke",
    "impact_phase_rolling",
    "optimal_stroke",
    "eta_rolling",
    "energy_per_cycle_rolling",
    "eta_theory",
    "rolling_mass_ratio",
    "SCATTERED_MASS_RATIO",
    "closed_form_fields",
    "Mode",
    "required_force",
    "OperatingPoint",
    "operating_points",
    "ETA_MAX_BOUNCING",
    "impact_phase_bouncing",
    "optimal_stroke_bouncing",
    "eta_bouncing",
    "energy_per_cycle_bouncing",
    "GRAVITY",
    "TILT_MARGIN",
    "angular_frequency",
    "velocity_amplitude",
    "acceleration_amplitude",
    "max_stroke_no_liftoff",
    "min_acceleration_tilt",
    "min_stroke_tilt",
    "BlockImpact",
    "integrate_rolling_block",
    "natural_frequency",
    "free_decay",
    "steady_amplitude",
    "oscillator_response",
    "den_hartog_tuning",
    "den_hartog_damping",
    "den_hartog_peak",
    "den_hartog_equivalent_damping",
    "warburton_tuning",
    "warburton_damping",
    "added_mass_detuning",
]
