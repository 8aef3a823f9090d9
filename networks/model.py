"""The network as this tool holds it: lanes, edges, connections, junctions, roundabouts.

:func:`clearance.networks.reader.read_network` fills a :class:`Network` from a ``.net.xml``;
everything else reads it. Only what curve extraction, the areas and the exports need is kept (lanes
with 3-D shapes as numpy arrays, connections as named tuples), with SUMO's vehicle classes and
lane width defaults.

Example
-------
>>> lane = Lane("a_0", "a", 0, 3.2, "normal", resolve_allowed(None, "pedestrian"),
...             np.zeros((2, 3)), 10.0, 13.9)
>>> lane.allows_road_vehicles(), lane.is_internal
(True, False)
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path
from typing import NamedTuple

import numpy as np

__all__ = ["Connection", "DEFAULT_LANE_WIDTH_M", "Edge", "Junction", "Lane", "Location",
           "MAX_LANE_WIDTH_M", "Network", "ROAD_VCLASSES", "Roundabout", "SUMO_VCLASSES",
           "new_connection", "resolve_allowed"]

#: SUMO's lane width when a lane has none (``SUMO_const_laneWidth``).
DEFAULT_LANE_WIDTH_M = 3.2

#: The widest lane accepted, in metres. Road lanes are 2.5-4.5 m wide and netconvert's
#: widest defaults (sidewalks, wide shoulders, OSM squares mapped as one lane) stay well under
#: 20 m; a lane of 50 m or more is a broken file, not a road. A width must also be > 0.
MAX_LANE_WIDTH_M = 50.0

#: Every SUMO vehicle class (``allow="all"`` means these).
SUMO_VCLASSES = frozenset(
    (
        "private emergency authority army vip pedestrian passenger hov taxi bus coach delivery "
        "truck trailer motorcycle moped bicycle evehicle tram rail_urban rail rail_electric "
        "rail_fast ship container cable_car subway aircraft wheelchair scooter drone custom1 "
        "custom2"
    ).split()
)

#: Classes whose lanes carry the vehicles this tool checks.
ROAD_VCLASSES = frozenset(("passenger", "bus", "truck", "coach", "delivery", "trailer"))


@dataclass(slots=True)
class Lane:
    """One lane: ``shape`` is an (N, 3) array of x, y, z in metres (z = 0 where absent)."""

    id: str
    edge: str
    index: int
    width_m: float
    function: str
    allowed: frozenset[str]
    shape: np.ndarray
    length_m: float
    speed_mps: float
    #: True when the file gives the lane's ``width``; False when SUMO's default is taken
    #: (netconvert writes a width only where its input had one:
    #: :mod:`clearance.networks.provenance`).
    width_given: bool = True

    @property
    def is_internal(self) -> bool:
        """True for a junction-internal lane (``function="internal"``)."""
        return self.function == "internal"

    def allows_road_vehicles(self) -> bool:
        """True when passenger cars, buses or trucks may use the lane."""
        return not self.allowed.isdisjoint(ROAD_VCLASSES)


@dataclass(slots=True)
class Edge:
    """One edge; ``lanes`` lists its lane ids by index (rightmost first)."""

    id: str
    from_junction: str
    to_junction: str
    function: str
    priority: int
    lanes: list[str] = field(default_factory=list)


class Connection(NamedTuple):
    """A link from one lane to another, through ``via`` (the first internal lane) if any.

    A named tuple: a large network has hundreds of thousands, made from parsed rows in
    one C-level call each.
    """

    from_edge: str
    to_edge: str
    from_lane_index: int
    to_lane_index: int
    via: str | None
    direction: str

    @property
    def from_lane(self) -> str:
        """Id of the lane the connection leaves."""
        return f"{self.from_edge}_{self.from_lane_index}"

    @property
    def to_lane(self) -> str:
        """Id of the lane the connection enters."""
        return f"{self.to_edge}_{self.to_lane_index}"


#: A :class:`Connection` from a row of its six fields (``tuple.__new__`` in C, without the
#: Python-level checks of ``Connection._make``: the rows come from the reader).
new_connection = partial(tuple.__new__, Connection)


@dataclass(slots=True)
class Junction:
    """A junction: its position and its polygon (``shape``, (N, 3), may be empty)."""

    id: str
    type: str
    x: float
    y: float
    z: float
    shape: np.ndarray
    inc_lanes: tuple[str, ...]
    int_lanes: tuple[str, ...]
    #: ``customShape="1"``: the polygon was drawn by someone, not computed by netconvert.
    custom_shape: bool = False
    #: The corner radius the file gives (``radius``, m); NaN when netconvert's default applies.
    radius_m: float = float("nan")


@dataclass(frozen=True, slots=True)
class Roundabout:
    """A ``<roundabout>`` element: its ring junctions and ring edges."""

    nodes: tuple[str, ...]
    edges: tuple[str, ...]


@dataclass(frozen=True, slots=True)
class Location:
    """The ``<location>`` element: offsets and boundaries in metres."""

    net_offset: tuple[float, float] = (0.0, 0.0)
    conv_boundary: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    orig_boundary: tuple[float, float, float, float] = (0.0, 0.0, 0.0, 0.0)
    proj_parameter: str = "!"


@dataclass
class Network:
    """The geometry of a SUMO network as read by :func:`read_network`."""

    path: Path
    lanes: dict[str, Lane]
    edges: dict[str, Edge]
    connections: list[Connection]
    junctions: dict[str, Junction]
    roundabouts: list[Roundabout]
    location: Location
    #: What was left out or repaired while reading, in words naming each element
    #: (:mod:`clearance.networks.integrity`): what SUMO loads but no vehicle can be judged on.
    repairs: list[str] = field(default_factory=list)
    #: Lane shape points whose lone height was repaired (:mod:`clearance.networks.elevation`): notes
    #: naming lane and point, by lane id.
    suspect_heights: dict[str, list[str]] = field(default_factory=dict)
    _out: dict[str, list[Connection]] | None = field(default=None, repr=False)
    _in: dict[str, list[Connection]] | None = field(default=None, repr=False)
    _clean: dict[str, tuple[np.ndarray, float]] = field(default_factory=dict, repr=False)
    #: Lane shapes cut into short pieces, by (lane id, step):
    #: :func:`clearance.networks.stacking.densified`.
    dense: dict[tuple[str, float], np.ndarray] = field(default_factory=dict, repr=False)

    def lane_line(self, lane_id: str) -> tuple[np.ndarray, float]:
        """A lane's shape without repeated points, and its plane length (cached)."""
        hit = self._clean.get(lane_id)
        if hit is None:
            pts = self.lanes[lane_id].shape
            d = pts[1:, :2] - pts[:-1, :2]
            step = np.hypot(d[:, 0], d[:, 1])
            if len(step) and step.min() <= 1e-6:
                pts = pts[np.concatenate(([True], step > 1e-6))]
            hit = self._clean[lane_id] = (pts, float(step.sum()))
        return hit

    @property
    def has_internal_lanes(self) -> bool:
        """True when the network was built with junction-internal lanes."""
        return any(c.via for c in self.connections)

    def outgoing(self, lane_id: str) -> list[Connection]:
        """Connections leaving lane ``lane_id`` (also from internal lanes)."""
        if self._out is None:
            self._out = self._index(0)
        return self._out.get(lane_id, [])

    def incoming(self, lane_id: str) -> list[Connection]:
        """Connections entering lane ``lane_id`` (also into internal lanes)."""
        if self._in is None:
            self._in = self._index(1)
        return self._in.get(lane_id, [])

    def _index(self, end: int) -> dict[str, list[Connection]]:
        """The connections by the lane they leave (``end`` 0) or enter (1); each index is
        made when first asked for (extracting turns needs only the first)."""
        index: dict[str, list[Connection]] = defaultdict(list)
        edge, lane = end, end + 2  # the lane ids as the from_lane / to_lane properties make them
        for c in self.connections:
            index[f"{c[edge]}_{c[lane]}"].append(c)
        return dict(index)


_ALLOW_CACHE: dict[tuple[str | None, str | None], frozenset[str]] = {}


def resolve_allowed(allow: str | None, disallow: str | None) -> frozenset[str]:
    """The vehicle classes a lane admits, from its ``allow`` and ``disallow`` attributes.

    Examples
    --------
    >>> sorted(resolve_allowed("bus passenger", None))
    ['bus', 'passenger']
    >>> "pedestrian" in resolve_allowed(None, "pedestrian")
    False
    >>> resolve_allowed(None, "all")
    frozenset()
    """
    key = (allow, disallow)
    hit = _ALLOW_CACHE.get(key)
    if hit is not None:
        return hit
    if allow is not None:
        words = set(allow.split())
        result = set(SUMO_VCLASSES) if "all" in words else words
    else:
        result = set(SUMO_VCLASSES)
    if disallow is not None:
        words = set(disallow.split())
        result = set() if "all" in words else result - words
    frozen = frozenset(result)
    _ALLOW_CACHE[key] = frozen
    return frozen
