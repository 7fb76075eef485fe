"""One module per CLI subcommand (see :mod:`kinverify.cli`), plus argument types they share."""

from __future__ import annotations

import argparse


def count(text: str) -> int:
    """argparse type: a whole number >= 0."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {value}")
    return value


def add_xacro_options(p: argparse.ArgumentParser) -> None:
    """``--package`` and ``--xacro-arg`` of a command that reads URDFs given as .xacro."""
    p.add_argument(
        "--package",
        action="append",
        default=[],
        metavar="NAME=PATH",
        help="for .xacro URDFs (compiled first): where ROS package NAME is (repeatable)",
    )
    p.add_argument(
        "--xacro-arg",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="for .xacro URDFs: a <xacro:arg> value (repeatable)",
    )
