"""What a context shares between everything drawn with it: one program cache, the vertex arrays
of the full-screen passes, the buffers of the uniform blocks and the buffers rewritten per draw."""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import moderngl

from ._buffers import DrawBuffers
from ._programs import ProgramCache
from ._vertex_arrays import VertexArrays


@dataclass
class ContextResources:
    programs: ProgramCache
    vertex_arrays: VertexArrays
    draw_buffers: DrawBuffers
    block_buffers: dict[str, moderngl.Buffer] = field(default_factory=dict)  # by block name


_BY_CONTEXT: "weakref.WeakKeyDictionary[moderngl.Context, ContextResources]" = weakref.WeakKeyDictionary()


def resources(ctx: moderngl.Context) -> ContextResources:
    found = _BY_CONTEXT.get(ctx)
    if found is None:
        found = _BY_CONTEXT[ctx] = ContextResources(ProgramCache(ctx), VertexArrays(ctx), DrawBuffers(ctx))
    return found


def programs(ctx: moderngl.Context) -> ProgramCache:
    """The context's one program cache."""
    return resources(ctx).programs


def draw_buffers(ctx: moderngl.Context) -> DrawBuffers:
    """The context's buffers rewritten from draw to draw, by name (see gl.DrawBuffers)."""
    return resources(ctx).draw_buffers
