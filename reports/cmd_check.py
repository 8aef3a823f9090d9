"""``clearance check``: a CI gate on the clearance of design vehicles.

Without ``--expect``: exit 0 when every curve is ``clear`` for every design vehicle (or has
only verdicts given with ``--allow``), 1 when any is not (each listed with curve, vehicle,
verdict and margin), 2 on bad input.

With ``--expect GOLDEN.csv``: the verdicts are compared with a golden file of the verdicts
the networks are meant to produce (columns ``network, vehicle, curve_id, verdict``): exit
1 when any verdict is worse than its golden one, or a golden run is missing; better
verdicts are reported (the golden file may be out of date) but pass. ``--write-golden``
writes the current verdicts as a new golden file.
"""

from __future__ import annotations

import argparse
import io
from pathlib import Path

import pandas as pd

from reports.atomic import write_text_atomic
from reports.options import add_clearance_option, add_table_option
from reports.study import METHODS, VERDICT_ORDER, run_study
from vehicles.errors import InputError
from vehicles.table import load_tables

GOLDEN_COLUMNS = ["network", "vehicle", "curve_id", "verdict"]
ALLOWABLE = ("encroaches", "fails", "cannot-turn")


def add_parser(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "check",
        help="CI gate: exit 1 when a design vehicle does not clear a curve",
        description="Exit 0 when every curve of the networks is clear for every design "
                    "vehicle (or has only allowed verdicts), 1 when any is not, 2 on bad "
                    "input. With --expect, compare with a golden file of verdicts instead.",
    )
    p.add_argument("-n", "--net", action="append", metavar="NET", required=True,
                   help="SUMO network (repeatable)")
    p.add_argument("--design-vehicle", action="append", metavar="NAME", required=True,
                   help="design vehicle (repeatable)")
    add_table_option(p)
    p.add_argument("--allow", action="append", choices=ALLOWABLE, default=[],
                   help="a verdict that does not fail the gate (repeatable)")
    p.add_argument("--method", choices=METHODS, default="simulate")
    add_clearance_option(p)
    p.add_argument("--expect", metavar="GOLDEN.csv",
                   help="compare with this golden file of verdicts")
    p.add_argument("--write-golden", metavar="GOLDEN.csv",
                   help="write the verdicts found as a golden file")
    p.set_defaults(run=run)


def read_golden(path: Path) -> pd.DataFrame:
    """A golden file; bad files raise :class:`InputError` naming the file and row."""
    if not path.is_file():
        raise InputError(f"{path}: no such golden file")
    try:
        frame = pd.read_csv(path, dtype=str, keep_default_na=False, comment="#")
    except (pd.errors.ParserError, UnicodeDecodeError, pd.errors.EmptyDataError) as exc:
        raise InputError(f"{path}: not a golden CSV file: {exc}") from None
    missing = [c for c in GOLDEN_COLUMNS if c not in frame.columns]
    if missing:
        raise InputError(f"{path}: missing column(s) {', '.join(missing)}")
    # the file's line of each row: pandas skips comment and blank lines
    lines = [i for i, text in enumerate(path.read_text(encoding="utf-8").split("\n"), 1)
             if text.split("#", 1)[0].strip()][1:]
    bad = frame[~frame.verdict.isin(list(VERDICT_ORDER))]
    if len(bad):
        row = lines[bad.index[0]]
        raise InputError(f"{path}:{row}: unknown verdict {bad.verdict.iloc[0]!r}")
    dupes = frame.duplicated(["network", "vehicle", "curve_id"])
    if dupes.any():
        row = lines[frame.index[dupes][0]]
        raise InputError(f"{path}:{row}: the same network, vehicle and curve twice")
    return frame[GOLDEN_COLUMNS]


def golden_text(frame: pd.DataFrame) -> str:
    """The golden file of a study frame (margins kept for information)."""
    out = io.StringIO()
    out.write("# Verdicts the networks are designed to produce (clearance check --expect).\n")
    out.write("# Regenerate with: clearance check ... --write-golden FILE\n")
    cols = GOLDEN_COLUMNS + ["margin_m"]
    frame[cols].assign(margin_m=frame.margin_m.round(2)).to_csv(
        out, index=False, lineterminator="\n")
    return out.getvalue()


def compare(found: pd.DataFrame, golden: pd.DataFrame) -> tuple[list[str], list[str]]:
    """Regressions (and missing runs) and improvements of ``found`` against ``golden``."""
    key = ["network", "vehicle", "curve_id"]
    merged = golden.merge(found[key + ["verdict", "margin_m"]], on=key, how="left",
                          suffixes=("_golden", ""))
    worse, better = [], []
    for r in merged.itertuples():
        where = f"{r.network}: {r.curve_id}: {r.vehicle}"
        if pd.isna(r.verdict):
            worse.append(f"{where}: no such run any more (expected {r.verdict_golden})")
            continue
        now, then = VERDICT_ORDER[r.verdict], VERDICT_ORDER[r.verdict_golden]
        if now < then:
            worse.append(f"{where}: {r.verdict} ({r.margin_m:+.2f} m), expected "
                         f"{r.verdict_golden}")
        elif now > then:
            better.append(f"{where}: {r.verdict} ({r.margin_m:+.2f} m), golden says "
                          f"{r.verdict_golden}")
    return worse, better


def run(args: argparse.Namespace) -> int:
    table = load_tables(args.table, args.design_vehicle)
    golden = read_golden(Path(args.expect)) if args.expect else None
    study = run_study(args.net, table, args.method, args.clearance)
    frame = study.frame()
    if args.write_golden:
        write_text_atomic(args.write_golden, golden_text(frame))
        print(f"wrote {args.write_golden} ({len(frame)} verdicts)")
    if golden is not None:
        golden = golden[golden.vehicle.isin(table.names)
                        & golden.network.isin([n.name for n in study.networks])]
        worse, better = compare(frame, golden)
        for line in better:
            print(f"better than expected: {line}")
        for line in worse:
            print(f"WORSE than expected: {line}")
        print(f"{len(golden)} expected verdicts: {len(worse)} worse, {len(better)} better, "
              f"{len(golden) - len(worse) - len(better)} as expected")
        return 1 if worse else 0
    allowed = {"clear", *args.allow}
    failing = frame[~frame.verdict.isin(allowed)]
    failing = failing.assign(_o=failing.verdict.map(VERDICT_ORDER)).sort_values(
        ["_o", "margin_m", "network", "curve_id", "vehicle"], kind="stable")
    for r in failing.itertuples():
        print(f"{r.network}: {r.curve_id}: {r.vehicle}: {r.verdict} ({r.margin_m:+.2f} m)")
    print(f"{len(frame)} runs, {len(failing)} not allowed "
          f"(allowed: {', '.join(sorted(allowed))})")
    return 1 if len(failing) else 0
