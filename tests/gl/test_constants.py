"""Constants shared by Python and GLSL are defined once, in Python (cityshade.shader_constants),
and reach the shaders as a generated include; no shader file defines them itself. Binding points
too: every one is a row of gl/_bindings.py, declared in the shaders by its generated name."""

from __future__ import annotations

import re
from pathlib import Path

from cityshade.gl import programs
from cityshade.gl.testing import BINDINGS, GENERATED, binding_defines, binding_macro
from cityshade.grammar import shader_defines
from cityshade.shader_constants import CONSTANTS

SHADERS = Path(__file__).resolve().parents[2] / "src" / "cityshade" / "shaders"


def hand_definitions(text: str) -> list[str]:
    """Names of shared constants that a shader text defines with #define or as a const."""
    names = "|".join(map(re.escape, CONSTANTS))
    pattern = re.compile(rf"^\s*(?:#define\s+({names})\b|const\s+\w+\s+({names})\s*=)", re.M)
    return [a or b for a, b in pattern.findall(text)]


def test_no_shader_defines_a_shared_constant_itself():
    found = {
        str(p.relative_to(SHADERS)): hand_definitions(p.read_text(encoding="utf-8"))
        for p in sorted(SHADERS.rglob("*.glsl"))
    }
    found = {path: names for path, names in found.items() if names}
    assert not found, f"shaders that define shared constants by hand (use the generated names): {found}"


def test_the_check_sees_a_hand_definition():
    assert hand_definitions("#define FACE_CURTAIN 7\nconst int SHAPE_DOME = 2;\n#define OTHER 1\n") == [
        "FACE_CURTAIN",
        "SHAPE_DOME",
    ]


# binding = NAME) [readonly|writeonly] uniform TYPE name / buffer Name / uniform Name
_DECLARED = re.compile(
    r"binding\s*=\s*(\w+)\s*\)\s*(?:(?:readonly|writeonly)\s+)?(?:uniform\s+\w+\s+(\w+)\s*;|\w+\s+(\w+)\s*\{)"
)


def binding_declarations() -> dict[str, str]:
    """Each resource that the shader files and generated includes give a binding: name -> what it is bound at."""
    texts = [p.read_text(encoding="utf-8") for p in sorted(SHADERS.rglob("*.glsl"))] + list(GENERATED.values())
    return {image or block: point for text in texts for point, image, block in _DECLARED.findall(text)}


def test_no_shader_writes_a_binding_number():
    literal = {
        str(p.relative_to(SHADERS)): re.findall(r"binding\s*=\s*\d+", p.read_text(encoding="utf-8"))
        for p in sorted(SHADERS.rglob("*.glsl"))
    }
    assert not {path: found for path, found in literal.items() if found}, f"binding numbers by hand: {literal}"


def test_every_binding_point_is_a_row_of_the_table_under_its_own_name():
    declared = binding_declarations()
    assert {name: binding_macro(name) for name in declared} == declared
    assert set(declared) == {name for names in BINDINGS.values() for name in names}  # no row unused
    assert len(binding_defines()) == len(declared)  # no name in two kinds


def test_programs_compile_against_the_generated_names(gl_context):
    """Programs that use the shared names compile with no local definitions of them left; a name
    missing from the generated include would fail to compile."""
    cache = programs(gl_context)
    cache.get("city/building.glsl", {**shader_defines(), "ID_PASS": True})
    cache.get("city/ground.glsl", {"ID_PASS": True})
    cache.get("interior/polygonised.glsl")
    cache.get("relief/facade.glsl", {"TRACER_FDM": True, "CODEC_BMF": True})
