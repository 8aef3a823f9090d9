"""Fixtures for network tests: SUMO's netconvert and small networks built in tmp dirs."""

from __future__ import annotations

from pathlib import Path

import pytest

from clearance.networks.sumo.tools import find_sumo_binary, netconvert_plain

GAME_DIR_PARTS = ("tools", "game")


@pytest.fixture(scope="session")
def netconvert() -> Path:
    try:
        return find_sumo_binary("netconvert")
    except FileNotFoundError as exc:  # pragma: no cover - depends on the install
        pytest.skip(f"netconvert is not available: {exc}")


@pytest.fixture()
def build_net(tmp_path: Path, netconvert: Path):
    """Build a network from plain-XML strings: ``build_net(nodes, edges, cons=None, *opts)``."""

    def build(
        nodes: str, edges: str, connections: str | None = None, *options: str, name: str = "t"
    ) -> Path:
        return netconvert_plain(
            tmp_path,
            name,
            nodes=f"<nodes>{nodes}</nodes>",
            edges=f"<edges>{edges}</edges>",
            connections=f"<connections>{connections}</connections>" if connections else None,
            options=list(options),
        )

    return build


@pytest.fixture(scope="session")
def small_grid(tmp_path_factory, netconvert: Path) -> Path:
    """A 5 x 5 grid of two-lane streets (netgenerate, as the benchmark's 100 x 100 one)."""
    from clearance.networks.sumo.tools import run_sumo_tool

    path = tmp_path_factory.mktemp("grid") / "grid5.net.xml"
    run_sumo_tool("netgenerate", ["--grid", "--grid.number", "5", "--default.lanenumber", "2",
                                  "-o", str(path)])
    return path
