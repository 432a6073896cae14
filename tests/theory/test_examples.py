"""The docstring examples of pdamper.theory run and give what they show."""

import doctest
import importlib

import pytest

MODULES = ["", ".clearance", ".scattered", ".rolling", ".bouncing", ".bounds", ".block_model", ".fields", ".balance"]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name):
    module = importlib.import_module("pdamper.theory" + name)
    result = doctest.testmod(module, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
