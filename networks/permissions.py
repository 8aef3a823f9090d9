"""Which vehicle classes may drive a curve: SUMO's ``allow``/``disallow`` on the lanes that
decide it (docs/design.md §6). A vehicle is checked only on curves its class may use; the
others are "not permitted", never a failure.
"""

from __future__ import annotations

from typing import Protocol

from clearance.networks.model import Network

__all__ = ["permits", "permitted_lanes"]


class _Laned(Protocol):
    lanes: tuple[str, ...]
    core_lanes: tuple[str, ...]


def permitted_lanes(curve: _Laned) -> tuple[str, ...]:
    """The lanes whose permissions decide whether a vehicle may drive a curve: the
    feature's lanes with the lane just before and just after them (a turn's approach
    lane, internal lanes and exit lane). Lanes further along the lead-in and run-out
    belong to the neighbouring curves.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> permitted_lanes(NS(lanes=("a", "b", ":J_0_0", "c", "d"), core_lanes=(":J_0_0",)))
    ('b', ':J_0_0', 'c')
    >>> permitted_lanes(NS(lanes=("e_0",), core_lanes=("e_0",)))
    ('e_0',)
    """
    lanes, core = curve.lanes, curve.core_lanes
    if not core:
        return tuple(lanes)
    n = len(core)
    for i in range(len(lanes) - n + 1):
        if lanes[i : i + n] == core:
            return tuple(lanes[max(i - 1, 0) : i + n + 1])
    return tuple(core)


def permits(net: Network, curve: _Laned, vclass: str) -> bool:
    """Whether SUMO's ``allow``/``disallow`` let vehicles of class ``vclass`` drive the
    curve: every lane of :func:`permitted_lanes` admits it (a lane the network does not
    know is taken as admitting it)."""
    lanes = net.lanes
    return all(k not in lanes or vclass in lanes[k].allowed for k in permitted_lanes(curve))
