"""The one texture upload: 2D images or arrays, with their colour space said explicitly, and the
sky's cube map."""

from __future__ import annotations

import moderngl
import numpy as np

from ._colour import srgb_to_linear

COLOUR_SPACES = ("srgb", "stored")


def upload_texture(
    ctx: moderngl.Context,
    data: np.ndarray,
    colour_space: str,
    mipmaps: bool = True,
    repeat: bool = True,
    dtype: str | None = None,
):
    """A 2D texture (HxWxC) or texture array (NxHxWxC).

    colour_space "srgb": 8-bit sRGB colour, converted exactly to linear float16 (alpha stays linear)
    so that filtering and shading are linear; "stored": the values go up as given, in `dtype`
    (default: the array's own) - linear data (heights, normals, rule texels) or colour that a
    shader decodes itself with common/srgb.glsl."""
    if colour_space not in COLOUR_SPACES:
        raise ValueError(f"colour space {colour_space!r}; use one of {COLOUR_SPACES}")
    if colour_space == "srgb":
        data = data.astype(np.float32) / 255.0
        data[..., :3] = srgb_to_linear(data[..., :3])
        data, dtype = data.astype(np.float16), "f2"
    data = np.ascontiguousarray(data)
    dtype = (
        dtype or {np.uint8: "f1", np.float16: "f2", np.float32: "f4", np.uint32: "u4", np.int32: "i4"}[data.dtype.type]
    )
    if data.ndim == 4:
        n, h, w, c = data.shape
        tex = ctx.texture_array((w, h, n), c, data.tobytes(), dtype=dtype)
    else:
        h, w, c = data.shape if data.ndim == 3 else (*data.shape, 1)
        tex = ctx.texture((w, h), c, data.tobytes(), dtype=dtype)
    if mipmaps:
        # trilinear, not anisotropic: llvmpipe's anisotropic filtering costs seconds per frame
        tex.build_mipmaps()
        tex.filter = (moderngl.LINEAR_MIPMAP_LINEAR, moderngl.LINEAR)
    else:
        tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
    tex.repeat_x = tex.repeat_y = repeat
    return tex


def upload_cubemap(ctx: moderngl.Context, faces: np.ndarray) -> moderngl.TextureCube:
    """A cube map of linear radiance, faces (6, H, W, 3) in GL's order (+x, -x, +y, -y, +z, -z),
    stored as float16 and filtered linearly."""
    faces = np.ascontiguousarray(faces.astype(np.float16))
    tex = ctx.texture_cube((faces.shape[2], faces.shape[1]), 3, faces.tobytes(), dtype="f2")
    tex.filter = (moderngl.LINEAR, moderngl.LINEAR)
    return tex
