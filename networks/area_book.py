"""Curve areas built on demand, a batch of curves at a time, with a bound on what is kept.

The three areas of every curve of a large network do not fit in memory beside the network
and its curves (the 10,000-junction grid's 196,408 curves hold about 1.5 GB of polygons),
and most uses need few of them at a time (``clearance curves`` needs none; a simulation
needs those of its batch of runs). :func:`clearance.networks.curves.extract_curves` therefore gives
its curves an :class:`AreaBook`: the first time a curve's ``own_lanes``, ``roadway`` or
``paved`` is read, the areas of its whole batch (:data:`BATCH_CURVES` consecutive curves,
never splitting a junction's curves) are built together with
:func:`clearance.networks.areas.build_areas`, and the curves keep them until the book releases the
batch. The book keeps at most :data:`MAX_BATCHES` batches: building one more releases the
one built first. A released curve builds its batch again when asked (the same geometry:
a batch's unions do not depend on what else is built). An area a caller still holds stays
valid; the book only drops its own references.

Curves are in kind then id order, so a junction's turns are consecutive and a sweep over
the curves in that order builds each batch once.

**Levels** (docs/design.md §6, :mod:`clearance.analysis.levels`,
:mod:`clearance.networks.stacking`). A curve
some of whose parts lie over or under another part of the network (a helix, a garage, a
flyover) gets level segments (:func:`curve_levels`, through :meth:`AreaBook.levels`): for
each slot of its centre line's heights, the same members as its ``own_lanes``, ``roadway``
and ``paved`` areas, cut to the parts that storey meets (within
:data:`~clearance.analysis.levels.LEVEL_BAND_M` of the slot's height, or not stacked and reached
from those along the road). Every other curve, however steep, has none and is judged in plan; a
flat network's curves have none at no cost.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Iterator, Sequence

import numpy as np
import shapely
from shapely.geometry.base import BaseGeometry

from clearance.analysis.clearance import Areas
from clearance.analysis.levels import LEVEL_BAND_M, LEVEL_STEP_M, Level, band_pieces, level_slots
from clearance.networks.area_groups import AreaCurve, AreaIndex, BatchPlan
from clearance.networks.model import Network
from clearance.networks.stacking import Stacking, densified, densify, met_pieces

__all__ = ["AreaBook", "BATCH_CURVES", "MAX_BATCHES", "curve_levels", "network_is_flat"]

#: Curves per batch (a batch ends at the first change of junction after this many).
BATCH_CURVES = 8192

#: Batches whose areas an :class:`AreaBook` keeps at once (the oldest is released first).
MAX_BATCHES = 2


class AreaBook:
    """Builds the areas of a list of curves on demand, per batch, keeping a few batches.

    Parameters
    ----------
    net
        The network the curves come from.
    curves
        The curves (in the order they are usually read: batches are runs of it).
    batch_curves
        Curves per batch (at least; a junction's curves are not split; default
        :data:`BATCH_CURVES`).
    max_batches
        Batches kept at once (at least 1; default :data:`MAX_BATCHES`).
    index
        The network's :class:`~clearance.networks.area_groups.AreaIndex`, when already made.

    Attributes
    ----------
    batches
        The curves of each batch.
    built
        How many batches have been built so far (a batch built again counts again).

    Examples
    --------
    >>> from clearance.networks.curves import extract_curves
    >>> from clearance.networks.reader import read_network
    >>> net = read_network("networks/samples/intersection/intersection.net.xml")
    >>> curves = extract_curves(net)          # no area is built yet
    >>> book = curves[0].area_book
    >>> book.built, book.held()
    (0, [])
    >>> curves[0].paved.geom_type, book.built, book.held()
    ('Polygon', 1, [0])
    """

    def __init__(
        self,
        net: Network,
        curves: Sequence[AreaCurve],
        batch_curves: int | None = None,
        max_batches: int | None = None,
        index: AreaIndex | None = None,
    ):
        batch_curves = BATCH_CURVES if batch_curves is None else batch_curves
        max_batches = MAX_BATCHES if max_batches is None else max_batches
        if batch_curves < 1 or max_batches < 1:
            raise ValueError("batch_curves and max_batches must be >= 1")
        self.net = net
        self._index = index
        self.max_batches = max_batches
        self.batches: list[tuple[AreaCurve, ...]] = _batches(curves, batch_curves)
        self.built = 0
        self._flat: bool | None = None
        self._held: OrderedDict[int, None] = OrderedDict()
        for b, batch in enumerate(self.batches):
            for c in batch:
                c.area_book, c.area_batch = self, b

    @property
    def index(self) -> AreaIndex:
        """The network's topology for grouping areas (made when the first batch is built:
        a caller that never reads an area does not pay for it)."""
        if self._index is None:
            self._index = AreaIndex(self.net)
        return self._index

    def held(self) -> list[int]:
        """The batches whose areas are kept now, oldest first."""
        return list(self._held)

    def load(self, batch: int) -> None:
        """Build the areas of a batch and give them to its curves (releasing the oldest
        batch when more than ``max_batches`` would be kept)."""
        from clearance.networks.areas import build_areas

        curves = self.batches[batch]
        own, roadway, paved = build_areas(self.index, curves)
        for c, o, r, p in zip(curves, own, roadway, paved, strict=True):
            if c.area_book is self:
                c.set_areas(o, r, p, book=self)
        self._held.pop(batch, None)
        self._held[batch] = None
        self.built += 1
        while len(self._held) > self.max_batches:
            self._drop(self._held.popitem(last=False)[0])

    def levels(self, curve: AreaCurve) -> tuple[Level, ...]:
        """The curve's level segments (:func:`curve_levels`; none on a flat network)."""
        if self._flat is None:
            self._flat = network_is_flat(self.net)
        return () if self._flat else curve_levels(self.index, curve)

    def release(self) -> None:
        """Drop every area the book keeps (they are built again when asked)."""
        while self._held:
            self._drop(self._held.popitem(last=False)[0])

    def _drop(self, batch: int) -> None:
        for c in self.batches[batch]:
            if c.area_book is self:
                c.set_areas(None, None, None, book=self)


def _batches(curves: Sequence[AreaCurve], size: int) -> list[tuple[AreaCurve, ...]]:
    """Runs of at least ``size`` consecutive curves, cut only where the junction changes.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> cs = [NS(junction=j) for j in "AABBBC"]
    >>> [[c.junction for c in b] for b in _batches(cs, 2)]
    [['A', 'A'], ['B', 'B', 'B'], ['C']]
    >>> _batches([], 2)
    []
    """
    cuts = [0, *_ends(curves, size), len(curves)] if curves else []
    return [tuple(curves[a:b]) for a, b in zip(cuts, cuts[1:], strict=False)]


def _ends(
    curves: Sequence[AreaCurve], size: int, start: int = 0, seen: int = 0
) -> Iterator[int]:
    """Where the batches from ``start`` on end, but the last (which may still grow): each
    at the first change of junction after ``size`` curves. ``seen``: the curves already
    looked at (none of them ends a batch).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> list(_ends([NS(junction=j) for j in "AABBBCC"], 2))
    [2, 5]
    """
    for i in range(max(seen, start + size), len(curves)):
        if i - start >= size and curves[i].junction != curves[i - 1].junction:
            yield i
            start = i


def network_is_flat(net: Network) -> bool:
    """True when every lane's and junction's height lies within
    :data:`~clearance.analysis.levels.LEVEL_STEP_M` of every other's (judged in plan).

    Examples
    --------
    >>> from clearance.networks.reader import read_network
    >>> network_is_flat(read_network("networks/samples/intersection/intersection.net.xml"))
    True
    >>> network_is_flat(read_network("networks/samples/helix/helix.net.xml"))
    False
    """
    lo, hi = np.inf, -np.inf
    for lane in net.lanes.values():
        z = lane.shape[:, 2]
        lo, hi = min(lo, float(z.min())), max(hi, float(z.max()))
    for j in net.junctions.values():
        lo, hi = min(lo, j.z), max(hi, j.z)
    return not np.isfinite(lo) or hi - lo <= LEVEL_STEP_M


def curve_levels(index: AreaIndex, curve: AreaCurve, force: bool = False) -> tuple[Level, ...]:
    """A curve's level segments, each with its storey's own lanes, roadway and paved area.

    The members of the curve's areas (:class:`~clearance.networks.area_groups.BatchPlan`) and its
    own line are cut to the parts each slot (:func:`clearance.analysis.levels.level_slots` of the
    centre line) meets (:func:`clearance.networks.stacking.met_pieces`: within
    :data:`~clearance.analysis.levels.LEVEL_BAND_M` of its middle height, or not stacked and reached
    from those along the road); the paved area covers the roadway and the own lanes and is
    closed over its cracks, as in plan. None (an empty tuple) when no part of the curve is
    stacked (:mod:`clearance.networks.stacking`): the plan areas are then the storey's, however
    steep the curve (``force`` builds the levels all the same, for checks).

    Examples
    --------
    >>> from clearance.networks.curves import extract_curves
    >>> from clearance.networks.reader import read_network
    >>> net = read_network("networks/samples/helix/helix.net.xml")
    >>> ramp = [c for c in extract_curves(net) if c.kind == "ramp"][0]
    >>> levels = curve_levels(AreaIndex(net), ramp)
    >>> len(levels), round(levels[0].z_m, 2), round(levels[-1].z_m, 2)  # 9.6 m of rise
    (10, 0.5, 9.5)
    >>> bool(levels[5].areas.own_lanes.area < 0.5 * ramp.own_lanes.area)
    True
    """
    from clearance.networks.areas import SEAL_M, _fill_small_holes, close_cracks, designed_line

    net = index.net
    plan = BatchPlan(index)
    road_group, paved_group = plan.add(curve)
    r_pieces, r_alone, _ = _members(plan, plan.road_groups[road_group])
    road = list(dict.fromkeys([*r_pieces, *r_alone]))
    p_pieces, p_alone, junctions = _members(plan, plan.paved_groups[paved_group])
    paved_lanes = list(dict.fromkeys([*p_pieces, *p_alone, *road]))
    cl = np.asarray(curve.centerline, dtype=float)
    s = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(cl[:, :2], axis=0).T))))
    flat = designed_line(cl, curve.curve_id)
    own_line = _with_heights(densify(np.column_stack([flat, np.zeros(len(flat))]))[:, :2], cl, s)
    half = curve.lane_width_m / 2.0
    st = index.stacking
    own_mask = st.line_mask(own_line, half)
    stacked = (own_mask.any() or any(k in st.lanes for k in paved_lanes)
               or not st.junctions.isdisjoint(junctions))
    if not force and not stacked:
        return ()  # no part of it over or under another: judged in plan, however steep
    members = list(dict.fromkeys([*paved_lanes, *(k for j in junctions
                                                  for k in net.junctions[j].int_lanes
                                                  if k in net.lanes)]))
    lines = {k: densified(net, k) for k in members}
    lines[_OWN] = own_line
    links = {k: [c.to_lane if c.via is None else c.via for c in net.outgoing(k)]
             for k in members}
    stacked_pieces = {k: st.lanes[k] for k in members if k in st.lanes}
    stacked_pieces[_OWN] = own_mask
    out = []
    for z_lo, z_hi in level_slots(cl[:, 2], LEVEL_STEP_M):
        z_mid = 0.5 * (z_lo + z_hi)
        lo, hi = z_mid - LEVEL_BAND_M, z_mid + LEVEL_BAND_M
        met = met_pieces(lines, stacked_pieces, links, lo, hi)
        own = shapely.union_all([shapely.buffer(shapely.LineString(p), half, quad_segs=4,
                                                cap_style="flat", join_style="round")
                                 for p in _met_lines(own_line, met[_OWN], own_mask, lo, hi)])
        if own.is_empty:
            continue
        road_k = _union(net, {k: lines[k] for k in road}, met, st, lo, hi, SEAL_M)
        polys = [net.junctions[j].shape for j in junctions
                 if len(net.junctions[j].shape) >= 3 and _junction_met(net, st, j, met, lo, hi)]
        junction_k = [shapely.buffer(shapely.make_valid(shapely.Polygon(p[:, :2])), SEAL_M,
                                     quad_segs=1, join_style="mitre") for p in polys]
        paved_k = shapely.union_all([
            _union(net, {k: lines[k] for k in paved_lanes}, met, st, lo, hi, SEAL_M),
            *junction_k, own])
        # closed over the cracks as the plan's paved area is (clearance.networks.areas.close_cracks)
        paved_k = close_cracks(np.array([shapely.make_valid(paved_k)], dtype=object))[0]
        paved_k = _fill_small_holes(paved_k)
        areas = Areas(own, paved_k, None if road_k.is_empty else _fill_small_holes(road_k))
        out.append(Level(z_lo, z_hi, areas))
    return tuple(out)


#: The key of a curve's own line among its members' lines (no lane id is empty).
_OWN = ""


def _with_heights(line: np.ndarray, centerline: np.ndarray, s_m: np.ndarray) -> np.ndarray:
    """A plane line drawn along a 3-D centre line (its designed line), each point at the
    centre line's height at the same share of their lengths.

    >>> cl = np.array([[0.0, 0, 0], [10.0, 0, 5]])
    >>> _with_heights(np.array([[0.0, 1.0], [2.0, 1.0], [10.0, 1.0]]), cl,
    ...               np.array([0.0, 10.0]))[:, 2]
    array([0., 1., 5.])
    """
    along = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(line, axis=0).T))))
    z = np.interp(along * s_m[-1] / max(along[-1], 1e-9), s_m, centerline[:, 2])
    return np.column_stack([line, z])


def _met_lines(pts: np.ndarray, met: np.ndarray, stacked: np.ndarray | None, lo: float,
               hi: float) -> list[np.ndarray]:
    """The plane polylines of a 3-D polyline that a storey meets
    (:func:`clearance.networks.stacking.met_pieces`): of its stacked pieces the parts within the
    band ``lo .. hi`` (cut where they cross it, :func:`clearance.analysis.levels.band_pieces`), and
    its runs of other pieces met, whole.

    >>> ramp = np.array([[0, 0, 0.0], [2, 0, 2], [4, 0, 4]])
    >>> [p.tolist() for p in _met_lines(ramp, np.array([True, True]), None, -1.0, 1.0)]
    [[[0.0, 0.0], [2.0, 0.0], [4.0, 0.0]]]
    >>> [p.tolist() for p in _met_lines(ramp, np.array([True, False]), np.array([True, True]),
    ...                                 -1.0, 1.0)]
    [[[0.0, 0.0], [1.0, 0.0]]]
    """
    free = met if stacked is None else met & ~stacked
    out = [] if stacked is None or not stacked.any() else [
        p for p in band_pieces(pts, lo, hi) if len(p) > 1]
    if free.any():  # met and not stacked: whole pieces
        edges = np.flatnonzero(np.diff(np.concatenate(([0], free.astype(np.int8), [0]))))
        for a, b in zip(edges[::2].tolist(), edges[1::2].tolist(), strict=True):
            out.append(pts[a:b + 1, :2])
    return out


def _junction_met(net: Network, st: Stacking, j: str, met: dict[str, np.ndarray], lo: float,
                  hi: float) -> bool:
    """Whether a storey meets a junction's polygon: its heights reach into the band, or it
    is not stacked and a lane on it is met (an internal lane, or a lane's end on it)."""
    if _meets(st.junction_z.get(j, (net.junctions[j].z,) * 2), lo, hi):
        return True
    if j in st.junctions:
        return False
    for k in net.junctions[j].int_lanes:
        if k in met and met[k].any():
            return True
    for k, m in met.items():
        if k and len(m) and k in net.lanes:
            e = net.edges.get(net.lanes[k].edge)
            if e is not None and ((e.to_junction == j and m[-1]) or (e.from_junction == j
                                                                     and m[0])):
                return True
    return False


def _meets(z_range: tuple[float, float], lo: float, hi: float) -> bool:
    """Whether a height range reaches into the band ``lo .. hi``.

    >>> _meets((0.0, 1.0), 0.5, 2.0), _meets((3.0, 4.0), 0.5, 2.0)
    (True, False)
    """
    return z_range[0] <= hi and z_range[1] >= lo


def _members(plan: BatchPlan, keys: Sequence[str]) -> tuple[list[str], list[str], list[str]]:
    """A group's members as lanes (of pieces), lanes (named alone) and junctions."""
    pieces: list[str] = []
    lanes: list[str] = []
    junctions: list[str] = []
    for key in keys:
        if key.startswith("L:"):
            lanes.append(key[2:])
        elif key.startswith("J:"):
            junctions.append(key[2:])
        else:
            pieces.extend(plan.pieces.get(key, ()))
    return pieces, lanes, junctions


def _union(net: Network, lines: dict[str, np.ndarray], met: dict[str, np.ndarray],
           st: Stacking, lo: float, hi: float, seal_m: float) -> BaseGeometry:
    """The union of the lanes' parts a storey meets (:func:`_met_lines`), with round ends as
    the plan areas' lanes, grown by ``seal_m``."""
    polys = []
    for k, pts in lines.items():
        width = net.lanes[k].width_m / 2.0 + seal_m
        for p in _met_lines(pts, met[k], st.lanes.get(k), lo, hi):
            polys.append(shapely.buffer(shapely.LineString(p), width, quad_segs=4))
    return shapely.union_all(polys) if polys else shapely.Polygon()
