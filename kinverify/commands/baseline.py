"""``kinverify baseline save|check``: record what a model computes, and check it later.

``save MODEL --out FILE.json`` writes the baseline (see :mod:`kinverify.baseline`);
``check MODEL --baseline FILE.json [--report PATH]`` exits 0 when nothing moved beyond
tolerance, 1 when something did (each moved quantity listed with the spec changes that explain
it), 2 on bad input (unreadable, corrupt, truncated, newer-format or other-model baseline).
"""

from __future__ import annotations

import argparse

from kinverify.commands import count as _count


def _positive(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not 0 < value < float("inf"):  # also refuses NaN: a tolerance of inf would pass anything
        raise argparse.ArgumentTypeError(f"must be a finite number > 0, got {text}")
    return value


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "baseline",
        help="save a model's baseline (FK, Jacobians, IK, dynamics), or check a model against one",
        description="Save what a model computes at a fixed seeded sample set, or check that nothing moved.",
    )
    actions = p.add_subparsers(dest="action", required=True, metavar="ACTION")
    save = actions.add_parser("save", help="write a baseline JSON", description="Write MODEL's baseline to --out.")
    save.add_argument("model", help="spec file (models/*.toml)")
    save.add_argument("--out", required=True, help="baseline file to write (JSON)")
    save.add_argument(
        "--samples", type=_count, default=None, help="uniform configurations after the edge configurations (default 30)"
    )
    save.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    check = actions.add_parser(
        "check",
        help="compare a model with a baseline",
        description="Re-evaluate MODEL at the baseline's configurations. Exit 0 when nothing "
        "moved beyond tolerance, 1 when something did, 2 on bad input.",
    )
    check.add_argument("model", help="spec file (models/*.toml)")
    check.add_argument("--baseline", required=True, help="baseline JSON written by `kinverify baseline save`")
    check.add_argument("--report", help="also write the result: HTML, or JSON if PATH ends in .json")
    check.add_argument("--tolerance", type=_positive, help="one tolerance for every property (default: 1e-9 m, rad, m/rad)")
    return p


def run(args) -> int:
    import sys

    from kinverify.text import console as text_console, markup

    from kinverify.model.specfile import load_spec

    console = text_console() if sys.stdout.isatty() else text_console(width=160)
    spec = load_spec(args.model)
    if args.action == "save":
        from kinverify.regression.baseline import DEFAULT_SAMPLES, save_baseline

        samples = DEFAULT_SAMPLES if args.samples is None else args.samples
        path = save_baseline(spec, args.out, samples, args.seed)
        console.print(f"baseline of {markup(spec.name)} written: {markup(path)}")
        return 0
    from kinverify.regression.baseline import BASELINE_TOLERANCES, Tolerance
    from kinverify.regression.check import check
    from kinverify.report.regression import check_document, print_document, write_document

    tolerances = None
    if args.tolerance is not None:
        tolerances = {k: Tolerance(args.tolerance, t.unit) for k, t in BASELINE_TOLERANCES.items()}
    result = check(spec, args.baseline, tolerances)
    doc = check_document(result)
    print_document(doc, console)
    if args.report:
        console.print(f"report: {markup(write_document(doc, args.report))}")
    return 0 if result.passed else 1
