"""Figures of the ik report section: present in verify's section, valid SVG, redrawn identically
from the data the section keeps, and the page re-rendered from the JSON is the same page."""

from __future__ import annotations

import base64
import json
import re

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from kinverify.backends import ModelSources
from kinverify.ik.figures import ik_figures
from kinverify.report.html import render_html
from kinverify.results import VerifyResult
from kinverify.model.specfile import load_spec
from kinverify.suites.base import Section
from kinverify.run import VerifyOptions, verify
from tests.paths import MODELS

ARM3 = MODELS / "arm3.toml"


@pytest.fixture(scope="module")
def ik_result():
    opts = VerifyOptions(samples=5, suites=["ik"], extra={"ik_targets": 12})
    return verify(ModelSources.from_spec(load_spec(ARM3)), opts, command="pytest ik figures")


def _svg(fig) -> str:
    assert fig.mime == "image/svg+xml"
    text = base64.b64decode(fig.data, validate=True).decode("utf-8")
    assert text.startswith("<svg") and text.rstrip().endswith("</svg>")
    return text


def test_ik_section_has_success_and_time_figures(ik_result):
    section = ik_result.sections["ik"]
    titles = [f.title for f in section.figures]
    assert titles == ["IK success rate per solver and backend", "IK solve time per target"]
    for fig in section.figures:
        svg = _svg(fig)
        assert "<script" not in svg and not re.search(r'href="(?!#)', svg)  # nothing to fetch or run
    # the data behind the plots: one record per row of the solver table, same counts
    table = section.tables[0]
    assert [[r[0], r[1], r[2], r[3]] for r in table.rows] == [
        [d["solver"], d["backend"], d["targets"], d["solved"]] for d in section.data["solvers"]
    ]
    for d, row in zip(section.data["solvers"], table.rows, strict=True):
        assert len(d["time_ms"]) == d["targets"] == 12
        assert np.median(d["time_ms"]) == pytest.approx(row[6], rel=1e-3)  # 4 significant digits kept


def test_figures_are_redrawn_identically_from_the_section_data(ik_result):
    section = Section.from_dict(json.loads(json.dumps(ik_result.sections["ik"].to_dict())))  # what a saved JSON holds
    assert ik_figures(section.data["solvers"], **section.data["tolerance"]) == section.figures


def test_report_rerendered_from_json_shows_the_same_ik_figures(ik_result, tmp_path):
    page = render_html(ik_result)
    again = render_html(VerifyResult.from_dict(json.loads(json.dumps(ik_result.to_dict()))))
    assert page == again
    for fig in ik_result.sections["ik"].figures:
        assert f"data:image/svg+xml;base64,{fig.data}" in page


records = st.builds(
    lambda solver, backend, n, solved, own, batched, times: {
        "solver": solver,
        "backend": backend,
        "targets": n,
        "solved": min(solved, n),
        "solved_own": min(own, n),
        "batched": batched,
        "time_ms": (times * n)[:n] if not batched else [times[0]] * n,
    },
    st.sampled_from(["lm", "seed-pinv"]),
    st.sampled_from(["analytic", "mujoco", "<b>x</b>"]),
    st.integers(0, 20),
    st.integers(0, 20),
    st.integers(0, 20),
    st.booleans(),
    st.lists(st.one_of(st.just(0.0), st.floats(1e-4, 1e4)), min_size=1, max_size=20),
)


@settings(max_examples=6, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(records, min_size=1, max_size=5))
def test_any_solver_records_give_two_svg_figures(solvers):
    figs = ik_figures(solvers, 1e-6, 1e-6)
    assert len(figs) == 2
    for fig in figs:
        svg = _svg(fig)
        assert "<b>" not in svg  # text is drawn as paths: a backend name is never markup
    # one bar pair per record: the tick labels are paths, so count the bars' rectangles by id
    assert len(re.findall(r'<g id="patch_\d+">', _svg(figs[0]))) >= 2 * len(solvers)


def test_no_solver_records_no_figures():
    assert ik_figures([], 1e-6, 1e-6) == []
