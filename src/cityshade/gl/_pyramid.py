"""Textures for max-reduction pyramids (a hierarchical depth buffer): one float channel per texel,
the full mip chain allocated, read texel by texel (no filtering)."""

from __future__ import annotations

import moderngl

R32F = 0x822E  # GL_R32F: the image format compute shaders write the levels in


def pyramid_levels(size: tuple[int, int]) -> list[tuple[int, int]]:
    """The sizes of a full mip chain, level 0 first (OpenGL's rule: each level halves, rounding down)."""
    width, height = size
    levels = [(width, height)]
    while levels[-1] != (1, 1):
        w, h = levels[-1]
        levels.append((max(w // 2, 1), max(h // 2, 1)))
    return levels


def pyramid_texture(ctx: moderngl.Context, size: tuple[int, int]) -> moderngl.Texture:
    """An r32f texture of `size` with every level of its mip chain allocated."""
    texture = ctx.texture(size, 1, dtype="f4")
    texture.build_mipmaps(0, len(pyramid_levels(size)) - 1)  # allocates the levels; compute fills them
    texture.filter = (moderngl.NEAREST_MIPMAP_NEAREST, moderngl.NEAREST)
    texture.repeat_x = texture.repeat_y = False
    return texture
