"""Fixtures shared by the reports tests."""

from __future__ import annotations

import pytest


@pytest.fixture
def bus_street_net(tmp_path):
    """A T junction X whose west arm WX admits buses only (``allow="bus"``), with two
    one-lane streets SX and XN open to all: a car may drive S->N, only a bus W->N."""
    from clearance.networks.sumo.tools import netconvert_plain

    try:
        return netconvert_plain(
            tmp_path, "bus",
            nodes=('<nodes><node id="W" x="-60" y="0"/><node id="X" x="0" y="0" '
                   'type="priority"/><node id="N" x="0" y="60"/><node id="S" x="0" y="-60"/>'
                   '</nodes>'),
            edges=('<edges><edge id="WX" from="W" to="X" numLanes="1" allow="bus"/>'
                   '<edge id="SX" from="S" to="X" numLanes="1"/>'
                   '<edge id="XN" from="X" to="N" numLanes="1"/></edges>'),
            options=["--no-turnarounds"])
    except FileNotFoundError as exc:  # pragma: no cover - depends on the install
        pytest.skip(f"netconvert is not available: {exc}")
