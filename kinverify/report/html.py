"""HTML report rendered from Jinja2 templates shipped as package data (autoescaped)."""

from __future__ import annotations

from pathlib import Path

from jinja2 import Environment, PackageLoader, select_autoescape

from ..results import VerifyResult
from .writer import write_atomic


def _environment() -> Environment:
    env = Environment(loader=PackageLoader("kinverify", "report/templates"), autoescape=select_autoescape(["html", "j2"]))
    env.filters["sci"] = lambda x: f"{x:.2e}"
    return env


def render_html(result: VerifyResult) -> str:
    return _environment().get_template("report.html.j2").render(r=result, first=result.first_failures())


def write_html(result: VerifyResult, path) -> Path:
    return write_atomic(path, render_html(result))
