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
the curves in that order builds each batch once. When batches are read in that order, the
worker process that builds part of each large batch (:mod:`networks.area_worker`) has its
parts of the next batches queued, so that it is never idle while this process reads its
answer and builds its own part; a read out of order drops that work (see
:func:`networks.areas.build_areas`). A caller that will read every curve's areas in
order can have the worker start on the first batches while the curves are still being
extracted (an :class:`AreaFeed`).
"""

from __future__ import annotations

from collections import OrderedDict, deque
from collections.abc import Iterator, Sequence
from typing import TYPE_CHECKING

from networks.area_groups import AreaIndex
from networks.reader import Network

if TYPE_CHECKING:
    from networks.curves import Curve

#: Curves per batch (a batch ends at the first change of junction after this many).
BATCH_CURVES = 8192

#: Batches whose areas an :class:`AreaBook` keeps at once (the oldest is released first).
MAX_BATCHES = 2

#: Batches after the one built that a book read in order names as next (the worker's
#: parts of those not queued yet are queued, up to its limit).
LOOKAHEAD = 8


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
        The network's :class:`~networks.area_groups.AreaIndex`, when already made (e.g.
        by an :class:`AreaFeed`).

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
        curves: Sequence[Curve],
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
        self.batches: list[tuple[Curve, ...]] = _batches(curves, batch_curves)
        self.built = 0
        self._held: OrderedDict[int, None] = OrderedDict()
        self._last: int | None = None  # the batch built last
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
        # read in order (the first batch, or the one after the last built): the next
        # batches are likely next, and a worker process may start on its parts at once
        in_order = self._last in (None, batch - 1)
        ahead = self.batches[batch + 1 : batch + 1 + LOOKAHEAD] if in_order else ()
        own, roadway, paved = build_areas(self.index, curves, ahead)
        self._last = batch
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


class AreaFeed:
    """Gives the worker process its parts of the first batches of curves while the rest
    are still being extracted (:func:`networks.curves.extract_curves` with
    ``build_ahead``), so that it is not idle meanwhile; the :class:`AreaBook` made for the
    curves then finds those parts in flight when it is read in order.

    :meth:`offer` the curves extracted so far, each time more are there: a prefix of the
    final list of curves, in its order (the batches cut from it are then those the book
    cuts). Batches are sent when complete, in order, while the worker can take them
    (:func:`networks.area_worker.send_ahead`); nothing is sent when no worker process is
    used.

    Parameters
    ----------
    net
        The network the curves come from.
    batch_curves
        Curves per batch (as the book's; default :data:`BATCH_CURVES`).
    worker
        Use the worker process (started now when the network has a batch's worth of
        connections, so that it is ready for the first batch); False: the batches are
        found, nothing is sent.
    """

    def __init__(self, net: Network, batch_curves: int | None = None, worker: bool = True):
        from networks import area_worker, areas

        self.net = net
        self.batch_curves = BATCH_CURVES if batch_curves is None else batch_curves
        self.index: AreaIndex | None = None
        self._ready: deque[tuple[int, int]] = deque()  # complete batches not sent yet
        self._start = 0  # where the batch being completed starts
        self._seen = 0  # curves looked at so far
        self._on = worker and area_worker.use_process() and areas._may_split()
        if self._on and len(net.connections) >= self.batch_curves:
            area_worker.worker()  # likely needed: it starts up while curves are extracted

    def offer(self, curves: Sequence[Curve]) -> None:
        """Send the worker the complete batches of ``curves`` not sent yet (see above).

        Examples
        --------
        >>> from types import SimpleNamespace as NS
        >>> feed = AreaFeed(None, batch_curves=2, worker=False)  # the batches are only found
        >>> feed.offer([NS(junction=j) for j in "AAAB"]); list(feed._ready)
        [(0, 3)]
        >>> feed.offer([NS(junction=j) for j in "AAABBBC"]); list(feed._ready)
        [(0, 3), (3, 6)]
        """
        for end in _ends(curves, self.batch_curves, self._start, self._seen):
            self._ready.append((self._start, end))
            self._start = end
        self._seen = max(self._seen, len(curves))
        if not self._on:
            return
        from networks.area_worker import send_ahead

        while self._ready:
            a, b = self._ready[0]
            if self.index is None:
                self.index = AreaIndex(self.net)
            if not send_ahead(self.index, tuple(curves[a:b])):
                return
            self._ready.popleft()


def _batches(curves: Sequence[Curve], size: int) -> list[tuple[Curve, ...]]:
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
    curves: Sequence[Curve], size: int, start: int = 0, seen: int = 0
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
