"""Command line: ``kinverify <command> ...`` (also ``python -m kinverify``).

Each subcommand is a module in :mod:`kinverify.commands` with ``add_parser(subparsers)`` and
``run(args) -> int``; heavy imports happen inside ``run``. Exit codes: 0 agreement, 1 a check
failed (the models disagree), 2 bad input, an unusable output path or a system error such as a
full disk (one line on stderr, no traceback), 3 an internal error (a kinverify bug: one line saying where to report it; ``verify``
still writes what it computed), 130 interrupted (SIGINT), 143 terminated (SIGTERM).

Before a command runs, its arguments that name files are checked here, in one place: seeds,
sample counts and chunk sizes against :mod:`kinverify.pipeline.limits`, and every output path
against every input (:mod:`kinverify.io.plan`), so a bad path is refused before a long run.
Set ``KINVERIFY_DEBUG=1`` to see the traceback of an internal error.
"""

from __future__ import annotations

import argparse
import importlib
import os
import signal
import sys

from kinverify import __version__

COMMANDS = ("verify", "generate", "report", "ik", "track", "baseline", "diff", "check", "map")
ISSUES = "the kinverify issue tracker"
# argument -> how messages name it; these name files a command reads
# (files found while loading, such as an MJCF's includes, are added by the reader: kinverify.io.read)
INPUTS = {
    "model": "the spec MODEL",
    "urdf": "--urdf",
    "mjcf": "--mjcf",
    "results": "RESULTS",
    "baseline": "--baseline",
    "old": "OLD",
    "new": "NEW",
    "accept": "--accept",
    "targets": "--targets",
    "initial": "--initial",
    "actuators": "--actuators",
}
OUTPUTS = {
    "json": "--json",
    "report": "--report",
    "junit": "--junit",
    "out": "--out",  # generate's --out is a directory
    "write_accepted": "--write-accepted",
}


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit 2), like every other kinverify error."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(
        prog="kinverify",
        description="Prove that a robot arm's models agree: "
        "analytic FK, Pinocchio (URDF and MJCF), MuJoCo and yourdfpy, property by property.",
    )
    parser.add_argument("--version", action="version", version=f"kinverify {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name in COMMANDS:
        module = importlib.import_module(f".commands.{name}", __package__)
        module.add_parser(sub).set_defaults(run=module.run)
    return parser


def check_args(args) -> None:
    """Limits on numeric arguments (see docs/robustness.md); :class:`InputError` on the first bad one."""
    from kinverify.errors import InputError
    from kinverify.pipeline import limits

    if getattr(args, "seed", None) is not None:
        limits.check_seed(args.seed)
    stored = args.command in ("baseline", "diff")
    if getattr(args, "samples", None) is not None:
        limits.check_count(args.samples, "--samples", limits.MAX_STORED_SAMPLES if stored else limits.MAX_SAMPLES)
    if getattr(args, "chunk", None) is not None:
        limits.check_count(args.chunk, "--chunk", limits.MAX_CHUNK, minimum=1)
    if getattr(args, "jobs", None) is not None:
        limits.check_count(args.jobs, "--jobs", limits.MAX_SAMPLES, minimum=1)
    if getattr(args, "ik_targets", None) is not None:
        limits.check_count(args.ik_targets, "--ik-targets", limits.MAX_STORED_SAMPLES)
    for flag in ("duration", "hold"):
        value = getattr(args, flag, None) if args.command == "track" else None
        if value is not None and value > limits.MAX_TRACK_SECONDS:  # NaN and negative values: track's own checks
            raise InputError(f"--{flag} {value:g} s is above the maximum {limits.MAX_TRACK_SECONDS:g} s (see docs/robustness.md)")


def run_files(args) -> tuple[list, list]:
    """``(label, path)`` of the files ``args`` names: inputs, then outputs."""
    inputs = [(label, getattr(args, key)) for key, label in INPUTS.items() if isinstance(getattr(args, key, None), str)]
    outputs = [
        (label, getattr(args, key))
        for key, label in OUTPUTS.items()
        if isinstance(getattr(args, key, None), str) and not (key == "out" and args.command == "generate")
    ]
    return inputs, outputs


def _one_line(err: BaseException, limit: int | None = None) -> str:
    from kinverify.text import shown

    text = shown(" ".join(str(err).split()) or type(err).__name__)
    return text if limit is None or len(text) <= limit else text[: limit - 3] + "..."


def main(argv: list[str] | None = None) -> int:
    """Run ``kinverify argv`` (default: the process's arguments); returns the exit code.

    SIGINT and SIGTERM are handled from the first line (:mod:`kinverify.interrupts`): whenever one
    arrives, no output is written and the exit code is 130 or 143. Library messages stay off the
    terminal (:mod:`kinverify.io.quiet`). The outputs are committed together at the end
    (:mod:`kinverify.io.plan`), with the signals held for the renames."""
    from kinverify import interrupts
    from kinverify.text import restore_streams, tolerant_streams

    previous = interrupts.install()
    streams = tolerant_streams()  # a name the terminal's encoding cannot show is replaced, never fatal
    try:
        try:
            return _main(argv)
        except KeyboardInterrupt:  # a signal while an error was being reported
            return _interrupted()
    finally:
        restore_streams(streams)
        if argv is not None or not previous:  # called in-process: give the caller its handlers back
            interrupts.restore(previous)
        else:  # the process exits now: a late signal must not print a traceback on the way out
            interrupts.restore({sig: signal.SIG_IGN for sig in previous})


def _interrupted() -> int:
    from kinverify import interrupts

    code = interrupts.exit_code()
    print(f"kinverify: {'terminated' if code == 128 + signal.SIGTERM else 'interrupted'}", file=sys.stderr)
    return code


def _main(argv: list[str] | None) -> int:
    from kinverify import interrupts
    from kinverify.errors import KinverifyError
    from kinverify.io.quiet import library_output

    parser = build_parser()
    args = parser.parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)
    debug = bool(os.environ.get("KINVERIFY_DEBUG"))
    try:
        with library_output(quiet=not debug):
            from kinverify.io.plan import output_plan

            check_args(args)
            inputs, outputs = run_files(args)
            with output_plan(inputs, outputs) as plan:
                code = args.run(args)
                interrupts.check()  # a signal a library swallowed: nothing is written
                with interrupts.held():
                    interrupts.check()
                    plan.commit()
            interrupts.check()  # held during the renames: the outputs are complete, the signal still counts
            return code
    except KeyboardInterrupt:
        return _interrupted()
    except KinverifyError as err:
        if interrupts.received():  # e.g. a library whose import was interrupted, reported as unavailable
            return _interrupted()
        print(f"kinverify: error: {_one_line(err)}", file=sys.stderr)
        return 2
    except OSError as err:  # the system refused (disk full, file size limit, permissions): not a bug
        if interrupts.received():
            return _interrupted()
        from kinverify.text import shown

        where = f"{shown(err.filename)}: " if err.filename else ""
        print(f"kinverify: error: {where}{err.strerror or _one_line(err)} (a system error)", file=sys.stderr)
        return 2
    except Exception as err:  # a kinverify bug: say so in one line, never a traceback
        if interrupts.received():  # an interrupted import or call surfacing as another exception
            return _interrupted()
        if debug:
            import traceback

            traceback.print_exc()
        print(
            f"kinverify: internal error: {type(err).__name__}: {_one_line(err, 300)} (please report it at {ISSUES} "
            "with the command line)",
            file=sys.stderr,
        )
        return 3


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
