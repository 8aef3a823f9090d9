"""Drive the design vehicles through the sample networks and print the verdict tables.

The README's tables come from this script::

    python -m clearance.networks.samples.verdicts            # Markdown tables on stdout

Vehicles: the AASHTO design vehicles P, SU-30, CITY-BUS and WB-62 (bundled table
``aashto_green_book``) and a large van (the 2008 Chrysler Town & Country of
``paper_table1``). Each drives lane-keeping along the curve's (smoothed) centre line at
crawl speed with the kinematic model, exactly as ``clearance report`` drives it
(:func:`clearance.networks.driving.drive.drive`, here without SUMO, which only replays the model);
its swept envelope is measured against the curve's own lanes, roadway and paved area, with no
clearance offset.
"""

from __future__ import annotations

import sys

from clearance.networks.curves import Curve, extract_curves
from clearance.networks.driving.drive import DriveOptions, drive
from clearance.networks.reader import read_network
from clearance.networks.samples.build import SAMPLES, SAMPLES_DIR
from clearance.vehicles.table import bundled_table, load_tables

__all__ = ["SHORT", "VEHICLES", "curves_of", "main", "table"]

VEHICLES = ("P", "2008 Chrysler Town & Country", "SU-30", "CITY-BUS", "WB-62")
SHORT = {"2008 Chrysler Town & Country": "van"}


def curves_of(name: str) -> list[Curve]:
    """The curves of a sample worth a verdict (no straight-on turns; one roundabout arm)."""
    net = read_network(SAMPLES_DIR / name / f"{name}.net.xml")
    out = []
    for c in extract_curves(net):
        if c.kind == "turn" and abs(c.turn_angle_deg) < 30:
            continue
        if c.kind == "roundabout" and c.junction not in ("R0", "C0"):
            continue  # the four arms of each ring are alike
        out.append(c)
    return out


def table(name: str) -> str:
    """A Markdown table of verdicts (own-lane margin in metres) for one sample."""
    vehicles = load_tables(
        [bundled_table("aashto_green_book"), bundled_table("paper_table1")], names=VEHICLES
    ).vehicles()
    heads = ["curve", "R min [m]", "turn [°]", *(SHORT.get(v.name, v.name) for v in vehicles)]
    lines = ["| " + " | ".join(heads) + " |", "|" + "---|" * len(heads)]
    net = read_network(SAMPLES_DIR / name / f"{name}.net.xml")
    for c in curves_of(name):
        # the kinematic model on the smoothed centre line, as `clearance report` drives it
        runs = drive(net, [(v, c) for v in vehicles],
                     options=DriveOptions(use_sumo=False, swing=False))
        cells = [f"`{c.curve_id}`", f"{c.min_radius_m:.1f}", f"{round(c.turn_angle_deg):+d}"]
        for run in runs:
            if run.result is None:  # without SUMO every run has its model result
                raise RuntimeError(f"{run.vehicle.name} x {c.curve_id}: {run.error}")
            cells.append(f"{run.verdict} ({run.result.margin_m:+.2f})")
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    names = (argv if argv is not None else sys.argv[1:]) or list(SAMPLES)
    for name in names:
        print(f"### {name}\n\n{table(name)}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
