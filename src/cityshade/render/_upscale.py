"""A frame drawn at a reduced internal resolution, stretched bilinearly to the window's size
(shaders/post/upscale.glsl), and the same stretch in numpy to check it against."""

from __future__ import annotations

import moderngl
import numpy as np

from ..gl import ProgramCache, bind_textures, draw_fullscreen, set_uniforms


def upscale(programs: ProgramCache, frame: moderngl.Texture, target: moderngl.Framebuffer):
    """Draws `frame` stretched over all of `target`."""
    program = programs.get("post/upscale.glsl")
    target.use()
    target.viewport = (0, 0, *target.size)
    bind_textures(program, {"u_frame": frame})
    set_uniforms(program, u_output_size=tuple(int(v) for v in target.size))
    programs.ctx.disable(moderngl.DEPTH_TEST | moderngl.BLEND)
    draw_fullscreen(program)


def upscale_reference(image: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """The shader's bilinear stretch of an HxWxC uint8 image to size (width, height): pixel centres
    map onto the source's, edges clamp."""
    height, width = image.shape[:2]
    source = image.astype(np.float32) / 255.0

    def axis(out: int, n: int):
        at = np.maximum((np.arange(out, dtype=np.float32) + 0.5) * np.float32(n / out) - 0.5, 0.0)
        low = np.minimum(np.floor(at).astype(int), n - 1)
        return low, np.minimum(low + 1, n - 1), (at - low).astype(np.float32)

    x0, x1, tx = axis(size[0], width)
    y0, y1, ty = axis(size[1], height)
    tx, ty = tx[None, :, None], ty[:, None, None]
    bottom = source[y0][:, x0] * (1 - tx) + source[y0][:, x1] * tx
    top = source[y1][:, x0] * (1 - tx) + source[y1][:, x1] * tx
    return np.round((bottom * (1 - ty) + top * ty) * 255.0).astype(np.uint8)
