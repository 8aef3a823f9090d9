"""The README's promises about the command line: every option in the synopses, and the
first two commands as `.ci/run` runs them."""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import pytest

from clearance.reports.cli.main import COMMANDS, build_parser

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text(encoding="utf-8")
#: Options every command has, which the README gives in a sentence, not in each row.
COMMON = {"-h", "--help", "-v", "--verbose"}


def subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    (sub,) = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(sub.choices)


def synopsis(command: str) -> str:
    """The first cell of the README's Commands row of ``command``."""
    rows = re.findall(rf"^\| `clearance {command}( [^`]*)?` \|", README, flags=re.M)
    assert len(rows) == 1, f"README: {len(rows)} rows for clearance {command}"
    return rows[0]


def tokens(text: str) -> set[str]:
    """The option strings written in a synopsis: ``-n/--net`` gives both."""
    return set(re.findall(r"(?<![\w-])(--?[a-z][\w-]*)", text))


@pytest.mark.parametrize("command", COMMANDS)
def test_the_synopsis_lists_every_option_of_the_help(command: str):
    p = subparsers()[command]
    helped = {s for a in p._actions for s in a.option_strings} - COMMON
    help_text = p.format_help()
    assert all(s in help_text for s in helped)  # the options the help lists
    written = tokens(synopsis(command))
    assert sorted(helped - written) == [], f"README lacks these options of {command}"
    assert sorted(written - helped) == [], f"README lists options {command} does not know"


def test_the_common_options_are_said_once_and_accepted_after_the_command():
    assert "`-v/--verbose`" in README and "`clearance report -v`" in README
    args = build_parser().parse_args(["vehicles", "-v", "--output-file", "x.csv"])
    assert args.verbose_sub == 1 and args.output == "x.csv"
    args = build_parser().parse_args(["report", "--net-file", "a.net.xml", "--output-dir", "d"])
    assert args.net == ["a.net.xml"] and args.output == "d"


def test_the_first_two_commands_and_ci():
    block = re.search(r"```bash\n(.*?)```", README, flags=re.S).group(1).splitlines()
    install, tests = block[0], block[1]
    assert install.startswith("python3 -m venv .venv && ")
    # the tests run with the environment's own Python: no activate needed in a new shell
    assert tests == ".venv/bin/python -m pytest -q"
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert re.search(r'^VENV="?\.venv"?$', ci, flags=re.M)
    assert re.search(r"^\.venv/bin/python -m pytest -q$", ci, flags=re.M)
    assert 'pip install --quiet -e ".[test]"' in ci
