"""``kinverify diff OLD NEW``: what changed between two versions of a model.

Two spec files (.toml), two URDFs (read through Pinocchio) or two MJCFs (through MuJoCo; meshes
dropped as in file mode). Parameter level (origins, axes, limits, inertias, names added or
removed) and behaviour level (per-frame FK and Jacobian change over a seeded sample set,
workspace reach), printed and written as HTML. A URDF against an MJCF is file mode's job
(``kinverify verify --urdf --mjcf``): one-line error, exit 2.
"""

from __future__ import annotations

import argparse

from kinverify.commands import add_xacro_options


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "diff",
        help="parameter- and behaviour-level differences between two versions of a model",
        description="Compare two versions of a model: two spec files, two URDFs or two MJCFs. Exit 0 "
        "when they behave identically and no parameter differs, 1 when something changed, 2 on bad input.",
    )
    p.add_argument("old", help="old spec file (.toml), URDF or MJCF")
    p.add_argument("new", help="new file, of the same kind")
    p.add_argument("--samples", type=int, default=None, help="uniform configurations after the edges (default 200)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--report", help="HTML report path (default reports/diff-<old>-<new>.html; .json for JSON)")
    add_xacro_options(p)
    return p


def run(args) -> int:
    import sys
    from pathlib import Path

    from kinverify.text import console as text_console, markup

    from kinverify.errors import InputError
    from kinverify.regression.filediff import diff_files, file_kind
    from kinverify.regression.modeldiff import DIFF_SAMPLES, diff_models
    from kinverify.report.regression import diff_document, print_document, write_document
    from kinverify.model.specfile import load_spec

    samples = DIFF_SAMPLES if args.samples is None else args.samples
    if samples < 0:
        raise InputError(f"--samples must be >= 0, got {args.samples}")
    specs = [Path(p).suffix.lower() == ".toml" for p in (args.old, args.new)]
    if all(specs):
        old, new = load_spec(args.old), load_spec(args.new)
        result = diff_models(old, new, samples, args.seed)
    elif any(specs):
        spec, other = (args.old, args.new) if specs[0] else (args.new, args.old)
        kind = {"urdf": "a URDF", "mjcf": "an MJCF"}.get(file_kind(other) or "", "not a spec")
        raise InputError(
            f"{spec} is a spec and {other} {kind}: diff compares two files of one kind "
            f"(generate the spec's files with `kinverify generate {spec}` to compare files)"
        )
    else:
        from kinverify.filemode.read.loading import given_packages
        from kinverify.filemode.read.xacro import parse_pairs

        with given_packages(parse_pairs(args.package, "--package"), parse_pairs(args.xacro_arg, "--xacro-arg")):
            result = diff_files(args.old, args.new, samples, args.seed)
    console = text_console() if sys.stdout.isatty() else text_console(width=160)
    doc = diff_document(result, args.old, args.new)
    print_document(doc, console)
    from kinverify.io.plan import default_output

    path = write_document(doc, args.report or default_output(f"diff-{result.old_name}-{result.new_name}", ".html"))
    console.print(f"report: {markup(path)}")
    return 0 if doc["passed"] else 1
