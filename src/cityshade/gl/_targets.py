"""Offscreen render targets: HDR colour (optionally multisampled), depth, integer id AOVs."""

from __future__ import annotations

import moderngl
import numpy as np

from .._budget import check_gl_size


class RenderTarget:
    """A framebuffer with colour attachments of given dtypes plus a depth buffer."""

    def __init__(self, ctx: moderngl.Context, size: tuple[int, int], colors=(("f2", 4),), samples: int = 0):
        check_gl_size(ctx, size)
        self.ctx = ctx
        self.size = size
        self.samples = min(samples, ctx.max_samples) if samples else 0
        self.colors = [ctx.texture(size, comps, dtype=dtype, samples=self.samples) for dtype, comps in colors]
        for tex in self.colors:
            if not self.samples:
                tex.filter = (moderngl.NEAREST, moderngl.NEAREST)
        self.depth = ctx.depth_texture(size, samples=self.samples)
        self.fbo = ctx.framebuffer(color_attachments=self.colors, depth_attachment=self.depth)

    def use(self):
        self.fbo.use()

    def read(self, attachment: int = 0) -> np.ndarray:
        """The attachment as an HxWxC array, top row first."""
        tex = self.colors[attachment]
        dtype = {"f1": np.uint8, "f2": np.float16, "f4": np.float32, "u4": np.uint32, "i4": np.int32, "u1": np.uint8}[
            tex.dtype
        ]
        data = np.frombuffer(
            self.fbo.read(components=tex.components, attachment=attachment, dtype=tex.dtype), dtype=dtype
        )
        return data.reshape(self.size[1], self.size[0], tex.components)[::-1]

    def release(self):
        self.fbo.release()
        for tex in self.colors:
            tex.release()
        self.depth.release()
