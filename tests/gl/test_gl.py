"""The GL layer: programs from .glsl files with includes and defines, errors that name file and line."""

from __future__ import annotations

import moderngl
import pytest

from cityshade.errors import GLUnavailableError, ShaderError
from cityshade.gl import (
    MAX_SAMPLERS,
    ProgramCache,
    _programs,
    create_buffer,
    create_context,
    grow_buffer,
    sampler_units,
)

pytestmark = pytest.mark.gl  # renders or opens a context of its own, not only through gl_context

SOURCES = {
    "test/lib.glsl": "float twice(float x) { return 2.0 * x; }\n",
    "test/ok.glsl": (
        '#include "test/lib.glsl"\n'
        "#if defined VERTEX_SHADER\nvoid main() { gl_Position = vec4(twice(0.5)); }\n#endif\n"
        "#if defined FRAGMENT_SHADER\nout vec4 c;\nvoid main() { c = vec4(SCALE); }\n#endif\n"
    ),
    "test/broken.glsl": (
        '#include "test/lib.glsl"\n'
        "#if defined VERTEX_SHADER\nvoid main() { gl_Position = vec4(1.0); }\n#endif\n"
        "#if defined FRAGMENT_SHADER\nout vec4 c;\nvoid main() { c = undefined_thing; }\n#endif\n"
    ),
    "test/samplers.glsl": (
        "#if defined VERTEX_SHADER\nvoid main() { gl_Position = vec4(0.0); }\n#endif\n"
        "#if defined FRAGMENT_SHADER\nout vec4 c;\nuniform sampler2D u_many[COUNT];\n"
        "void main() { c = vec4(0.0); for (int i = 0; i < COUNT; i++) c += texture(u_many[i], vec2(0.5)); }\n#endif\n"
    ),
    # city/building.glsl's street lamps and LOD colours as they once were: both at one binding
    "test/binding_6.glsl": (
        "#undef BINDING_BUILDING_LOD_COLOURS\n#define BINDING_BUILDING_LOD_COLOURS BINDING_STREET_LAMPS\n"
        "#if defined VERTEX_SHADER\nvoid main() { gl_Position = vec4(0.0); }\n#endif\n"
        '#if defined FRAGMENT_SHADER\n#include "city/street_lights.glsl"\n#include "city/lod.glsl"\n'
        "out vec4 c;\nvoid main() { c = lamps[0] + building_lod_colours[0]; }\n#endif\n"
    ),
}


@pytest.fixture
def fake_sources(monkeypatch):
    real = _programs.shader_source
    monkeypatch.setattr(_programs, "shader_source", lambda path: SOURCES[path] if path in SOURCES else real(path))


def test_programs_are_cached_by_file_and_defines(gl_context, fake_sources):
    cache = ProgramCache(gl_context)
    a = cache.get("test/ok.glsl", {"SCALE": 1.0})
    assert cache.get("test/ok.glsl", {"SCALE": 1.0}) is a
    assert cache.get("test/ok.glsl", {"SCALE": 2.0}) is not a


def test_compile_error_names_the_file_and_line(gl_context, fake_sources):
    with pytest.raises(ShaderError) as info:
        ProgramCache(gl_context).get("test/broken.glsl")
    assert "shaders/test/broken.glsl:7:19" in str(info.value)  # line and column of the bad name
    assert "undefined_thing" in str(info.value)


def test_every_city_program_variant_compiles(gl_context):
    from cityshade.grammar import shader_defines

    cache = ProgramCache(gl_context)
    grammar = shader_defines()
    for path, defines in [
        ("city/building.glsl", {**grammar, "INTERIOR_MAPPING": True, "INTERIOR_LOD": True}),
        ("city/building.glsl", {**grammar, "INTERIOR_MAPPING": True, "IM_SINGLE_ATLAS": True, "ID_PASS": True}),
        ("city/building.glsl", grammar),
        ("city/building.glsl", {**grammar, "BUILDING_LOD": True, "PREPASS_FARTHEST": True}),
        ("city/building.glsl", {"DEPTH_ONLY": True}),
        ("city/ground.glsl", {}),
        ("frame/sky.glsl", {}),
        ("frame/tonemap.glsl", {}),
    ]:
        assert cache.get(path, defines) is not None


def test_a_program_with_two_storage_buffers_at_one_binding_is_refused(gl_context, fake_sources):
    """The facades read whichever of the two was bound last as both (the lamps as LOD colours)."""
    with pytest.raises(ShaderError, match="storage buffers BuildingLodColours and StreetLamps share binding"):
        ProgramCache(gl_context).get("test/binding_6.glsl")


def test_missing_gl_gives_one_clear_error(monkeypatch):
    def fail(**kwargs):
        raise Exception("eglGetDisplay failed")

    monkeypatch.setattr(moderngl, "create_standalone_context", fail)
    with pytest.raises(GLUnavailableError) as info:
        create_context()
    assert "apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri" in str(info.value)


def test_samplers_get_units_of_their_own_and_at_most_16(gl_context, fake_sources):
    cache = ProgramCache(gl_context)
    fits = cache.get("test/samplers.glsl", {"COUNT": MAX_SAMPLERS})
    assert sampler_units(fits) == {"u_many": 0}
    assert fits["u_many"].value == list(range(MAX_SAMPLERS))
    with pytest.raises(ShaderError, match="test/samplers.glsl has 17 active samplers"):
        sampler_units(cache.get("test/samplers.glsl", {"COUNT": MAX_SAMPLERS + 1}))


def test_a_grown_buffer_keeps_its_name_and_never_shrinks(gl_context):
    buffer = create_buffer(gl_context, reserve=20)
    name = buffer.glo
    grow_buffer(buffer, 1, 20)
    assert buffer.size == 20
    grow_buffer(buffer, 5, 20)  # the next power of two of items
    assert (buffer.size, buffer.glo) == (160, name)
    buffer.write(bytes(range(100)))
    grow_buffer(buffer, 2, 20)
    assert buffer.size == 160 and buffer.read(100) == bytes(range(100))
    buffer.release()
