"""Curve areas built on demand, a batch of curves at a time, with a bound on what is kept.

The three areas of every curve of a large network do not fit in memory beside the network
and its curves (the 10,000-junction grid's 196,408 curves hold about 1.5 GB of polygons),
and most uses need few of them at a time (``clearance curves`` needs none; a simulation
needs those of its batch of runs). :func:`networks.curves.extract_curves` therefore gives
its curves an :class:`AreaBook`: the first time a curve's ``own_lanes``, ``roadway`` or
``paved`` is read, the areas of its whole batch (:data:`BATCH_CURVES` consecutive curves,
never splitting a junction's curves) are built together with
:func:`networks.areas.build_areas`, and the curves keep them until the book releases the
batch. The book keeps at most :data:`MAX_BATCHES` batches: building one more releases the
one built first. A released curve builds its batch again when asked (the same geometry:
a batch's unions do not depend on what else is built). An area a caller still holds stays
valid; the book only drops its own references.

Curves are in kind then id order, so a junction's turns are consecutive and a sweep over
the curves in that order builds each batch once.

**Levels** (docs/design.md §6, :mod:`analysis.levels`). On a network with heights that
differ by more than :data:`~analysis.levels.LEVEL_STEP_M`, a curve whose run or whose
areas' lanes and junctions span more than that also gets its level segments
(:func:`curve_levels`, through :meth:`AreaBook.levels`): for each slot of its centre
line's heights, the same members as its ``own_lanes``, ``roadway`` and ``paved`` areas, cut to the
parts within :data:`~analysis.levels.LEVEL_BAND_M` of the stretch's height (a lane by its
shape points' heights, a junction polygon by its node's). A flat network's curves have
none and are judged in plan, exactly as before, at no cost.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Iterator, Sequence

import numpy as np
import shapely

from analysis.clearance import Areas
from analysis.levels import LEVEL_BAND_M, LEVEL_STEP_M, Level, band_pieces, is_flat, level_slots
from networks.area_groups import AreaCurve, AreaIndex, BatchPlan
from networks.model import Network

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
        The network's :class:`~networks.area_groups.AreaIndex`, when already made.

    Attributes
    ----------
    batches
        The curves of each batch.
    built
        How many batches have been built so far (a batch built again counts again).

    Examples
    --------
    >>> from networks.curves import extract_curves
    >>> from networks.reader import read_network
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
        from networks.areas import build_areas

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
    :data:`~analysis.levels.LEVEL_STEP_M` of every other's (judged in plan).

    Examples
    --------
    >>> from networks.reader import read_network
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

    The members of the curve's areas (:class:`~networks.area_groups.BatchPlan`) are cut to
    the parts within :data:`~analysis.levels.LEVEL_BAND_M` of each slot's middle height
    (:func:`analysis.levels.level_slots` of the centre line); the paved area covers the
    roadway and the own lanes and is closed over its cracks, as in plan. None (an empty
    tuple) when the run and every member lie within :data:`~analysis.levels.LEVEL_STEP_M`
    of each other: the plan areas are then the storey's (``force`` builds the levels all
    the same, for checks).

    Examples
    --------
    >>> from networks.curves import extract_curves
    >>> from networks.reader import read_network
    >>> net = read_network("networks/samples/helix/helix.net.xml")
    >>> ramp = [c for c in extract_curves(net) if c.kind == "ramp"][0]
    >>> levels = curve_levels(AreaIndex(net), ramp)
    >>> len(levels), round(levels[0].z_m, 2), round(levels[-1].z_m, 2)  # 9.6 m of rise
    (10, 0.5, 9.5)
    >>> bool(levels[5].areas.own_lanes.area < 0.5 * ramp.own_lanes.area)
    True
    """
    from networks.areas import SEAL_M, _fill_small_holes, close_cracks, designed_line

    net = index.net
    plan = BatchPlan(index)
    road_group, paved_group = plan.add(curve)
    r_pieces, r_alone, _ = _members(plan, plan.road_groups[road_group])
    road = list(dict.fromkeys([*r_pieces, *r_alone]))
    p_pieces, p_alone, junctions = _members(plan, plan.paved_groups[paved_group])
    paved_lanes = list(dict.fromkeys([*p_pieces, *p_alone, *road]))
    cl = np.asarray(curve.centerline, dtype=float)
    s = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(cl[:, :2], axis=0).T))))
    heights = [cl[:, 2], *(net.lanes[k].shape[:, 2] for k in paved_lanes),
               np.array([net.junctions[j].z for j in junctions])]
    if not force and is_flat(np.concatenate(heights)):
        return ()
    line = designed_line(cl, curve.curve_id)
    along = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(line, axis=0).T))))
    own_line = np.column_stack([line, np.interp(along * s[-1] / max(along[-1], 1e-9), s,
                                                cl[:, 2])])
    half = curve.lane_width_m / 2.0
    out = []
    for z_lo, z_hi in level_slots(cl[:, 2], LEVEL_STEP_M):
        z_mid = 0.5 * (z_lo + z_hi)
        lo, hi = z_mid - LEVEL_BAND_M, z_mid + LEVEL_BAND_M
        own = shapely.union_all([shapely.buffer(shapely.LineString(p), half, quad_segs=4,
                                                cap_style="flat", join_style="round")
                                 for p in band_pieces(own_line, lo, hi) if len(p) > 1])
        if own.is_empty:
            continue
        road_k = _band_union(net, road, lo, hi, SEAL_M)
        polys = [net.junctions[j].shape for j in junctions
                 if lo <= net.junctions[j].z <= hi and len(net.junctions[j].shape) >= 3]
        junction_k = [shapely.buffer(shapely.make_valid(shapely.Polygon(p[:, :2])), SEAL_M,
                                     quad_segs=1, join_style="mitre") for p in polys]
        paved_k = shapely.union_all([_band_union(net, paved_lanes, lo, hi, SEAL_M),
                                     *junction_k, own])
        # closed over the cracks as the plan's paved area is (networks.areas.close_cracks)
        paved_k = close_cracks(np.array([shapely.make_valid(paved_k)], dtype=object))[0]
        paved_k = _fill_small_holes(paved_k)
        areas = Areas(own, paved_k, None if road_k.is_empty else _fill_small_holes(road_k))
        out.append(Level(z_lo, z_hi, areas))
    return tuple(out)


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


def _band_union(net: Network, lanes: Sequence[str], lo: float, hi: float, seal_m: float):
    """The union of the lanes' parts within heights ``lo .. hi`` (round ends, as the plan
    areas' lanes, grown by ``seal_m``)."""
    polys = []
    for k in lanes:
        lane = net.lanes[k]
        for p in band_pieces(lane.shape, lo, hi):
            geom = shapely.LineString(p) if len(p) > 1 else shapely.Point(p[0])
            polys.append(shapely.buffer(geom, lane.width_m / 2.0 + seal_m, quad_segs=4))
    return shapely.union_all(polys) if polys else shapely.Polygon()
