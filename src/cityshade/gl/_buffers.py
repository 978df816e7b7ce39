"""GPU buffers: vertex, index, instance and storage buffers made from numpy arrays, and buffers whose
contents change from draw to draw, kept with their vertex arrays across draws."""

from __future__ import annotations

from typing import Hashable, Sequence

import moderngl
import numpy as np

from ._vertex_arrays import VertexArrays

MIN_BYTES = 16  # GL has no empty buffers, and a bound storage buffer of no size faults


def _raw(data: np.ndarray | bytes) -> bytes:
    return data if isinstance(data, bytes) else np.ascontiguousarray(data).tobytes()


def create_buffer(ctx: moderngl.Context, data: np.ndarray | bytes = b"", reserve: int = 0) -> moderngl.Buffer:
    """A buffer holding `data` (a numpy array or bytes), or `reserve` bytes of zeros; MIN_BYTES
    zero bytes when there is nothing to hold (a city without lamps still binds its lamp buffer)."""
    raw = _raw(data)
    if raw:
        return ctx.buffer(raw)
    return ctx.buffer(reserve=max(reserve, MIN_BYTES))


def grow_buffer(buffer: moderngl.Buffer, count: int, item_bytes: int):
    """Makes `buffer` hold at least `count` items of `item_bytes` (its contents then undefined):
    reallocated in place for the next power of two of items, so its GL name, and the vertex arrays
    over it, stay valid."""
    if buffer.size < count * item_bytes:
        buffer.orphan(item_bytes << (count - 1).bit_length())


class DrawBuffers:
    """Buffers whose contents are replaced from draw to draw (instance lists that change with the
    view), and the vertex arrays over them, both kept across draws: a buffer is remade, and the
    vertex arrays with it, only when new contents outgrow it."""

    def __init__(self, ctx: moderngl.Context):
        self.ctx = ctx
        self._buffers: dict[str, moderngl.Buffer] = {}
        self._vertex_arrays = VertexArrays(ctx)

    def write(self, name: str, data: np.ndarray | bytes) -> moderngl.Buffer:
        """The buffer called `name`, now holding `data` from its start."""
        raw = _raw(data)
        buffer = self._buffers.get(name)
        if buffer is None or buffer.size < len(raw):
            if buffer is not None:
                buffer.release()
                self._vertex_arrays.release()  # they point at the buffer being replaced
            buffer = self._buffers[name] = create_buffer(self.ctx, reserve=len(raw))
        if raw:
            buffer.write(raw)
        return buffer

    def vertex_array(self, key: Hashable, program, bindings: Sequence[tuple], index_buffer=None):
        """A vertex array over these buffers (see gl.VertexArrays.get)."""
        return self._vertex_arrays.get(key, program, bindings, index_buffer)

    def release(self):
        self._vertex_arrays.release()
        for buffer in self._buffers.values():
            buffer.release()
        self._buffers.clear()
