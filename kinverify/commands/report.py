"""``kinverify report RESULTS.json --out PATH``: re-render the HTML report from a saved JSON."""

from __future__ import annotations

import argparse

from kinverify.text import shown


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "report",
        help="re-render the HTML report from a saved results JSON",
        description="Read RESULTS.json (written by `kinverify verify`) and write the same HTML "
        "report again, e.g. after upgrading kinverify or on another machine. Exit code is the saved "
        "verdict's: 0 pass, 1 fail, 3 error (kinverify failed in that run); 2 on bad input.",
    )
    p.add_argument("results", help="results JSON (reports/<model>.json)")
    p.add_argument("--out", help="HTML path (default: RESULTS with the suffix .html)")
    return p


def run(args) -> int:
    from pathlib import Path

    from kinverify.report.html import write_html
    from kinverify.report.json_ import load_result_json

    result = load_result_json(args.results)
    out = write_html(result, args.out or Path(args.results).with_suffix(".html"))
    print(
        f"{shown(result.model)}: {result.verdict} ({len(result.failed)} of {len(result.checks)} checks failed, "
        f"{len(result.failing_findings)} error findings); report: {shown(out)}"
    )
    return result.exit_code
