"""Sample networks damaged one way each: what SUMO refuses, and what it loads though the
element is broken (numbers out of range, NaN, a reference it tolerates).

Each case is (sample, damage, expected message after the file name). Those in
:data:`REFUSED` SUMO refuses to load (``sumo -n NET --end 1`` exits 1: checked by
``tests/networks/sumo/test_load_check.py``): the expected message is SUMO's reason, as the
tool quotes it; the others SUMO loads, and the expected message is the tool's note on the
element it repaired or left out. The damage replaces an exact piece of the sample's text, so
a sample that changes fails loudly here (:func:`damage`) instead of testing nothing.
"""

from __future__ import annotations

import re
from pathlib import Path

from clearance.networks.samples.sources import SAMPLES_DIR

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


def scaled(text: str, by: float) -> str:
    """A network's XML drawn ``by`` times its size: every coordinate, length, width and
    boundary multiplied (SUMO loads it all the same)."""
    def points(m: re.Match[str]) -> str:
        pts = [",".join(repr(float(v) * by) for v in p.split(",")) for p in m.group(2).split()]
        return f'{m.group(1)}="{" ".join(pts)}"'

    text = re.sub(r'\b(shape|customShape)="([^"]*)"', points, text)
    text = re.sub(r'\b(x|y|z|length|width|radius)="([-0-9.e+]+)"',
                  lambda m: f'{m.group(1)}="{float(m.group(2)) * by!r}"', text)
    return re.sub(r'\b(netOffset|convBoundary)="([^"]*)"', lambda m: f'{m.group(1)}="'
                  + ",".join(repr(float(v) * by) for v in m.group(2).split(",")) + '"', text)


#: name -> (sample, (old, new) or a function of the text, expected message)
CASES: dict[str, tuple[str, object, str]] = {
    # -- SUMO refuses these (its own words)
    "via-to-a-missing-lane": (
        "intersection", (CONNECTION, CONNECTION.replace(":T_0_0", ":nope_0")),
        "SUMO refuses to load this network: An unknown lane (':nope_0') should be set as a "
        "via-lane for lane 'TW_out_0'."),
    "unknown-to-edge": (
        "intersection", (CONNECTION, CONNECTION.replace('to="TW_out"', 'to="NOPE"')),
        "SUMO refuses to load this network: Unknown to-edge 'NOPE' in connection."),
    "unknown-from-edge": (
        "intersection", (CONNECTION, CONNECTION.replace('from="TE_in"', 'from="NOPE"')),
        "SUMO refuses to load this network: Unknown from-edge 'NOPE' in connection."),
    "duplicate-edge": (
        "intersection", ('<edge id="TE_out" ', '<edge id="TE_in" '),
        "SUMO refuses to load this network: Another edge with the id 'TE_in' exists."),
    "from-lane-out-of-range": (
        "intersection", (CONNECTION, CONNECTION.replace('fromLane="0"', 'fromLane="7"')),
        "SUMO refuses to load this network: Invalid lane index in connection from 'TE_in' to "
        "'TW_out'."),
    "to-lane-out-of-range": (
        "intersection", (CONNECTION, CONNECTION.replace('toLane="0"', 'toLane="-1"')),
        "SUMO refuses to load this network: Invalid lane index in connection from 'TE_in' to "
        "'TW_out'."),
    "roundabout-unknown-edge": (
        "roundabout", ('edges="Cring0 Cring1', 'edges="NOPE Cring1'),
        "SUMO refuses to load this network: Unknown edge 'NOPE' in roundabout"),
    "lane-length-nan": (
        "intersection", (LANE, LANE.replace('length="104.50"', 'length="nan"')),
        "SUMO refuses to load this network: Attribute length of lane 'TE_in_0' is invalid "
        "(nan)"),
    "lane-one-point": (
        "intersection", (LANE + 'shape="520.00,1.75 415.50,1.75"', LANE + 'shape="520.00,1.75"'),
        "SUMO refuses to load this network: Shape of lane 'TE_in_0' is broken."),
    # -- SUMO loads these: the element is repaired or left out, with a note
    "lane-index-out-of-range": (
        "intersection", (LANE, LANE.replace('index="0"', 'index="3"')),
        "lane 'TE_in_0': index 3 beyond its edge 'TE_in''s 1 lane(s): taken as 0, its place"),
    "roundabout-unknown-junction": (
        "roundabout", ('nodes="C0 C1', 'nodes="C0 NOPE'),
        "<roundabout nodes=...>: unknown junction(s) 'NOPE': dropped from it"),
    "lane-width-nan": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="nan"')),
        "lane 'TE_in_0': width 'nan' is not a lane width in (0, 50] m: taken as SUMO's "
        "default 3.2 m"),
    "lane-width-huge": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="1e12"')),
        "lane 'TE_in_0': width '1e12' is not a lane width in (0, 50] m"),
    "lane-width-negative": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="-3.5"')),
        "lane 'TE_in_0': width '-3.5' is not a lane width in (0, 50] m"),
    "lane-width-zero": (
        "intersection", (LANE, LANE.replace('width="3.50"', 'width="0"')),
        "lane 'TE_in_0': width '0' is not a lane width in (0, 50] m"),
    "coordinate-1e300": (
        "intersection", (LANE + 'shape="520.00,', LANE + 'shape="1e300,'),
        "lane 'TE_in_0': coordinate beyond +/-1e+08 m in shape '1e300,1.75 415.50,1.75' "
        "(precision would be lost): left out"),
    "coordinate-inf": (
        "intersection", (LANE + 'shape="520.00,', LANE + 'shape="inf,'),
        "lane 'TE_in_0': non-finite coordinate in shape 'inf,1.75 415.50,1.75': left out"),
    "coordinate-nan": (
        "intersection", (LANE + 'shape="520.00,', LANE + 'shape="nan,'),
        "lane 'TE_in_0': non-finite coordinate in shape 'nan,1.75 415.50,1.75': left out"),
    "junction-shape-minus-nan": (
        "intersection", ('shape="392.50,3.50 415.50,3.50', 'shape="392.50,3.50 -nan,3.50'),
        "junction 'T': non-finite coordinate in shape '392.50,3.50 -nan,3.50 415.50,-3.50 "),
    "all-coordinates-offset-1e15": (
        "intersection", lambda text: _offset_all(text, 1e15),
        "junction 'T': coordinate beyond +/-1e+08 m in shape '1000000000000392.5,"),
    "junction-x-nan": (
        "intersection", ('<junction id="T" type="priority" x="400.00"',
                         '<junction id="T" type="priority" x="nan"'),
        "junction 'T': position (nan, 0, 0) is not a finite coordinate: taken as its "
        "shape's middle"),
    "net-offset-nan": (
        "intersection", ('netOffset="0.00,0.00"', 'netOffset="nan,0.00"'),
        '<location netOffset="nan,0.00" '),
    "net-offset-huge": (
        "intersection", ('netOffset="0.00,0.00"', 'netOffset="1e15,0.00"'),
        '<location netOffset="1e15,0.00" '),
    "conv-boundary-inf": (
        "intersection", ('convBoundary="-120.00', 'convBoundary="-inf'),
        '<location netOffset="0.00,0.00" convBoundary="-inf,'),
}

#: The cases SUMO refuses to load (exit 2 from every command, SUMO's reason quoted).
REFUSED = frozenset(k for k, (_, _, message) in CASES.items()
                    if message.startswith("SUMO refuses"))

#: The cases SUMO loads: read, the element repaired or left out with a note.
LOADED = frozenset(CASES) - REFUSED


def damage(case: str, directory: Path) -> tuple[Path, str]:
    """The damaged file of ``case`` written in ``directory``, and the full expected message
    (the file name, then the case's message: SUMO's reason or the note)."""
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
