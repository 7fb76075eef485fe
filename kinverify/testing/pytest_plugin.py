"""kinverify's pytest plugin, registered through the ``pytest11`` entry point: installing
kinverify is enough to use it in any project.

- option ``--kinverify-update-baselines``: rewrite baselines deliberately instead of checking them;
- marker ``@pytest.mark.kinverify(model="my_arm.toml")``: selects tests with ``-m kinverify``
  (tests using a ``kinverify_*`` fixture get it automatically); ``model`` is the spec that
  ``kinverify_spec()`` loads when called without an argument;
- fixtures ``kinverify_spec`` (spec factory), ``kinverify_backends`` (cached backends),
  ``kinverify_baseline`` (check or, with the option, rewrite a baseline) and
  ``kinverify_update_baselines`` (the option's value);
- the report header lists kinverify's and the backend libraries' versions.

Relative paths given to the fixtures are taken relative to the test file's directory.
"""

from __future__ import annotations

from pathlib import Path

import pytest

UPDATE_OPTION = "--kinverify-update-baselines"
FIXTURES = ("kinverify_spec", "kinverify_backends", "kinverify_baseline", "kinverify_update_baselines")


def pytest_addoption(parser) -> None:
    group = parser.getgroup("kinverify", "kinverify: robot model verification")
    group.addoption(
        UPDATE_OPTION,
        action="store_true",
        default=False,
        help="rewrite kinverify baselines (kinverify_baseline / assert_matches_baseline) instead of checking them",
    )


def pytest_configure(config) -> None:
    config.addinivalue_line(
        "markers",
        "kinverify(model=None): a kinverify model test; `model` is the spec file that "
        "the kinverify_spec fixture loads when called without an argument",
    )


def pytest_report_header(config) -> str:
    from kinverify.versions import library_versions

    versions = library_versions()
    libs = ", ".join(f"{k} {v}" for k, v in versions.items() if k != "kinverify")
    return f"kinverify {versions.get('kinverify', '?')} ({libs})"


def pytest_collection_modifyitems(items) -> None:
    for item in items:
        if any(name in getattr(item, "fixturenames", ()) for name in FIXTURES) and not item.get_closest_marker("kinverify"):
            item.add_marker("kinverify")


def _resolve(request, path) -> Path:
    path = Path(path)
    if path.is_absolute():
        return path
    return Path(request.path).parent / path


@pytest.fixture
def kinverify_update_baselines(request) -> bool:
    return bool(request.config.getoption(UPDATE_OPTION))


@pytest.fixture
def kinverify_spec(request):
    """``kinverify_spec(source=None) -> ArmSpec``: a spec file path, a dict in the spec format,
    or an ArmSpec; without an argument, the ``model`` of the test's ``kinverify`` marker."""
    from kinverify.model.spec import ArmSpec
    from kinverify.model.specfile import load_spec, spec_from_dict

    def factory(source=None):
        if source is None:
            marker = request.node.get_closest_marker("kinverify")
            source = marker.kwargs.get("model") if marker else None
            if source is None:
                raise pytest.UsageError("kinverify_spec() needs a spec, or @pytest.mark.kinverify(model=...) on the test")
        if isinstance(source, ArmSpec):
            return source
        if isinstance(source, dict):
            return spec_from_dict(source)
        return load_spec(_resolve(request, source))

    return factory


@pytest.fixture(scope="session")
def kinverify_backends():
    """``kinverify_backends(model, names=None) -> [Backend, ...]``: every available backend
    (or ``names``) for a spec or ModelSources, reference first, built once per session."""
    from kinverify.testing.assertions import resolve_backends

    return lambda model, names=None: resolve_backends(model, names)


@pytest.fixture
def kinverify_baseline(request, kinverify_update_baselines):
    """``kinverify_baseline(spec, path, tolerance=None)``: assert ``spec`` matches the baseline
    at ``path`` (relative to the test file), or rewrite it under ``--kinverify-update-baselines``."""
    from kinverify.testing.assertions import assert_matches_baseline

    def check(spec, path, tolerance=None):
        __tracebackhide__ = True
        return assert_matches_baseline(spec, _resolve(request, path), update=kinverify_update_baselines, tolerance=tolerance)

    return check
