"""What a context shares between everything drawn with it: one program cache and the vertex
arrays of the full-screen passes."""

from __future__ import annotations

import weakref
from dataclasses import dataclass

import moderngl

from ._programs import ProgramCache
from ._vertex_arrays import VertexArrays


@dataclass
class ContextResources:
    programs: ProgramCache
    vertex_arrays: VertexArrays


_BY_CONTEXT: "weakref.WeakKeyDictionary[moderngl.Context, ContextResources]" = weakref.WeakKeyDictionary()


def resources(ctx: moderngl.Context) -> ContextResources:
    found = _BY_CONTEXT.get(ctx)
    if found is None:
        found = _BY_CONTEXT[ctx] = ContextResources(ProgramCache(ctx), VertexArrays(ctx))
    return found


def programs(ctx: moderngl.Context) -> ProgramCache:
    """The context's one program cache."""
    return resources(ctx).programs
