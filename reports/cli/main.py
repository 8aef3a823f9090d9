"""The ``clearance`` command: one sub-command per module of :mod:`clearance.reports.cli`."""

from __future__ import annotations

import argparse
import logging
import sys
import traceback
from collections.abc import Sequence
from importlib import import_module

from clearance.reports.study.lifetime import Stopped, stop_on_signals
from clearance.vehicles.errors import ClearanceError, InputError

__all__ = ["COMMANDS", "OWN_LOGGERS", "build_parser", "chosen_command", "main"]

#: Sub-commands in the order ``clearance --help`` lists them; each names a module
#: ``clearance.reports.cli.<name>`` with ``add_parser(subparsers)`` and ``run(args) -> int``.
COMMANDS = ("report", "vehicles", "curves", "simulate", "compare", "check")


def build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """The command's parser; with ``only`` (a name of :data:`COMMANDS`), that sub-command's
    alone, so that a run imports only what its sub-command needs (``check`` does not load
    the drawing modules ``report`` does)."""
    parser = argparse.ArgumentParser(
        prog="clearance",
        description="Turning-circle and swept-path clearance of SUMO networks for vehicle tables.",
    )
    parser.add_argument("-v", "--verbose", action="count", default=0, help="log more (-vv: debug)")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS if only is None else (only,):
        try:
            module = import_module(f"clearance.reports.cli.{name}")
        except ModuleNotFoundError as exc:
            if exc.name != f"clearance.reports.cli.{name}":
                raise
            continue
        module.add_parser(sub)
    for command in sub.choices.values():  # -v is accepted after the sub-command too
        command.add_argument("-v", "--verbose", action="count", default=0, dest="verbose_sub",
                             help="log more (-vv: debug)")
    return parser


#: The packages whose loggers ``-v`` turns up (not the libraries').
OWN_LOGGERS = ("clearance",)

#: Exit statuses (docs/design.md §6; the README's "Exit codes").
EXIT_OK, EXIT_NOT_CLEAR, EXIT_BAD_INPUT, EXIT_INTERNAL = 0, 1, 2, 3


def chosen_command(argv: Sequence[str]) -> str | None:
    """The sub-command ``argv`` names: its first word that is not an option, when that is
    one of :data:`COMMANDS` (the options before it, ``-v``, take no value).

    Examples
    --------
    >>> chosen_command(["-v", "check", "-n", "x.net.xml"]), chosen_command(["--help"])
    ('check', None)
    >>> chosen_command(["chekc"]) is None  # argparse then names the choices
    True
    """
    first = next((a for a in argv if not a.startswith("-")), None)
    return first if first in COMMANDS else None


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser(chosen_command(sys.argv[1:] if argv is None else argv))
    args = parser.parse_args(argv)
    verbose = args.verbose + getattr(args, "verbose_sub", 0)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s: %(message)s")
    for name in OWN_LOGGERS:
        logging.getLogger(name).setLevel(logging.WARNING - 10 * min(verbose, 2))
    if not getattr(args, "run", None):
        parser.print_help()
        return EXIT_BAD_INPUT
    try:
        with stop_on_signals():
            return int(args.run(args) or 0)
    except Stopped as exc:  # SIGTERM, SIGHUP: unwound, workers and staging folder gone
        print(f"clearance: {exc}", file=sys.stderr)
        return exc.exit_status
    except InputError as exc:
        print(f"clearance {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT
    except ClearanceError as exc:  # the simulator or the tools SUMO ships failed
        if verbose:
            traceback.print_exc()
        print(f"clearance {args.command}: error: {exc}", file=sys.stderr)
        return EXIT_INTERNAL
    except BrokenPipeError:  # output piped into `head` and the like
        sys.stderr.close()
        return 0
    except KeyboardInterrupt:
        print("clearance: interrupted", file=sys.stderr)
        return 130
    except Exception as exc:  # noqa: BLE001 - an internal or simulator error: exit 3
        if verbose:
            traceback.print_exc()
        print(f"clearance {args.command}: internal error: {type(exc).__name__}: {exc}\n"
              "This is a bug or a simulator failure, not a verdict; please report it "
              "(run with -v for the traceback).", file=sys.stderr)
        return EXIT_INTERNAL


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
