"""A facade's detail maps on the GPU in all three codecs, so the renderer can switch per facade.

RENDERERS names the six renderers of the paper's Table 2 by (tracer, codec).
"""

from __future__ import annotations

import moderngl
import numpy as np

from ..gl import ProgramCache, RenderTarget, bind_textures, binding, create_buffer, draw_fullscreen, upload_texture
from ._compress import MAP_NAMES, CompressedFacade, compress, detail_matrices
from ._maps import DetailMaps
from ._pack import pack_bits

RENDERERS = {
    "rm": ("rm", "raw"),
    "fdm": ("fdm", "raw"),
    "crm": ("rm", "svd"),
    "bcrm": ("rm", "bmf"),
    "cfdm": ("fdm", "svd"),
    "bcfdm": ("fdm", "bmf"),
}


def renderer_defines(renderer: str, lsb_mod37: bool = False, tiled: bool = False) -> dict[str, object]:
    tracer, codec = RENDERERS[renderer]
    return {
        f"TRACER_{tracer.upper()}": True,
        f"CODEC_{codec.upper()}": True,
        "BMF_LSB_MOD37": lsb_mod37,
        "RELIEF_TILED": tiled,
    }


def _texture(ctx: moderngl.Context, array: np.ndarray, dtype: str) -> moderngl.Texture:
    """A one-channel texture of a (rows, columns) array; empty arrays become one zero texel."""
    if array.size == 0:
        array = np.zeros((1, 1), array.dtype)
    data = array.astype({"u2": np.uint16, "u4": np.uint32, "f4": np.float32}[dtype])
    return upload_texture(ctx, data, "stored", mipmaps=False, dtype=dtype)


def _texture_array(ctx: moderngl.Context, arrays: list[np.ndarray], dtype: str) -> moderngl.TextureArray:
    """One layer per (rows, columns) array, zero-padded to the largest: a shader reads only the
    texels of its own map, so one sampler serves all three maps."""
    rows = max(max(a.shape[0] for a in arrays), 1)
    cols = max(max(a.shape[1] for a in arrays), 1)
    layers = np.zeros((len(arrays), rows, cols, 1), {"u4": np.uint32, "f4": np.float32}[dtype])
    for layer, array in zip(layers, arrays):
        layer[: array.shape[0], : array.shape[1], 0] = array
    return upload_texture(ctx, layers, "stored", mipmaps=False, dtype=dtype)


def _set_array(program: moderngl.Program, name: str, values: list[int]):
    """Sets a uniform array; the driver drops trailing elements a variant never reads."""
    if name in program:
        uniform = program[name]
        uniform.value = values[: uniform.array_length] if uniform.array_length > 1 else values[0]


class GpuFacade:
    """Textures of D, M, A uncompressed and factorised (both ways unless `compressed` gives the
    factorisations to use), plus the box list."""

    def __init__(self, ctx: moderngl.Context, maps: DetailMaps, compressed: dict[str, CompressedFacade] | None = None):
        self.maps = maps
        self.compressed = compressed or {m: compress(maps, m) for m in ("svd", "bmf")}
        some = next(iter(self.compressed.values()))  # A and its boxes as factorised (an atlas brings its own)
        matrices, boxes = {**detail_matrices(maps)[0], "boxes": some.decompress()["boxes"]}, some.boxes
        self.raw = [
            _texture(ctx, matrices["depth"], "u2"),
            _texture(ctx, matrices["material"], "u2"),
            _texture(ctx, matrices["boxes"], "u4"),
        ]
        packed_boxes = boxes.astype(np.uint32)
        words = np.column_stack(
            [packed_boxes[:, 0] | packed_boxes[:, 1] << 16, packed_boxes[:, 2] | packed_boxes[:, 3] << 16]
        ).astype(np.uint32)
        self.boxes = create_buffer(ctx, words)
        self.codec_textures = {"raw": {"u_raw": self.raw}}
        for method, facade in self.compressed.items():
            fs = [facade.factors[name] for name in MAP_NAMES]
            if method == "svd":
                self.codec_textures["svd"] = {
                    "u_svd_x": [_texture(ctx, f.x, "f4") for f in fs],
                    "u_svd_y": [_texture(ctx, f.y, "f4") for f in fs],
                    "u_svd_s": [_texture(ctx, f.s[None, :], "f4") for f in fs],
                }
            else:
                # texture arrays (layer = map): three samplers where nine would crowd the city's program
                self.codec_textures["bmf"] = {
                    "u_bmf_x": [_texture_array(ctx, [pack_bits(f.x) for f in fs], "u4")],
                    "u_bmf_y": [_texture_array(ctx, [pack_bits(f.y) for f in fs], "u4")],
                    "u_bmf_s": [_texture_array(ctx, [f.s[None, :] for f in fs], "f4")],
                }
        # Per map: SVD terms, or BMF words of 32 terms.
        self.counts = {
            method: [f.terms if method == "svd" else -(-f.terms // 32) for f in facade.factors.values()]
            for method, facade in self.compressed.items()
        }

    @property
    def slab_depth(self) -> float:
        return float(self.maps.max_depth) + 1.0

    def bind(self, program: moderngl.Program, codec: str):
        """Binds the codec's textures and the box list, sets the map uniforms."""
        bind_textures(program, self.codec_textures[codec])
        count_name = {"svd": "u_terms", "bmf": "u_words"}.get(codec)
        if count_name:
            _set_array(program, count_name, self.counts[codec])
        rows, cols = self.maps.shape
        for name, value in (("u_map_size", (cols, rows)), ("u_slab_depth", self.slab_depth)):
            if name in program:
                program[name].value = value
        self.boxes.bind_to_storage_buffer(binding("ReliefBoxes"))

    def release(self):
        for textures in self.codec_textures.values():
            for group in textures.values():
                for tex in group:
                    tex.release()
        self.boxes.release()


def decode_on_gpu(
    ctx: moderngl.Context, facade: GpuFacade, codec: str, programs: ProgramCache, lsb_mod37: bool = False
) -> dict[str, np.ndarray]:
    """Every texel of D, M, A as the shaders decode it with one codec (for exactness checks)."""
    program = programs.get("relief/decode.glsl", {f"CODEC_{codec.upper()}": True, "BMF_LSB_MOD37": lsb_mod37})
    rows, cols = facade.maps.shape
    target = RenderTarget(ctx, (cols, rows), colors=(("u4", 4),))
    facade.bind(program, codec)
    target.use()
    ctx.disable(moderngl.DEPTH_TEST | moderngl.CULL_FACE | moderngl.BLEND)  # every texel, whatever was drawn before
    draw_fullscreen(program)
    decoded = target.read(0)[::-1]  # read() is top row first; maps have row 0 at the bottom
    target.release()
    return {name: decoded[..., k] for k, name in enumerate(MAP_NAMES)}
