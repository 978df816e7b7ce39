"""The one table of binding points that the shaders and Python share: uniform blocks, storage
buffers and images, each named by its GLSL name (block name or image uniform) and numbered by its
place in its kind's list, so no two resources of a kind ever share a number. Shaders write the
generated name (`layout(std430, binding = BINDING_STREET_LAMPS)`, from generated/bindings.glsl,
which every program gets) and Python binds with `binding("StreetLamps")`; no number is written by
hand. Samplers have no row: each program numbers its own (gl/_samplers.py).

The program cache checks every linked program against collisions (gl/_programs.py), so a number
written by hand that lands on another resource's binding is refused rather than read as it."""

from __future__ import annotations

import re

import moderngl

from ..errors import ShaderError

BINDINGS: dict[str, tuple[str, ...]] = {
    "uniform block": ("FrameBlock", "ShadingBlock"),  # gl/_blocks.py
    "storage buffer": (
        "Buildings",  # common/buildings.glsl: every building's record (render/_city_gpu.py)
        "Draws",  # frame/cull.glsl: each building's draw (render/_visibility.py)
        "Commands",  # frame/cull.glsl, trees/cull.glsl: the indirect draws a cull writes
        "Instances",  # trees/cull.glsl: the trees (trees/_tree_pass.py)
        "SampleFaces",  # grammar/lod_colours.glsl (render/_lod_colours.py)
        "ReliefBoxes",  # relief/trace.glsl (relief/_gpu.py)
        "StreetLamps",  # city/street_lights.glsl (render/_street_lights.py)
        "LampCellStarts",
        "LampCellIndices",
        "GrammarPageTable",  # grammar/cache.glsl (grammar/_cache.py)
        "GrammarPageRecords",  # grammar/cache_page.glsl
        "BuildingFaces",  # common/building_vertex.glsl: the face table (scene/_face_table.py)
        "BuildingPlacements",
        "BuildingBounds",  # common/building_vertex.glsl, frame/cull.glsl (render/_visibility.py)
        "GrammarRules",  # grammar/eval.glsl (grammar/_gpu.py)
        "BuildingLodColours",  # city/lod.glsl (render/_lod_colours.py)
    ),
    "image": (
        "u_prepass_farthest",  # city/building.glsl (render/_frame.py)
        "u_grammar_deferred_opening",  # relief/building.glsl (grammar/_frame_pass.py)
        "u_finer",  # frame/hiz.glsl (render/_visibility.py)
        "u_level",
    ),
}

_NUMBERS = {name: number for names in BINDINGS.values() for number, name in enumerate(names)}


def binding(name: str) -> int:
    """The binding point of the resource that the shaders declare as `name`."""
    if name not in _NUMBERS:
        raise ShaderError(f"no binding point named {name!r} in gl/_bindings.py")
    return _NUMBERS[name]


def binding_macro(name: str) -> str:
    """The generated GLSL name of a binding point: BINDING_STREET_LAMPS for StreetLamps,
    BINDING_FINER for the image u_finer."""
    words = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", name.removeprefix("u_"))
    return f"BINDING_{words.upper()}"


def binding_defines() -> dict[str, int]:
    """Every binding point's generated name and number, for generated/bindings.glsl."""
    return {binding_macro(name): number for name, number in _NUMBERS.items()}


_IMAGE_TYPES = frozenset(range(0x904C, 0x906D))  # GL_IMAGE_1D ... GL_UNSIGNED_INT_IMAGE_2D_MULTISAMPLE_ARRAY


def check_bindings(program, where: str):
    """Refuses a linked program in which two active resources of one kind share a binding point:
    the one bound last would be read as both. Read from the program (its blocks' bindings and its
    image uniforms' units), so a number written by hand is caught as well as the table's."""
    users: dict[tuple[str, int], list[str]] = {}
    for name in program:
        member = program[name]
        if isinstance(member, moderngl.UniformBlock):
            kind, points = "uniform block", [member.binding]
        elif isinstance(member, moderngl.StorageBlock):
            kind, points = "storage buffer", [member.binding]
        elif isinstance(member, moderngl.Uniform) and member.gl_type in _IMAGE_TYPES:
            kind, points = "image", member.value if member.array_length > 1 else [member.value]
        else:
            continue
        for point in points:
            users.setdefault((kind, point), []).append(name)
    for (kind, point), names in sorted(users.items()):
        if len(names) > 1:
            raise ShaderError(
                f"{where}: the {kind}s {' and '.join(sorted(names))} share binding {point}; "
                "give each its own row in gl/_bindings.py"
            )
