"""Designed right-hand corners for the swung-path tests (plain XML for netconvert).

An L corner: the approach runs east along y = 0 into junction J at the origin, the exit
south along x = 0. Each road has ``fwd`` lanes in the driving direction (right of its axis)
and ``opp`` opposing lanes (left of it), all ``width_m`` wide. The inside curb is a circular
arc of ``radius_m`` (the junction polygon's corner); each lane k's right turn is an arc
concentric with it at ``radius_m + (k + 0.5) width_m``. The paved area is the lanes and the
junction polygon only.
"""

from __future__ import annotations

import math


def _fmt(points: list[tuple[float, float]]) -> str:
    return " ".join(f"{x:.3f},{y:.3f}" for x, y in points)


def _arc(cx: float, cy: float, r: float, a0: float, a1: float, n: int = 24
         ) -> list[tuple[float, float]]:
    return [(cx + r * math.cos(math.radians(a0 + (a1 - a0) * i / n)),
             cy + r * math.sin(math.radians(a0 + (a1 - a0) * i / n))) for i in range(n + 1)]


def corner(radius_m: float, fwd: int, opp: int, width_m: float, arm_m: float = 60.0
           ) -> tuple[str, str, str]:
    """Nodes, edges and connections of the corner (see the module docstring)."""
    n, m, w, r = fwd, opp, width_m, radius_m
    c = n * w + r  # where the roads meet the junction polygon
    poly = [(-c, m * w), (-c, -n * w), *_arc(-c, -c, r, 90, 0)[1:-1], (-n * w, -c),
            (m * w, -c), (m * w, m * w)]
    nodes = (f'<node id="J" x="0" y="0" type="priority" shape="{_fmt(poly)}"/>'
             f'<node id="A" x="{-arm_m}" y="0"/><node id="B" x="0" y="{-arm_m}"/>')
    attrs = f'width="{w}" speed="13.89" spreadType="right"'
    edges = (f'<edge id="AJ" from="A" to="J" numLanes="{n}" {attrs}/>'
             f'<edge id="JB" from="J" to="B" numLanes="{n}" {attrs}/>')
    if m:
        edges += (f'<edge id="JA" from="J" to="A" numLanes="{m}" {attrs}/>'
                  f'<edge id="BJ" from="B" to="J" numLanes="{m}" {attrs}/>')
    cons = ""
    for k in range(n):
        off = (n - k - 0.5) * w  # lane k's centre from the road's axis (0 is rightmost)
        rr = r + (k + 0.5) * w
        shape = [(-c, -off), *_arc(-c, -c, rr, 90, 0), (-off, -c)]
        cons += (f'<connection from="AJ" to="JB" fromLane="{k}" toLane="{k}" '
                 f'shape="{_fmt(shape)}"/>')
    return nodes, edges, cons
