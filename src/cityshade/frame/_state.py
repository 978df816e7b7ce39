"""The fixed-function state a pass draws with, set in full before each pass."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl


@dataclass(frozen=True)
class GLState:
    """Every piece of fixed-function state a pass relies on; applied in full before it draws."""

    depth_test: bool = True
    depth_func: str = "<"
    depth_write: bool = True
    colour_write: bool = True
    blend: tuple[int, int] | None = None  # (source, destination) factors; None: off
    cull: bool = False  # back faces

    def apply(self, ctx: moderngl.Context) -> None:
        ctx.enable(moderngl.DEPTH_TEST) if self.depth_test else ctx.disable(moderngl.DEPTH_TEST)
        ctx.depth_func = self.depth_func
        ctx.depth_mask = self.depth_write
        ctx.color_mask = (self.colour_write,) * 4
        if self.blend is None:
            ctx.disable(moderngl.BLEND)
        else:
            ctx.enable(moderngl.BLEND)
            ctx.blend_func = self.blend
        ctx.enable(moderngl.CULL_FACE) if self.cull else ctx.disable(moderngl.CULL_FACE)
