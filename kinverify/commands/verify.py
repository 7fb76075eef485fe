"""``kinverify verify``: cross-validate every backend, print a table, write HTML + JSON.

Spec mode: ``kinverify verify MODEL.toml``. File mode: ``kinverify verify --urdf R.urdf --mjcf R.xml``
(or an SDFormat file, ``--sdf R.sdf``, or an OpenUSD file, ``--usd R.usda``, against either, or
several at once). One-file audit: ``kinverify
verify --urdf R.urdf`` (or ``--mjcf R.xml``, ``--sdf R.sdf``, ``--usd R.usda``) alone: every library that reads that
file, compared with each other. A ``.xacro`` URDF is compiled first (``--package``, ``--xacro-arg``).
"""

from __future__ import annotations

import argparse
import math

from kinverify.commands import count as _count
from kinverify.errors import InputError


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "verify",
        help="cross-validate all backends on a spec, a URDF against an MJCF, or one file's readers",
        description="Generate URDF and MJCF from MODEL (or read two or more of --urdf, --mjcf, --sdf and "
        "--usd), load them in every available backend and compare every property against the analytic "
        "reference. With one file alone: a one-file audit, every library that reads that file compared "
        "with the others (a USD: what it states and leaves unset). "
        "Exit 0 when all agree, 1 when a check fails, 2 on bad input.",
    )
    p.add_argument("model", nargs="?", help="spec file (models/*.toml); omit with --urdf/--mjcf")
    p.add_argument("--urdf", help="file mode: an existing URDF (or .xacro); alone: audit it with every library reading URDF")
    p.add_argument(
        "--mjcf", help="file mode: an existing MJCF; alone: audit it with MuJoCo, Pinocchio's and Drake's MJCF parsers"
    )
    p.add_argument(
        "--sdf",
        help="file mode: an existing SDFormat file, against --urdf or --mjcf or both (read by Drake: "
        "needs kinverify[drake]); alone: Drake's reading of it",
    )
    p.add_argument(
        "--usd",
        help="file mode: an existing OpenUSD robot (.usd, .usda, .usdc), against --urdf, --mjcf or --sdf, "
        "or several (read by usd-core: needs kinverify[usd]); alone: what the file states and leaves unset",
    )
    p.add_argument(
        "--package",
        action="append",
        default=[],
        metavar="NAME=PATH",
        help="where ROS package NAME is (repeatable): resolves package://NAME and xacro's $(find NAME)",
    )
    p.add_argument(
        "--xacro-arg",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="a xacro <xacro:arg> value for a .xacro --urdf (repeatable)",
    )
    p.add_argument("--frames", nargs="*", default=[], metavar="URDF_FRAME=MJCF_FRAME", help="file mode: frame pairs to compare")
    p.add_argument("--joints", nargs="*", default=[], metavar="URDF_JOINT=MJCF_JOINT", help="file mode: joint pairs")
    p.add_argument(
        "--accept",
        metavar="FILE",
        help="file mode: reviewed accepted differences (TOML; default: "
        "kinverify-accepted.toml beside the URDF when present); accepted findings pass, new or changed ones fail",
    )
    p.add_argument(
        "--write-accepted",
        metavar="FILE",
        help="file mode: write this run's error findings to FILE as accepted differences, to review (see docs/file-mode.md)",
    )
    p.add_argument(
        "--samples", type=_count, default=1000, help="uniform random configurations (default 1000), plus edge configurations"
    )
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--backends", help="comma-separated backend names (default: all available)")
    p.add_argument(
        "--ik-targets", type=_count, default=None, help="random reachable IK targets per solver (default: the IK suite's)"
    )
    p.add_argument(
        "--skip", action="append", default=[], metavar="SUITE", help="skip a property suite (repeatable), e.g. --skip ik"
    )
    p.add_argument(
        "--tolerance",
        action="append",
        default=[],
        metavar="PROPERTY=VALUE",
        help="override a property's tolerance or goal (repeatable), e.g. --tolerance fk.position=1e-12; "
        "every property name in the JSON is accepted",
    )
    p.add_argument(
        "--gate",
        action="append",
        default=[],
        metavar="PROPERTY[=GOAL]",
        help="make a performance property (ik.failure_rate, tracking.*) decide the verdict, at its default goal "
        "or GOAL (repeatable); by default only agreement between the models does",
    )
    p.add_argument("--report", help="HTML report path (default reports/<model>.html)")
    p.add_argument("--json", help="JSON results path (default reports/<model>.json)")
    p.add_argument(
        "--junit",
        metavar="PATH",
        help="also write JUnit XML: one test case per property and backend pair (and per file-mode finding), for CI systems",
    )
    p.add_argument("--quiet", action="store_true", help="print only the verdict line")
    p.add_argument(
        "--profile",
        action="store_true",
        help="print one line of wall and CPU time per suite and for the report "
        "(the JSON always holds them: timings, cpu_timings)",
    )
    # performance and scale
    p.add_argument(
        "--jobs", type=_count, default=1, help="worker processes for the chunks (default 1); results are identical for any N"
    )
    p.add_argument(
        "--executor",
        choices=["local", "dask"],
        default="local",
        help="run chunks here (local) or on dask.distributed (needs kinverify[dask])",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="with --executor dask: an existing scheduler (default: a LocalCluster of --jobs workers)",
    )
    p.add_argument(
        "--chunk",
        type=_count,
        default=2000,
        help="configurations per chunk (default 2000); memory is bounded by the chunk, not --samples",
    )
    p.add_argument(
        "--slow-samples",
        type=_count,
        default=2_000,
        help="slow backends (yourdfpy) compare only the first this many "
        "configurations (default 2000), their finite-difference Jacobians only as many as 300 FK evaluations allow",
    )
    return p


def _number(item: str, flag: str) -> tuple[str, float | None]:
    name, sep, value = item.partition("=")
    if not sep:
        return name, None
    try:
        number = float(value)
    except ValueError:
        raise InputError(f"{flag}: {item!r} is not PROPERTY=NUMBER") from None
    if not 0 <= number < math.inf:  # also refuses NaN
        raise InputError(f"{flag}: {item!r} must be a non-negative finite number")
    return name, number


def _not_renamed(prop: str, flag: str) -> None:
    from kinverify.results import RENAMED_PROPERTIES

    if prop in RENAMED_PROPERTIES:
        raise InputError(f"{flag}: property {prop!r} is now named {RENAMED_PROPERTIES[prop]!r} (see docs/properties.md)")


def options_from_args(args):
    from kinverify.run import VerifyOptions
    from kinverify.suites.base import PERFORMANCE
    from kinverify.suites.registry import properties, suite_names

    names = suite_names()
    for skip in args.skip:
        if skip not in names:
            raise InputError(f"--skip: unknown suite {skip!r}; suites: {', '.join(names)}")
    props = properties()
    extra = {} if args.ik_targets is None else {"ik_targets": args.ik_targets}
    tolerances: dict[str, float] = {}
    for item in args.tolerance:
        prop, value = _number(item, "--tolerance")
        _not_renamed(prop, "--tolerance")
        if prop not in props:
            raise InputError(f"--tolerance: unknown property {prop!r}; properties: {', '.join(props)}")
        if value is None:
            raise InputError(f"--tolerance: {item!r} is not PROPERTY=NUMBER")
        tolerances[prop] = value
    gates: dict[str, float | None] = {}
    for item in args.gate:
        prop, goal = _number(item, "--gate")
        _not_renamed(prop, "--gate")
        performance = [n for n, p in props.items() if p.kind == PERFORMANCE]
        if prop not in performance:
            raise InputError(f"--gate: {prop!r} is not a performance property; performance properties: {', '.join(performance)}")
        gates[prop] = goal
    if args.chunk < 1:
        raise InputError("--chunk must be >= 1")
    if not [n for n in names if n not in args.skip]:
        raise InputError("--skip: every suite is skipped, so nothing would be compared (drop a --skip)")
    return VerifyOptions(
        samples=args.samples,
        seed=args.seed,
        extra=extra,
        tolerances=tolerances,
        gates=gates,
        backends=args.backends.split(",") if args.backends else None,
        suites=[n for n in names if n not in args.skip],
        jobs=args.jobs,
        executor=args.executor,
        scheduler=args.scheduler,
        chunk=args.chunk,
        slow_samples=args.slow_samples,
    )


def profile_line(result, report_s: float, total_s: float) -> str:
    """``profile: kinematics 2.10 s (cpu 2.05 s), ik ...; report 1.52 s; total 9.81 s``: wall time per
    suite (CPU of this process and its renderers/workers in brackets), writing JSON + HTML, and the
    whole command from the end of argument parsing."""
    cpu = result.cpu_timings
    parts = [
        f"{name} {wall:.2f} s" + (f" (cpu {cpu[name]:.2f} s)" if name in cpu else "") for name, wall in result.timings.items()
    ]
    return f"profile: {', '.join(parts)}; report {report_s:.2f} s; total {total_s:.2f} s"


def _audit(args, options, console, command: str, packages: dict, xacro_args: dict):
    """``verify --urdf X``, ``--mjcf Y`` or ``--sdf Z`` alone: the one-file audit."""
    from kinverify.filemode.audit import audit_file
    from kinverify.report.progress import VerifyProgress

    for flag, given in (
        ("--frames", args.frames),
        ("--joints", args.joints),
        ("--accept", args.accept),
        ("--write-accepted", args.write_accepted),
    ):
        if given:
            raise InputError(
                f"{flag} pairs two files: give two of --urdf, --mjcf, --sdf and --usd, or drop {flag} for a one-file audit"
            )
    if not args.urdf and (packages or xacro_args):
        raise InputError("--package and --xacro-arg go with --urdf")
    kind, path = next((k, p) for k, p in (("urdf", args.urdf), ("mjcf", args.mjcf), ("sdf", args.sdf), ("usd", args.usd)) if p)
    if kind == "sdf":
        _needs_drake()
    if kind == "usd":
        _needs_usd()
    with VerifyProgress(console, "audit") as bar:
        bar.suite("kinematics")
        options.on_progress = bar.advance
        return audit_file(path, kind, options, command=command, packages=packages, xacro_args=xacro_args)


def _needs_drake() -> None:
    """An SDFormat file is read by Drake alone: without the extra, say how to install it (exit 2)."""
    from kinverify.backends import backend_info

    info = backend_info("drake-sdf")
    if not info.available:
        raise InputError(
            f"--sdf: SDFormat is read by Drake, which is not installed: pip install 'kinverify[drake]' ({info.reason})"
        )


def _needs_usd() -> None:
    """A USD file is read by usd-core (pxr): without the extra, say how to install it (exit 2)."""
    from kinverify.backends import backend_info

    info = backend_info("usd")
    if not info.available:
        raise InputError(
            f"--usd: OpenUSD is read by usd-core, which is not installed: pip install 'kinverify[usd]' ({info.reason})"
        )


def run(args) -> int:
    import shlex
    import time

    t_run = time.perf_counter()
    from rich.cells import cell_len
    from rich.text import Text

    from kinverify.text import console as text_console, markup

    from kinverify.report import print_result, write_json
    from kinverify.report.html import write_html

    options = options_from_args(args)
    command = "kinverify " + shlex.join(args.argv)
    console = text_console()  # the terminal's width (COLUMNS, or 80 when not a terminal); tables fit it
    files = [f for f in (args.urdf, args.mjcf, args.sdf, args.usd) if f]
    if files:
        if args.model:
            raise InputError("give either a spec MODEL or --urdf/--mjcf/--sdf/--usd, not both")
        from kinverify.filemode.read.xacro import parse_pairs
        from kinverify.report.progress import VerifyProgress

        packages, xacro_args = parse_pairs(args.package, "--package"), parse_pairs(args.xacro_arg, "--xacro-arg")
        if len(files) == 1:
            result = _audit(args, options, console, command, packages, xacro_args)
        else:
            from kinverify.filemode.pipeline import verify_files, verify_three
            from kinverify.filemode.read.files import sides
            from kinverify.filemode.read.loading import given_packages, load_urdf

            if args.sdf:
                _needs_drake()
            if args.usd:
                _needs_usd()
            with given_packages(packages, xacro_args):
                if args.urdf:
                    load_urdf(args.urdf, keep_meshes=False, packages=packages, xacro_args=xacro_args)  # bad input: exit 2 first
                with VerifyProgress(console, "files") as bar:
                    bar.suite("kinematics")  # file mode: alignment, then the suites on the aligned files
                    options.on_progress = bar.advance
                    if len(files) >= 3:
                        if args.frames or args.joints or args.write_accepted:
                            raise InputError(
                                "--frames, --joints and --write-accepted pair two files: give two of --urdf, "
                                "--mjcf, --sdf and --usd"
                            )
                        result = verify_three(
                            args.urdf, args.mjcf, args.sdf, options, command=command, accept=args.accept, usd=args.usd
                        )
                    else:
                        (kind_a, a), (kind_b, b) = sides(args.urdf, args.mjcf, args.sdf, args.usd)
                        result = verify_files(
                            a,
                            b,
                            options,
                            frames=args.frames,
                            joints=args.joints,
                            command=command,
                            accept=args.accept,
                            write_accepted=args.write_accepted,
                            kinds=(kind_a, kind_b),
                        )
    else:
        if not args.model:
            raise InputError(
                "give a spec MODEL (models/*.toml), or --urdf, --mjcf, --sdf, --usd (one to audit, two or more to compare)"
            )
        if args.accept or args.write_accepted:
            raise InputError("--accept and --write-accepted are for file mode (--urdf and --mjcf)")
        if args.package or args.xacro_arg:
            raise InputError("--package and --xacro-arg go with --urdf")
        from kinverify.report.progress import VerifyProgress
        from kinverify.model.specfile import load_spec
        from kinverify.run import verify_spec

        spec = load_spec(args.model)
        with VerifyProgress(console, spec.name) as bar:
            options.on_progress = bar.advance
            result = verify_spec(spec, options, source=str(args.model), command=command, progress=bar.suite)
    if not (result.checks or result.findings or result.internal_errors):
        raise InputError(
            f"{result.source}: nothing was compared (no check and no finding with these options: "
            f"--skip {', --skip '.join(args.skip) or '(none)'}, --backends {args.backends or 'all'}); "
            "no report written"
        )
    if not args.quiet:
        print_result(result, console)
    from kinverify.io.plan import claim_outputs, default_output

    json_out, html_out = args.json or default_output(result.model, ".json"), args.report or default_output(result.model, ".html")
    claim_outputs(("--json", json_out), ("--report", html_out))  # both checked before either is written
    t_report = time.perf_counter()
    json_path = write_json(result, json_out)  # the JSON first: it holds everything the page shows
    written = [f"report: {markup(write_html(result, html_out))}", f"json: {markup(json_path)}"]
    if args.junit:
        from kinverify.report.junit import junit_xml
        from kinverify.io.write import write_atomic

        written.append(f"junit: {markup(write_atomic(args.junit, junit_xml(result)))}")
    outputs = "  ".join(written)
    if args.quiet:  # one line, whatever the terminal's width
        console.print(
            f"{markup(result.model)}: {result.verdict} ({len(result.failed)} of {len(result.checks)} checks failed, "
            f"{len(result.failing_findings)} error findings); {outputs}",
            soft_wrap=True,
        )
    else:  # paths are never broken: one line, or one line each when that is too wide
        wide = cell_len(Text.from_markup(outputs, emoji=False).plain) > console.width
        console.print("\n".join(written) if wide else outputs, soft_wrap=True, highlight=False)
    if args.profile:
        console.print(profile_line(result, time.perf_counter() - t_report, time.perf_counter() - t_run), highlight=False)
    for err in result.internal_errors:
        console.print(
            f"[bold red]internal error[/] (a kinverify bug, not a property of the model; please report it "
            f"with the JSON): {markup(err)}"
        )
    return result.exit_code
