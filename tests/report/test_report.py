"""The HTML report, read back from the HTML itself: a passing and a failing model, escaping of
names from a model file, re-rendering from JSON, the CLI, and a real headless Chromium (first
screen, page height, no network)."""

from __future__ import annotations

import dataclasses
import html as htmllib
import json
import re

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.backends import ModelSources, backend_info
from kinverify.backends.analytic import AnalyticBackend
from kinverify.cli import main
from kinverify.model.specfile import load_spec
from kinverify.model.transforms import geodesic_distance
from kinverify.report.html import cell, render_html
from kinverify.report.json_ import load_result_json, write_json
from kinverify.results import VerifyResult
from kinverify.suites.base import Finding
from kinverify.run import VerifyOptions, verify
from tests.paths import ROOT
from tests.report import browser
from tests.report.flipped import FLIPPED, flipped_backend
from tests.report.terminal_checks import PASSING_LINES, assert_fits, render


@pytest.fixture(scope="module")
def arm3():
    return load_spec(ROOT / "models" / "arm3.toml")


@pytest.fixture(scope="module")
def passing(arm3):
    opts = VerifyOptions(samples=30, suites=["kinematics", "diagnosis", "workspace"])
    return verify(ModelSources.from_spec(arm3), opts, command="kinverify verify models/arm3.toml --samples 30")


@pytest.fixture(scope="module")
def failing(arm3):
    sources = ModelSources.from_spec(arm3)
    return verify(
        sources, VerifyOptions(samples=30), extra_backends=[flipped_backend(sources, "joint2")], command="pytest failing fixture"
    )


@pytest.fixture(scope="module")
def failing_page(failing):
    return render_html(failing)


@pytest.fixture(scope="module")
def default_arm3(tmp_path_factory):
    """The default ``kinverify verify models/arm3.toml`` (only the output paths changed)."""
    folder = tmp_path_factory.mktemp("default")
    html, js = folder / "arm3.html", folder / "arm3.json"
    assert main(["verify", str(ROOT / "models" / "arm3.toml"), "--quiet", "--report", str(html), "--json", str(js)]) == 0
    return html, js


def _text(fragment: str) -> str:
    return " ".join(htmllib.unescape(re.sub(r"<[^>]+>", "", fragment)).split())


def _between(page: str, start: str, end: str) -> str:
    i = page.index(start)
    return page[i : page.index(end, i)]


def _worst_rows(page: str) -> list[tuple[list[float], list[float], str]]:
    """(q rad, q deg, where) of every row of the first worst-configuration table."""
    table = _between(page, '<table class="worst">', "</table>")
    rows = []
    for row in re.findall(r"<tr><td>\d+</td>(.*?)</tr>", table, re.S):
        cells = re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)
        rad, deg = (json.loads(_text(c)) for c in cells[:2])
        rows.append((rad, deg, _text(cells[2])))
    return rows


def test_passing_report_states_the_verdict_and_what_was_compared(passing):
    page = render_html(passing)
    banner = _between(page, '<header class="banner', "</header>")
    assert 'class="banner pass"' in banner and "PASS" in banner and "exit 0: the models agree" in _text(banner)
    assert f"all {len(passing.checks)} checks agree" in _text(banner)
    assert f"{passing.samples} configurations (seed {passing.seed})" in _text(banner)
    assert 'id="failures"' not in page and "FAIL</td>" not in page
    for name in passing.backends:
        assert name in _text(banner)
    for key in ("python", "numpy", "pin", "mujoco", "yourdfpy", "kinverify"):
        assert f"{key} {passing.versions[key]}" in page
    assert passing.command in page and f"{passing.seed} · {passing.samples} configurations" in _text(page)
    assert page.count("<svg") >= 2  # error distributions and workspace, inline


def test_a_warning_of_a_suite_is_shown_on_a_passing_page(passing):
    """A suite's warning (here the IK one: a solver that solves almost nothing) has its own
    section on the page, not only a count in the banner; the verdict stays PASS."""
    warning = Finding(
        "ik_solver_fails",
        "warning",
        "LM IK on reachable targets for end_effector: analytic solves 0 of 50",
        subject="end_effector",
        subject_type="frame",
        property="ik.failure_rate",
    )
    page = render_html(dataclasses.replace(passing, findings=[warning]))
    section = _text(_between(page, '<section id="findings">', "</section>"))
    assert "frame end_effector" in section and "warning" in section and warning.message in section
    assert 'class="banner pass"' in page and "1 warning" in _text(_between(page, '<header class="banner', "</header>"))


def test_every_check_is_in_the_heat_map_with_its_value_and_a_link_to_its_detail(failing, failing_page):
    page = failing_page
    heat = _between(page, '<section id="matrix">', "</section>")
    cells = re.findall(r'<a class="cell( bad)?" href="#([^"]+)" style="background:(#[0-9a-f]{6})[^"]*" title="([^"]*)">', heat)
    assert cells
    ids = set(re.findall(r' id="([^"]+)"', page))
    for bad, anchor, colour, title in cells:
        assert anchor in ids  # the detail row the cell links to
        assert (colour == "#c62828") == bool(bad) or "below goal" in htmllib.unescape(title)
    for c in failing.checks:  # every property is a row; the failing ones are red where they fail
        assert f'<th class="prop">{c.property}' in heat
    titles = [htmllib.unescape(t) for _, _, _, t in cells]
    for c in failing.failed:
        assert any(t.startswith(f"{c.property}: ") and "fail" in t for t in titles)
    worst = max((c for c in failing.checks if c.property == "fk.position"), key=lambda c: c.max_error)
    assert any(f"{worst.max_error:.3g} {worst.unit}" in t for t in titles)


def test_failing_report_names_the_failure_where_it_starts_and_what_to_check(failing, failing_page, arm3):
    page = failing_page
    banner = _text(_between(page, '<header class="banner', "</header>"))
    assert "FAIL" in banner and "exit 1: the models disagree" in banner
    assert f"{len(failing.failed)} of {len(failing.checks)} checks failed" in banner
    assert failing.failed and all(FLIPPED in c.backends for c in failing.failed)
    first = min(failing.failed, key=lambda c: failing.frames.index(c.frame))
    assert f"{FLIPPED}:" in banner and f"from frame {first.frame}" in banner
    card = _text(_between(page, '<article class="failure"', "</article>"))
    assert card.startswith(f"{FLIPPED}: {len(failing.failed)} failing checks, starting at frame {first.frame}")
    assert "What to check: sign flip of joint joint2" in card
    # the worst configurations, read from the page, really reproduce the disagreement
    rows = _worst_rows(page)
    assert rows
    ref, flipped = AnalyticBackend(arm3), flipped_backend(ModelSources.from_spec(arm3), "joint2")
    for rad, deg, where in rows[:3]:
        np.testing.assert_allclose(np.radians(deg), rad, atol=1e-6)
        q = np.array([rad])
        a, b = ref.poses(q)[0], flipped.poses(q)[0]
        err = np.linalg.norm(a[:, :3, 3] - b[:, :3, 3], axis=-1) + geodesic_distance(a[:, :3, :3], b[:, :3, :3])
        frame = where.split(" at ")[-1]
        assert err[list(failing.frames).index(frame)] > 1e-3
    # both values at the worst configuration: what each model computes there
    values = re.search(
        r'<p class="values">At <code class="vec">(\[[^<]*\])</code>.*?frame <b>([^<]+)</b> is at <code>(\[[^<]*\])</code> m in '
        r"analytic and at <code>(\[[^<]*\])</code> m in " + FLIPPED,
        page,
        re.S,
    )
    assert values
    q, frame = np.array([json.loads(values.group(1))]), values.group(2)
    k = list(failing.frames).index(frame)
    np.testing.assert_allclose(json.loads(values.group(3)), ref.poses(q)[0, k, :3, 3], atol=1e-5)
    np.testing.assert_allclose(json.loads(values.group(4)), flipped.poses(q)[0, k, :3, 3], atol=1e-5)
    assert np.linalg.norm(np.subtract(json.loads(values.group(3)), json.loads(values.group(4)))) > 1e-3


def test_rerender_from_json_is_identical(failing, failing_page, tmp_path):
    json_path = write_json(failing, tmp_path / "r.json")
    assert main(["report", str(json_path), "--out", str(tmp_path / "again.html")]) == 1  # the saved run failed
    assert (tmp_path / "again.html").read_text(encoding="utf-8") == failing_page


def test_a_results_json_from_before_the_ik_rename_reads_as_the_same_result(failing, tmp_path):
    """Schema 2 named the fraction of IK targets not solved ``ik.success_rate``; such a saved JSON
    reads under the property's name now, ``ik.failure_rate``, with the same values, so ``kinverify
    report`` draws the same page from it (a page is the result's alone: test above)."""
    data = failing.to_dict()
    old = [c for c in data["checks"] if c["property"] == "ik.failure_rate"]
    assert old
    for c in old:
        c["property"] = "ik.success_rate"
    data["schema_version"] = 2
    (tmp_path / "old.json").write_text(json.dumps(data))
    assert load_result_json(tmp_path / "old.json").to_dict() == failing.to_dict()


def test_report_command_rejects_a_file_that_is_not_a_result(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    assert main(["report", str(bad), "--out", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("kinverify: error: ") and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.html").exists()


EVIL = "<script>alert(1)</script>"


def test_names_from_a_model_file_are_escaped(arm3):
    """A URDF whose joint, link and model names are markup: shown as text, never as markup
    (tables, the kinematic tree, the skeleton)."""
    base = ModelSources.from_spec(arm3)
    urdf = base.urdf
    renames = {"joint2": EVIL, "link3": EVIL + "_link", arm3.name: "evil"}
    for old, new in renames.items():
        urdf = urdf.replace(f'"{old}"', '"' + htmllib.escape(new, quote=True) + '"')
    urdf = urdf.replace("<robot ", f"<!-- {EVIL} -->\n<robot ", 1)  # raw markup in the model text too
    joints = tuple(renames.get(j, j) for j in base.joint_names)
    frames = tuple(renames.get(f, f) for f in base.frames)
    sources = ModelSources("evil" + EVIL, joints, frames, base.lower, base.upper, base.revolute, urdf=urdf)
    result = verify(sources, VerifyOptions(samples=5, backends=["pinocchio-urdf", "yourdfpy"], reference="pinocchio-urdf"))
    assert EVIL in result.joint_names and EVIL + "_link" in result.frames and EVIL in result.model_info["urdf"]
    assert {EVIL, EVIL + "_link"} <= {
        n for j in result.sections["pictures"].data["tree"]["joints"] for n in (j["name"], j["child"])
    }
    page = render_html(result)
    assert EVIL not in page and "<script>alert" not in page
    assert htmllib.escape(EVIL) in _between(page, '<svg class="tree"', "</svg>")
    assert page.count("<script") == 1  # the page's own script only
    assert page.count("</script>") == 1


def test_verify_cli_writes_a_report_that_report_cli_reproduces_from_the_json(default_arm3, tmp_path):
    """The default run's page (the CLI, its command line shown) is what ``kinverify report`` renders
    again from its JSON, byte for byte; the outputs' atomic writes leave no temporary file."""
    html, js = default_arm3
    page = html.read_text(encoding="utf-8")
    assert 'class="banner pass"' in page and "kinverify verify " in page and "arm3.toml" in page
    assert main(["report", str(js), "--out", str(tmp_path / "again.html")]) == 0
    assert (tmp_path / "again.html").read_text(encoding="utf-8") == page
    assert not [p for p in [*html.parent.iterdir(), *tmp_path.iterdir()] if p.name.endswith(".tmp")]


def test_default_arm3_report_stays_under_5_mb_and_shows_every_section(default_arm3):
    """One page under 5 MB with every section, its plots, the pictures, and the tracking
    animation or the note saying why not; histograms only for sampled properties."""
    html, js = default_arm3
    size = html.stat().st_size
    assert size < 5_000_000, f"{size / 1e6:.2f} MB"
    page, data = html.read_text(encoding="utf-8"), json.loads(js.read_text())
    for name in ("ik", "tracking", "dynamics", "workspace"):
        assert f'<details class="fold" id="suite-{name}">' in page
        for fig in data["sections"][name]["figures"]:  # the JSON form of a Section
            assert f"base64,{fig['data']}" in page
    for fig in data["sections"]["pictures"]["figures"]:
        assert f"base64,{fig['data']}" in _between(page, '<section id="section-pictures">', "</section>")
    assert '<svg class="tree"' in page and page.count('<figure class="plot skeleton">') == 1
    assert len(data["sections"]["ik"]["figures"]) == 2
    tracking = data["sections"]["tracking"]
    gifs = [f for f in tracking["figures"] if f["mime"] == "image/gif"]
    unavailable = [n for n in tracking["notes"] if n.startswith("rendering unavailable")]
    assert (len(gifs), len(unavailable)) in ((1, 0), (0, 1))  # the computed-torque animation, or why it is missing
    assert not gifs or "computed-torque" in gifs[0]["title"]
    # section tables are formatted for reading: no 17-digit floats
    sections = _between(page, '<section id="details">', '<details class="fold" id="distributions">')
    tables = re.findall(r"<table>(.*?)</table>", sections, re.S)  # the suites' own tables (the overviews have a class)
    cells = [c for t in tables for c in re.findall(r'<td class="num">([^<]*)</td>', t)]
    assert cells and max(len(c) for c in cells) <= 11, max(cells, key=len)


def test_the_default_arm3_run_prints_in_40_lines_at_80_columns(default_arm3):
    """The full default run (every suite, tracking's rows included), printed from its saved JSON as
    an 80-column terminal and as a log: every row on one line, every number whole, 40 lines."""
    result = load_result_json(default_arm3[1])
    assert {c.property for c in result.checks} >= {"tracking.pd+gravity", "ik.closed_form"} and "pictures" in result.timings
    for terminal in (True, False):
        lines = render(result, 80, terminal)
        assert_fits(lines, result, 80)
        assert len(lines) <= PASSING_LINES - 1  # and the line naming the report and the JSON
    if not backend_info("drake-sdf").available:
        pytest.skip("docs/report.md shows the run with the test extra, Drake's backends included")
    shown = _between((ROOT / "docs" / "report.md").read_text(encoding="utf-8"), "```text\n", "\n```").splitlines()[1:]

    def numbers(line):  # the layout, not the timings
        return " ".join(re.sub(r"\d[\d.e+-]*", "#", line).split())

    assert [numbers(line) for line in shown[:-1]] == [numbers(line) for line in lines]  # docs/report.md shows this run
    assert shown[-1] == "report: reports/arm3.html  json: reports/arm3.json"


def test_error_distributions_only_for_sampled_properties(default_arm3):
    from kinverify.report.plots import error_distributions_svg

    result = VerifyResult.from_dict(json.loads(default_arm3[1].read_text()))
    single = [c for c in result.checks if c.samples <= 1]
    assert single  # parameter checks (damping, friction, armature) are single values
    sampled_only = VerifyResult.from_dict({**result.to_dict(), "checks": [c.to_dict() for c in result.checks if c.samples > 1]})
    assert error_distributions_svg(result) == error_distributions_svg(sampled_only)
    assert error_distributions_svg(VerifyResult.from_dict({**result.to_dict(), "checks": [c.to_dict() for c in single]})) is None


@settings(max_examples=50, deadline=None)
@given(
    st.one_of(
        st.floats(-1e300, 1e300), st.floats(allow_nan=False), st.integers(-(10**9), 10**9), st.booleans(), st.text(max_size=20)
    )
)
def test_section_cells_are_short_and_faithful(value):
    text = cell(value)
    if isinstance(value, bool):
        assert text == ("yes" if value else "no")
    elif isinstance(value, float):
        assert len(text) <= 11
        if abs(value) < 1e300:  # (rounding the largest floats up to 4 digits overflows to inf)
            assert float(text) == pytest.approx(value, rel=5e-4)
    else:
        assert text == str(value)


# --- a real browser -------------------------------------------------------------------------


@browser.needs_chromium
def test_passing_report_answers_on_its_first_screen(default_arm3, tmp_path):
    """Default arm3 at 1280×900: verdict and the whole heat map on the first screen, the page
    under 5,000 px with the details folded, every image decoded, no network request."""
    page = default_arm3[0].read_text(encoding="utf-8")
    layout, requests = browser.probe(page, tmp_path, ["#verdict", "#matrix", "#section-pictures", "#details"])
    boxes = layout["boxes"]
    assert boxes["#verdict"]["top"] == 0 and boxes["#matrix"]["bottom"] <= browser.HEIGHT, boxes
    assert layout["height"] < 5000, layout["height"]
    assert layout["width"] <= browser.WIDTH  # nothing sticks out sideways
    assert layout["images"] >= 2 and layout["decoded"] == layout["images"], layout
    assert layout["svgs"] >= 2  # the skeleton and the kinematic tree
    assert requests == []


@browser.needs_chromium
def test_failing_report_shows_its_first_failure_without_scrolling(failing, failing_page, tmp_path):
    from matplotlib.image import imread

    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", failing_page, re.I)
    layout, requests = browser.probe(failing_page, tmp_path, ["article.failure h3", "article.failure .hint", ".answer-picture"])
    boxes = layout["boxes"]
    assert boxes["article.failure h3"]["bottom"] <= browser.HEIGHT and boxes["article.failure .hint"]["bottom"] <= browser.HEIGHT
    assert boxes[".answer-picture"]["top"] < browser.HEIGHT  # the two models drawn beside the failure
    n_img = len(failing.sections["pictures"].figures)
    assert layout["images"] >= n_img and layout["decoded"] == layout["images"], layout
    assert requests == []
    # the detector itself sees a page that does reach for the network
    control = tmp_path / "control.html"
    control.write_text('<img src="http://example.invalid/x.png">')
    assert any("example.invalid" in url for _, url in browser.run(control, tmp_path, "--dump-dom")[1])
    # a screenshot: the first thing on screen is the red FAIL banner
    pixels = imread(browser.screenshot(failing_page, tmp_path))
    assert pixels.shape[:2] == (browser.HEIGHT, browser.WIDTH)
    r, g, b = pixels[10, 640, :3]
    assert r > 0.5 and g < 0.3 and b < 0.3


def test_an_internal_error_says_so_first_and_keeps_what_was_computed(passing, tmp_path):
    data = passing.to_dict()
    data["internal_errors"] = ["suite ik: ZeroDivisionError: division by zero (lm.py:12)"]
    result = VerifyResult.from_dict(data)
    page = render_html(result)
    banner = _text(_between(page, '<header class="banner', "</header>"))
    assert 'class="banner error"' in page and banner.startswith("ERROR exit 3: kinverify itself failed")
    assert "Internal error (a kinverify bug, not a property of the model): suite ik: ZeroDivisionError" in _text(page)
    assert '<section id="matrix">' in page  # what the other suites computed is still shown
    path = write_json(result, tmp_path / "e.json")
    assert main(["report", str(path), "--out", str(tmp_path / "e.html")]) == 3
