"""Uploads the procedural assets the city's shaders sample."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from .. import assets
from ..gl import upload_texture
from ..grammar import DeferredGrammarPass, GrammarTextures, library_texture_with

ROOM_FACES = ("ceiling", "floor", "wall_x", "wall_z")


@dataclass
class CityTextures:
    """GL textures for rooms, facade bay, furniture sprites, curtains and the sky."""

    rooms: moderngl.TextureArray  # layer = face index in ROOM_FACES * room_variants + variant
    atlas: moderngl.Texture
    atlas_layout: dict
    facade: moderngl.Texture
    glass_rect: tuple[float, float, float, float]
    sprites: moderngl.TextureArray
    sprite_kinds: int
    sprite_frames: int
    curtain: moderngl.Texture
    room_variants: int
    grammar: GrammarTextures  # facade grammar library (and settings.grammar_files): rules, noise, tile array
    grammar_pass: DeferredGrammarPass  # targets of the deferred grammar evaluation

    @classmethod
    def create(
        cls, ctx: moderngl.Context, room_size: int = 256, variants: int = 8, grammar_files: tuple[str, ...] = ()
    ) -> "CityTextures":
        rooms_np = assets.room_textures(size=room_size, variants=variants)
        # one array, face after face (shaders/interior/interior.glsl room_layer)
        rooms = upload_texture(ctx, np.concatenate([rooms_np[face] for face in ROOM_FACES]), "srgb", repeat=False)
        atlas_np, layout = assets.room_atlas(rooms_np)
        atlas = upload_texture(ctx, atlas_np, "srgb", repeat=False)
        facade_np, glass = assets.facade_texture()
        sprites_np = assets.furniture_sprites()
        kinds, frames = sprites_np.shape[:2]
        sprites = upload_texture(ctx, sprites_np.reshape(kinds * frames, *sprites_np.shape[2:]), "srgb", repeat=False)
        curtain = upload_texture(ctx, assets.curtain_texture(), "srgb")
        grammar = GrammarTextures(ctx, library_texture_with(grammar_files), assets.tile_array())
        return cls(
            rooms,
            atlas,
            layout,
            upload_texture(ctx, facade_np, "srgb"),
            tuple(float(g) for g in glass),
            sprites,
            kinds,
            frames,
            curtain,
            variants,
            grammar,
            DeferredGrammarPass(ctx),
        )

    def release(self):
        for tex in (self.rooms, self.atlas, self.facade, self.sprites, self.curtain):
            tex.release()
        self.grammar.release()
        self.grammar_pass.release()
