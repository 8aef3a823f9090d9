"""Every lane's shape and length at once, for extracting many curves (vectorised numpy).

:meth:`networks.reader.Network.lane_line` cleans and measures one lane at a time (a few
numpy calls per lane, kept in a cache on the network). Extraction touches nearly every
lane, so :class:`LaneTable` does the same for all lanes in a handful of array operations and
keeps the cleaned points end to end in one array: the same points and the same lengths,
bit for bit, without an array object per lane.
"""

from __future__ import annotations

import numpy as np

from networks.reader import Network

__all__ = ["LaneTable", "REPEAT_M"]

#: Points closer than this (metres, in the plane) to the one before are dropped, as in
#: :meth:`networks.reader.Network.lane_line`.
REPEAT_M = 1e-6

#: Lanes with fewer chords than this are measured with one vectorised sum per chord
#: (numpy sums shorter arrays in order, longer ones pairwise: those are summed one by one).
_SEQUENTIAL_MAX = 8


def _stacked(shapes: list[np.ndarray]) -> np.ndarray | None:
    """Shapes of (k, 3) points each, end to end; None when some shape is not (k, 3).

    Examples
    --------
    >>> _stacked([np.zeros((2, 3)), np.ones((1, 3))]).shape
    (3, 3)
    >>> _stacked([np.zeros((2, 3)), np.zeros(3)]) is None, _stacked([]).shape
    (True, (0, 3))
    """
    if not shapes:
        return np.zeros((0, 3))
    try:
        raw = np.concatenate(shapes)  # as read: (k, 3) each
    except ValueError:
        return None
    return raw if raw.ndim == 2 and raw.shape[1] == 3 else None


class LaneTable:
    """The cleaned shape and the plane length of every lane of a network.

    Attributes
    ----------
    ids
        Lane ids in network order (the network's own string objects).
    index
        Lane id -> row.
    points
        (M, 3) cleaned points of all lanes, end to end.
    start, count
        Each lane's first point in ``points`` and its number of points.
    length, lengths
        Each lane's plane length (of its shape as read, as ``Network.lane_line`` gives), as
        an array and as a list of floats.

    Examples
    --------
    >>> from networks.reader import Lane, Location
    >>> shape = np.array([[0, 0, 0], [3, 4, 0], [3, 4, 0], [3, 5, 1.0]])
    >>> lane = Lane("e_0", "e", 0, 3.2, "normal", frozenset(), shape, 6.0, 13.9)
    >>> net = Network(None, {"e_0": lane}, {}, [], {}, [], Location())
    >>> t = LaneTable(net)
    >>> t.line("e_0").tolist(), t.length_m("e_0")
    ([[0.0, 0.0, 0.0], [3.0, 4.0, 0.0], [3.0, 5.0, 1.0]], 6.0)
    """

    def __init__(self, net: Network):
        self.ids = list(net.lanes)
        n = len(self.ids)
        self.index = dict(zip(self.ids, range(n), strict=True))
        shapes = [lane.shape for lane in net.lanes.values()]
        raw = _stacked(shapes)
        if raw is None:  # a shape of another layout (e.g. flat): each made (k, 3) first
            shapes = [s.reshape(-1, 3) for s in shapes]
            raw = np.concatenate(shapes)
        raw_count = np.fromiter(map(len, shapes), dtype=np.int64, count=n)
        raw_start = np.concatenate(([0], np.cumsum(raw_count)[:-1])).astype(np.int64)
        d = raw[1:, :2] - raw[:-1, :2]
        step = np.hypot(d[:, 0], d[:, 1])
        chords = np.maximum(raw_count - 1, 0)
        # lengths: sum of each lane's chords, as ndarray.sum() adds them
        length = np.zeros(n)
        short = np.flatnonzero(chords < _SEQUENTIAL_MAX)
        for j in range(_SEQUENTIAL_MAX):
            rows = short[chords[short] > j]
            if not len(rows):
                break
            length[rows] = length[rows] + step[raw_start[rows] + j] if j else step[raw_start[rows]]
        for i in np.flatnonzero(chords >= _SEQUENTIAL_MAX).tolist():
            length[i] = float(step[raw_start[i] : raw_start[i] + chords[i]].sum())
        # cleaned points: a lane's first point, then every point not on top of the last
        keep = np.ones(len(raw), dtype=bool)
        if len(raw) > 1:
            keep[1:] = step > REPEAT_M
            keep[raw_start] = True
        lane_of = np.repeat(np.arange(n), raw_count)
        self.points = raw[keep]
        self.count = np.bincount(lane_of[keep], minlength=n).astype(np.int64)
        self.start = np.concatenate(([0], np.cumsum(self.count)[:-1])).astype(np.int64)
        self.length = length
        self.lengths: list[float] = length.tolist()

    def row(self, lane_id: str) -> int:
        """The row of a lane (KeyError if the network has no such lane)."""
        return self.index[lane_id]

    def line(self, lane_id: str) -> np.ndarray:
        """A lane's cleaned shape (a view into :attr:`points`)."""
        i = self.index[lane_id]
        return self.points[self.start[i] : self.start[i] + self.count[i]]

    def length_m(self, lane_id: str) -> float:
        """A lane's plane length."""
        return self.lengths[self.index[lane_id]]

    def gather(self, rows: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The cleaned points of the lanes ``rows``, end to end, and each one's count."""
        count = self.count[rows]
        total = int(count.sum())
        offset = np.repeat(self.start[rows] - (np.cumsum(count) - count), count)
        return self.points[offset + np.arange(total)], count
