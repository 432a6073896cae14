"""The design workflow: which particle damper for a vibrating structure, and does it hold in the DEM.

One module per idea (docs/structure.md, "Design for a structure"; docs/architecture.md):

- :mod:`.filling` -- the filling for a stroke: :func:`design_filling` (the N_p that puts a stroke
  at X_opt, eqs. 6, 17 inverted), :func:`check_fits`; the margin a design keeps above X_opt
  (:data:`MARGIN_TABLE`, :func:`auto_margin`, :func:`margin_note`);
- :mod:`.search` -- the structure search: :func:`design_for_structure` (the filling and container
  length for a mode under a harmonic force, from the energy balance at resonance with the paper's
  closed forms, :mod:`pdamper.theory.fields` and :mod:`pdamper.theory.balance`), its
  :class:`StructureDesign`, :func:`structure_mode`;
- :mod:`.verify` -- the DEM check and its verdict: :func:`verify_design` (a design for a
  structure: a :class:`Verification`), :func:`verify_filling` (a filling for a stroke),
  :func:`judge_verification`;
- :mod:`.case` -- the case: :func:`load_structure` (a structure file, read by
  :func:`pdamper.config.load_case`), :func:`design_for_case`, :func:`design_case` and
  :func:`design_case_text` (the design written as one runnable case);
- :mod:`.transient` -- the design against a load in time: :func:`design_for_load` (candidates
  screened by the closed-form fields in the structure's equations in time, the lightest expected to
  meet the targets checked by coupled DEM transients), its :class:`TransientDesign`,
  :func:`load_design_case` and :func:`load_design_text` (the design with its load, one case);
- :mod:`.several` -- one damper per mode: :func:`design_for_modes` (a damper for each of several
  modes at the structure's damper points), :func:`design_case_several` (them as one case with a
  ``[[damper]]`` each);
- :mod:`.robust` -- the robust design against a load in time: :func:`design_robust` (the lightest
  filling whose targets hold in a given share of an ensemble over the unknowns: the candidates
  screened at every sample, the lightest expected to reach the share run as DEM ensembles at the
  same samples), its :class:`RobustDesign` and :class:`RobustCheck` (the share with its Wilson
  interval, the ratios' percentiles, the unknowns that drive the failures), :func:`robust_design_text`
  (the design with its load, one case);
- :mod:`.names` -- how its messages name its parameters (:func:`naming`: the CLI's options).

The closed forms it rests on (:func:`rolling_mass_ratio`, :func:`closed_form_fields`,
:func:`required_force`, :func:`operating_points`, :class:`Mode`) live in :mod:`pdamper.theory`
and are named here too.
"""

from __future__ import annotations

from ..theory.balance import Mode, OperatingPoint, operating_points, required_force
from ..theory.fields import SCATTERED_MASS_RATIO, closed_form_fields
from ..theory.rolling import rolling_mass_ratio
from .case import design_case, design_case_text, design_container, design_for_case, load_structure
from .filling import (MARGIN_MEASURED, MARGIN_TABLE, MARGINAL, MIN_ROWS, TILT_MARGIN, Design, auto_margin,
                      check_fits, design_filling, margin_note, most_spheres)
from .names import naming
from .robust import RobustCheck, RobustDesign, design_robust, robust_design_text
from .search import StructureDesign, design_for_structure, structure_mode
from .transient import (TransientCheck, TransientDesign, check_candidate, design_for_load, load_design_case,
                        load_design_text, measured_reasons, screen_candidates)
from .several import SeveralDesign, design_case_several, design_for_modes
from .verify import (ROLLING_MODE, VERIFY_REACH, FillingCheck, RigSweep, Verification, judge_verification,
                     rig_case, rig_sweep, verify_design, verify_factors, verify_filling)

__all__ = ["Design", "design_filling", "design_container", "check_fits", "most_spheres", "margin_note", "TILT_MARGIN", "MIN_ROWS",
           "MARGINAL", "MARGIN_TABLE", "MARGIN_MEASURED", "auto_margin", "Mode", "structure_mode",
           "rolling_mass_ratio", "closed_form_fields", "SCATTERED_MASS_RATIO", "required_force", "OperatingPoint",
           "operating_points", "StructureDesign", "design_for_structure", "design_for_case", "load_structure",
           "verify_factors", "judge_verification", "ROLLING_MODE", "VERIFY_REACH", "verify_design", "verify_filling",
           "Verification", "FillingCheck", "RigSweep", "rig_case", "rig_sweep", "design_case", "design_case_text",
           "naming", "TransientDesign", "TransientCheck", "design_for_load", "screen_candidates", "check_candidate",
           "measured_reasons", "load_design_case", "load_design_text",
           "SeveralDesign", "design_for_modes", "design_case_several", "RobustDesign", "RobustCheck", "design_robust",
           "robust_design_text"]
