"""Every public module says what it exports (``__all__``), and says it truly.

A module is public when no part of its name starts with ``_``. Its ``__all__`` lists names
it defines or re-exports; every public name another module of the project imports from it
with ``from module import name`` is among them.
"""

from __future__ import annotations

import ast
import functools
import importlib
import pkgutil
from pathlib import Path

import pytest

PACKAGES = ("clearance.vehicles", "clearance.analysis", "clearance.networks",
            "clearance.reports")
ROOT = Path(__file__).resolve().parents[1]


def public_modules() -> list[str]:
    names = []
    for pkg in PACKAGES:
        package = importlib.import_module(pkg)
        for info in pkgutil.walk_packages(package.__path__, prefix=f"{pkg}."):
            if not info.ispkg and not any(p.startswith("_") for p in info.name.split(".")):
                names.append(info.name)
    return sorted(names) + ["clearance"]


@functools.cache
def project_imports() -> dict[str, dict[str, list[str]]]:
    """Per module, the public names the project's own source files import from it (with
    the files): ``from module import name``."""
    found: dict[str, dict[str, list[str]]] = {}
    for pkg in PACKAGES:
        for path in sorted((ROOT / pkg.removeprefix("clearance.")).rglob("*.py")):
            tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
            if path.name == "__init__.py" and path.parent == ROOT:
                continue
            for node in ast.walk(tree):
                if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    for alias in node.names:
                        if not alias.name.startswith("_"):
                            names = found.setdefault(node.module, {})
                            names.setdefault(alias.name, []).append(
                                str(path.relative_to(ROOT)))
    return found


MODULES = public_modules()


def test_the_packages_have_public_modules() -> None:
    # the walk finds the modules: a broken walk would pass every test below vacuously
    assert {"clearance.vehicles.vehicle", "clearance.analysis.tracking",
            "clearance.networks.reader", "clearance.reports.cli.main"} <= set(
        MODULES)
    assert len(MODULES) > 50


@pytest.mark.parametrize("name", MODULES)
def test_all_lists_defined_public_names(name: str) -> None:
    module = importlib.import_module(name)
    exported = getattr(module, "__all__", None)
    assert isinstance(exported, list | tuple), f"{name} has no __all__"
    assert exported, f"{name}: __all__ is empty"
    assert all(isinstance(n, str) for n in exported), name
    assert len(set(exported)) == len(exported), f"{name}: a name twice in __all__"
    missing = [n for n in exported if not hasattr(module, n)]
    assert not missing, f"{name}: __all__ names what it does not define: {missing}"
    private = [n for n in exported if n.startswith("_")]
    assert not private, f"{name}: __all__ names private names: {private}"


@pytest.mark.parametrize("name", MODULES)
def test_all_covers_what_the_project_imports(name: str) -> None:
    module = importlib.import_module(name)
    exported = set(getattr(module, "__all__", ()))
    absent = {n: files for n, files in project_imports().get(name, {}).items() if n not in exported}
    assert not absent, f"{name}: imported from it but not in its __all__: {absent}"



def test_import_clearance_gives_the_public_api_lazily() -> None:
    import subprocess
    import sys

    code = ("import sys, clearance; heavy = [m for m in ('pandas', 'shapely', 'libsumo') "
            "if m in sys.modules]; print(heavy); "
            "t = clearance.load_tables(clearance.bundled_table_paths()); "
            "print(len(t.vehicles()) > 10, clearance.run_study.__module__, "
            "issubclass(clearance.NetworkError, clearance.InputError))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split("\n")
    assert out[0] == "[]"  # nothing heavy until a name is used
    assert out[1] == "True clearance.reports.study.run True"
