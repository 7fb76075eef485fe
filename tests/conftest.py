"""Shared test configuration: pytest's ``pytester`` (tests of the pytest plugin) and kinverify's
own plugin, the same one users get. The plugin normally arrives through its ``pytest11`` entry
point; it is loaded here only when the installed metadata does not have that entry point yet
(an install made before the plugin existed: re-run ``pip install -e .``)."""

import os
from importlib.metadata import entry_points

from hypothesis import settings

pytest_plugins = ["pytester"]
if not any(ep.value == "kinverify.testing.pytest_plugin" for ep in entry_points(group="pytest11")):
    pytest_plugins.append("kinverify.testing.pytest_plugin")

# CI runs the same examples every time (a red CI must be reproducible); locally hypothesis explores.
settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")
