"""Uploads the procedural assets the city's shaders sample."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from .. import assets
from ..grammar._city import library_texture
from ..grammar._frame_pass import DeferredGrammarPass
from ..grammar._gpu import GrammarTextures

ROOM_FACES = ("ceiling", "floor", "wall_x", "wall_z")


def linear(image: np.ndarray) -> np.ndarray:
    """sRGB-encoded uint8 -> linear float16 (alpha stays linear), so shading and filtering are linear."""
    x = image.astype(np.float32) / 255.0
    rgb = x[..., :3]
    x[..., :3] = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    return x.astype(np.float16)


def _mipmapped(tex):
    # trilinear, not anisotropic: llvmpipe's anisotropic filtering costs seconds per frame
    tex.build_mipmaps()
    tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    return tex


def texture_2d(ctx: moderngl.Context, image: np.ndarray, repeat: bool = True):
    image = np.ascontiguousarray(linear(image))
    h, w, c = image.shape
    tex = _mipmapped(ctx.texture((w, h), c, image.tobytes(), dtype="f2"))
    tex.repeat_x = tex.repeat_y = repeat
    return tex


def texture_array(ctx: moderngl.Context, layers: np.ndarray, repeat: bool = False):
    layers = np.ascontiguousarray(linear(layers))
    n, h, w, c = layers.shape
    tex = _mipmapped(ctx.texture_array((w, h, n), c, layers.tobytes(), dtype="f2"))
    tex.repeat_x = tex.repeat_y = repeat
    return tex


def cubemap(ctx: moderngl.Context, faces: np.ndarray):
    faces = np.ascontiguousarray(faces.astype(np.float16))
    tex = ctx.texture_cube((faces.shape[2], faces.shape[1]), 3, faces.tobytes(), dtype="f2")
    tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
    return tex


@dataclass
class CityTextures:
    """GL textures for rooms, facade bay, furniture sprites, curtains and the sky."""

    rooms: dict
    atlas: moderngl.Texture
    atlas_layout: dict
    facade: moderngl.Texture
    glass_rect: tuple[float, float, float, float]
    sprites: moderngl.TextureArray
    sprite_kinds: int
    sprite_frames: int
    curtain: moderngl.Texture
    room_variants: int
    grammar: GrammarTextures  # facade grammar library: rules, noise, tile array
    grammar_pass: DeferredGrammarPass  # targets of the deferred grammar evaluation

    @classmethod
    def create(cls, ctx: moderngl.Context, room_size: int = 256, variants: int = 8) -> "CityTextures":
        rooms_np = assets.room_textures(size=room_size, variants=variants)
        rooms = {face: texture_array(ctx, rooms_np[face]) for face in ROOM_FACES}
        atlas_np, layout = assets.room_atlas(rooms_np)
        atlas = texture_2d(ctx, atlas_np, repeat=False)
        facade_np, glass = assets.facade_texture()
        sprites_np = assets.furniture_sprites()
        kinds, frames = sprites_np.shape[:2]
        sprites = texture_array(ctx, sprites_np.reshape(kinds * frames, *sprites_np.shape[2:]))
        curtain = texture_2d(ctx, assets.curtain_texture())
        grammar = GrammarTextures(ctx, library_texture(), assets.tile_array())
        return cls(rooms, atlas, layout, texture_2d(ctx, facade_np), tuple(float(g) for g in glass), sprites,
                   kinds, frames, curtain, variants, grammar, DeferredGrammarPass(ctx))

    def release(self):
        for tex in (*self.rooms.values(), self.atlas, self.facade, self.sprites, self.curtain):
            tex.release()
        self.grammar.release()
        self.grammar_pass.release()
