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
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Iterator, Sequence

from networks.area_groups import AreaCurve, AreaIndex
from networks.reader import Network

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
