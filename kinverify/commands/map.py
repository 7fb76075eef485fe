"""``kinverify map FILE...``: the sim-to-sim contract between two or more robot files (URDF or
xacro, MJCF, SDFormat, OpenUSD), and an Isaac Lab-style actuator table (``--actuators``).

Prints each file's joint order (URDF declaration order, MuJoCo's ``qpos`` order, Drake's plant
order, a USD articulation breadth-first as PhysX orders it) and actuator order, the index maps between every two files, and side by side, per radian,
the default pose, PD gains, effort and velocity limits, armature, friction, drives and couplings;
what differs is a finding with its size. ``--json OUT`` writes the maps ready for deployment code.
Exit 0 the files agree on the contract, 1 they differ (an error finding), 2 bad input, 3 a
kinverify bug. See docs/map.md.
"""

from __future__ import annotations

import argparse

from kinverify.commands import add_xacro_options


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not 0 < value < 1:
        raise argparse.ArgumentTypeError(f"must be between 0 and 1, got {text}")
    return value


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "map",
        help="the sim-to-sim contract: joint and actuator orders, index maps, gains per radian",
        description="Read two or more robot files (URDF/xacro, MJCF, SDFormat, OpenUSD) and print the order each "
        "file's simulator gives the joints and actuators, the index maps between every two files "
        "(to = from[index]) and, side by side per radian, the default pose, PD gains, effort and velocity "
        "limits, armature, friction, drives and couplings. Exit 0 they agree, 1 they differ, 2 bad input.",
    )
    p.add_argument(
        "files",
        nargs="+",
        metavar="FILE",
        help="URDF (.urdf, .xacro), MJCF (.xml, .mjcf), SDFormat (.sdf) or OpenUSD (.usd, .usda, .usdc) files",
    )
    p.add_argument(
        "--keyframe",
        metavar="NAME",
        help="the MJCF keyframe that is the default pose, in every MJCF given (default: qpos0, the joints' ref)",
    )
    p.add_argument(
        "--actuators",
        metavar="TABLE",
        help="an Isaac Lab-style actuator table (YAML or TOML: joint-name regex -> "
        "stiffness, damping, effort_limit, velocity_limit, armature, friction; per radian unless units = "
        '"degree"), compared as one more side',
    )
    p.add_argument(
        "--rtol",
        type=_positive,
        default=1e-3,
        help="relative tolerance of gains, limits, armature and "
        "friction (default 1e-3; default positions agree within 1e-4 rad or m)",
    )
    p.add_argument("--json", metavar="OUT", help="write the orders, maps, values and findings as JSON")
    add_xacro_options(p)
    return p


def run(args) -> int:
    import json

    from rich.console import Console

    from kinverify.filemode.read.loading import given_packages
    from kinverify.filemode.read.xacro import parse_pairs
    from kinverify.io.plan import claim_outputs, note_input
    from kinverify.map.contract import MapOptions, map_files
    from kinverify.map.render import print_map

    for path in args.files:
        note_input(path, "FILE")
    if args.json:
        claim_outputs(("--json", args.json))
    options = MapOptions(keyframe=args.keyframe, actuators=args.actuators, rtol=args.rtol)
    with given_packages(parse_pairs(args.package, "--package"), parse_pairs(args.xacro_arg, "--xacro-arg")):
        result = map_files(list(args.files), options)
    written = None
    if args.json:
        from kinverify.io.write import write_atomic

        written = str(write_atomic(args.json, json.dumps(result.to_dict(), indent=1, allow_nan=False) + "\n"))
    print_map(result, Console(), written)
    return result.exit_code
