"""The buildings' vertices as the GPU holds them (scene.face_table): a 36-byte vertex and a row of
the face table per distinct face. The vertex stage must see every meshed value bit for bit: the
table is checked on the CPU (expanded back: the very bytes of the meshed records) and on the GPU
(the vertex stage's outputs captured with transform feedback equal the meshed records' fields)."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from cityshade.gl import ProgramCache, RenderTarget, VertexArrays, create_buffer
from cityshade.maps import load_map, map_city
from cityshade.scene import (
    FACES_BINDING,
    GPU_VERTEX_ATTRIBUTES,
    GPU_VERTEX_DTYPE,
    GPU_VERTEX_FORMAT,
    batch,
    default_city,
    expand_face_table,
    face_table,
)
from cityshade.scene import _face_table


def _round_trip(vertices: np.ndarray, first_row: int = 0):
    compact, rows = face_table(vertices, first_row)
    assert compact.dtype == GPU_VERTEX_DTYPE and compact.dtype.itemsize == 36
    back = expand_face_table(compact, rows, first_row)
    as_bytes = [np.ascontiguousarray(v).view(np.uint8).reshape(len(v), v.dtype.itemsize) for v in (back, vertices)]
    differing = int(np.count_nonzero(np.any(as_bytes[0] != as_bytes[1], axis=1)))
    assert differing == 0, f"{differing} of {len(vertices)} vertices changed"
    return compact, rows


def test_the_district_round_trips_bit_for_bit():
    """Boxes, the cylinder tower (a normal per vertex) and the dome, rows shared across faces."""
    vertices, _ = batch(default_city(blocks=6).masses)
    compact, rows = _round_trip(vertices)
    assert len(np.unique(rows.view(np.dtype((np.void, rows.dtype.itemsize))))) == len(rows)  # each row once
    assert len(rows) < len(vertices) / 4


def test_helsinki_round_trips_bit_for_bit(helsinki_pbf):
    """Pitched, skeleton and pointed roofs, courtyards, undersides, dormers."""
    vertices, _ = batch(map_city(load_map(helsinki_pbf)).masses)
    _round_trip(vertices)
    _round_trip(vertices[: len(vertices) // 2], first_row=1234)  # a tile's table placed after others


def test_colliding_hashes_still_give_distinct_rows(monkeypatch):
    """Every row hashed alike: the rows are told apart by their bytes."""
    monkeypatch.setattr(_face_table, "FNV_PRIME", np.uint64(0))
    vertices, _ = batch(default_city(blocks=2).masses)
    _round_trip(vertices)


def test_the_vertex_stage_reads_each_row_exactly(gl_context):
    """The vertex stage's normal, spacing, face and ids (captured before rasterising) are the
    meshed records' bits, for every vertex of the district."""
    vertices, _ = batch(default_city(blocks=4).masses)
    compact, rows = face_table(vertices)
    programs = ProgramCache(gl_context)
    outputs = ("v_normal", "v_spacing", "v_face", "v_ids")
    program = programs.get("city/building.glsl", {"DEPTH_ONLY": True}, varyings=outputs)
    program["u_view_proj"].write(np.identity(4, np.float32).tobytes())
    vbo, faces = create_buffer(gl_context, compact), create_buffer(gl_context, rows)
    out = gl_context.buffer(reserve=len(vertices) * 13 * 4)
    vaos = VertexArrays(gl_context)
    vao = vaos.get("faces", program, [(vbo, GPU_VERTEX_FORMAT, *GPU_VERTEX_ATTRIBUTES)])
    target = RenderTarget(gl_context, (4, 4))  # transform feedback still wants a framebuffer bound
    try:
        target.use()
        faces.bind_to_storage_buffer(FACES_BINDING)
        vao.transform(out, moderngl.TRIANGLES, vertices=len(vertices))
        words = np.frombuffer(out.read(), np.uint32).reshape(len(vertices), 13)
    finally:
        for obj in (vbo, faces, out, target):
            obj.release()
        vaos.release()
    fields = (vertices["normal"], vertices["facade"][:, 2:], vertices["face"], vertices["ids"])
    meshed = np.concatenate([np.ascontiguousarray(f).view(np.uint32) for f in fields], axis=1)
    differing = int(np.count_nonzero(np.any(words != meshed, axis=1)))
    assert differing == 0, f"{differing} of {len(vertices)} vertices read other values than meshed"


@pytest.mark.parametrize("count", [0, 1])
def test_tiny_arrays(count):
    vertices, _ = batch(default_city(blocks=2).masses)
    compact, rows = _round_trip(np.ascontiguousarray(vertices[:count]))
    assert len(compact) == count and len(rows) == count
