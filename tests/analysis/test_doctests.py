"""Every example in the analysis docstrings runs and gives what it shows."""

from __future__ import annotations

import doctest
import importlib

import pytest

MODULES = [
    "analysis.kinematics",
    "analysis.trailer",
    "analysis.polyline",
    "analysis.tracking",
    "analysis.envelope",
    "analysis.clearance",
]


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name: str) -> None:
    module = importlib.import_module(name)
    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    failures, tried = doctest.testmod(module, optionflags=flags)
    assert tried > 0, f"{name} has no examples"
    assert failures == 0
