"""The batched city's chunks (its vertex order) and the box-against-frustum test; the GPU culling
itself is tested in test_culling_gpu.py."""

from __future__ import annotations

import numpy as np
import pytest

from cityshade.errors import UsageError
from cityshade.frame import boxes_visible, chunk_vertices, frustum_planes
from cityshade.render import Renderer, RenderSettings
from cityshade.render.testing import building_boxes, building_ranges
from cityshade.scene import Camera, batch, make_city
from render_checks import render_finite


def test_chunks_cover_every_vertex_once_and_keep_triangles_whole():
    city = make_city("default")
    unsorted, _ = batch(city.masses)
    vertices, chunks = chunk_vertices(unsorted)
    assert chunks.count.sum() == len(unsorted)
    # a reordering: the same vertices, each once
    assert np.array_equal(np.sort(vertices.view(np.void)), np.sort(unsorted.view(np.void)))
    assert np.all(chunks.first[1:] == chunks.first[:-1] + chunks.count[:-1])
    assert np.all(chunks.count % 3 == 0)
    # every triangle's three vertices come from one building
    ids = vertices["ids"][:, 0].reshape(-1, 3)
    assert np.all(ids == ids[:, :1])
    assert len(chunks) > 10
    # each building one contiguous range (the GPU culling draws it as one command), its box exact
    first, count = building_ranges(vertices, len(city.masses))
    building = vertices["ids"][:, 0]
    for index in (0, 17, len(city.masses) - 1):
        assert np.all(building[first[index] : first[index] + count[index]] == index)
    assert count.sum() == len(vertices)
    boxes = building_boxes(vertices, first, count)
    positions = vertices["position"]
    lo, hi = np.full((len(city.masses), 3), np.inf, np.float32), np.full((len(city.masses), 3), -np.inf, np.float32)
    np.minimum.at(lo, building, positions)
    np.maximum.at(hi, building, positions)
    # in vertex-buffer order (the draw order of one plain draw), every building with vertices once
    assert np.all(np.diff(boxes["draw"][:, 1].astype(np.int64)) > 0)
    index = boxes["draw"][:, 2]
    assert sorted(index) == list(range(len(city.masses)))
    assert np.array_equal(boxes["draw"][:, 0], count[index]) and np.array_equal(boxes["draw"][:, 1], first[index])
    assert np.array_equal(boxes["lo"][:, :3], lo[index]) and np.array_equal(boxes["hi"][:, :3], hi[index])


def test_box_test_is_exact_for_clear_cases():
    camera = Camera((0.0, 0.0, 0.0), (0.0, 0.0, -1.0), fov_y=60.0, near=0.5, far=100.0)
    planes = frustum_planes(camera.view_projection(1.0))
    lo = np.array([[-1.0, -1.0, -11.0], [-1.0, -1.0, 9.0], [50.0, -1.0, -11.0], [-1, -1, -200.0]])
    hi = lo + 2.0
    assert boxes_visible(planes, lo, hi).tolist() == [True, False, False, False]


def test_chunk_culled_frame_equals_unculled_frame(gl_context):
    city = make_city("default")
    camera = city.camera("street")
    pictures = {}
    for culling in ("frustum", "off"):
        renderer = Renderer((128, 72), RenderSettings(samples=0, culling=culling), ctx=gl_context)
        renderer.set_city(city)
        try:
            pictures[culling] = render_finite(renderer, camera)
        finally:
            renderer.release()
    chunks = chunk_vertices(batch(city.masses)[0])[1]
    assert np.count_nonzero(chunks.visible(camera.view_projection(128 / 72))) < len(chunks), (
        "a street-level view leaves chunks behind the camera"
    )
    assert np.array_equal(pictures["frustum"], pictures["off"])


def test_unknown_culling_is_one_clear_error():
    with pytest.raises(UsageError, match="unknown culling 'fast'; allowed: gpu, frustum, off"):
        RenderSettings(culling="fast")
