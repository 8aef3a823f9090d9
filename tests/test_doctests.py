"""Every example in every module's docstrings runs and gives what it shows."""

from __future__ import annotations

import doctest
import importlib
import pkgutil

import pytest

PACKAGES = ("clearance.vehicles", "clearance.analysis", "clearance.networks",
            "clearance.reports")


def modules() -> list[str]:
    names = ["clearance"]
    for pkg in PACKAGES:
        module = importlib.import_module(pkg)
        for info in pkgutil.walk_packages(module.__path__, prefix=f"{pkg}."):
            names.append(info.name)
    return sorted(names)


@pytest.mark.parametrize("name", modules())
def test_docstring_examples(name: str) -> None:
    module = importlib.import_module(name)
    flags = doctest.NORMALIZE_WHITESPACE | doctest.ELLIPSIS
    failures, _tried = doctest.testmod(module, optionflags=flags)
    assert failures == 0


def test_the_geometry_modules_have_examples() -> None:
    for name in ("clearance.vehicles.steering",
                 "clearance.vehicles.lock",
                 "clearance.analysis.turning",
                 "clearance.analysis.control_law",
                 "clearance.analysis.kinematics",
                 "clearance.analysis.polyline",
                 "clearance.analysis.envelope",
                 "clearance.analysis.clearance",
                 "clearance.analysis.levels",
                 "clearance.networks.geometry",
                 "clearance.networks.driving.analytic",
                 "clearance.reports.documents.templates"):
        finder = doctest.DocTestFinder()
        tests = finder.find(importlib.import_module(name))
        assert sum(len(t.examples) for t in tests) > 0, name
