"""``kinverify check FILE...``: a quick verdict per changed robot model, for pre-commit hooks and CI.

Each spec ``NAME.toml`` is verified (``--samples``, default 100; the kinematics, limits, inertia
and dynamics suites unless ``--suites`` says otherwise) and, when a baseline of it exists
(``baselines/NAME.json`` beside the spec, else in the current folder; ``--baselines DIR`` names
the folder), checked against it as ``kinverify baseline check`` does. A URDF or an MJCF ``.xml`` is verified in file
mode against the file of the other format with the same stem in the same folder (its
``kinverify-accepted.toml`` applies); a changed ``kinverify-accepted.toml`` re-checks the pairs
in its folder. One line per model; nothing is written. Exit 0 every model agrees, 1 a model
disagrees or moved from its baseline, 2 bad input (a spec or baseline kinverify cannot read), 3 a
kinverify bug; with several models the highest code.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from kinverify.commands import count as _count
from kinverify.text import shown

DEFAULT_SUITES = "kinematics,limits,inertia,dynamics"  # the agreement suites; ik and tracking are slower
ACCEPTED = "kinverify-accepted.toml"


def add_parser(sub) -> argparse.ArgumentParser:
    p = sub.add_parser(
        "check",
        help="a quick verdict per changed model (specs, URDF/MJCF pairs): for pre-commit and CI",
        description="Verify each spec (.toml) with modest samples and check it against its baseline when "
        "one exists; verify each URDF or MJCF against its same-stem partner in file mode, or audit it alone when it has "
        "none (every library that reads it, compared). One line per "
        "model, nothing written. Exit 0 all agree, 1 a model disagrees or moved, 2 bad input.",
    )
    p.add_argument(
        "files",
        nargs="+",
        metavar="FILE",
        help=f"specs (.toml), URDFs (.urdf), MJCFs (.xml), {ACCEPTED} files; other files are skipped with a line",
    )
    p.add_argument("--samples", type=_count, default=100, help="uniform random configurations per model (default 100)")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument(
        "--suites",
        default=DEFAULT_SUITES,
        help=f"comma-separated property suites to run (default {DEFAULT_SUITES}; "
        "'all' for every suite, as kinverify verify runs)",
    )
    p.add_argument(
        "--baselines",
        metavar="DIR",
        help="folder of baselines named <spec stem>.json (default: baselines/ "
        "beside the spec, else baselines/ in the current folder)",
    )
    return p


def baseline_for(spec_path: Path, folder: str | None) -> Path | None:
    """The baseline of ``spec_path``, when one exists: ``DIR/<stem>.json`` (a FIFO or folder of that
    name is refused when read)."""
    places = [Path(folder)] if folder else [spec_path.parent / "baselines", Path("baselines")]
    return next((p / f"{spec_path.stem}.json" for p in places if (p / f"{spec_path.stem}.json").exists()), None)


def jobs(files: list[str]) -> list[tuple[str, Path, Path | None]]:
    """What to run, once each: ``("spec", path, None)``, ``("pair", urdf, mjcf)``, or
    ``("skip", path, None)`` for a file that names no model."""
    out: list[tuple[str, Path, Path | None]] = []
    for name in files:
        path = Path(name)
        if path.name == ACCEPTED:
            pairs = [
                ("pair", u, u.with_suffix(".xml")) for u in sorted(path.parent.glob("*.urdf")) if u.with_suffix(".xml").is_file()
            ]
            out += pairs or [("skip", path, None)]
        elif path.suffix == ".toml":
            out.append(("spec", path, None))
        elif path.suffix in (".urdf", ".xml"):
            urdf, mjcf = path.with_suffix(".urdf"), path.with_suffix(".xml")
            partner = mjcf if path.suffix == ".urdf" else urdf
            if partner.is_file():
                out.append(("pair", urdf, mjcf))
            else:  # alone: does every library read it alike? (an .xml only when it is an MJCF)
                out.append(("audit", path, None) if path.suffix == ".urdf" or _is_mjcf(path) else ("skip", path, None))
        else:
            out.append(("skip", path, None))
    return list(dict.fromkeys(out))


def _first_failure(result) -> str:
    failures = result.first_failures()
    if failures:
        c = failures[0]
        return (
            f"{c.property} at {c.frame} ({c.backends[0]} vs {c.backends[1]}): {c.max_error:.3g} {c.unit} > {c.tolerance:g}"
        ).replace("  ", " ")
    if result.failing_findings:
        f = result.failing_findings[0]
        return f"{f.kind} ({f.label}): {f.message}"
    return "; ".join(result.internal_errors)[:200]


def _summary(result) -> str:
    findings = len(result.failing_findings)
    line = f"{len(result.failed)} of {len(result.checks)} checks failed, {findings} error finding{'s' * (findings != 1)}"
    return line if result.passed else f"{line}; first: {_first_failure(result)}"


STATUS = {0: "ok", 1: "FAIL", 3: "ERROR (a kinverify bug)"}


def check_spec(path: Path, options, args) -> tuple[int, str]:
    from kinverify.model.specfile import load_spec
    from kinverify.run import verify_spec

    spec = load_spec(path)
    result = verify_spec(spec, options, source=str(path), command=f"kinverify check {path}")
    code, line = result.exit_code, _summary(result)
    baseline = baseline_for(path, args.baselines)
    if baseline is not None:
        from kinverify.regression.check import check

        moved = check(spec, baseline)
        if moved.passed:
            line += f"; baseline {baseline}: nothing moved"
        else:
            code = max(code, 1)
            first = (
                f", first {moved.moved[0].property} at {moved.moved[0].frame} by {moved.moved[0].delta:.3g} {moved.moved[0].unit}"
                if moved.moved
                else ""
            )
            line += (
                f"; baseline {baseline}: {len(moved.moved)} quantities moved{first} "
                f"(details: kinverify baseline check {path} --baseline {baseline})"
            )
    if result.exit_code:
        line += f"; details: kinverify verify {path}"
    return code, f"{STATUS[code]}: {line}"


def _is_mjcf(path: Path) -> bool:
    from kinverify.io.read import InputFileError, read_head

    try:
        return b"<mujoco" in read_head(path, 4096)
    except InputFileError:  # absent, or not a regular file (a FIFO is never opened): not a model to check
        return False


def check_audit(path: Path, options) -> tuple[int, str]:
    from kinverify.filemode.audit import audit_file

    kind = "urdf" if path.suffix == ".urdf" else "mjcf"
    result = audit_file(str(path), kind, options, command=f"kinverify check {path}")
    line = "every library reads it alike; " + _summary(result) if not result.exit_code else _summary(result)
    if result.exit_code:
        line += f"; details: kinverify verify --{kind} {path}"
    return result.exit_code, f"{STATUS[result.exit_code]}: {line}"


def check_pair(urdf: Path, mjcf: Path, options) -> tuple[int, str]:
    from kinverify.filemode.pipeline import verify_files

    result = verify_files(str(urdf), str(mjcf), options, command=f"kinverify check {urdf} {mjcf}")
    line = _summary(result)
    if result.exit_code:
        line += f"; details: kinverify verify --urdf {urdf} --mjcf {mjcf}"
    return result.exit_code, f"{STATUS[result.exit_code]}: {line}"


def run(args) -> int:
    import os
    import sys

    from kinverify.errors import InputError, KinverifyError
    from kinverify.run import VerifyOptions
    from kinverify.suites.registry import suite_names

    names = suite_names()
    suites = names if args.suites == "all" else [s.strip() for s in args.suites.split(",") if s.strip()]
    unknown = [s for s in suites if s not in names]
    if unknown or not suites:
        raise InputError(f"--suites: unknown suite {', '.join(map(repr, unknown)) or '(none given)'}; suites: {', '.join(names)}")
    options = VerifyOptions(samples=args.samples, seed=args.seed, suites=suites)
    worst = 0
    for kind, path, other in jobs(args.files):
        label = shown(f"{path} + {other.name}" if kind == "pair" else path)  # type: ignore[union-attr]  # a pair has its other file
        if kind == "skip":
            print(f"{label}: skipped (not a spec .toml, a URDF or an MJCF)", flush=True)
            continue
        try:
            code, line = (
                check_spec(path, options, args)
                if kind == "spec"
                else check_pair(path, other, options)  # type: ignore[arg-type]  # a pair has its other file
                if kind == "pair"
                else check_audit(path, options)
            )
        except KinverifyError as err:  # the message names the file
            message = shown(" ".join(str(err).split()))
            print(f"error: {message}" if shown(path) in message else f"{label}: error: {message}", file=sys.stderr, flush=True)
            worst = max(worst, 2)
            continue
        except (KeyboardInterrupt, OSError):
            raise
        except Exception as err:  # a kinverify bug: this model's line says so, the others still run
            if os.environ.get("KINVERIFY_DEBUG"):
                import traceback

                traceback.print_exc()
            code, line = 3, f"ERROR (internal): {type(err).__name__}: {shown(' '.join(str(err).split())[:300])} (a kinverify bug)"
        print(f"{label}: {shown(line)}", flush=True)
        worst = max(worst, code)
    return worst
