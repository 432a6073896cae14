"""The OpenSees model reader joins the fuzz suite (tests/fuzz_helpers.py): a model file damaged,
random bytes, any file name -- one clear InputError line or a model read; never a traceback, never
a hang (the child process under a 4 s limit here). Skipped, one line, where openseespy does not load."""

from __future__ import annotations

import pytest

from fuzz_helpers import Reader, reader_tests
from pdamper.structure.opensees import available, read_model

pytestmark = pytest.mark.skipif(available() is not None, reason=f"openseespy does not load here: {available()}")

MODEL = b"""import openseespy.opensees as ops

ops.wipe()
ops.model("basic", "-ndm", 1, "-ndf", 1)
ops.node(0, 0.0)
ops.fix(0, 1)
for i in (1, 2):
    ops.node(i, 0.0)
    ops.mass(i, 2.0)
    ops.uniaxialMaterial("Elastic", i, 3000.0)
    ops.element("zeroLength", i, i - 1, i, "-mat", i, "-dir", 1, "-doRayleigh", 1)
ops.rayleigh(0.1, 0.0, 0.0, 0.001)
"""


def _read(path):
    model = read_model(path, damper_nodes=[2], timeout=4.0)
    return model


def _check(model):
    assert model.M.shape == (2, 2) and model.nonlinear == ()


OPENSEES = Reader(name="OpenSees model file (.py)", suffix=".py", good=lambda folder: MODEL, read=_read, check=_check)
TestOpenSeesModel = reader_tests(OPENSEES)
