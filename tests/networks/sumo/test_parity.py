"""SUMO parity: the tool reads exactly the networks SUMO loads.

For every network: ``sumo -n NET --end 1`` loads it ⇔ ``clearance curves -n NET`` exits 0;
SUMO refuses it ⇔ exit 2; never a traceback, never exit 3. Run on the hand-picked networks
of ``tests/data/sumo_corpus`` always, and on a whole corpus of SUMO's test-suite networks
when ``CLEARANCE_SUMO_CORPUS`` names its folder (it stays outside the repository). As a
script, ``python -m tests.networks.sumo.test_parity DIR`` prints the table for a folder.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from clearance.networks.sumo.tools import find_sumo_binary, sumo_home
from tests.cli import CLI

REPO = Path(__file__).resolve().parents[3]
HAND_PICKED = REPO / "tests" / "data" / "sumo_corpus"
CORPUS_ENV = "CLEARANCE_SUMO_CORPUS"


def sumo_loads(net: Path) -> bool:
    """Whether SUMO itself loads the network (``sumo -n NET --end 1`` exits 0)."""
    proc = subprocess.run(
        [str(find_sumo_binary("sumo")), "-n", str(net), "--end", "1", "--no-step-log",
         "--no-warnings"], capture_output=True, text=True, timeout=300, check=False,
        env=dict(os.environ, SUMO_HOME=str(sumo_home())))
    return proc.returncode == 0


def curves_exit(net: Path, out: Path) -> tuple[int, str]:
    """``clearance curves -n NET -o OUT`` in its own process: exit status and stderr."""
    proc = subprocess.run([*CLI, "curves", "-n", str(net),
                           "-o", str(out)], capture_output=True, text=True, timeout=300,
                          cwd=REPO, check=False)
    return proc.returncode, proc.stderr


def check_parity(net: Path, out: Path) -> tuple[bool, int, str]:
    """SUMO's verdict, the tool's exit status and stderr; asserts the rule."""
    loads = sumo_loads(net)
    code, err = curves_exit(net, out)
    assert "Traceback" not in err, err
    assert code == (0 if loads else 2), (net.name, loads, code, err[-2000:])
    if not loads:
        assert f"{net}: SUMO refuses to load this network: " in err, err
    return loads, code, err


@pytest.mark.parametrize("name", sorted(p.name for p in HAND_PICKED.glob("*.net.xml")))
def test_hand_picked_networks_are_read_exactly_when_sumo_loads_them(tmp_path, name):
    check_parity(HAND_PICKED / name, tmp_path / "curves.csv")


def test_the_hand_picked_dozen_has_both_kinds():
    refused = [p.name for p in HAND_PICKED.glob("*.net.xml") if not sumo_loads(p)]
    assert refused == ["railway_bidi_endoffset_invalid.net.xml"]


def _corpus() -> list[Path]:
    folder = os.environ.get(CORPUS_ENV)
    return sorted(Path(folder).glob("*.net.xml*")) if folder and Path(folder).is_dir() else []


@pytest.mark.skipif(not _corpus(), reason=f"{CORPUS_ENV} names no folder of networks")
@pytest.mark.parametrize("net", _corpus(), ids=lambda p: p.name)
def test_the_corpus_of_sumos_test_suite(tmp_path, net):
    check_parity(net, tmp_path / "curves.csv")


if __name__ == "__main__":  # pragma: no cover - the table for a folder
    import tempfile

    folder = Path(sys.argv[1])
    rows = {"loads, exit 0": 0, "refused, exit 2": 0, "mismatch": 0}
    with tempfile.TemporaryDirectory() as tmp:
        for net in sorted(folder.glob("*.net.xml*")):
            try:
                loads, code, _ = check_parity(net, Path(tmp) / "c.csv")
                rows["loads, exit 0" if loads else "refused, exit 2"] += 1
            except AssertionError as exc:
                rows["mismatch"] += 1
                print(f"MISMATCH {net.name}: {str(exc)[:300]}")
    for k, n in rows.items():
        print(f"{k}: {n}")
