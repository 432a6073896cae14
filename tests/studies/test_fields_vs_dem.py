"""The response from the fields against the direct DEM response on the two-mode mast (issue 22,
item 5 at CI size; docs/structure.md, "Fields against DEM").

tests/studies/data/fields_36_mast.nc: the fields of examples/cuboid_36.toml from
``pdamper sweep examples/cuboid_36.toml --vary drive.stroke=0.8mm:45mm:16 --vary
drive.frequency=1.85Hz:2.15Hz:5 --seeds 2`` then ``pdamper fields`` (Gear, 20 cycles per case).
"""

from pathlib import Path

import pytest

from pdamper.config import load_case
from pdamper.studies.fields import load_fields
from pdamper.studies.structure import run_response, run_response_fields

ROOT = Path(__file__).resolve().parents[2]
MAST = ROOT / "examples" / "mast_modal.toml"
FIELDS = Path(__file__).parent / "data" / "fields_36_mast.nc"


@pytest.mark.parametrize("force, frequency", [(0.21, 2.0), (0.4, 2.0)], ids=["near X_opt", "above X_opt"])
def test_fields_within_15_percent_of_the_direct_dem_on_the_two_mode_mast(force, frequency):
    case = load_case(MAST, {"numerics.integrator": "gear", "run.cycles": 12})
    fields = load_fields(FIELDS)
    pred = run_response_fields(case, [frequency], fields, force_amplitude=force)
    (x_fields,) = pred.summary["damper_amplitude_m"]  # one stable solution at these points
    dem = run_response(case, [frequency], force_amplitude=force, measure_cycles=4, start="fields", fields=fields,
                       progress=False)
    assert dem.summary["steady"] == [True]
    assert dem.damped[0] == pytest.approx(x_fields, rel=0.15)
    assert dem.damped[0] < 0.7 * pred.summary["resonance_bare_m"]  # and the damper does damp (bare: 16 / 31 mm)
