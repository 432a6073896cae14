"""The public API: every name in ``pdamper.__all__`` resolves, and ``import pdamper`` stays light."""

from __future__ import annotations

import importlib
import inspect
import re
import subprocess
import sys
import types

import pytest

import pdamper

CORE = ["Case", "ParticleSet", "Container", "ContactModel", "Numerics", "Recording", "InitialState",
        "Cuboid", "Cylinder", "HarmonicDrive", "SampledDrive", "Still", "Material", "STEEL_S235",
        "PVC", "ConstantRestitution", "TabulatedRestitution", "ThorntonRestitution", "Simulation",
        "RunResult", "run_case", "load_case", "complex_power", "analyze_record", "theory",
        "InputError", "SimulationError", "parse_quantity"]


@pytest.mark.parametrize("name", pdamper.__all__)
def test_every_public_name_is_the_object_of_its_module(name):
    obj = getattr(pdamper, name)
    if name == "__version__":
        assert re.fullmatch(r"\d+\.\d+\S*", obj), obj
        return
    assert name in dir(pdamper)
    module = pdamper._LAZY.get(name, "")
    if module is None:  # a submodule
        assert obj is importlib.import_module(f"pdamper.{name}")
    else:  # lazy (from _LAZY) or imported with the package
        owner = importlib.import_module(f"pdamper.{module}") if module else inspect.getmodule(obj)
        assert owner.__name__.startswith("pdamper.")
        assert getattr(owner, name) is obj


def test_the_core_objects_are_public_and_documented():
    for name in CORE:
        assert name in pdamper.__all__, name
        assert name in pdamper.__doc__, name


def test_names_are_the_objects_of_their_modules():
    from pdamper import analysis, config, materials, params, run, simulation, theory

    assert pdamper.Case is params.Case
    assert pdamper.STEEL_S235 is materials.STEEL_S235
    assert pdamper.run_case is run.run_case
    assert pdamper.Simulation is simulation.Simulation
    assert pdamper.load_case is config.load_case
    assert pdamper.complex_power is analysis.complex_power
    assert inspect.isfunction(pdamper.complex_power)
    assert isinstance(pdamper.theory, types.ModuleType) and pdamper.theory is theory
    assert callable(pdamper.theory.clearance)


def test_unknown_attribute_is_an_attribute_error():
    with pytest.raises(AttributeError, match="no attribute 'Nope'"):
        pdamper.Nope  # noqa: B018


def test_star_import_gives_all():
    ns: dict = {}
    exec("from pdamper import *", ns)
    assert set(pdamper.__all__) <= set(ns)


def test_import_is_light():
    """``import pdamper`` (and the CLI's --help) must not load numba, scipy, matplotlib or pint."""
    code = ("import sys, pdamper, pdamper.cli; "
            "print(sorted(m for m in ('numba', 'scipy', 'matplotlib', 'pint', 'xarray') "
            "if m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_theory_submodule_names_survive_lazy_loading():
    code = ("import pdamper.theory.clearance, pdamper.theory.rolling; from pdamper import theory; "
            "assert callable(theory.clearance) and callable(theory.optimal_stroke); "
            "assert theory.rolling.X_OPT_OVER_H == theory.X_OPT_OVER_H; print('ok')")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert out.stdout.strip() == "ok", out.stderr
