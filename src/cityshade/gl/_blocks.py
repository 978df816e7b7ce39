"""Uniform blocks (std140): one field list gives both the GLSL declaration, emitted as a generated
include, and the packing of the values written into the block's buffer."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ._bindings import binding, binding_macro

# std140: (alignment, size) in bytes of the types the blocks use
_STD140 = {"float": (4, 4), "int": (4, 4), "vec2": (8, 8), "vec3": (16, 12), "vec4": (16, 16), "mat4": (16, 64)}
_ARRAY_STRIDE = 16  # std140: every array element starts on a vec4


def _array(kind: str) -> tuple[str, int | None]:
    """("float", 8) for "float[8]"; (kind, None) for a kind that is not an array."""
    if kind.endswith("]"):
        base, count = kind[:-1].split("[")
        return base, int(count)
    return kind, None


def _layout(kind: str) -> tuple[int, int]:
    """(alignment, size) in bytes of a field's type under std140."""
    base, count = _array(kind)
    if count is None:
        return _STD140[base]
    return _ARRAY_STRIDE, _ARRAY_STRIDE * count


@dataclass(frozen=True)
class UniformBlock:
    name: str
    fields: tuple[tuple[str, str, str], ...]  # (GLSL name, GLSL type, comment)

    @property
    def binding(self) -> int:
        return binding(self.name)

    @property
    def include(self) -> str:
        """The path programs #include to declare the block."""
        return f"generated/{self.name}.glsl"

    def glsl(self) -> str:
        lines = [
            f"// Generated from cityshade.gl ({self.name}): do not edit.",
            f"layout(std140, binding = {binding_macro(self.name)}) uniform {self.name} {{",
        ]
        for name, kind, comment in self.fields:
            base, count = _array(kind)
            lines.append(f"    {base} {name}{'' if count is None else f'[{count}]'};  // {comment}")
        return "\n".join(lines + ["};", ""])

    def offsets(self) -> tuple[dict[str, int], int]:
        offsets, offset = {}, 0
        for name, kind, _ in self.fields:
            align, size = _layout(kind)
            offset = -(-offset // align) * align
            offsets[name] = offset
            offset += size
        return offsets, -(-offset // 16) * 16

    def pack(self, values: dict) -> bytes:
        """The block's bytes; every field must be given, and nothing else."""
        names = {name for name, _, _ in self.fields}
        if set(values) != names:
            raise ValueError(
                f"{self.name}: missing {sorted(names - set(values))}, unknown {sorted(set(values) - names)}"
            )
        offsets, size = self.offsets()
        data = bytearray(size)
        for name, kind, _ in self.fields:
            base, count = _array(kind)
            value = np.asarray(values[name], dtype=np.int32 if base == "int" else np.float32)
            if base == "mat4":
                value = value.T  # GLSL matrices are column-major
            if count is None:
                raw = value.tobytes()
                data[offsets[name] : offsets[name] + len(raw)] = raw
                continue
            if len(value) != count:
                raise ValueError(f"{self.name}.{name}: {count} values expected, got {len(value)}")
            for i, element in enumerate(value):
                start = offsets[name] + i * _ARRAY_STRIDE
                data[start : start + element.nbytes] = element.tobytes()
        return bytes(data)

    def write(self, ctx: moderngl.Context, **values):
        """Writes the values into this context's buffer of the block and binds it to its binding."""
        from ._resources import resources  # the per-context buffers live with the context's resources

        buffers = resources(ctx).block_buffers
        data = self.pack(values)
        if self.name not in buffers:
            buffers[self.name] = ctx.buffer(reserve=len(data))
        buffers[self.name].write(data)
        buffers[self.name].bind_to_uniform_block(self.binding)


# The per-frame values every program shares: written once per frame (cityshade.render), or by
# any code that draws with the city's shaders on its own.
FRAME_BLOCK = UniformBlock(
    "FrameBlock",
    (
        ("u_inv_view_proj", "mat4", "the camera's clip space -> world"),
        ("u_camera", "vec3", "the eye, world"),
        ("u_time", "float", "seconds: furniture sprites, wind"),
        ("u_sun_dir", "vec3", "unit vector toward the sun (world)"),
        ("u_exposure", "float", "HDR scale before tone mapping"),
        ("u_sun_color", "vec3", "sun radiance"),
        ("u_sky_ambient", "vec3", "sky irradiance from above"),
        ("u_ground_ambient", "vec3", "bounce light from below"),
    ),
)


MAX_USES = 8  # building use codes the shading block has room for (cityshade.scene.USES)

# The city's shading values of one frame (rooms, windows, lamps), shared by the building, ground,
# grammar and room programs; written once per frame with FRAME_BLOCK. Shaders that read them
# #include its generated declaration (interior/interior.glsl, city/street_lights.glsl,
# city/building.glsl).
SHADING_BLOCK = UniformBlock(
    "ShadingBlock",
    (
        ("u_room_light", "vec3", "radiance of a lit room"),
        (
            "u_lit_share",
            f"float[{MAX_USES}]",
            "per building use code: probability c that a room is lit (interior mapping §4.1)",
        ),
        ("u_room_dark", "vec3", "what an unlit room still receives"),
        ("u_street_lights", "float", "0 by day, 1 when the lamps are on"),
        ("u_window_tint", "vec3", "the glass where no room is drawn behind it"),
        ("u_feature_mask", "int", "FLAG_* bits switched on for this frame"),
        ("u_glass_rect", "vec4", "the glass in one window bay: (u0, v0, u1, v1)"),
        ("u_atlas_layout", "vec4", "single room atlas: tile size, padding (texels), width, height"),
        ("u_lod_range", "vec2", "interiors fade to lit-window colours between these distances"),
        ("u_building_lod", "vec4", "building LOD bands, metres: relief (start, end), cheap level (start, end)"),
        ("u_bay_mean", "vec4", "window bay's wall colour (linear, untinted), glass share: the cheap level"),
        ("u_relief_mean", "vec4", "relief bay's wall colour (linear, untinted), glass share: the cheap level"),
        ("u_room_variants", "int", "rooms in the atlas (interior mapping §4.2)"),
        ("u_sprite_kinds", "int", "kinds of furniture sprite"),
        ("u_sprite_frames", "int", "animation frames per sprite kind"),
    ),
)
