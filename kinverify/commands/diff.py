"""``kinverify diff OLD NEW``: what changed between two versions of a model.

Parameter level (origins, axes, limits, inertias, names added or removed) and behaviour level
(per-frame FK and Jacobian change over a seeded sample set, workspace reach), printed and
written as HTML. Two spec files (.toml) now; URDF/MJCF pairs once file mode has landed.
"""

from __future__ import annotations

import argparse

SUPPORTED = (".toml",)


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("diff", help="parameter- and behaviour-level differences between two specs",
                       description="Compare two versions of a model (two spec files). Exit 0 when they behave "
                       "identically and no parameter differs, 1 when something changed, 2 on bad input.")
    p.add_argument("old", help="old spec file (.toml)")
    p.add_argument("new", help="new spec file (.toml)")
    p.add_argument("--samples", type=int, default=None, help="uniform configurations after the edges (default 200)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--report", help="HTML report path (default reports/diff-<old>-<new>.html; .json for JSON)")
    return p


def _check_type(path: str) -> None:
    from pathlib import Path

    from ..errors import InputError

    suffix = Path(path).suffix.lower()
    if suffix not in SUPPORTED:
        kind = {".urdf": "URDF", ".xml": "MJCF", ".mjcf": "MJCF"}.get(suffix, f"'{suffix or 'no extension'}'")
        raise InputError(f"{path}: diff compares spec files (.toml); {kind} pairs are not supported yet (file mode)")


def run(args) -> int:
    import sys

    from rich.console import Console

    from ..errors import InputError
    from ..modeldiff import DIFF_SAMPLES, diff_models
    from ..report.regression import diff_document, print_document, write_document
    from ..specfile import load_spec

    for path in (args.old, args.new):
        _check_type(path)
    samples = DIFF_SAMPLES if args.samples is None else args.samples
    if samples < 0:
        raise InputError(f"--samples must be >= 0, got {args.samples}")
    old, new = load_spec(args.old), load_spec(args.new)
    console = Console() if sys.stdout.isatty() else Console(width=160)
    doc = diff_document(diff_models(old, new, samples, args.seed), args.old, args.new)
    print_document(doc, console)
    path = write_document(doc, args.report or f"reports/diff-{old.name}-{new.name}.html")
    console.print(f"report: {path}")
    return 0 if doc["passed"] else 1
