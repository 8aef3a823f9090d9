"""The plan of a network (clearance.networks.plot): a few artists however large the
network, every junction and lane edge in them."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import to_rgba  # noqa: E402

from clearance.networks.plot import EDGE_OF_PAVEMENT, JUNCTION, plot_plan  # noqa: E402
from clearance.networks.reader import read_network  # noqa: E402
from clearance.networks.samples.build import sample_networks  # noqa: E402


def test_a_plan_is_a_few_collections_holding_every_junction():
    path = next(p for p in sample_networks() if p.stem.startswith("roundabout"))
    net = read_network(path)
    fig, ax = plt.subplots()
    try:
        plot_plan(net, ax, decorate=False)
        # one artist per kind of thing drawn, not one per lane or junction (a town's
        # plan had 19,000 patches and took 17 s)
        assert len(ax.patches) + len(ax.lines) + len(ax.collections) <= 5
        shaped = sum(len(j.shape) >= 3 for j in net.junctions.values())
        assert shaped > 5
        [junctions] = [c for c in ax.collections if len(c.get_facecolor())
                       and np.allclose(c.get_facecolor()[0], to_rgba(JUNCTION))]
        assert len(junctions.get_paths()) == shaped
        [edges] = [c for c in ax.collections
                   if len(c.get_edgecolor()) and np.allclose(c.get_edgecolor()[0],
                                                             to_rgba(EDGE_OF_PAVEMENT))]
        assert len(edges.get_segments()) >= 2  # the ring's outer and inner edges
        x0, y0, x1, y1 = ax.dataLim.extents
        xy = np.vstack([lane.shape[:, :2] for lane in net.lanes.values()])
        assert x0 <= xy[:, 0].min() and x1 >= xy[:, 0].max()
        assert y0 <= xy[:, 1].min() and y1 >= xy[:, 1].max()
    finally:
        plt.close(fig)
