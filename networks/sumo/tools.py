"""Finding and running the SUMO tools the ``eclipse-sumo`` package ships (netconvert...)."""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Sequence
from pathlib import Path

from clearance.vehicles.errors import ClearanceError

__all__ = ["NETCONVERT_TIMEOUT_S", "find_sumo_binary", "netconvert_plain", "run_sumo_tool",
           "sumo_home"]

#: netconvert runs longer than this (seconds) are stopped.
NETCONVERT_TIMEOUT_S = 300


def sumo_home() -> Path:
    """SUMO_HOME of the installed ``eclipse-sumo`` package (else the environment's).

    Raises
    ------
    FileNotFoundError
        Neither is available.
    """
    try:
        import sumo  # the eclipse-sumo wheel

        return Path(sumo.SUMO_HOME)
    except (ImportError, AttributeError):
        env = os.environ.get("SUMO_HOME")
        if env:
            return Path(env)
    raise FileNotFoundError(
        "SUMO is not installed (pip install eclipse-sumo) and SUMO_HOME is unset"
    )


def find_sumo_binary(name: str) -> Path:
    """Path of a SUMO program (``netconvert``, ``netgenerate``, ``sumo``)."""
    candidate = sumo_home() / "bin" / name
    if candidate.exists():
        return candidate
    found = shutil.which(name)
    if found:
        return Path(found)
    raise FileNotFoundError(f"{name} not found under {candidate.parent} or on PATH")


def run_sumo_tool(name: str, args: Sequence[str], timeout_s: float = NETCONVERT_TIMEOUT_S) -> None:
    """Run a SUMO program with SUMO_HOME set (so that it validates its XML input).

    Raises
    ------
    InputError
        The program fails; the message holds its error output.
    """
    exe = find_sumo_binary(name)
    env = dict(os.environ, SUMO_HOME=str(sumo_home()))
    proc = subprocess.run(
        [str(exe), *args], capture_output=True, text=True, env=env, timeout=timeout_s, check=False
    )
    if proc.returncode != 0:
        raise ClearanceError(f"{name} failed ({proc.returncode}): {proc.stderr.strip()[-2000:]}")


def netconvert_plain(
    out_dir: Path,
    name: str,
    nodes: str,
    edges: str,
    connections: str | None = None,
    options: Sequence[str] = (),
) -> Path:
    """Write plain-XML sources ``<name>.nod.xml`` etc. into ``out_dir`` and build the network.

    Returns the path of ``<name>.net.xml``.
    """
    out_dir.mkdir(parents=True, exist_ok=True)
    nod = out_dir / f"{name}.nod.xml"
    edg = out_dir / f"{name}.edg.xml"
    nod.write_text(nodes)
    edg.write_text(edges)
    args = ["-n", str(nod), "-e", str(edg)]
    if connections:
        con = out_dir / f"{name}.con.xml"
        con.write_text(connections)
        args += ["-x", str(con)]
    net = out_dir / f"{name}.net.xml"
    run_sumo_tool("netconvert", [*args, *options, "-o", str(net), "--no-warnings"])
    return net
