"""The grammar's GPU resources (rules, noise, tile array) and the standalone facade render."""

from __future__ import annotations

import moderngl
import numpy as np

from ..assets import TileArray
from ..gl import RenderTarget, bind_textures, binding, create_buffer, draw_fullscreen, programs, upload_texture
from . import _limits as limits
from ._compiler import CompiledGrammars
from ._expressions import BUILDING, FACADE_LEVEL, PARAMETER
from ._random import noise_texture
from ._reference import FACADE_LIGHT

MAX_TILES = 64  # size of u_grammar_tile_labels[] in eval.glsl


def shader_defines(nearest: bool = False) -> dict[str, object]:
    """The #defines every program that includes grammar/eval.glsl needs."""
    return dict(
        limits.DEFINES,
        GRAMMAR_NEAREST=nearest,
        GRAMMAR_FIRST_BUILDING=BUILDING,
        GRAMMAR_FACADE_LEVEL=FACADE_LEVEL,
        GRAMMAR_FIRST_PARAMETER=PARAMETER,
    )


class GrammarTextures:
    """Uploads a compiled grammar, the noise texture and the tile array; binds them to a program.
    The rules are a storage buffer of float32 texels (the compiled float16 values, exactly): on
    llvmpipe a buffer read is cheaper than a texel fetch, and the evaluator reads one or more a step."""

    def __init__(self, ctx: moderngl.Context, compiled: CompiledGrammars, tiles: TileArray):
        self.compiled = compiled
        self.tiles = tiles
        self.rules = create_buffer(ctx, compiled.flat())
        self.noise = upload_texture(ctx, noise_texture(), "stored", mipmaps=False, dtype="f4")
        # sRGB tiles, decoded by the shader (common/srgb.glsl) after the grammar picks and filters them
        self.tile_array = upload_texture(ctx, tiles.layers, "stored")
        if len(tiles.labels) > MAX_TILES:
            raise ValueError(f"{len(tiles.labels)} tiles; eval.glsl holds labels for {MAX_TILES}")
        self.labels = np.zeros(MAX_TILES, np.int32)
        self.labels[: len(tiles.labels)] = tiles.labels

    def bind(self, program):
        """Binds the rules' storage buffer and the two textures, and sets the tile uniforms."""
        self.rules.bind_to_storage_buffer(binding("GrammarRules"))
        bind_textures(program, {"u_grammar_noise": self.noise, "u_grammar_tiles": self.tile_array})
        if "u_grammar_tile_size" in program:
            program["u_grammar_tile_size"] = self.tiles.size
        if "u_grammar_tile_labels" in program:
            program["u_grammar_tile_labels"].write(self.labels.tobytes())

    def release(self):
        for resource in (self.rules, self.noise, self.tile_array):
            resource.release()


class FacadeRenderer:
    """Renders one facade head-on: colour (lit) and ids (terminal + 1, label, tile + 1, glass). With
    `hole_shift` (metres) the ids are each pixel's hole + 1 and what that hole shows `hole_shift`
    further along (terminal + 1, label, glass; facade.glsl GRAMMAR_HOLES)."""

    def __init__(self, ctx: moderngl.Context, textures: GrammarTextures, nearest: bool = False, hole_shift=None):
        self.ctx = ctx
        self.textures = textures
        defines = dict(shader_defines(nearest), GRAMMAR_HOLES=hole_shift is not None)
        self.program = programs(ctx).get("grammar/facade.glsl", defines)
        self.hole_shift = hole_shift

    def render(
        self, start: int, facade, size, seed, building=(0, 0, 0, 0), face: int = 0, level: int = 0
    ) -> tuple[np.ndarray, np.ndarray]:
        """(colour HxWx4 float, ids HxWx4 uint32), top row first; `seed` is the building's seed
        vector, `face` which of its facades (its own stream: _random.facade_seed_vector) and `level`
        the storey the facade starts at (facade.level)."""
        target = RenderTarget(self.ctx, tuple(size), colors=(("f2", 4), ("u4", 4)))
        try:
            target.use()
            self.ctx.viewport = (0, 0, *size)
            self.textures.bind(self.program)
            self.program["u_facade_size"] = tuple(float(x) for x in facade)
            self.program["u_viewport_size"] = tuple(float(x) for x in size)
            self.program["u_facade_seed"] = tuple(float(x) for x in seed)
            self.program["u_facade_building"] = tuple(float(x) for x in building)
            self.program["u_facade_index"] = int(face)
            self.program["u_facade_level"] = float(level)
            self.program["u_start_rule"] = int(start)
            if self.hole_shift is not None:
                self.program["u_hole_shift"] = tuple(float(x) for x in self.hole_shift)
            light = np.array(FACADE_LIGHT)
            self.program["u_light_dir"] = tuple(light / np.linalg.norm(light))
            self.ctx.disable(moderngl.DEPTH_TEST)
            draw_fullscreen(self.program)
            return target.read(0).astype(np.float32), target.read(1)
        finally:
            target.release()
