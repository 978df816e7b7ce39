"""What a context shares between everything drawn with it: one program cache, the vertex arrays
of the full-screen passes and the buffers of the uniform blocks."""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field

import moderngl

from ._programs import ProgramCache
from ._vertex_arrays import VertexArrays


@dataclass
class ContextResources:
    programs: ProgramCache
    vertex_arrays: VertexArrays
    block_buffers: dict[str, moderngl.Buffer] = field(default_factory=dict)  # by block name


_BY_CONTEXT: "weakref.WeakKeyDictionary[moderngl.Context, ContextResources]" = weakref.WeakKeyDictionary()


def resources(ctx: moderngl.Context) -> ContextResources:
    found = _BY_CONTEXT.get(ctx)
    if found is None:
        found = _BY_CONTEXT[ctx] = ContextResources(ProgramCache(ctx), VertexArrays(ctx))
    return found


def programs(ctx: moderngl.Context) -> ProgramCache:
    """The context's one program cache."""
    return resources(ctx).programs
