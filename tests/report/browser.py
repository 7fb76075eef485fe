"""A real headless Chromium for the report tests: the page as a user sees it at 1280×900 (its
height, where things are, whether images decode), the network requests it makes, screenshots."""

from __future__ import annotations

import html as htmllib
import json
import re
import shutil
import subprocess
from pathlib import Path

import pytest

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser")
needs_chromium = pytest.mark.skipif(CHROMIUM is None, reason="chromium is not installed (.ci/run installs Debian's chromium)")
WIDTH, HEIGHT = 1280, 900
FLAGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--hide-scrollbars",
    # network off: every request goes to a closed local port and no host name resolves
    "--proxy-server=http://127.0.0.1:9",
    "--host-resolver-rules=MAP * ~NOTFOUND",
]

# Appended to a copy of the page: once loaded, writes what the test reads into <pre id="probe">.
PROBE = """<script>
window.addEventListener("load", function () {  // after "load" every image has loaded (or failed)
  var images = Array.prototype.slice.call(document.images);
  var box = function (sel) { var el = document.querySelector(sel); if (!el) { return null; }
    var r = el.getBoundingClientRect(); return {top: r.top + window.scrollY, bottom: r.bottom + window.scrollY, width: r.width}; };
  var svgs = Array.prototype.filter.call(document.querySelectorAll("figure.plot svg, svg.tree"), function (s) { return s.getBoundingClientRect().width > 0; });
  var out = {images: images.length, decoded: images.filter(function (i) { return i.complete && i.naturalWidth > 0; }).length,
             svgs: svgs.length, height: document.documentElement.scrollHeight, width: document.documentElement.scrollWidth, boxes: {}};
  SELECTORS.forEach(function (sel) { out.boxes[sel] = box(sel); });
  var pre = document.createElement("pre"); pre.id = "probe"; pre.textContent = JSON.stringify(out); document.body.appendChild(pre);
});
</script>"""


def run(page: Path, tmp: Path, *extra: str) -> tuple[str, list[tuple[str, str]]]:
    """Load ``page`` from disk at 1280×900; return the DOM after scripts ran and the (initiator,
    url) of every network request a page started (from Chromium's net log; the browser's own
    background requests have no origin and are left out)."""
    netlog = tmp / f"net-{page.stem}.json"
    cmd = [
        CHROMIUM,
        *FLAGS,
        f"--user-data-dir={tmp / 'profile'}",
        f"--log-net-log={netlog}",
        f"--window-size={WIDTH},{HEIGHT}",
        *extra,
        page.as_uri(),
    ]
    proc = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    log = json.loads(netlog.read_text())
    start = log["constants"]["logEventTypes"]["URL_REQUEST_START_JOB"]
    requests = [
        (e["params"].get("initiator", ""), e["params"]["url"])
        for e in log["events"]
        if e["type"] == start and "url" in (e.get("params") or {})
    ]
    return proc.stdout, [r for r in requests if r[0] != "not an origin"]


def probe(page_html: str, tmp: Path, selectors=()) -> tuple[dict, list[tuple[str, str]]]:
    """Layout facts of a page as Chromium lays it out at 1280 px wide (details as rendered:
    folded), and its network requests."""
    probed = tmp / "probed.html"
    script = PROBE.replace("SELECTORS", json.dumps(list(selectors)))
    probed.write_text(page_html.replace("</body>", script + "</body>"), encoding="utf-8")
    dom, requests = run(probed, tmp, "--virtual-time-budget=10000", "--dump-dom")
    found = re.search(r'<pre id="probe">(.*?)</pre>', dom, re.S)
    assert found, "the probe did not run"
    return json.loads(htmllib.unescape(found.group(1))), requests


def screenshot(page_html: str, tmp: Path, name: str = "shot") -> Path:
    page = tmp / f"{name}.html"
    page.write_text(page_html, encoding="utf-8")
    shot = tmp / f"{name}.png"
    run(page, tmp, f"--screenshot={shot}")
    return shot
