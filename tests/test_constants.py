"""Constants shared by Python and GLSL are defined once, in Python (cityshade.shader_constants),
and reach the shaders as a generated include; no shader file defines them itself."""

from __future__ import annotations

import re
from pathlib import Path

from cityshade.gl import programs
from cityshade.grammar import shader_defines
from cityshade.shader_constants import CONSTANTS

SHADERS = Path(__file__).resolve().parent.parent / "src" / "cityshade" / "shaders"


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


def test_programs_compile_against_the_generated_names(gl_context):
    """Programs that use the shared names compile with no local definitions of them left; a name
    missing from the generated include would fail to compile."""
    cache = programs(gl_context)
    cache.get("city/building.glsl", {**shader_defines(), "ID_PASS": True})
    cache.get("city/ground.glsl", {"ID_PASS": True})
    cache.get("interior/polygonised.glsl")
    cache.get("relief/facade.glsl", {"TRACER_FDM": True, "CODEC_BMF": True})
