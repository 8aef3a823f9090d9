"""Reading a large network in two parts at once, on two cores.

A SUMO network lists its edges (with their lanes) first, then its junctions (with their
right-of-way ``<request>`` rows) and connections. A large plain ``.net.xml`` is cut at the
first ``<edge``, ``<junction``, ``<tlLogic`` or ``<connection`` tag from halfway through the
file on (:data:`SPLIT_FRACTION`): this process parses the part before it (closed with
``</net>``), and a second Python process (``python -m networks.read_split FILE OFFSET``)
parses the part after it (opened with ``<net>``) with the same parser state, sends back what
it read (pickled plain tuples, :func:`dump`) and leaves at once. The two are merged in
document order.

Both parts parsed without error prove the cut was at the top level: a tag found inside a
comment, a CDATA section, a processing instruction or another element leaves one of the
parts malformed. Any failure of either part (a malformed file, a truncated one, a bad value,
a second process that cannot start) falls back to reading the whole file in one pass, which
then raises the error a sequential read gives; so the result, and every error message, is
that of :func:`networks.reader.read_network` read in one pass.

Only plain (not gzip) files of at least :data:`MIN_SPLIT_BYTES` without a DOCTYPE, in UTF-8,
are split, and only when two or more cores may be used (``CLEARANCE_THREADS=1`` keeps every
read in one process).
"""

from __future__ import annotations

import os
import pickle
import re
import subprocess
import sys
from pathlib import Path

from lxml import etree

from networks.reader import (
    EMPTY_SHAPE,
    Edge,
    Junction,
    Lane,
    Location,
    Roundabout,
    _ParseState,
    cores,
    make_parser,
)
from vehicles.errors import InputError

__all__ = ["CHILD_TIMEOUT_S", "ConnectionRow", "MIN_SPLIT_BYTES", "SPLIT_FRACTION", "dump", "merge",
           "read_in_two", "split_offset"]

#: Plain files smaller than this are read in one pass (a second process costs ~0.2 s).
MIN_SPLIT_BYTES = 24 * 1024 * 1024

#: Where to cut, as a share of the file's bytes: the part before it (mostly edges and lanes,
#: whose shapes take longest to parse) is read here, the rest by the second process, which
#: also has to start Python and send what it read (measured on a 10,000-junction grid).
SPLIT_FRACTION = 0.5

#: The longest a second process may take once this one is done (it reads a finite file).
CHILD_TIMEOUT_S = 600.0

_HEAD_BYTES = 1 << 16
_CHUNK = 1 << 22
_CUT_RE = re.compile(rb"<(?:edge|junction|tlLogic|connection)[\s/>]")
_ROOT_RE = re.compile(rb"<net[\s>][^>]*>")
_ENCODING_RE = re.compile(rb"""^\s*<\?xml[^>]*encoding\s*=\s*["']([^"']+)["']""")


def split_offset(
    path: Path, min_bytes: int | None = None, fraction: float | None = None
) -> int | None:
    """Byte offset to cut ``path`` at, or None when it is read in one pass.

    The cut is at the first top-level tag (``<edge``, ``<junction``, ``<tlLogic`` or
    ``<connection``) at or after ``fraction`` of the file (default
    :data:`SPLIT_FRACTION`); files under ``min_bytes`` (default :data:`MIN_SPLIT_BYTES`)
    are not cut.

    Examples
    --------
    >>> import tempfile
    >>> f = Path(tempfile.mkdtemp()) / "n.net.xml"
    >>> _ = f.write_bytes(b'<net><edge id="e"/><junction id="j"/></net>')
    >>> split_offset(f, min_bytes=0, fraction=0.2)
    19
    >>> split_offset(f) is None  # small files are read in one pass
    True
    """
    fraction = SPLIT_FRACTION if fraction is None else fraction
    min_bytes = MIN_SPLIT_BYTES if min_bytes is None else min_bytes
    try:
        size = path.stat().st_size
        if size < min_bytes or cores() < 2:
            return None
        with open(path, "rb") as fh:
            head = fh.read(_HEAD_BYTES)
            if head[:2] == b"\x1f\x8b" or b"<!DOCTYPE" in head.upper():
                return None
            enc = _ENCODING_RE.match(head)
            if enc and enc.group(1).lower().replace(b"_", b"-") not in (b"utf-8", b"utf8"):
                return None
            root = _ROOT_RE.search(head)
            if root is None:
                return None
            pos = max(int(size * fraction), root.end())
            fh.seek(pos)
            tail = b""
            while chunk := fh.read(_CHUNK):
                buf = tail + chunk
                m = _CUT_RE.search(buf)
                if m:
                    return pos - len(tail) + m.start()
                tail = buf[-16:]
                pos += len(chunk)
    except OSError:
        return None
    return None


def read_in_two(path: Path, offset: int) -> _ParseState | None:
    """Parse ``path`` in two processes, cut at ``offset``; the merged state, or None.

    None means some part failed (see the module docstring): the caller reads the file in
    one pass instead.
    """
    env = dict(os.environ)
    root = str(Path(__file__).resolve().parents[1])
    env["PYTHONPATH"] = root + os.pathsep + env.get("PYTHONPATH", "")
    try:
        child = subprocess.Popen(
            [sys.executable, "-m", "networks.read_split", str(path), str(offset)],
            stdout=subprocess.PIPE,
            stderr=subprocess.DEVNULL,
            env=env,
        )
    except OSError:
        return None
    try:
        state = _ParseState(path)
        parser = make_parser(state)
        try:
            with open(path, "rb") as fh:
                left = offset
                while left > 0 and (chunk := fh.read(min(_CHUNK, left))):
                    parser.feed(chunk)
                    state.check_size()
                    left -= len(chunk)
            parser.feed(b"</net>")
            parser.close()
            state.settle_shapes()  # while the other process still reads
        except (etree.XMLSyntaxError, InputError, OSError, ValueError):
            return None
        assert child.stdout is not None
        out = child.stdout.read()  # the child is bounded: it reads a finite file
        if child.wait(timeout=CHILD_TIMEOUT_S) != 0:
            return None
        try:
            merge(state, out)
            state.check_size()
        except Exception:  # noqa: BLE001 - whatever is wrong with the second part
            return None  # (a lane id used twice, no output at all): one pass names it
        return state
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()


def dump(state: _ParseState) -> bytes:
    """What a parser state read, pickled for :func:`merge` (shapes still as strings).

    Plain tuples of strings and numbers only: pickle makes and reads them in C, and
    shares the one frozenset of vehicle classes many lanes have (and the interned edge ids
    of the connections). Strings of which there are very many (a connection's ``via``, a
    junction's lane lists) are sent joined, one string each, which is faster both ways.
    """
    loc = state.location
    return pickle.dumps(
        (
            [(ln.id, ln.edge, ln.index, ln.width_m, ln.function, ln.allowed, ln.length_m,
              ln.speed_mps) for ln in state.lanes.values()],
            state.lane_shapes,
            [(e.id, e.from_junction, e.to_junction, e.function, e.priority, e.lanes)
             for e in state.edges.values()],
            _connection_columns(state.connection_rows),
            [(j.id, j.type, j.x, j.y, j.z, " ".join(j.inc_lanes), " ".join(j.int_lanes))
             for j in state.junctions.values()],  # lane ids hold no spaces (split on them)
            state.junction_shapes,
            [(r.nodes, r.edges) for r in state.roundabouts],
            (loc.net_offset, loc.conv_boundary, loc.orig_boundary, loc.proj_parameter)
            if state.location_seen
            else None,
        ),
        protocol=pickle.HIGHEST_PROTOCOL,
    )


def merge(state: _ParseState, data: bytes) -> None:
    """Append what :func:`dump` gave (the part after the cut) to ``state`` (the part before).

    Examples
    --------
    >>> a, b = _ParseState(Path("a")), _ParseState(Path("b"))
    >>> b.connection_rows.append(("e", "f", 0, 1, None, "s"))
    >>> merge(a, dump(b))
    >>> a.connection_rows
    [('e', 'f', 0, 1, None, 's')]
    """
    lanes, lane_shapes, edges, connections, junctions, junction_shapes, rounds, loc = (
        pickle.loads(data)  # noqa: S301 - written by our own child process
    )
    for row, shape in zip(lanes, lane_shapes, strict=True):
        state.add_lane(Lane(*row[:6], EMPTY_SHAPE, *row[6:]), shape)
    for row in edges:
        if row[0] in state.edges:
            raise InputError(f"edge {row[0]!r} is defined twice")  # one pass names the file
        state.edges[row[0]] = Edge(*row)
    state.connection_rows.extend(_connection_rows(connections))
    for row, shape in zip(junctions, junction_shapes, strict=True):
        junction = Junction(*row[:5], EMPTY_SHAPE, tuple(row[5].split()), tuple(row[6].split()))
        state.add_junction(junction, shape)
    state.roundabouts.extend(Roundabout(*r) for r in rounds)
    if loc is not None:
        state.location = Location(*loc)
        state.location_seen = True


_SEP = "\x00"  # neither can occur in XML text
_NONE = "\x01"  # stands for a missing ``via``

ConnectionRow = tuple[str, str, int, int, str | None, str]


def _connection_columns(rows: list[ConnectionRow]) -> tuple:
    """Connection rows as columns, the ``via`` column as one string."""
    if not rows:
        return ()
    frm, to, from_lane, to_lane, via, direction = zip(*rows, strict=True)
    vias = _SEP.join([_NONE if v is None else v for v in via])
    return frm, to, from_lane, to_lane, vias, direction


def _connection_rows(columns: tuple) -> zip:
    """The rows :func:`_connection_columns` was given.

    Examples
    --------
    >>> rows = [("a", "b", 0, 1, ":j_0_0", "r"), ("c", "d", 2, 0, None, "s")]
    >>> rows.append(("e", "f", 0, 0, "", ""))  # an empty via is not a missing one
    >>> list(_connection_rows(_connection_columns(rows))) == rows
    True
    >>> list(_connection_rows(_connection_columns([])))
    []
    """
    if not columns:
        return zip()
    frm, to, from_lane, to_lane, vias, direction = columns
    via = [None if v == _NONE else v for v in vias.split(_SEP)]
    return zip(frm, to, from_lane, to_lane, via, direction, strict=True)


def _child(path: str, offset: int) -> int:
    """Parse ``path`` from ``offset`` (opened with ``<net>``) and write :func:`dump` of it to
    standard output; the exit status (2: the part could not be read)."""
    state = _ParseState(Path(path))
    parser = make_parser(state)
    try:
        with open(path, "rb") as fh:
            fh.seek(offset)
            parser.feed(b"<net>")
            while chunk := fh.read(_CHUNK):
                parser.feed(chunk)
                state.check_size()
        parser.close()
    except (etree.XMLSyntaxError, InputError, OSError, ValueError):
        return 2
    if state.orphan_lanes:
        return 2  # lanes outside any edge: read in one pass, where they join the last edge
    sys.stdout.buffer.write(dump(state))
    return 0


if __name__ == "__main__":
    import gc  # noqa: I001

    gc.disable()  # a short-lived process that only builds lasting objects
    code = _child(sys.argv[1], int(sys.argv[2]))
    sys.stdout.flush()
    # out now, without freeing what it read one object at a time (~0.4 s on a large
    # network): the reader waits for the end of the pipe, which comes with the exit
    os._exit(code)
