"""The generated GLSL includes: text made from Python definitions when programs are built, so a
value or layout is written once (in Python) and never copied into a shader by hand."""

from __future__ import annotations

from collections.abc import Mapping

from ._bindings import binding_defines
from ._blocks import FRAME_BLOCK, SHADING_BLOCK
from ._programs import GENERATED, PRELUDE


def declare_constants(name: str, values: Mapping[str, object]):
    """`#define NAME value` for each value, in a generated include that every program gets."""
    path = f"generated/{name}.glsl"
    lines = [f"// Generated from Python ({name}): do not edit."]
    lines += [f"#define {key} {value}" for key, value in values.items()]
    GENERATED[path] = "\n".join(lines) + "\n"
    if path not in PRELUDE:
        PRELUDE.append(path)


declare_constants("bindings", binding_defines())  # before the blocks, which bind by these names
GENERATED[FRAME_BLOCK.include] = FRAME_BLOCK.glsl()
PRELUDE.append(FRAME_BLOCK.include)  # shared by all programs: declared in every one
GENERATED[SHADING_BLOCK.include] = SHADING_BLOCK.glsl()  # included by the shaders that read it
