"""Write the plain-XML sources of the sample networks from their design parameters.

The sources (``*.nod.xml``, ``*.edg.xml``, ``*.con.xml``) are committed; run this only to
change a design, then rebuild with ``python -m clearance.networks.samples.build``::

    python -m clearance.networks.samples.sources   # rewrites networks/samples/*/*.{nod,edg,con}.xml

Coordinates are metres, x east, y north; netconvert keeps them (no offset normalisation).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

__all__ = ["Corners", "GARAGE_AISLE_M", "GARAGE_CORNER_M", "GARAGE_DECK_M", "GARAGE_RADIUS_M",
           "GARAGE_RAMP_M", "GARAGE_STOREY_M", "HELIX_LANE_M", "HELIX_RADIUS_M",
           "HELIX_RISE_PER_TURN_M", "HELIX_TURNS", "INTERSECTION_CORNERS", "LEVEL_HELIX_LANE_M",
           "LEVEL_HELIX_RADIUS_M", "LEVEL_HELIX_RISE_PER_TURN_M", "LEVEL_HELIX_TURNS", "Point",
           "ROUNDABOUTS", "RingDesign", "SAMPLES_DIR", "TEE_TIGHT_CORNER_M", "TEE_WIDE_CORNER_M",
           "WRITERS", "arc", "fmt", "four_leg", "main", "ring", "tee", "write_garage",
           "write_helix", "write_intersection", "write_parking_ramp", "write_roundabout"]

SAMPLES_DIR = Path(__file__).resolve().parent

Point = tuple[float, ...]


def arc(
    centre: tuple[float, float],
    radius_m: float,
    a0_deg: float,
    a1_deg: float,
    step_deg: float = 5.0,
) -> list[Point]:
    """Points on a circular arc from angle ``a0_deg`` to ``a1_deg`` (either direction).

    Examples
    --------
    >>> [tuple(round(v, 6) for v in p) for p in arc((0, 0), 2.0, 0, 90, 45)]
    [(2.0, 0.0), (1.414214, 1.414214), (0.0, 2.0)]
    >>> len(arc((0, 0), 1.0, 30, 30))  # a zero-length arc is its single point, twice
    2
    """
    n = max(int(math.ceil(abs(a1_deg - a0_deg) / step_deg)), 1)
    a = np.radians(np.linspace(a0_deg, a1_deg, n + 1))
    return [(centre[0] + radius_m * math.cos(t), centre[1] + radius_m * math.sin(t)) for t in a]


def fmt(points: Iterable[Point]) -> str:
    """A SUMO shape string (``x,y`` or ``x,y,z``, 3 decimals)."""
    return " ".join(",".join(f"{v:.3f}" for v in p) for p in points)


def _write(
    directory: Path,
    name: str,
    nodes: Sequence[str],
    edges: Sequence[str],
    connections: Sequence[str] = (),
) -> None:
    directory.mkdir(parents=True, exist_ok=True)
    head = (
        '<?xml version="1.0" encoding="UTF-8"?>\n<!-- written by networks/samples/sources.py -->\n'
    )
    (directory / f"{name}.nod.xml").write_text(
        head + "<nodes>\n    " + "\n    ".join(nodes) + "\n</nodes>\n"
    )
    (directory / f"{name}.edg.xml").write_text(
        head + "<edges>\n    " + "\n    ".join(edges) + "\n</edges>\n"
    )
    if connections:
        (directory / f"{name}.con.xml").write_text(
            head + "<connections>\n    " + "\n    ".join(connections) + "\n</connections>\n"
        )


# --------------------------------------------------------------------------- intersection


@dataclass(frozen=True)
class Corners:
    """Curb radii (m) of the four corners of a four-leg junction."""

    ne: float
    se: float
    sw: float
    nw: float


def four_leg(
    jid: str, cx: float, cy: float, corners: Corners, lanes: int, width_m: float, arm_m: float
) -> tuple[list[str], list[str], list[str]]:
    """A signalised four-leg junction with a custom polygon and circular right turns.

    Each right turn from the rightmost lane follows an arc concentric with its corner at
    ``corner radius + width/2``; the other movements are left to netconvert.
    """
    h = lanes * width_m  # half the road width (two directions)
    off = width_m / 2  # rightmost lane centre from the curb
    lane0 = h - off  # rightmost lane centre from the road's centre line
    r = corners
    d = {
        "N": h + max(r.ne, r.nw),
        "E": h + max(r.ne, r.se),
        "S": h + max(r.se, r.sw),
        "W": h + max(r.sw, r.nw),
    }
    poly: list[Point] = [(-h, d["N"]), (h, d["N"])]
    poly += arc((h + r.ne, h + r.ne), r.ne, 180, 270)
    poly += [(d["E"], h), (d["E"], -h)]
    poly += arc((h + r.se, -h - r.se), r.se, 90, 180)
    poly += [(h, -d["S"]), (-h, -d["S"])]
    poly += arc((-h - r.sw, -h - r.sw), r.sw, 0, 90)
    poly += [(-d["W"], -h), (-d["W"], h)]
    poly += arc((-h - r.nw, h + r.nw), r.nw, 270, 360)
    shape = [(x + cx, y + cy) for x, y in poly]
    nodes = [f'<node id="{jid}" x="{cx}" y="{cy}" type="traffic_light" shape="{fmt(shape)}"/>']
    arms = {"N": (0, 1), "E": (1, 0), "S": (0, -1), "W": (-1, 0)}
    edges = []
    for arm, (ux, uy) in arms.items():
        nid = f"{jid}{arm}"
        nodes.append(f'<node id="{nid}" x="{cx + ux * arm_m}" y="{cy + uy * arm_m}"/>')
        attrs = f'numLanes="{lanes}" width="{width_m}" speed="13.89"'
        edges.append(f'<edge id="{nid}_in" from="{nid}" to="{jid}" {attrs}/>')
        edges.append(f'<edge id="{nid}_out" from="{jid}" to="{nid}" {attrs}/>')
    # right turns: (from arm, to arm, corner centre, radius, start angle, end angle)
    rights = [
        ("N", "W", (-h - r.nw, h + r.nw), r.nw, 360, 270),
        ("E", "N", (h + r.ne, h + r.ne), r.ne, 270, 180),
        ("S", "E", (h + r.se, -h - r.se), r.se, 180, 90),
        ("W", "S", (-h - r.sw, -h - r.sw), r.sw, 90, 0),
    ]
    cons = []
    left_of = {"N": "E", "E": "S", "S": "W", "W": "N"}
    straight_of = {"N": "S", "E": "W", "S": "N", "W": "E"}
    for frm, to, centre, radius, a0, a1 in rights:
        pts = arc(centre, radius + off, a0, a1)
        # the approach lane's end and the exit lane's start, on the polygon
        start = _lane_point(frm, d[frm], lane0, inbound=True)
        end = _lane_point(to, d[to], lane0, inbound=False)
        relative = [start, *pts, end]
        shape = [(x + cx, y + cy) for x, y in relative]
        cons.append(
            f'<connection from="{jid}{frm}_in" to="{jid}{to}_out" fromLane="0" toLane="0" '
            f'shape="{fmt(shape)}"/>'
        )
    for frm in arms:
        s = straight_of[frm]
        for k in range(lanes):
            cons.append(
                f'<connection from="{jid}{frm}_in" to="{jid}{s}_out" fromLane="{k}" toLane="{k}"/>'
            )
        top = lanes - 1
        cons.append(
            f'<connection from="{jid}{frm}_in" to="{jid}{left_of[frm]}_out" '
            f'fromLane="{top}" toLane="{top}"/>'
        )
    return nodes, edges, cons


def _lane_point(arm: str, dist: float, off: float, inbound: bool) -> Point:
    """Where the rightmost lane of an arm meets the junction polygon (relative coords).

    ``dist`` is the arm's end from the junction centre, ``off`` the lane's centre from the
    road's centre line.
    """
    # inbound lanes drive toward the centre: their right side is to the west on the N arm
    table = {
        ("N", True): (-off, dist),
        ("N", False): (off, dist),
        ("E", True): (dist, off),
        ("E", False): (dist, -off),
        ("S", True): (off, -dist),
        ("S", False): (-off, -dist),
        ("W", True): (-dist, -off),
        ("W", False): (-dist, off),
    }
    return table[(arm, inbound)]


def tee(
    jid: str, cx: float, cy: float, r_sw: float, r_se: float, width_m: float, arm_m: float
) -> tuple[list[str], list[str], list[str]]:
    """A priority T-junction (arms W, E, S; one lane each way) with two corner radii."""
    h = width_m
    off = width_m / 2
    d_w, d_e, d_s = h + r_sw, h + r_se, h + max(r_sw, r_se)
    poly: list[Point] = [(-d_w, h), (d_e, h), (d_e, -h)]
    poly += arc((h + r_se, -h - r_se), r_se, 90, 180)
    poly += [(h, -d_s), (-h, -d_s)]
    poly += arc((-h - r_sw, -h - r_sw), r_sw, 0, 90)
    poly += [(-d_w, -h)]
    shape = [(x + cx, y + cy) for x, y in poly]
    nodes = [f'<node id="{jid}" x="{cx}" y="{cy}" type="priority" shape="{fmt(shape)}"/>']
    arms = {"E": (1, 0), "S": (0, -1), "W": (-1, 0)}
    edges = []
    for arm, (ux, uy) in arms.items():
        nid = f"{jid}{arm}"
        nodes.append(f'<node id="{nid}" x="{cx + ux * arm_m}" y="{cy + uy * arm_m}"/>')
        attrs = f'numLanes="1" width="{width_m}" speed="13.89"'
        prio = ' priority="2"' if arm in "EW" else ' priority="1"'
        edges.append(f'<edge id="{nid}_in" from="{nid}" to="{jid}" {attrs}{prio}/>')
        edges.append(f'<edge id="{nid}_out" from="{jid}" to="{nid}" {attrs}{prio}/>')
    cons = []
    for frm, to, centre, radius, a0, a1, dists in (
        ("W", "S", (-h - r_sw, -h - r_sw), r_sw, 90, 0, (d_w, d_s)),
        ("S", "E", (h + r_se, -h - r_se), r_se, 180, 90, (d_s, d_e)),
    ):
        start = _lane_point(frm, dists[0], h - off, inbound=True)
        end = _lane_point(to, dists[1], h - off, inbound=False)
        pts = [start, *arc(centre, radius + off, a0, a1), end]
        cons.append(
            f'<connection from="{jid}{frm}_in" to="{jid}{to}_out" fromLane="0" toLane="0" '
            f'shape="{fmt([(x + cx, y + cy) for x, y in pts])}"/>'
        )
    return nodes, edges, cons


#: The designs the README describes.
INTERSECTION_CORNERS = Corners(ne=12.0, se=15.0, sw=20.0, nw=9.5)
TEE_TIGHT_CORNER_M = 4.0
TEE_WIDE_CORNER_M = 12.0


def write_intersection(directory: Path) -> None:
    """The ``intersection`` sample: junction X (four legs) and T-junction T."""
    n1, e1, c1 = four_leg("X", 0.0, 0.0, INTERSECTION_CORNERS, 2, 3.25, 120.0)
    n2, e2, c2 = tee("T", 400.0, 0.0, TEE_TIGHT_CORNER_M, TEE_WIDE_CORNER_M, 3.5, 120.0)
    _write(directory, "intersection", n1 + n2, e1 + e2, c1 + c2)


# ----------------------------------------------------------------------------- roundabout


@dataclass(frozen=True)
class RingDesign:
    """A single-lane roundabout with four radial two-way arms (one lane each way).

    The ring lane's outer edge is the inscribed circle; an optional truck apron (a lane
    that only ``custom1`` may use: paved, not a traffic lane) lies inside it, and optional
    paved shoulders (likewise ``custom1`` lanes) flank the arms' lanes on the right, as
    entry and exit flares would. Entries and exits are circular arcs of ``entry_radius_m``
    / ``exit_radius_m`` (lane centre lines) tangent to the arm's lane and to the ring
    lane's centre line.
    """

    rid: str
    cx: float
    cy: float
    inscribed_diameter_m: float
    ring_lane_m: float
    entry_radius_m: float
    exit_radius_m: float
    apron_m: float = 0.0
    arm_m: float = 100.0
    arm_lane_m: float = 3.5
    shoulder_m: float = 0.0

    @property
    def ring_centre_radius_m(self) -> float:
        """Radius of the ring lane's centre line."""
        return self.inscribed_diameter_m / 2 - self.ring_lane_m / 2


ROUNDABOUTS = (
    RingDesign(
        "R",
        0.0,
        0.0,
        34.0,
        5.0,
        entry_radius_m=14.0,
        exit_radius_m=16.0,
        apron_m=9.0,
        shoulder_m=2.0,
    ),
    RingDesign("C", 300.0, 0.0, 26.0, 5.0, entry_radius_m=10.0, exit_radius_m=12.0),
)


def _reverse_curve(rc: float, lane_off: float, radius: float) -> tuple[float, float]:
    """Where an arc of ``radius`` tangent to the line y = lane_off meets the ring circle.

    Returns the x of the tangent point on the line and the ring angle (deg) of the
    tangent point on the circle (local frame: arm along +x, ring centred at the origin).
    """
    x_c = math.sqrt((rc + radius) ** 2 - (lane_off + radius) ** 2)
    phi = math.degrees(math.atan2(lane_off + radius, x_c))
    return x_c, phi


def ring(design: RingDesign) -> tuple[list[str], list[str], list[str]]:
    """Nodes, edges (with the ``<roundabout>`` element) and connections of one roundabout."""
    layout = _ring_layout(design)
    nodes: list[str] = []
    edges: list[str] = []
    cons: list[str] = []
    for k, ang in enumerate(_RING_ANGLES):
        nid = f"{design.rid}{k}"
        nodes += _arm_nodes(design, layout, nid, ang)
        edges += _arm_edges(design, nid)
        cons += _arm_connections(design, layout, k, ang)
    edges += _ring_edges(design, layout.r_mid)
    return nodes, edges, cons


#: Directions (deg) of a roundabout's arms, counter-clockwise from east.
_RING_ANGLES = (0, 90, 180, 270)


@dataclass(frozen=True)
class _RingLayout:
    """Radii and cuts of a roundabout (m, deg; local frame: an arm along +x, centre at 0).

    ``outer`` is the inscribed radius, ``inner`` the paved ring's inner edge (apron
    included), ``r_mid`` its centre line, ``rc`` the ring lane's centre line, ``off`` an arm
    lane's centre from the arm's axis; ``x_in``/``phi_in`` and ``x_out``/``phi_out`` are the
    entry's and exit's tangent points (:func:`_reverse_curve`); the ring is cut ``beta``
    either side of an arm, the arms at ``x = x_arm``.
    """

    outer: float
    inner: float
    r_mid: float
    rc: float
    off: float
    x_in: float
    phi_in: float
    x_out: float
    phi_out: float
    beta: float
    x_arm: float


def _ring_layout(design: RingDesign) -> _RingLayout:
    """The radii and cuts of ``design``."""
    outer = design.inscribed_diameter_m / 2
    width = design.ring_lane_m + design.apron_m
    inner = outer - width
    r_mid = outer - width / 2
    rc = design.ring_centre_radius_m
    off = design.arm_lane_m / 2
    x_in, phi_in = _reverse_curve(rc, off, design.entry_radius_m)
    x_out, phi_out = _reverse_curve(rc, off, design.exit_radius_m)
    beta = max(phi_in, phi_out) + 2.0  # where the ring lanes are cut, either side of an arm
    x_arm = max(x_in, x_out) + 2.0  # where the arms are cut
    return _RingLayout(outer, inner, r_mid, rc, off, x_in, phi_in, x_out, phi_out, beta, x_arm)


def _place(design: RingDesign, points: Iterable[Point], ang: float) -> list[Point]:
    """Local points turned by ``ang`` (deg) and moved to the roundabout's centre."""
    c, s_ = math.cos(math.radians(ang)), math.sin(math.radians(ang))
    return [(design.cx + x * c - y * s_, design.cy + x * s_ + y * c) for x, y in points]


def _arm_nodes(design: RingDesign, layout: _RingLayout, nid: str, ang: float) -> list[str]:
    """The ring junction ``nid`` where the arm at ``ang`` (deg) meets, and the arm's end."""
    outer, off, beta, x_arm = layout.outer, layout.off, layout.beta, layout.x_arm
    b = math.radians(beta)
    poly = arc((0, 0), layout.inner, -beta, beta, 3.0)
    half = 2 * off + design.shoulder_m  # half the arm's paved width
    poly += [(outer * math.cos(b), outer * math.sin(b)), (x_arm, half), (x_arm, -half)]
    poly += [(outer * math.cos(b), -outer * math.sin(b))]
    ((x, y),) = _place(design, [(layout.r_mid, 0.0)], ang)
    ((ax, ay),) = _place(design, [(outer + design.arm_m, 0.0)], ang)
    return [
        f'<node id="{nid}" x="{x:.3f}" y="{y:.3f}" type="priority" '
        f'shape="{fmt(_place(design, poly, ang))}"/>',
        f'<node id="{nid}a" x="{ax:.3f}" y="{ay:.3f}"/>',
    ]


def _arm_edges(design: RingDesign, nid: str) -> list[str]:
    """The two edges of the arm of junction ``nid`` (with a shoulder lane if designed)."""
    if design.shoulder_m:
        attrs = 'numLanes="2" speed="13.89" priority="1"'
        lanes = (
            f'<lane index="0" width="{design.shoulder_m}" allow="custom1"/>'
            f'<lane index="1" width="{design.arm_lane_m}"/>'
        )
    else:
        attrs = f'numLanes="1" width="{design.arm_lane_m}" speed="13.89" priority="1"'
        lanes = ""
    return [
        f'<edge id="{nid}_in" from="{nid}a" to="{nid}" {attrs}>{lanes}</edge>',
        f'<edge id="{nid}_out" from="{nid}" to="{nid}a" {attrs}>{lanes}</edge>',
    ]


def _arm_connections(design: RingDesign, layout: _RingLayout, k: int, ang: float
                     ) -> list[str]:
    """Entry, exit and through connections (and the apron's) at the ``k``-th junction."""
    rc, off, beta, x_arm = layout.rc, layout.off, layout.beta, layout.x_arm
    nid = f"{design.rid}{k}"
    arm_lane = 1 if design.shoulder_m else 0
    ring_in = f"{design.rid}ring{(k - 1) % 4}"
    ring_out = f"{design.rid}ring{k}"
    # entry: along the arm's lane, a right-hand arc onto the ring, round to the cut
    e_centre = (layout.x_in, off + design.entry_radius_m)
    entry: list[Point] = [(x_arm, off), (layout.x_in, off)]
    entry += arc(e_centre, design.entry_radius_m, -90, -90 - (90 - layout.phi_in))[1:]
    entry += arc((0, 0), rc, layout.phi_in, beta)[1:]
    # exit: round the ring from the cut, a right-hand arc onto the arm's lane
    x_centre = (layout.x_out, -off - design.exit_radius_m)
    exit_ = arc((0, 0), rc, -beta, -layout.phi_out)
    exit_ += arc(x_centre, design.exit_radius_m, 90 + (90 - layout.phi_out), 90)[1:]
    exit_ += [(x_arm, -off)]
    through = arc((0, 0), rc, -beta, beta)
    cons = [
        f'<connection from="{frm}" to="{to}" fromLane="{lane_from}" toLane="{lane_to}" '
        f'shape="{fmt(_place(design, pts, ang))}"/>'
        for frm, to, lane_from, lane_to, pts in (
            (f"{nid}_in", ring_out, arm_lane, 0, entry),
            (ring_in, f"{nid}_out", 0, arm_lane, exit_),
            (ring_in, ring_out, 0, 0, through),
        )
    ]
    if design.apron_m:
        cons.append(f'<connection from="{ring_in}" to="{ring_out}" fromLane="1" toLane="1"/>')
    return cons


def _ring_edges(design: RingDesign, r_mid: float) -> list[str]:
    """The four ring edges (centre line at ``r_mid``) and the ``<roundabout>`` element."""
    edges: list[str] = []
    ring_ids: list[str] = []
    for k, ang in enumerate(_RING_ANGLES):
        eid = f"{design.rid}ring{k}"
        ring_ids.append(eid)
        pts = arc((design.cx, design.cy), r_mid, ang, ang + 90, 3.0)
        lanes = f'<lane index="0" width="{design.ring_lane_m}"/>'
        if design.apron_m:
            lanes += f'<lane index="1" width="{design.apron_m}" allow="custom1"/>'
        edges.append(
            f'<edge id="{eid}" from="{design.rid}{k}" to="{design.rid}{(k + 1) % 4}" '
            f'numLanes="{2 if design.apron_m else 1}" speed="8.33" priority="3" '
            f'spreadType="center" shape="{fmt(pts)}">{lanes}</edge>'
        )
    ring_nodes = " ".join(f"{design.rid}{k}" for k in range(4))
    edges.append(f'<roundabout nodes="{ring_nodes}" edges="{" ".join(ring_ids)}"/>')
    return edges


def write_roundabout(directory: Path) -> None:
    """The ``roundabout`` sample: a 34 m roundabout with a truck apron and a 26 m compact one."""
    nodes: list[str] = []
    edges: list[str] = []
    cons: list[str] = []
    for design in ROUNDABOUTS:
        n, e, c = ring(design)
        nodes += n
        edges += e
        cons += c
    _write(directory, "roundabout", nodes, edges, cons)


# --------------------------------------------------------------------------- parking ramp

HELIX_RADIUS_M = 7.5
HELIX_RISE_PER_TURN_M = 3.0
HELIX_TURNS = 2.25
HELIX_LANE_M = 3.5


def write_parking_ramp(directory: Path) -> None:
    """The ``parking_ramp`` sample: a one-way rising helix with a short approach and exit."""
    # the lead-in and lead-out keep the end junctions 9 m clear of the helix: netconvert cuts
    # an edge where it crosses its end junction's polygon, in plan, whatever the level
    r, lead = HELIX_RADIUS_M, 15.0
    a0, a1 = -90.0, -90.0 + 360.0 * HELIX_TURNS
    top = HELIX_RISE_PER_TURN_M * HELIX_TURNS
    n = int(math.ceil((a1 - a0) / 5.0))
    helix = [
        (r * math.cos(math.radians(a)), r * math.sin(math.radians(a)), top * (a - a0) / (a1 - a0))
        for a in np.linspace(a0, a1, n + 1)
    ]
    end = helix[-1]
    t = math.radians(a1)
    tangent = (-math.sin(t), math.cos(t))
    out = (end[0] + lead * tangent[0], end[1] + lead * tangent[1], top)
    far = (end[0] + (lead + 30) * tangent[0], end[1] + (lead + 30) * tangent[1], top)
    pts = [(-lead, -r, 0.0), *helix, out]
    nodes = [
        f'<node id="A" x="{-lead - 30:.3f}" y="{-r:.3f}" z="0"/>',
        f'<node id="H0" x="{-lead:.3f}" y="{-r:.3f}" z="0"/>',
        f'<node id="H1" x="{out[0]:.3f}" y="{out[1]:.3f}" z="{top:.3f}"/>',
        f'<node id="B" x="{far[0]:.3f}" y="{far[1]:.3f}" z="{top:.3f}"/>',
    ]
    attrs = f'numLanes="1" width="{HELIX_LANE_M}" speed="4.17" spreadType="center"'
    edges = [
        f'<edge id="approach" from="A" to="H0" {attrs}/>',
        f'<edge id="helix" from="H0" to="H1" {attrs} shape="{fmt(pts)}"/>',
        f'<edge id="exit" from="H1" to="B" {attrs}/>',
    ]
    _write(directory, "parking_ramp", nodes, edges)


# --------------------------------------------------------------------------- helix

#: The ``helix`` sample (issue 17): three turns of radius 9 m, 3.5 m lane, 3.2 m per turn.
LEVEL_HELIX_RADIUS_M = 9.0
LEVEL_HELIX_RISE_PER_TURN_M = 3.2
LEVEL_HELIX_TURNS = 3
LEVEL_HELIX_LANE_M = 3.5


def _helix_points(
    centre: tuple[float, float], radius_m: float, a0_deg: float, turn_deg: float,
    z0_m: float, z1_m: float, step_deg: float = 5.0,
) -> list[Point]:
    """Points of a helix (an arc whose z rises linearly from ``z0_m`` to ``z1_m``).

    Examples
    --------
    >>> [tuple(round(v, 3) for v in p) for p in _helix_points((0, 0), 2.0, 0, 180, 0, 1, 90)]
    [(2.0, 0.0, 0.0), (0.0, 2.0, 0.5), (-2.0, 0.0, 1.0)]
    """
    n = max(int(math.ceil(abs(turn_deg) / step_deg)), 1)
    a = np.linspace(a0_deg, a0_deg + turn_deg, n + 1)
    z = np.linspace(z0_m, z1_m, n + 1)
    return [(centre[0] + radius_m * math.cos(math.radians(t)),
             centre[1] + radius_m * math.sin(math.radians(t)), float(h))
            for t, h in zip(a, z, strict=True)]


def write_helix(directory: Path) -> None:
    """The ``helix`` sample: a one-way helix of :data:`LEVEL_HELIX_TURNS` turns, in and out
    by straights. It starts and ends heading east at the bottom of its circle, so that in
    plan its turns lie on each other and the exit straight lies over the first turn's
    start, one storey per turn above it."""
    r, lead = LEVEL_HELIX_RADIUS_M, 15.0
    top = LEVEL_HELIX_RISE_PER_TURN_M * LEVEL_HELIX_TURNS
    helix = _helix_points((0.0, 0.0), r, -90.0, 360.0 * LEVEL_HELIX_TURNS, 0.0, top)
    pts = [(-lead, -r, 0.0), *helix, (lead, -r, top)]
    nodes = [
        f'<node id="A" x="{-lead - 30:.3f}" y="{-r:.3f}" z="0"/>',
        f'<node id="H0" x="{-lead:.3f}" y="{-r:.3f}" z="0"/>',
        f'<node id="H1" x="{lead:.3f}" y="{-r:.3f}" z="{top:.3f}"/>',
        f'<node id="B" x="{lead + 30:.3f}" y="{-r:.3f}" z="{top:.3f}"/>',
    ]
    attrs = f'numLanes="1" width="{LEVEL_HELIX_LANE_M}" speed="4.17" spreadType="center"'
    edges = [
        f'<edge id="approach" from="A" to="H0" {attrs}/>',
        f'<edge id="helix" from="H0" to="H1" {attrs} shape="{fmt(pts)}"/>',
        f'<edge id="exit" from="H1" to="B" {attrs}/>',
    ]
    _write(directory, "helix", nodes, edges)


# --------------------------------------------------------------------------- garage

#: The ``garage`` sample (issue 17): storey height, the lanes' widths, the turnaround's
#: radius and the radius of the upper floor's corner.
GARAGE_STOREY_M = 3.5
GARAGE_AISLE_M = 6.5
GARAGE_DECK_M = 3.0
GARAGE_RAMP_M = 3.5
GARAGE_RADIUS_M = 10.0
GARAGE_CORNER_M = 6.6


def _teardrop(radius_m: float, step_deg: float = 5.0) -> list[Point]:
    """A turnaround from (0, 0) heading east back to (0, 0) heading west: right 60 degrees,
    left 300 degrees, right 60 degrees, all of ``radius_m`` (its neck is the origin).

    Examples
    --------
    >>> t = _teardrop(9.0)
    >>> [round(v, 6) + 0.0 for v in t[0] + t[-1]]
    [0.0, 0.0, 0.0, 0.0]
    """
    r = radius_m
    a = arc((0.0, -r), r, 90.0, 30.0, step_deg)
    b = arc((math.sqrt(3.0) * r, 0.0), r, 210.0, 510.0, step_deg)
    c = arc((0.0, r), r, -30.0, -90.0, step_deg)
    return [*a, *b[1:], *c[1:]]


def write_garage(directory: Path) -> None:
    """The ``garage`` sample: two storeys joined by a ramp that turns round in a teardrop.

    The lower floor's aisle (z 0) comes north; the ramp begins with a wide bend to the
    right (radius 14.4 m, the aisle's width, and 15 m straight on), rises one storey round
    the teardrop, comes back west above its own start and turns left round a tight corner
    (radius :data:`GARAGE_CORNER_M`) onto the narrow deck lane, which runs south exactly
    above the aisle. The wide bend passes under the inside of that corner: in plan the ramp's own
    lanes there cover the inside of the corner, where a vehicle offtracks, so judged in
    plan it stays on its own lanes; judged by level it leaves the only lane of its floor."""
    r, c = GARAGE_RADIUS_M, GARAGE_CORNER_M
    corner = (-30.0, -c)  # the upper corner's centre: from heading west to heading south
    d = 11.0  # the wide bend's centre lies this far from the corner's, away from its inside
    bend_r = c + d / math.sqrt(2.0)  # its top is at y = 0, its west point under the deck
    bend = (corner[0] + d / math.sqrt(2.0), corner[1] - d / math.sqrt(2.0))
    x_deck = corner[0] - c
    # the wide lane goes on 15 m past the bend before the ramp narrows (node B), so that
    # a vehicle reaches B straightened out
    bend_pts = arc(bend, bend_r, 180.0, 90.0)
    plan = [(x_deck, bend[1]), *bend_pts[1:], (bend[0] + 15.0, 0.0), *_teardrop(r),
            *arc(corner, c, 90.0, 180.0), (x_deck, -20.0)]
    xy = np.array(plan)
    s = np.concatenate(([0.0], np.cumsum(np.hypot(*np.diff(xy, axis=0).T))))
    z = GARAGE_STOREY_M * s / s[-1]
    pts = [(float(x), float(y), float(h)) for (x, y), h in zip(plan, z, strict=True)]
    # cut where the bend ends (node B) and at the apex (node M): netconvert cuts an edge
    # where it passes over its own end junctions in plan, whatever the level, and the
    # ramp's return passes over B
    b = len(bend_pts)
    apex = int(np.argmax(xy[:, 0]))
    u = pts[-1]
    nodes = [
        f'<node id="A" x="{x_deck:.3f}" y="-70.000" z="0"/>',
        f'<node id="S" x="{x_deck:.3f}" y="{bend[1]:.3f}" z="0"/>',
        f'<node id="B" x="{pts[b][0]:.3f}" y="{pts[b][1]:.3f}" z="{pts[b][2]:.3f}"/>',
        f'<node id="M" x="{pts[apex][0]:.3f}" y="{pts[apex][1]:.3f}" z="{pts[apex][2]:.3f}"/>',
        f'<node id="U" x="{u[0]:.3f}" y="{u[1]:.3f}" z="{u[2]:.3f}"/>',
        f'<node id="D" x="{u[0]:.3f}" y="-50.000" z="{u[2]:.3f}"/>',
    ]
    common = 'numLanes="1" speed="4.17" spreadType="center"'
    wide, ramp = f'{common} width="{GARAGE_AISLE_M}"', f'{common} width="{GARAGE_RAMP_M}"'
    edges = [
        f'<edge id="aisle" from="A" to="S" {wide}/>',
        f'<edge id="ramp_in" from="S" to="B" {wide} shape="{fmt(pts[: b + 1])}"/>',
        f'<edge id="ramp_up" from="B" to="M" {ramp} shape="{fmt(pts[b: apex + 1])}"/>',
        f'<edge id="ramp_down" from="M" to="U" {ramp} shape="{fmt(pts[apex:])}"/>',
        f'<edge id="deck" from="U" to="D" {common} width="{GARAGE_DECK_M}"/>',
    ]
    _write(directory, "garage", nodes, edges)


WRITERS = {
    "intersection": write_intersection,
    "roundabout": write_roundabout,
    "parking_ramp": write_parking_ramp,
    "helix": write_helix,
    "garage": write_garage,
}


def main() -> int:
    for name, writer in WRITERS.items():
        writer(SAMPLES_DIR / name)
        print(f"wrote the sources of {name}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
