"""Command line: ``kinverify <command> ...`` (also ``python -m kinverify``).

Each subcommand is a module in :mod:`kinverify.commands` with ``add_parser(subparsers)`` and
``run(args) -> int``; heavy imports happen inside ``run``. Exit codes: 0 agreement, 1 a check
failed, 2 bad input (one line on stderr, no traceback).
"""

from __future__ import annotations

import argparse
import importlib
import sys

from kinverify import __version__

COMMANDS = ("verify", "generate", "report", "ik", "track", "baseline", "diff")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="kinverify", description="Prove that a robot arm's models agree: "
                                     "analytic FK, Pinocchio (URDF and MJCF), MuJoCo and yourdfpy, property by property.")
    parser.add_argument("--version", action="version", version=f"kinverify {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMANDS:
        module = importlib.import_module(f".commands.{name}", __package__)
        module.add_parser(sub).set_defaults(run=module.run)
    return parser


def main(argv: list[str] | None = None) -> int:
    from kinverify.errors import KinverifyError

    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)
    try:
        return args.run(args)
    except KinverifyError as err:
        print(f"kinverify: error: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("kinverify: interrupted", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
