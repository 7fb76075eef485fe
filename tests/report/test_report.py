"""The HTML report, read back from the HTML itself: a passing and a failing model, escaping of
names from a model file, re-rendering from JSON, the CLI, and a real headless Chromium."""

from __future__ import annotations

import html as htmllib
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from kinverify.backends import ModelSources
from kinverify.backends.analytic import AnalyticBackend
from kinverify.backends.pinocchio_ import PinocchioBackend
from kinverify.cli import main
from kinverify.report.html import cell, render_html
from kinverify.report.json_ import write_json
from kinverify.results import VerifyResult
from kinverify.model.specfile import load_spec
from kinverify.model.transforms import geodesic_distance
from kinverify.run import VerifyOptions, verify
from tests.paths import ROOT

FLIPPED = "flipped-urdf"


@pytest.fixture(scope="module")
def arm3():
    return load_spec(ROOT / "models" / "arm3.toml")


@pytest.fixture(scope="module")
def passing(arm3):
    opts = VerifyOptions(samples=30, suites=["kinematics", "diagnosis", "workspace"])
    return verify(ModelSources.from_spec(arm3), opts, command="kinverify verify models/arm3.toml --samples 30")


def flipped_backend(sources: ModelSources, joint: str) -> PinocchioBackend:
    """The generated URDF with ``joint``'s axis negated, loaded by the real Pinocchio."""
    pattern = re.compile(rf'(<joint name="{joint}".*?<axis xyz=")([^"]*)(")', re.S)
    axis = [float(v) for v in pattern.search(sources.urdf).group(2).split()]
    urdf = pattern.sub(lambda m: m.group(1) + " ".join(str(-v + 0.0) for v in axis) + m.group(3), sources.urdf, count=1)
    assert urdf != sources.urdf
    return PinocchioBackend.from_urdf(urdf, sources.joint_names, sources.frames, name=FLIPPED)


@pytest.fixture(scope="module")
def failing(arm3):
    sources = ModelSources.from_spec(arm3)
    return verify(sources, VerifyOptions(samples=30), extra_backends=[flipped_backend(sources, "joint2")],
                  command="pytest failing fixture")


@pytest.fixture(scope="module")
def failing_page(failing):
    return render_html(failing)


def _text(fragment: str) -> str:
    return " ".join(htmllib.unescape(re.sub(r"<[^>]+>", "", fragment)).split())


def _worst_rows(page: str) -> list[tuple[list[float], list[float], str]]:
    """(q rad, q deg, where) of every row of the first worst-configuration table."""
    table = page[page.index('<table class="worst">'):]
    table = table[: table.index("</table>")]
    rows = []
    for row in re.findall(r"<tr><td>\d+</td>(.*?)</tr>", table, re.S):
        cells = re.findall(r"<td[^>]*>(.*?)</td>", row, re.S)
        rad, deg = (json.loads(_text(c)) for c in cells[:2])
        rows.append((rad, deg, _text(cells[2])))
    return rows


def test_passing_report_states_the_verdict(passing):
    page = render_html(passing)
    banner = page[page.index('<header class="banner'):page.index("</header>")]
    assert 'class="banner pass"' in banner and "PASS" in banner
    assert f"all {len(passing.checks)} checks agree" in _text(banner)
    assert "Where the models disagree" not in page and "FAIL</td>" not in page
    for name in passing.backends:
        assert name in _text(banner)
    for key in ("python", "numpy", "pin", "mujoco", "yourdfpy", "kinverify"):
        assert f"{key} {passing.versions[key]}" in page
    assert passing.command in page and f"{passing.seed} · {passing.samples} configurations" in _text(page)
    assert page.count("<svg") >= 2  # error distributions and workspace, inline


def test_failing_report_names_the_check_and_a_worst_configuration_that_reproduces_it(failing, failing_page, arm3):
    page = failing_page
    banner = _text(page[page.index('<header class="banner'):page.index("</header>")])
    assert "FAIL" in banner and f"{len(failing.failed)} of {len(failing.checks)} checks failed" in banner
    assert failing.failed and all(FLIPPED in c.backends for c in failing.failed)
    first = min(failing.failed, key=lambda c: failing.frames.index(c.frame))
    assert f"analytic vs {FLIPPED}" in banner and f"starts at frame {first.frame}" in banner
    assert "sign flip of joint joint2" in _text(page)
    # summary: failures first
    overview = page[page.index('<table class="overview'):]
    results = re.findall(r'<tr class="(ok|bad)">', overview[: overview.index("</table>")])
    assert results[0] == "bad" and results == sorted(results)
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


def test_rerender_from_json_is_identical(failing, failing_page, tmp_path):
    json_path = write_json(failing, tmp_path / "r.json")
    assert main(["report", str(json_path), "--out", str(tmp_path / "again.html")]) == 1  # the saved run failed
    assert (tmp_path / "again.html").read_text(encoding="utf-8") == failing_page


def test_report_command_rejects_a_file_that_is_not_a_result(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    assert main(["report", str(bad), "--out", str(tmp_path / "x.html")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("kinverify: error: ") and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "x.html").exists()


EVIL = "<script>alert(1)</script>"


def test_names_from_a_model_file_are_escaped(arm3):
    """A URDF whose joint, link and model names are markup: shown as text, never as markup."""
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
    page = render_html(result)
    assert EVIL not in page and "<script>alert" not in page
    assert htmllib.escape(EVIL) in page
    assert page.count("<script") == 1  # the page's own sorting script only
    assert page.count("</script>") == 1


# --- a real browser -------------------------------------------------------------------------

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync", "--hide-scrollbars",
         # network off: every request goes to a closed local port and no host name resolves
         "--proxy-server=http://127.0.0.1:9", "--host-resolver-rules=MAP * ~NOTFOUND"]

PROBE = """<script>
window.addEventListener("load", function () {
  var srcs = Array.prototype.map.call(document.images, function (i) { return i.src; });
  document.querySelectorAll("svg image").forEach(function (i) { srcs.push(i.getAttribute("href") || i.getAttribute("xlink:href")); });
  Promise.allSettled(srcs.map(function (s) { var im = new Image(); im.src = s; return im.decode().then(function () { return im.naturalWidth; }); }))
    .then(function (res) {
      var svgs = Array.prototype.filter.call(document.querySelectorAll("figure.plot > svg"), function (s) { return s.getBoundingClientRect().width > 0; });
      var out = {images: res.length, decoded: res.filter(function (r) { return r.status === "fulfilled" && r.value > 0; }).length, svgs: svgs.length};
      var pre = document.createElement("pre"); pre.id = "probe"; pre.textContent = JSON.stringify(out); document.body.appendChild(pre);
    });
});
</script>"""


def _chromium(page: Path, tmp: Path, *extra: str) -> tuple[str, list[tuple[str, str]]]:
    """Load ``page`` from disk; return the DOM after scripts ran and the (initiator, url) of
    every network request a page started (from Chromium's net log; the browser's own
    background requests have no origin and are left out)."""
    netlog = tmp / f"net-{page.stem}.json"
    cmd = [CHROMIUM, *FLAGS, f"--user-data-dir={tmp / 'profile'}", f"--log-net-log={netlog}", *extra, page.as_uri()]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    log = json.loads(netlog.read_text())
    start = log["constants"]["logEventTypes"]["URL_REQUEST_START_JOB"]
    requests = [(e["params"].get("initiator", ""), e["params"]["url"]) for e in log["events"]
                if e["type"] == start and "url" in (e.get("params") or {})]
    return proc.stdout, [r for r in requests if r[0] != "not an origin"]


@pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (.ci/run installs Debian's chromium)")
def test_report_in_headless_chromium(failing, failing_page, tmp_path):
    from matplotlib.image import imread

    assert failing.sections["pictures"].figures or failing.sections["pictures"].notes
    report = tmp_path / "report.html"
    report.write_text(failing_page, encoding="utf-8")
    assert not re.search(r"""(src|href)\s*=\s*["']?(https?:|//)""", failing_page, re.I)
    probed = tmp_path / "probed.html"
    probed.write_text(failing_page.replace("</body>", PROBE + "</body>"), encoding="utf-8")
    dom, requests = _chromium(probed, tmp_path, "--virtual-time-budget=10000", "--dump-dom")
    probe = json.loads(htmllib.unescape(re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S).group(1)))
    n_img = len(failing.sections["pictures"].figures)
    assert probe["images"] >= n_img and probe["decoded"] == probe["images"], probe
    assert probe["svgs"] >= 2, probe
    assert requests == []
    # the detector itself sees a page that does reach for the network
    control = tmp_path / "control.html"
    control.write_text('<img src="http://example.invalid/x.png">')
    assert any("example.invalid" in url for _, url in _chromium(control, tmp_path, "--dump-dom")[1])
    # a screenshot: the first thing on screen is the red FAIL banner
    shot = tmp_path / "shot.png"
    _chromium(report, tmp_path, "--window-size=1280,900", f"--screenshot={shot}")
    pixels = imread(shot)
    assert pixels.shape[:2] == (900, 1280)
    r, g, b = pixels[10, 640, :3]
    assert r > 0.5 and g < 0.3 and b < 0.3


def test_verify_cli_writes_a_report_that_report_cli_reproduces_from_the_json(tmp_path):
    html, js = tmp_path / "arm3.html", tmp_path / "arm3.json"
    args = ["verify", str(ROOT / "models" / "arm3.toml"), "--samples", "5", "--skip", "pictures", "--quiet",
            "--report", str(html), "--json", str(js)]
    assert main(args) == 0
    page = html.read_text(encoding="utf-8")
    assert 'class="banner pass"' in page and "kinverify verify " in page and "--samples 5" in page
    assert main(["report", str(js), "--out", str(tmp_path / "again.html")]) == 0
    assert (tmp_path / "again.html").read_text(encoding="utf-8") == page
    assert not [p for p in tmp_path.iterdir() if p.name.endswith(".tmp")]  # atomic writes leave nothing behind


def test_default_arm3_report_stays_under_5_mb_and_shows_every_section(tmp_path):
    """The default ``kinverify verify models/arm3.toml`` (only the output paths changed): one page
    under 5 MB with every section, its plots, and the tracking animation or the note saying why not."""
    html, js = tmp_path / "arm3.html", tmp_path / "arm3.json"
    assert main(["verify", str(ROOT / "models" / "arm3.toml"), "--quiet", "--report", str(html), "--json", str(js)]) == 0
    size = html.stat().st_size
    assert size < 5_000_000, f"{size / 1e6:.2f} MB"
    page, data = html.read_text(encoding="utf-8"), json.loads(js.read_text())
    toc = page[page.index('<nav class="toc"'):page.index("</nav>")]
    for name in ("pictures", "workspace", "ik", "tracking", "dynamics"):
        assert f'<section id="section-{name}">' in page and f'href="#section-{name}"' in toc
        for fig in data["sections"][name]["figures"]:  # the JSON form of a Section
            assert f"base64,{fig['data']}" in page
    assert len(data["sections"]["ik"]["figures"]) == 2
    tracking = data["sections"]["tracking"]
    gifs = [f for f in tracking["figures"] if f["mime"] == "image/gif"]
    unavailable = [n for n in tracking["notes"] if n.startswith("rendering unavailable")]
    assert (len(gifs), len(unavailable)) in ((1, 0), (0, 1))  # the computed-torque animation, or why it is missing
    assert not gifs or "computed-torque" in gifs[0]["title"]
    # section tables are formatted for reading: no 17-digit floats
    sections = page[page.index('<section id="section-'):page.index('<section id="checks">')]
    cells = re.findall(r'<td class="num">([^<]*)</td>', sections)
    assert cells and max(len(c) for c in cells) <= 11, max(cells, key=len)


@settings(max_examples=50, deadline=None)
@given(st.one_of(st.floats(-1e300, 1e300), st.floats(allow_nan=False), st.integers(-10**9, 10**9), st.booleans(), st.text(max_size=20)))
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


def test_file_mode_findings_are_summarised_once_not_repeated_as_notes(passing):
    data = passing.to_dict()
    findings = [{"kind": "damping_difference", "severity": "error", "subject": f"j{i}", "subject_type": "joint",
                 "message": f"joint j{i}: damping 0.003 in the URDF, 1 in the MJCF"} for i in range(3)]
    findings += [{"kind": "rounding", "severity": "info", "subject": "j0", "subject_type": "joint", "message": "quat rounded"}]
    data["findings"] = findings
    data["notes"] = [f"{f['kind']}: {f['message']}" for f in findings] + ["URDF: meshes skipped", "a run note"]
    data["sections"]["filemode"] = {"title": "File mode: URDF vs MJCF", "summary": "", "figures": [],
                                    "notes": ["URDF: meshes skipped"],
                                    "tables": [{"title": "Findings", "columns": ["kind", "subject", "finding"],
                                                "rows": [[f["kind"], f["subject"], f["message"]] for f in findings]}]}
    result = VerifyResult.from_dict(data)
    assert result.verdict == "fail" and len(result.failing_findings) == 3
    page = render_html(result)
    text = _text(page)
    assert "4 file-mode findings (3 error, 1 info)" in text
    for f in findings:
        assert text.count(f["message"]) == 1  # in the findings table only
    assert text.count("URDF: meshes skipped") == 1 and "a run note" in text
    assert 'href="#section-filemode"' in page
