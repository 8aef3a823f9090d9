"""Plan figures of networks, drawn from our own reader: lanes, junctions, scale, north."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import shapely

from clearance.networks.areas import lane_polygons
from clearance.networks.model import Network
from clearance.networks.reader import read_network

__all__ = ["EDGE_OF_PAVEMENT", "JUNCTION", "LANE_LINE", "MAX_MARKED_LANES", "NON_ROAD", "PAVEMENT",
           "draw_lines", "fill_geometry", "fill_polygons", "nice_scale_m", "pavement_area",
           "plot_plan", "save_plan"]


def nice_scale_m(span_m: float) -> float:
    """A round scale-bar length of about a fifth of ``span_m`` (1, 2, 5 × 10^k metres).

    Examples
    --------
    >>> nice_scale_m(100.0), nice_scale_m(37.0), nice_scale_m(0.0)
    (20.0, 5.0, 1.0)
    """
    if span_m <= 0:
        return 1.0
    target = span_m / 5
    base = 10 ** math.floor(math.log10(target))
    for m in (5, 2, 1):
        if m * base <= target:
            return float(m * base)
    return float(base)


def fill_geometry(ax, geom, **kw) -> None:
    """Fill (multi)polygons, holes left open: one patch for the whole geometry (its
    polygons do not overlap).

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> fill_geometry(ax, shapely.box(0, 0, 2, 2).difference(shapely.box(0.5, 0.5, 1, 1)))
    >>> fill_geometry(ax, shapely.Polygon())             # nothing to fill: no patch
    >>> len(ax.patches)
    1
    >>> plt.close(fig)
    """
    from matplotlib.patches import PathPatch
    from matplotlib.path import Path as MplPath

    rings = [MplPath(r, closed=True) for poly in _polygons(geom) for r in _rings(poly)]
    if rings:
        ax.add_patch(PathPatch(MplPath.make_compound_path(*rings), **kw))


def fill_polygons(ax, geoms, **kw) -> None:
    """Fill many (multi)polygons as one collection (one artist however many there are: a
    town's plan has thousands), each polygon on its own with its holes left open, so that
    overlapping ones fill alike.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> fill_polygons(ax, [shapely.box(0, 0, 1, 1), shapely.box(0.5, 0, 2, 1)], color="grey")
    >>> fill_polygons(ax, [])                            # nothing to fill: no collection
    >>> len(ax.collections), [float(v) for v in ax.dataLim.bounds]
    (1, [0.0, 0.0, 2.0, 1.0])
    >>> plt.close(fig)
    """
    from matplotlib.collections import PathCollection
    from matplotlib.path import Path as MplPath

    paths = [MplPath.make_compound_path(*[MplPath(r, closed=True) for r in _rings(poly)])
             for g in geoms for poly in _polygons(g)]
    if paths:
        ax.add_collection(PathCollection(paths, transform=ax.transData, **kw))


def draw_lines(ax, lines, **kw) -> None:
    """Draw many polylines (arrays of x, y) as one collection.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> fig, ax = plt.subplots()
    >>> draw_lines(ax, [np.array([[0.0, 0.0], [3.0, 4.0]]), np.zeros((1, 2))])
    >>> len(ax.collections), len(ax.collections[0].get_segments())  # a lone point: no line
    (1, 1)
    >>> plt.close(fig)
    """
    from matplotlib.collections import LineCollection

    segments = [np.asarray(xy, dtype=float)[:, :2] for xy in lines if len(xy) >= 2]
    if segments:
        ax.add_collection(LineCollection(segments, **kw))


def _polygons(geom) -> list:
    """The non-empty polygons of a (multi)polygon or collection."""
    return [p for p in getattr(geom, "geoms", [geom])
            if not p.is_empty and p.geom_type == "Polygon"]


def _rings(poly) -> list[np.ndarray]:
    """A polygon's exterior and holes as (N, 2) arrays."""
    return [np.asarray(r.coords)[:, :2] for r in (poly.exterior, *poly.interiors)]


#: Colours of the base plan (a CAD-like drawing: grey pavement, white lane lines, black
#: edge of pavement).
PAVEMENT = "#d5d5d5"
JUNCTION = "#c4c4c4"
NON_ROAD = "#e8dcb0"
EDGE_OF_PAVEMENT = "#111111"
LANE_LINE = "#ffffff"
#: Above this many lanes in view the lane lines are left out (an overview of a city).
MAX_MARKED_LANES = 600


def pavement_area(net: Network, lane_ids: list[str], junctions: list) -> shapely.Geometry:
    """The paved surface of road lanes and junctions: one area, seams between lanes closed.

    Its boundary is the edge of pavement (curb): lanes of one road and the junctions
    between them leave no line inside it.

    Examples
    --------
    >>> from clearance.networks.reader import Lane, Network, Location
    >>> shape = lambda y: np.array([[0, y, 0], [10, y, 0.0]])
    >>> lanes = {f"e_{i}": Lane(f"e_{i}", "e", i, 3.0, "normal", frozenset(), shape(3.0 * i),
    ...                         10.0, 13.9) for i in range(2)}
    >>> net = Network(None, lanes, {}, [], {}, [], Location())
    >>> a = pavement_area(net, list(lanes), [])
    >>> a.geom_type, round(a.area, 6), len(a.interiors)
    ('Polygon', 60.0, 0)
    >>> pavement_area(net, [], []).is_empty                         # nothing paved
    True
    """
    polys = list(lane_polygons(net, lane_ids)) if lane_ids else []
    polys += [shapely.Polygon(j.shape[:, :2]) for j in junctions if len(j.shape) >= 3]
    if not polys:
        return shapely.Polygon()
    polys = [shapely.make_valid(p) for p in polys]
    seam = 0.05  # closes the hair-line gaps where a lane meets its junction
    area = shapely.union_all(shapely.buffer(np.array(polys, dtype=object), seam,
                                            join_style="mitre"))
    return shapely.buffer(area, -seam, join_style="mitre")


def plot_plan(
    net: Network,
    ax,
    title: str | None = None,
    bounds: tuple[float, float, float, float] | None = None,
    decorate: bool = True,
) -> None:
    """Draw a network's plan on a matplotlib axis (metres, x east, y north).

    The pavement in grey with the lane lines in white (between lanes of one road and of
    the two directions) and the edge of pavement in black, only where the pavement ends;
    lanes closed to road vehicles (sidewalks, bicycle lanes) in sand. ``bounds``
    (x min, x max, y min, y max) zooms in; the default shows everything. ``decorate`` adds
    axis labels, a scale bar and a north arrow in metres (the reports draw their own in the
    report's units).
    """
    lanes = net.lanes
    junctions = list(net.junctions.values())
    if bounds is not None:
        # only what can show in the view: a curve's figure of a city network stays small
        x0, x1, y0, y1 = bounds
        pad = 10.0

        def near(shape: np.ndarray) -> bool:
            return bool(len(shape)) and not (
                shape[:, 0].max() < x0 - pad or shape[:, 0].min() > x1 + pad
                or shape[:, 1].max() < y0 - pad or shape[:, 1].min() > y1 + pad)

        lanes = {k: lane for k, lane in lanes.items() if near(lane.shape)}
        junctions = [j for j in junctions if near(j.shape)]
    road = [k for k, lane in lanes.items() if lane.allows_road_vehicles()]
    other = [k for k, lane in lanes.items() if not lane.allows_road_vehicles()]
    fill_polygons(ax, [shapely.make_valid(p) for p in lane_polygons(net, other)] if other
                  else [], color=NON_ROAD, lw=0, zorder=1)
    paved = pavement_area(net, road, junctions)
    fill_polygons(ax, [paved], color=PAVEMENT, lw=0, zorder=1.5)
    fill_polygons(ax, [shapely.Polygon(j.shape[:, :2]) for j in junctions
                       if len(j.shape) >= 3], color=JUNCTION, lw=0, zorder=1.6)
    normal = [k for k in road if not net.lanes[k].is_internal]
    if len(normal) <= MAX_MARKED_LANES:
        draw_lines(ax, [np.asarray(part.coords) for k in normal for part in _lane_edges(net, k)],
                   color=LANE_LINE, lw=0.7, linestyle=(0, (4, 3)), zorder=2)
    draw_lines(ax, [np.asarray(ring.coords) for poly in _polygons(paved)
                    for ring in (poly.exterior, *poly.interiors)],
               color=EDGE_OF_PAVEMENT, lw=1.1, zorder=3)
    ax.set_aspect("equal")
    if bounds is not None:
        ax.set_xlim(bounds[0], bounds[1])
        ax.set_ylim(bounds[2], bounds[3])
    else:
        ax.autoscale_view()
    if title:
        ax.set_title(title)
    if not decorate:
        return
    ax.set_xlabel("x [m] (east)")
    ax.set_ylabel("y [m] (north)")
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    height = y1 - y0
    bar = nice_scale_m(x1 - x0)
    bx, by = x0 + 0.05 * (x1 - x0), y0 + 0.05 * height
    ax.plot([bx, bx + bar], [by, by], color="black", lw=3, solid_capstyle="butt", zorder=5)
    ax.text(bx + bar / 2, by + 0.015 * height, f"{bar:g} m", ha="center", va="bottom", fontsize=8)
    nx, ny = x1 - 0.06 * (x1 - x0), y1 - 0.16 * height
    ax.annotate(
        "N",
        xy=(nx, ny + 0.1 * height),
        xytext=(nx, ny),
        ha="center",
        va="top",
        fontsize=10,
        fontweight="bold",
        arrowprops={"arrowstyle": "-|>", "color": "black", "lw": 1.5},
        zorder=5,
    )


def _lane_edges(net: Network, lane_id: str) -> list:
    """The two edges of a lane (lines half its width either side of its centre line)."""
    lane = net.lanes[lane_id]
    line = shapely.LineString(lane.shape[:, :2])
    out = []
    for side in (1, -1):
        edge = shapely.offset_curve(line, side * lane.width_m / 2)
        out += [part for part in getattr(edge, "geoms", [edge]) if not part.is_empty]
    return out


def save_plan(
    net_path: Path,
    png_path: Path,
    views: list[tuple[str, tuple[float, float, float, float] | None]] | None = None,
) -> Path:
    """Read a network and write its plan as a PNG, one panel per view (no GUI needed).

    Each view is a title and bounds (x min, x max, y min, y max) or None for everything.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    net = read_network(net_path)
    views = views or [(Path(net_path).name, None)]
    fig, axes = plt.subplots(1, len(views), figsize=(5.5 * len(views), 5.5), dpi=100, squeeze=False)
    for ax, (title, bounds) in zip(axes[0], views, strict=True):
        plot_plan(net, ax, title, bounds)
    fig.tight_layout()
    fig.savefig(png_path)
    plt.close(fig)
    return png_path
