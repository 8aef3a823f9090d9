"""Build the sample networks from their plain-XML sources with SUMO's netconvert.

One command rebuilds every sample (``.net.xml``) and its plan figure (``.png``)::

    python -m clearance.networks.samples.build            # all samples, in place
    python -m clearance.networks.samples.build --out DIR  # into DIR/<name>/ instead
    python -m clearance.networks.samples.build roundabout --no-figures

The netconvert options of each sample are in :data:`OPTIONS`; coordinates are kept as
designed (``--offset.disable-normalization``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from clearance.networks.sumo.tools import run_sumo_tool

__all__ = ["COMMON_OPTIONS", "OPTIONS", "SAMPLES", "SAMPLES_DIR", "VIEWS", "build", "main",
           "sample_networks", "sources"]

SAMPLES_DIR = Path(__file__).resolve().parent
SAMPLES = ("intersection", "roundabout", "parking_ramp", "helix", "garage")

#: netconvert options shared by every sample.
COMMON_OPTIONS = (
    "--offset.disable-normalization",
    "--no-turnarounds",
    "--tls.default-type",
    "static",
    "--output.original-names",
    "false",
    "--no-warnings",
)

#: Panels of each sample's plan figure: a title and (x min, x max, y min, y max) in metres.
VIEWS: dict[str, list[tuple[str, tuple[float, float, float, float] | None]]] = {
    "intersection": [
        ("junction X (corners NE 12, SE 15, SW 20, NW 9.5 m)", (-45.0, 45.0, -45.0, 45.0)),
        ("T-junction T (corners SW 4, SE 12 m)", (365.0, 435.0, -50.0, 20.0)),
    ],
    "roundabout": [
        ("roundabout R (ICD 34 m, truck apron)", (-50.0, 50.0, -50.0, 50.0)),
        ("compact roundabout C (ICD 26 m)", (250.0, 350.0, -50.0, 50.0)),
    ],
    "parking_ramp": [("helix: R 7.5 m, 3 m rise per turn, 2.25 turns", None)],
    "helix": [("helix: R 9 m, 3.2 m per turn, 3 turns", None)],
    "garage": [("garage: aisle (z 0), ramp, deck above (z 3.5)", None)],
}

#: Extra options per sample.
OPTIONS: dict[str, tuple[str, ...]] = {
    "intersection": (),
    "roundabout": (),
    "parking_ramp": (),
    "helix": (),
    "garage": (),
}


def sample_networks() -> list[Path]:
    """The bundled sample networks."""
    return [SAMPLES_DIR / n / f"{n}.net.xml" for n in SAMPLES]


def sources(name: str, directory: Path = SAMPLES_DIR) -> list[str]:
    """netconvert input arguments for the plain-XML sources of sample ``name``."""
    base = directory / name / name
    args = ["-n", f"{base}.nod.xml", "-e", f"{base}.edg.xml"]
    con = Path(f"{base}.con.xml")
    if con.exists():
        args += ["-x", str(con)]
    return args


def build(name: str, out_dir: Path | None = None) -> Path:
    """Build sample ``name`` into ``out_dir/<name>/<name>.net.xml`` (default: in place)."""
    if name not in SAMPLES:
        raise SystemExit(f"unknown sample {name!r}; choose from {', '.join(SAMPLES)}")
    target_dir = (out_dir or SAMPLES_DIR) / name
    target_dir.mkdir(parents=True, exist_ok=True)
    target = target_dir / f"{name}.net.xml"
    args = [*sources(name), *COMMON_OPTIONS, *OPTIONS[name], "-o", str(target)]
    run_sumo_tool("netconvert", args)
    return target


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m clearance.networks.samples.build",
        description=(__doc__ or "").split("\n")[0],
    )
    parser.add_argument("names", nargs="*", default=list(SAMPLES), help="samples to build")
    parser.add_argument("--out", type=Path, help="build into this directory instead")
    parser.add_argument("--no-figures", action="store_true", help="do not draw the plans")
    args = parser.parse_args(argv)
    for name in args.names:
        net_path = build(name, args.out)
        print(f"built {net_path}")
        if not args.no_figures:
            from clearance.networks.plot import save_plan

            png = save_plan(net_path, net_path.with_suffix("").with_suffix(".png"), VIEWS[name])
            print(f"drew {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
