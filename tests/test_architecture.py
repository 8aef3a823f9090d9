"""The house rules of docs/design.md §2, checked on the source: data flows vehicles ->
analysis -> networks -> reports, no module imports another in a circle (counting imports
inside functions and those made only for type checkers), every import of ours goes through
the package ``clearance``, libsumo has one home, and no function runs over 80 lines."""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LAYERS = ("vehicles", "analysis", "networks", "reports")


def _modules() -> dict[str, Path]:
    out = {}
    for layer in LAYERS:
        for p in (ROOT / layer).rglob("*.py"):
            name = ".".join(("clearance",) + p.relative_to(ROOT).with_suffix("").parts)
            out[name.removesuffix(".__init__")] = p
    return out


def _imports(path: Path, known: set[str]) -> set[str]:
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module] + [f"{node.module}.{a.name}" for a in node.names]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        found.update(n for n in names if n in known)
    return found


def _graph() -> dict[str, set[str]]:
    mods = _modules()
    return {m: _imports(p, set(mods)) - {m} for m, p in mods.items()}


def _circles(graph: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    out: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in graph:
        if v not in index:
            visit(v)
    return out


def test_the_scan_finds_a_circle_where_there_is_one():
    assert _circles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert _circles({"a": {"b"}, "b": set()}) == []


def test_no_module_imports_another_in_a_circle():
    assert _circles(_graph()) == []


def test_data_flows_from_vehicles_to_reports_only():
    rank = {layer: i for i, layer in enumerate(LAYERS)}
    upstream = [(a, b) for a, targets in _graph().items() for b in targets
                if rank[b.split(".")[1]] > rank[a.split(".")[1]]]
    assert upstream == []


def test_only_the_sumo_session_imports_libsumo_or_traci():
    found = set()
    for name, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            mods = ([a.name for a in node.names] if isinstance(node, ast.Import)
                    else [node.module or ""] if isinstance(node, ast.ImportFrom) else [])
            if any(m.split(".")[0] in ("libsumo", "traci") for m in mods):
                found.add(name)
    assert found == {"clearance.networks.sumo.session"}


def test_driving_a_run_has_one_home():
    driving = {n.rsplit(".", 1)[1] for n in _modules() if n.startswith(
        "clearance.networks.driving.")}
    assert {"runs", "candidates", "shapes", "refine", "room", "swing", "drive",
            "analytic"} <= driving


def test_every_import_of_our_packages_goes_through_clearance():
    """A bare ``import vehicles`` would load a second copy of a module beside
    ``clearance.vehicles`` (and only works from the repository's folder)."""
    bare = []
    for name, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            mods = ([a.name for a in node.names] if isinstance(node, ast.Import)
                    else [node.module or ""] if isinstance(node, ast.ImportFrom)
                    and node.level == 0 else [])
            bare += [(name, m) for m in mods if m.split(".")[0] in LAYERS]
    assert bare == []


#: A function body longer than this is split where its steps part; a numba kernel that must
#: stay one piece says so in its docstring (``must be one piece``).
MAX_FUNCTION_LINES = 80


def _long_functions() -> dict[str, int]:
    long = {}
    for name, path in _modules().items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                continue
            doc = ast.get_docstring(node) or ""
            first = node.body[1] if doc and len(node.body) > 1 else node.body[0]
            lines = (node.end_lineno or first.lineno) - first.lineno + 1
            if lines > MAX_FUNCTION_LINES and "must be one piece" not in doc:
                long[f"{name}.{node.name}"] = lines
    return long


def test_no_function_is_over_80_lines():
    assert _long_functions() == {}
