"""The shared base of the structures (pdamper.structure.base) changed no written config: a result
store made by pdamper 8500ec3 (before the structures had a package and a base) on a structure
case re-opens with this code, with the same fingerprint, and resumes.

The two ``store.json`` files in ``data/`` were written by 8500ec3's ``ResultStore.create_or_open``
for a friction sweep (0.1, 0.2; seed 0) over ``examples/structure_36.toml`` and
``examples/mast_modal.toml`` (their config text is the one the fingerprint was taken of)."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import pytest

from pdamper.config import case_to_dict, dumps_case, load_case, loads_case
from pdamper.structure import CoupledStructure, ModalStructure, StructureBase
from pdamper.studies.store import ResultStore
from pdamper.studies.sweep import Axis, SweepSpec

ROOT = Path(__file__).resolve().parents[2]
DATA = Path(__file__).resolve().parent / "data"


def _spec(name):
    case = load_case(ROOT / "examples" / f"{name}.toml")
    return SweepSpec(base=case, axes=[Axis(key="contact.friction", values=(0.1, 0.2), spacing="list")], seeds=(0,))


@pytest.mark.parametrize("name", ["structure_36", "mast_modal"])
def test_a_store_of_8500ec3_reopens_with_its_fingerprint_and_resumes(tmp_path, name):
    old = json.loads((DATA / f"store_8500ec3_{name}.json").read_text())
    store = tmp_path / "store"
    (store / "cases").mkdir(parents=True)
    (store / "store.json").write_text(json.dumps(old))
    spec = _spec(name)
    reopened = ResultStore.create_or_open(store, spec)  # a different fingerprint would be refused
    assert reopened.meta["fingerprint"] == old["fingerprint"]
    body = lambda text: [ln for ln in text.splitlines() if not ln.startswith("#")]  # noqa: E731
    assert body(reopened.meta["config"]) == body(old["config"])
    assert reopened.records() == []  # nothing ran: every point is still to do, the sweep resumes there
    assert loads_case(old["config"]).drive == spec.base.drive  # the stored text reads back into the structure


def test_the_models_own_fields_come_first_then_the_shared_ones():
    shared = [f.name for f in dataclasses.fields(StructureBase)]
    for cls in (CoupledStructure, ModalStructure):
        names = [f.name for f in dataclasses.fields(cls)]
        own = [n for n in names if n not in shared and n != "kind"]
        assert names == own + shared + ["kind"], cls.__name__
    s = load_case(ROOT / "examples" / "structure_36.toml")
    written = list(case_to_dict(s)["structure"])
    assert written[:3] == ["mass", "stiffness", "damping_ratio"] and list(case_to_dict(s))[-1] == "structure"
    assert "kind" not in written  # a [structure] tells its model by its keys
    assert dumps_case(s).count("[structure]") == 1
