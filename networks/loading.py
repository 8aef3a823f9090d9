"""Loading a network for a command: SUMO's verdict on the file and the reader's, once.

:func:`load_network` is what every command calls before any run: the file must be a regular
file of XML (:func:`clearance.networks.safe_xml.scan_prolog`: SUMO is never started on a FIFO or a
device), SUMO is asked whether it loads it
(:class:`clearance.networks.sumo.load_check.SumoLoadCheck`,
in a process of its own while this one reads), and the reader reads it
(:func:`clearance.networks.reader.read_network`). What SUMO refuses is an
:class:`~clearance.vehicles.errors.InputError` naming the file and giving SUMO's reason; what it
loads is read, and what the reader repaired or left out is logged as warnings naming each element.
Workers read their copy with :func:`~clearance.networks.reader.read_network` alone: the check was
made.
"""

from __future__ import annotations

import logging
import os
from pathlib import Path

from clearance.networks.model import Network
from clearance.networks.reader import read_network
from clearance.networks.safe_xml import scan_prolog
from clearance.networks.sumo.load_check import SumoLoadCheck
from clearance.vehicles.errors import InputError, LimitError, NetworkError

__all__ = ["MAX_REPAIRS_LOGGED", "load_network", "load_networks"]

log = logging.getLogger(__name__)

#: Repairs logged one by one; beyond these, a count.
MAX_REPAIRS_LOGGED = 8


def load_network(path: str | os.PathLike[str]) -> Network:
    """Read a network the way SUMO loads it (see the module's text).

    Raises
    ------
    InputError
        The file is not a regular file of XML, SUMO refuses it (SUMO's reason), or the
        reader refuses it.
    """
    return _read_checked(Path(path), _start_check(Path(path)))


def load_networks(paths: list[Path]) -> list[Network]:
    """:func:`load_network` of each path, in order; SUMO checks the next file while this
    process reads one.

    Raises
    ------
    InputError
        As :func:`load_network`, for the first file at fault.
    """
    out: list[Network] = []
    checks: list[SumoLoadCheck] = []
    try:
        for k, p in enumerate(paths):
            while len(checks) < min(k + 2, len(paths)):
                checks.append(_start_check(paths[len(checks)]))
            out.append(_read_checked(p, checks[k]))
    except BaseException:
        for c in checks[len(out):]:
            c.cancel()
        raise
    return out


def _start_check(p: Path) -> SumoLoadCheck:
    root = scan_prolog(p)  # a regular file of XML, before SUMO is started on it
    if root != "net":
        raise NetworkError(f"{p}: not a SUMO network (root element <{root}>, expected <net>)",
                           file=p)
    return SumoLoadCheck(p)


def _read_checked(p: Path, check: SumoLoadCheck) -> Network:
    try:
        net = read_network(p)
    except LimitError:  # the tool's own cap: SUMO's word is not needed (nor its memory)
        check.cancel()
        raise
    except InputError as ours:
        why = check.refusal()
        if why is not None:
            raise NetworkError(f"{p}: SUMO refuses to load this network: {why}", file=p) from None
        raise ours
    except BaseException:
        check.cancel()
        raise
    why = check.refusal()
    if why is not None:
        raise NetworkError(f"{p}: SUMO refuses to load this network: {why}", file=p)
    for note in net.repairs[:MAX_REPAIRS_LOGGED]:
        log.warning("%s: %s", p, note)
    if len(net.repairs) > MAX_REPAIRS_LOGGED:
        log.warning("%s: %d more element(s) repaired or left out (SUMO loads them; no vehicle "
                    "is judged on them)", p, len(net.repairs) - MAX_REPAIRS_LOGGED)
    return net
