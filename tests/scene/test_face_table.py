"""The buildings' vertices as the GPU holds them (scene.face_table, scene.shared_vertices): a 24-byte
vertex, a row of the face table per distinct face, each building's placement, and an index buffer.
The vertex stage must see every meshed value bit for bit: checked on the CPU (expanded back: the
very bytes of the meshed records) and on the GPU (the vertex stage's outputs, captured with
transform feedback, equal the meshed records' fields, the world position included)."""

from __future__ import annotations

import moderngl
import numpy as np
import pytest

from cityshade.gl import ProgramCache, RenderTarget, VertexArrays, binding, create_buffer
from cityshade.maps import load_map, map_city
from cityshade.scene import (
    GPU_VERTEX_ATTRIBUTES,
    GPU_VERTEX_DTYPE,
    GPU_VERTEX_FORMAT,
    _face_table,
    batch,
    box,
    default_city,
    expand_face_table,
    face_table,
    placements,
    shared_vertices,
)

OUTPUTS = ("v_world", "v_local", "v_normal", "v_facade", "v_spacing", "v_face", "v_ids")
OUTPUT_FIELDS = (  # the meshed record's words each output must carry
    ("position", slice(None)),
    ("local", slice(None)),
    ("normal", slice(None)),
    ("facade", slice(0, 2)),
    ("facade", slice(2, 4)),
    ("face", slice(None)),
    ("ids", slice(None)),
)


def _differing(a: np.ndarray, b: np.ndarray) -> int:
    rows = [np.ascontiguousarray(x).view(np.uint8).reshape(len(x), x.dtype.itemsize) for x in (a, b)]
    return int(np.count_nonzero(np.any(rows[0] != rows[1], axis=1)))


def _round_trip(masses, first_row: int = 0):
    vertices, _ = batch(masses)
    placement = placements(masses)
    compact, rows = face_table(vertices, placement, first_row)
    assert compact.dtype == GPU_VERTEX_DTYPE and compact.dtype.itemsize == 24
    differing = _differing(expand_face_table(compact, rows, placement, first_row), vertices)
    assert differing == 0, f"{differing} of {len(vertices)} vertices changed"
    shared, indices = shared_vertices(compact)
    assert _differing(shared[indices], compact) == 0
    return vertices, compact, rows


def test_the_district_round_trips_bit_for_bit():
    """Boxes, the cylinder tower (a normal per vertex) and the dome, rows shared across faces."""
    vertices, compact, rows = _round_trip(default_city(blocks=6).masses)
    assert len(np.unique(rows.view(np.dtype((np.void, rows.dtype.itemsize))))) == len(rows)  # each row once
    assert len(rows) < len(vertices) / 4
    assert len(shared_vertices(compact)[0]) < 0.8 * len(compact)


def test_helsinki_round_trips_bit_for_bit(helsinki_pbf):
    """Pitched, skeleton and pointed roofs, courtyards, undersides, dormers."""
    masses = map_city(load_map(helsinki_pbf)).masses
    _round_trip(masses)
    _round_trip(masses[: len(masses) // 2], first_row=1234)  # a tile's table placed after others


def test_turned_buildings_round_trip_bit_for_bit():
    _round_trip([box((10.0 * i - 0.3, 3.7 * i), 12.0 + i, 9.5, 30.0, yaw=0.37 * i - 2.0) for i in range(30)])


def test_colliding_hashes_still_give_distinct_rows(monkeypatch):
    """Every row hashed alike: the rows are told apart by their bytes."""
    monkeypatch.setattr(_face_table, "FNV_PRIME", np.uint64(0))
    _round_trip(default_city(blocks=2).masses)


def test_a_vertex_placed_otherwise_is_refused():
    masses = default_city(blocks=2).masses
    vertices, _ = batch(masses)
    vertices["position"][5, 0] = np.nextafter(vertices["position"][5, 0], np.float32(np.inf))
    with pytest.raises(ValueError, match="1 vertices are not where their building's placement puts them"):
        face_table(vertices, placements(masses))


@pytest.mark.parametrize("blocks", [0, 2])
def test_empty_and_small_cities(blocks):
    masses = default_city(blocks=blocks).masses
    _round_trip(masses)


def test_the_vertex_stage_reads_each_value_exactly(gl_context):
    """The vertex stage's outputs (captured before rasterising, through the index buffer) are the
    meshed records' bits, for every vertex of the district, turned buildings among them."""
    masses = default_city(blocks=4).masses + [box((5.0 * i, -80.0), 9.0, 7.0, 12.0, yaw=0.61 * i) for i in range(12)]
    vertices, _ = batch(masses)
    placement = placements(masses)
    compact, rows = face_table(vertices, placement)
    shared, indices = shared_vertices(compact)
    programs = ProgramCache(gl_context)
    program = programs.get("city/building.glsl", {"DEPTH_ONLY": True}, varyings=OUTPUTS)
    program["u_view_proj"].write(np.identity(4, np.float32).tobytes())
    buffers = [create_buffer(gl_context, data) for data in (shared, indices, rows, placement)]
    vbo, ibo, faces, placed = buffers
    meshed = np.concatenate(
        [np.ascontiguousarray(vertices[name][:, part]).view(np.uint32) for name, part in OUTPUT_FIELDS], axis=1
    )
    out = gl_context.buffer(reserve=meshed.nbytes)
    vaos = VertexArrays(gl_context)
    vao = vaos.get("faces", program, [(vbo, GPU_VERTEX_FORMAT, *GPU_VERTEX_ATTRIBUTES)], index_buffer=ibo)
    target = RenderTarget(gl_context, (4, 4))  # transform feedback still wants a framebuffer bound
    try:
        target.use()
        faces.bind_to_storage_buffer(binding("BuildingFaces"))
        placed.bind_to_storage_buffer(binding("BuildingPlacements"))
        vao.transform(out, moderngl.TRIANGLES, vertices=len(indices))
        got = np.frombuffer(out.read(), np.uint32).reshape(meshed.shape)
    finally:
        for obj in (*buffers, out, target):
            obj.release()
        vaos.release()
    differing = int(np.count_nonzero(np.any(got != meshed, axis=1)))
    assert differing == 0, f"{differing} of {len(vertices)} vertices read other values than meshed"
