"""The one way vertex arrays are made: from (buffer, format, attribute names...) bindings, skipping
the attributes a program variant compiled away, cached per key and released together."""

from __future__ import annotations

import re
from typing import Hashable, Sequence

import moderngl

_ATTRIBUTE = re.compile(r"(\d*)([fiu])(\d?)")


def _skip(fmt: str) -> str:
    """A moderngl format that skips an attribute's bytes: '3f' -> '12x', 'i4' -> '4x'."""
    match = _ATTRIBUTE.fullmatch(fmt)
    if match is None:
        raise ValueError(f"not an attribute format: {fmt!r}")
    count, _, size = match.groups()
    return f"{int(count or 1) * int(size or 4)}x"


def _binding(program, buffer, fmt: str, *attributes: str) -> tuple:
    per_instance = fmt.endswith("/i")
    parts = fmt[:-2].split() if per_instance else fmt.split()
    kept = [a for a in attributes if a in program]
    layout = " ".join(p if a in program else _skip(p) for p, a in zip(parts, attributes))
    return (buffer, layout + (" /i" if per_instance else ""), *kept)


class VertexArrays:
    """Vertex arrays keyed by the caller (usually program and mesh); made on first use."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self._vaos: dict[Hashable, moderngl.VertexArray] = {}

    def get(self, key: Hashable, program, bindings: Sequence[tuple], index_buffer=None) -> moderngl.VertexArray:
        vao = self._vaos.get(key)
        if vao is None:
            content = [_binding(program, *binding) for binding in bindings]
            vao = self.ctx.vertex_array(program, content, index_buffer=index_buffer, index_element_size=4)
            self._vaos[key] = vao
        return vao

    def release(self):
        for vao in self._vaos.values():
            vao.release()
        self._vaos.clear()
