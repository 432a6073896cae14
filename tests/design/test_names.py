"""The design names its parameters in its messages, the CLI its options (pdamper.design.names)."""

import pytest
from click.testing import CliRunner

from pdamper.cli.common import main
from pdamper.cli.design import design_option
from pdamper.design import design_filling, design_for_structure, naming, verify_factors
from pdamper.errors import InputError

from design_helpers import FRAME, frame


def test_the_library_names_its_parameters_and_the_cli_its_options():
    cases = [
        (lambda: verify_factors(0), "strokes = 0", "--verify-strokes = 0"),
        (lambda: design_for_structure(frame(), force=1.5, particles=(40, 30)), "particles 40:30", "--particles 40:30"),
        (lambda: design_for_structure(frame(), force=1.5, length_range=(0.2, 0.08)), "length_range 200mm:80mm",
         "--length 200mm:80mm"),
        (lambda: design_for_structure(frame(), force=1.5, max_bed_mass=0.001),
         "raise max_bed_mass / max_mass_ratio or use smaller spheres (sphere_radius)",
         "raise --max-bed-mass / --max-mass-ratio or use smaller spheres (--sphere-radius)"),
        (lambda: design_filling(frequency=2.0, stroke=0.01, sphere_radius=0.005, shape="cylinder",
                                sizes={"height": -1.0}), "sizes['height'] = -1.0 m", "--size height=VALUE = -1.0 m"),
    ]
    for call, library, cli in cases:
        with pytest.raises(InputError) as own:
            call()
        assert library in str(own.value) and "--" not in str(own.value), str(own.value)
        with naming(design_option), pytest.raises(InputError) as said:
            call()
        assert cli in str(said.value), str(said.value)
    with pytest.raises(InputError) as after:  # the naming ends with its block
        verify_factors(0)
    assert "--" not in str(after.value)


def test_the_command_speaks_of_its_options():
    r = CliRunner().invoke(main, ["design", "--structure", str(FRAME), "--force", "1.5N", "--max-bed-mass", "1g"])
    assert r.exit_code == 2 and "raise --max-bed-mass / --max-mass-ratio" in r.output, r.output
