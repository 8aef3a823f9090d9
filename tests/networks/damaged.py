"""Sample networks damaged one way each: what SUMO refuses, and numbers out of range.

Each case is (sample, damage, expected message after the file name). The damage replaces
an exact piece of the sample's text, so a sample that changes fails loudly here
(:func:`damage`) instead of testing nothing.
"""

from __future__ import annotations

import re
from pathlib import Path

from networks.samples.sources import SAMPLES_DIR

LANE = '<lane id="TE_in_0" index="0" speed="13.89" length="104.50" width="3.50" '
CONNECTION = '<connection from="TE_in" to="TW_out" fromLane="0" toLane="0" via=":T_0_0" '
TAG = '<connection from="TE_in" to="TW_out">'


def _offset_all(text: str, by: float) -> str:
    """Every shape point and junction position moved by ``by`` metres in x and y."""
    def shape(m: re.Match[str]) -> str:
        pts = []
        for pt in m.group(1).split():
            v = pt.split(",")
            pts.append(",".join([repr(float(v[0]) + by), repr(float(v[1]) + by), *v[2:]]))
        return f'shape="{" ".join(pts)}"'

    text = re.sub(r'shape="([^"]*)"', shape, text)
    return re.sub(r' ([xy])="([-0-9.]+)"', lambda m: f' {m.group(1)}="{float(m.group(2)) + by!r}"',
                  text)


#: name -> (sample, (old, new) or a function of the text, expected message)
CASES: dict[str, tuple[str, object, str]] = {
    "via-to-a-missing-lane": (
        "intersection", (CONNECTION, CONNECTION.replace(":T_0_0", ":nope_0")),
        f"{TAG}: via lane ':nope_0' does not exist"),
    "unknown-to-edge": (
        "intersection", (CONNECTION, CONNECTION.replace('to="TW_out"', 'to="NOPE"')),
        "<connection from=\"TE_in\" to=\"NOPE\">: unknown to-edge 'NOPE'"),
    "unknown-from-edge": (
        "intersection", (CONNECTION, CONNECTION.replace('from="TE_in"', 'from="NOPE"')),
        "<connection from=\"NOPE\" to=\"TW_out\">: unknown from-edge 'NOPE'"),
    "duplicate-edge": (
        "intersection", ('<edge id="TE_out" ', '<edge id="TE_in" '),
        "edge 'TE_in' is defined twice"),
    "from-lane-out-of-range": (
        "intersection", (CONNECTION, CONNECTION.replace('fromLane="0"', 'fromLane="7"')),
        f"{TAG}: fromLane 7 out of range (edge 'TE_in' has 1 lane(s))"),
    "to-lane-out-of-range": (
        "intersection", (CONNECTION, CONNECTION.replace('toLane="0"', 'toLane="-1"')),
        f"{TAG}: toLane -1 out of range (edge 'TW_out' has 1 lane(s))"),
    "lane-index-out-of-range": (
        "intersection", (LANE, LANE.replace('index="0"', 'index="3"')),
        "lane 'TE_in_0': index 3 out of range (edge 'TE_in' has 1 lane(s))"),
    "roundabout-unknown-edge": (
        "roundabout", ('edges="Cring0 Cring1', 'edges="NOPE Cring1'),
        "<roundabout edges=...>: unknown edge(s) 'NOPE'"),
    "roundabout-unknown-junction": (
        "roundabout", ('nodes="C0 C1', 'nodes="C0 NOPE'),
        "<roundabout nodes=...>: unknown junction(s) 'NOPE'"),
    "lane-width-nan": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="nan"')),
        "lane 'TE_in_0': width 'nan': not a width in (0, 50] m"),
    "lane-width-huge": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="1e12"')),
        "lane 'TE_in_0': width '1e12': not a width in (0, 50] m"),
    "lane-width-negative": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="-3.5"')),
        "lane 'TE_in_0': width '-3.5': not a width in (0, 50] m"),
    "lane-width-zero": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="0"')),
        "lane 'TE_in_0': width '0': not a width in (0, 50] m"),
    "coordinate-1e300": (
        "intersection", (LANE + 'shape="520.00,', LANE + 'shape="1e300,'),
        "lane 'TE_in_0': coordinate beyond +/-1e+08 m in shape '1e300,1.75 415.50,1.75' "
        "(precision would be lost)"),
    "coordinate-inf": (
        "intersection", (LANE + 'shape="520.00,', LANE + 'shape="inf,'),
        "lane 'TE_in_0': non-finite coordinate in shape 'inf,1.75 415.50,1.75'"),
    "coordinate-nan": (
        "intersection", (LANE + 'shape="520.00,', LANE + 'shape="nan,'),
        "lane 'TE_in_0': non-finite coordinate in shape 'nan,1.75 415.50,1.75'"),
    "all-coordinates-offset-1e15": (
        "intersection", lambda text: _offset_all(text, 1e15),
        "bad value in <junction T>: coordinate '1000000000000400.0' is not a number within "
        "+/-1e+08 m"),
    "junction-x-nan": (
        "intersection", ('<junction id="T" type="priority" x="400.00"',
                         '<junction id="T" type="priority" x="nan"'),
        "bad value in <junction T>: coordinate 'nan' is not a number within +/-1e+08 m"),
    "net-offset-nan": (
        "intersection", ('netOffset="0.00,0.00"', 'netOffset="nan,0.00"'),
        "bad value in <location netOffset='nan,0.00'"),
    "net-offset-huge": (
        "intersection", ('netOffset="0.00,0.00"', 'netOffset="1e15,0.00"'),
        "bad value in <location netOffset='1e15,0.00'"),
    "conv-boundary-inf": (
        "intersection", ('convBoundary="-120.00', 'convBoundary="-inf'),
        "bad value in <location netOffset='0.00,0.00'"),
}


def damage(case: str, directory: Path) -> tuple[Path, str]:
    """The damaged file of ``case`` written in ``directory``, and the full expected message
    (the file name, then the case's message)."""
    sample, change, message = CASES[case]
    text = (SAMPLES_DIR / sample / f"{sample}.net.xml").read_text()
    if callable(change):
        new = change(text)
    else:
        old, replacement = change
        if old not in text:
            raise AssertionError(f"{case}: {old!r} is no longer in the {sample} sample")
        new = text.replace(old, replacement, 1)
    assert new != text, case
    path = directory / f"{case}.net.xml"
    path.write_text(new)
    return path, f"{path}: {message}"
