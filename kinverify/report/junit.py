"""JUnit XML of a result, for CI systems that display test results per case.

One ``<testsuite>`` per property suite (in registry order) with one ``<testcase>`` per property ×
backend pair (``classname`` = the suite, ``name`` = ``property [a vs b]``); its frames are
counted in the case's ``assertions`` attribute, so the file counts the same checks as the JSON.
A failing case carries a ``<failure>`` naming the first frame along the chain that disagrees, the
error against the tolerance and the worst configuration to reproduce it. A performance property
below its goal that does not decide the verdict is ``<skipped>`` with the reason. File-mode
findings form a last suite ``findings``: an error finding is a failure, an accepted one is
skipped, warnings and infos pass with their message as output. A run that hit an internal
error adds an ``<error>`` case per suite that raised.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import defaultdict

from kinverify.results import VerifyResult
from kinverify.suites.base import EXPLAINED, Check
from kinverify.suites.registry import SUITES

SUITE_OF = {p.name: s.name for s in SUITES for p in s.properties}


def _suite_of(prop: str) -> str:
    return SUITE_OF.get(prop, prop.split(".", 1)[0])


def _q(check: Check) -> str:
    return "[" + ", ".join(repr(float(v)) for v in check.worst_q) + "]"


def _case(parent: ET.Element, classname: str, name: str, seconds: float = 0.0, assertions: int | None = None) -> ET.Element:
    attrs = {"classname": classname, "name": name, "time": f"{seconds:.3f}"}
    if assertions is not None:
        attrs["assertions"] = str(assertions)
    return ET.SubElement(parent, "testcase", attrs)


def junit_xml(result: VerifyResult) -> str:
    """The result as a JUnit XML document (a string)."""
    groups: dict[tuple[str, tuple[str, str]], list[Check]] = defaultdict(list)
    for c in result.checks:
        groups[(c.property, c.backends)].append(c)
    order = {name: i for i, name in enumerate(SUITE_OF)}
    by_suite: dict[str, list] = defaultdict(list)
    for key in sorted(groups, key=lambda k: (order.get(k[0], len(order)), k[1])):
        by_suite[_suite_of(key[0])].append(key)
    frame_rank = {f: i for i, f in enumerate(result.frames)}
    root = ET.Element("testsuites", {"name": f"kinverify {result.model}", "time": f"{result.duration_s:.3f}"})
    for suite, keys in by_suite.items():
        element = ET.SubElement(
            root, "testsuite", {"name": suite, "timestamp": result.started or "", "time": f"{result.timings.get(suite, 0.0):.3f}"}
        )
        counts = {"tests": 0, "failures": 0, "skipped": 0, "errors": 0}
        for prop, pair in keys:
            checks = groups[(prop, pair)]
            case = _case(element, f"kinverify.{suite}", f"{prop} [{' vs '.join(pair)}]", assertions=len(checks))
            counts["tests"] += 1
            failed = [c for c in checks if not c.passed]
            if not failed:
                continue
            first = min(failed, key=lambda c: frame_rank.get(c.frame, len(frame_rank)))
            text = (
                f"{prop} ({' vs '.join(pair)}) at {first.frame}: max error {first.max_error:.3e} {first.unit} > "
                f"tolerance {first.tolerance:.3g} {first.unit}; {len(failed)} of {len(checks)} checks; "
                f"worst configuration ({', '.join(result.joint_names)}): q = {_q(first)}"
            )
            if first.counts:
                ET.SubElement(case, "failure", {"type": "disagreement", "message": text}).text = text + (
                    f"\nnote: {first.note}" if first.note else ""
                )
                counts["failures"] += 1
            elif first.kind == EXPLAINED:
                ET.SubElement(case, "skipped", {"message": f"explained by a finding (the finding counts): {text}"})
                counts["skipped"] += 1
            else:
                ET.SubElement(case, "skipped", {"message": f"below its goal (performance, not counted): {text}"})
                counts["skipped"] += 1
        element.attrib.update({k: str(v) for k, v in counts.items()})
    if result.findings:
        element = ET.SubElement(root, "testsuite", {"name": "findings", "timestamp": result.started or "", "time": "0.000"})
        counts = {"tests": 0, "failures": 0, "skipped": 0, "errors": 0}
        for f in result.findings:
            case = _case(element, f"kinverify.findings.{f.kind}", f"{f.kind} [{f.label}]")
            counts["tests"] += 1
            if f.accepted:
                ET.SubElement(case, "skipped", {"message": f"accepted: {f.message}"})
                counts["skipped"] += 1
            elif f.severity == "error":
                ET.SubElement(case, "failure", {"type": f.kind, "message": f.message}).text = f.message
                counts["failures"] += 1
            else:
                ET.SubElement(case, "system-out").text = f"{f.severity}: {f.message}"
        element.attrib.update({k: str(v) for k, v in counts.items()})
    if result.internal_errors:
        element = ET.SubElement(
            root,
            "testsuite",
            {
                "name": "internal",
                "tests": str(len(result.internal_errors)),
                "failures": "0",
                "skipped": "0",
                "errors": str(len(result.internal_errors)),
            },
        )
        for message in result.internal_errors:
            case = _case(element, "kinverify.internal", message.split(":", 1)[0])
            ET.SubElement(case, "error", {"type": "internal error", "message": message}).text = message
    totals = {k: sum(int(s.get(k, 0)) for s in root) for k in ("tests", "failures", "errors", "skipped")}
    root.attrib.update({k: str(v) for k, v in totals.items()})
    ET.indent(root)
    return '<?xml version="1.0" encoding="utf-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
