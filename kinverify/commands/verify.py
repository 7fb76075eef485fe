"""``kinverify verify MODEL``: cross-validate every backend, print a table, write HTML + JSON."""

from __future__ import annotations

import argparse


def _positive_int(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if value < 0:
        raise argparse.ArgumentTypeError(f"must be >= 0, got {value}")
    return value


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser("verify", help="cross-validate FK and Jacobians of all backends",
                       description="Generate URDF and MJCF from MODEL, load them in every available backend, "
                       "compare FK and Jacobians of every frame against the analytic reference. "
                       "Exit 0 when all agree, 1 when a check fails, 2 on bad input.")
    p.add_argument("model", help="spec file (models/*.toml)")
    p.add_argument("--samples", type=_positive_int, default=1000, help="uniform random configurations (default 1000), plus edge configurations")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--backends", help="comma-separated backend names (default: all available)")
    p.add_argument("--report", help="HTML report path (default reports/<model>.html)")
    p.add_argument("--json", help="JSON results path (default reports/<model>.json)")
    p.add_argument("--quiet", action="store_true", help="print only the verdict line")
    return p


def run(args) -> int:
    import shlex
    import sys

    from rich.console import Console

    from ..report import print_result, write_json
    from ..report.html import write_html
    from ..specfile import load_spec
    from ..verify import VerifyOptions, verify_spec

    spec = load_spec(args.model)
    options = VerifyOptions(samples=args.samples, seed=args.seed,
                            backends=args.backends.split(",") if args.backends else None)

    console = Console() if sys.stdout.isatty() else Console(width=140)
    with console.status(f"verifying {spec.name}...") as status:
        result = verify_spec(spec, options, source=str(args.model),
                             command="kinverify " + shlex.join(args.argv),
                             progress=lambda suite: status.update(f"verifying {spec.name}: {suite}"))
    if args.quiet:
        console.print(f"{spec.name}: {result.verdict} ({len(result.failed)} of {len(result.checks)} checks failed)")
    else:
        print_result(result, console)
    json_path = write_json(result, args.json or f"reports/{spec.name}.json")
    html_path = write_html(result, args.report or f"reports/{spec.name}.html")
    console.print(f"report: {html_path}  json: {json_path}")
    return 0 if result.passed else 1
